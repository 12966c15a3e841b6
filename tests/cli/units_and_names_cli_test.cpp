// What the user types: lengths and angles with their units, a bare number that cannot be
// meant in mm refused at its place with the reading it suggests, and mistyped commands and
// options answered with the nearest (issue 48, points 1 and 6).
#include <gtest/gtest.h>

#include <filesystem>

#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

namespace fs = std::filesystem;

const std::string kPocket = sample("programs/pocket-xy.ngc");
const std::string kTools = sample("tools.tbl");
const std::string kHmc = sample("machines/hmc-xyzb-geometric.yaml");
const std::string kData = sample("measurements/hmc-laser-grid-sphere.csv");

struct Refused {
  const char* name;
  std::string args;  ///< after `ccomp`; OUT is replaced by a file in the test's folder
  std::vector<std::string> says;
};

class RefusedCommandLines : public testing::TestWithParam<Refused> {};

TEST_P(RefusedCommandLines, AreUsageErrorsThatSayWhatWasMeant) {
  const Refused& c = GetParam();
  const std::string dir = temp_dir(std::string("refused_") + c.name);
  std::string args = c.args;
  if (const auto at = args.find("OUT"); at != std::string::npos) args.replace(at, 3, shell_quote(dir + "/out.ngc"));
  const CommandResult r = run_command(ccomp() + " " + args);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  for (const std::string& s : c.says) EXPECT_NE(r.err.find(s), std::string::npos) << "wanted: " << s << "\n" << r.err;
  EXPECT_FALSE(fs::exists(dir + "/out.ngc"));
}

INSTANTIATE_TEST_SUITE_P(
    Cli, RefusedCommandLines,
    testing::Values(
        // A micrometre meant, the option in mm: 1 mm chords would be 0.34 mm off an R10 arc.
        Refused{"tolerance_bare_1", kPocket + " -m " + kHmc + " --tolerance 1 -o OUT",
                {"command line:1:", "error: --tolerance 1: a number without a unit is mm here",
                 "did you mean 1um?", "\n  ccomp "}},
        Refused{"tolerance_equals", kPocket + " -m " + kHmc + " --tolerance=5 -o OUT", {"did you mean 5um?"}},
        Refused{"tolerance_angle", kPocket + " -m " + kHmc + " --tolerance 5urad -o OUT",
                {"'urad' measures angle, but length belongs here"}},
        Refused{"verify_tolerance", "verify " + kPocket + " " + kPocket + " -m " + kHmc + " --tolerance 2",
                {"did you mean 2um?"}},
        Refused{"work_offset_unit", kPocket + " -m " + kHmc + " --work-offset G54=X0,Y0,Z-400furlong -o OUT",
                {"command line:1:", "unknown unit 'furlong'"}},
        Refused{"tool_length_unit", "simulate -m " + kHmc + " -o OUT --tool-length 100deg",
                {"'deg' measures angle, but length belongs here"}},
        Refused{"mistyped_command", "chek " + kData + " -m " + kHmc,
                {"error: unknown command 'chek'; did you mean 'check'?"}},
        Refused{"mistyped_command_with_its_option", "chek " + kData + " -m " + kHmc + " --report OUT",
                {"error: unknown command 'chek'; did you mean 'check'?"}},
        Refused{"unknown_word", "frobnicate -m " + kHmc + " -o OUT",
                {"'frobnicate' is neither a program file nor a command", "check"}},
        Refused{"mistyped_option", kPocket + " -m " + kHmc + " --tolerence 1um -o OUT",
                {"command line:1:", "unknown option '--tolerence'; did you mean '--tolerance'?"}},
        Refused{"mistyped_option_of_a_command", "check " + kData + " -m " + kHmc + " --reprot OUT",
                {"unknown option '--reprot' of 'check'; did you mean '--report'?"}}),
    [](const testing::TestParamInfo<Refused>& p) { return std::string(p.param.name); });

/// The main job's output and stderr for `options`.
CommandResult compensate(const std::string& dir, const std::string& name, const std::string& options) {
  const std::string out = dir + "/" + name + ".ngc";
  CommandResult r = run_command(ccomp() + " " + kPocket + " -m " + kHmc + " --tool-table " + kTools + " -o " + shell_quote(out) + " " + options);
  r.out = fs::exists(out) ? read_file(out) : "";
  return r;
}

TEST(CliUnits, AValueWithItsUnitIsTheSameValueInMm) {
  const std::string dir = temp_dir("cli_units_same");
  const CommandResult in_mm = compensate(dir, "mm", "--tolerance 0.001 --work-offset G54=X0,Y0,Z-400");
  const CommandResult in_um = compensate(dir, "um", "--tolerance 1um --work-offset G54=X0,Y0um,Z-0.4m");
  const CommandResult in_inch = compensate(dir, "in", "--tolerance=0.00003937in --work-offset 'G54 X0 Y0 Z-400mm'");
  ASSERT_EQ(in_mm.exit_code, 0) << in_mm.err;
  ASSERT_EQ(in_um.exit_code, 0) << in_um.err;
  ASSERT_EQ(in_inch.exit_code, 0) << in_inch.err;
  EXPECT_EQ(in_um.out, in_mm.out);
  EXPECT_NE(in_inch.out.find("B"), std::string::npos);  // (compensated at all: a header and moves)
  EXPECT_NE(in_mm.err.find("at 1 um"), std::string::npos) << in_mm.err;
  EXPECT_NE(in_um.err.find("at 1 um"), std::string::npos) << in_um.err;
}

TEST(CliUnits, AToleranceNotBelowTheErrorBeforeIsWarnedOf) {
  // The geometric HMC's error on the pocket is about 10 um: a 20 um tolerance cannot take it
  // out, and the chords it allows may leave more than the program as written.
  const std::string dir = temp_dir("cli_units_coarse");
  const CommandResult coarse = compensate(dir, "coarse", "--tolerance 20um");
  ASSERT_EQ(coarse.exit_code, 0) << coarse.err;
  EXPECT_NE(coarse.err.find("warning: the tolerance of 20 um is not below the machine's error on this program"),
            std::string::npos)
      << coarse.err;
  EXPECT_NE(coarse.err.find("--tolerance 1um takes the error out"), std::string::npos) << coarse.err;
  const CommandResult fine = compensate(dir, "fine", "--tolerance 1um");
  ASSERT_EQ(fine.exit_code, 0) << fine.err;
  EXPECT_EQ(fine.err.find("is not below the machine's error"), std::string::npos) << fine.err;
}

TEST(CliNames, HelpAndACorrectCommandAreNotTakenForMistakes) {
  EXPECT_EQ(run_command(ccomp() + " check --help").exit_code, 0);
  // A program file whose name is a word near a command is a program, not a mistyped command.
  const std::string dir = temp_dir("cli_names_file");
  fs::copy_file(source_dir() + "/samples/programs/pocket-xy.ngc", dir + "/chek");
  const CommandResult r =
      run_command("cd " + shell_quote(dir) + " && " + ccomp() + " chek -m " + kHmc + " --tool-table " + kTools + " -o out.ngc -q");
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

}  // namespace
}  // namespace ccomp::test
