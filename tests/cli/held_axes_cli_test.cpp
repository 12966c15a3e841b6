// A rotary axis the program does not turn stays still: an indexing or clamped table is
// never turned by the compensation, and what holding it leaves is reported (issue 48, point 4).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <regex>
#include <set>

#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

namespace fs = std::filesystem;

std::string sample_path(const std::string& path) {
  return source_dir() + "/samples/" + path;
}
const std::string kHmc = sample_path("machines/hmc-xyzb-geometric.yaml");

struct JobRun {
  CommandResult result;
  std::string output;  ///< the compensated program
};

JobRun compensate(const std::string& dir, const std::string& program, const std::string& model,
               const std::string& options, const std::string& name) {
  const std::string out = dir + "/" + name + ".ngc";
  JobRun run;
  run.result = run_command(ccomp() + " " + sample("programs/" + program) + " -m " + shell_quote(model) +
                           " --tool-table " + sample("tools.tbl") + " -o " + shell_quote(out) + " --json " + options);
  if (fs::exists(out)) run.output = read_file(out);
  return run;
}

/// The B values the program's lines write (comments and ccomp's header left out).
std::vector<double> b_words(const std::string& program) {
  std::vector<double> values;
  static const std::regex kB(R"(\bB\s*(-?[0-9]*\.?[0-9]+))", std::regex::icase);
  std::size_t start = 0;
  while (start < program.size()) {
    const std::size_t end = std::min(program.find('\n', start), program.size());
    std::string line = program.substr(start, end - start);
    start = end + 1;
    line = std::regex_replace(line, std::regex(R"(\([^)]*\))"), "");
    for (std::sregex_iterator it(line.begin(), line.end(), kB), last; it != last; ++it)
      values.push_back(std::stod((*it)[1].str()));
  }
  return values;
}

double json_number(const std::string& json, const std::string& key) {
  const std::regex field("\"" + key + "\":\\s*(-?[0-9.eE+-]+)");
  std::smatch m;
  if (!std::regex_search(json, m, field)) return std::nan("");
  return std::stod(m[1].str());
}

TEST(HeldAxes, AnAxisTheProgramNeverTurnsStaysStill) {
  // (hold: auto, a table clamped while the program does not turn it; free is the default.)
  const std::string dir = temp_dir("held_pocket");
  const JobRun held = compensate(dir, "pocket-xy.ngc", kHmc, "--hold B=auto", "held");
  ASSERT_EQ(held.result.exit_code, 0) << held.result.err;
  EXPECT_TRUE(b_words(held.output).empty()) << "the compensation turned B, which the program never names";
  EXPECT_NE(held.result.out.find("\"held_axes\": [\"B\"]"), std::string::npos) << held.result.out;
  // X Y Z still take the tip's error: the position is within the tolerance; the table's turn
  // about B that B would have corrected is what is left, as orientation error.
  EXPECT_LE(json_number(held.result.out, "error_after_um"), 1.0) << held.result.out;
  const double held_turn = json_number(held.result.out, "orientation_error_urad");
  const CommandResult verify = run_command(ccomp() + " verify " + sample("programs/pocket-xy.ngc") + " " +
                                           shell_quote(dir + "/held.ngc") + " -m " + shell_quote(kHmc) +
                                           " --tool-table " + sample("tools.tbl"));
  EXPECT_EQ(verify.exit_code, 0) << verify.err;

  // By default (free) B is turned: B words on the lines, less orientation error left.
  const JobRun free = compensate(dir, "pocket-xy.ngc", kHmc, "", "free");
  ASSERT_EQ(free.result.exit_code, 0) << free.result.err;
  EXPECT_FALSE(b_words(free.output).empty());
  EXPECT_NE(free.result.out.find("\"held_axes\": []"), std::string::npos) << free.result.out;
  EXPECT_LT(json_number(free.result.out, "orientation_error_urad"), held_turn);
}

TEST(HeldAxes, TheSummarySaysWhichAxisWasHeldAndWhy) {
  const std::string dir = temp_dir("held_summary");
  const std::string out = dir + "/out.ngc";
  const std::string command = ccomp() + " " + sample("programs/pocket-xy.ngc") + " -m " +
                              shell_quote(kHmc) + " --tool-table " + sample("tools.tbl") + " -o " + shell_quote(out);
  const CommandResult automatic = run_command(command + " --hold B=auto");
  ASSERT_EQ(automatic.exit_code, 0) << automatic.err;
  EXPECT_NE(automatic.err.find("orientation error left"), std::string::npos) << automatic.err;
  EXPECT_NE(automatic.err.find("(B held (the program does not turn it))"), std::string::npos) << automatic.err;
  const CommandResult clamped = run_command(command + " --hold b");
  ASSERT_EQ(clamped.exit_code, 0) << clamped.err;
  EXPECT_NE(clamped.err.find("(B held (hold: clamped))"), std::string::npos) << clamped.err;
}

TEST(HeldAxes, AClampedTableStandsWhereTheProgramPutsIt) {
  // Two faces at B0 and B90: under auto B is corrected once the program turns it; clamped
  // (an indexing table on its detents), every B written is the program's own.
  const std::string dir = temp_dir("held_faces");
  const JobRun automatic = compensate(dir, "face-b0-b90.ngc", kHmc, "--hold B=auto", "auto");
  ASSERT_EQ(automatic.result.exit_code, 0) << automatic.result.err;
  std::set<double> programmed;
  for (const double b : b_words(read_file(sample_path("programs/face-b0-b90.ngc")))) programmed.insert(b);
  ASSERT_EQ(programmed, (std::set<double>{0.0, 90.0}));
  bool corrected = false;
  for (const double b : b_words(automatic.output)) corrected = corrected || !programmed.count(b);
  EXPECT_TRUE(corrected) << "B turned by the program is corrected under auto";

  const JobRun clamped = compensate(dir, "face-b0-b90.ngc", kHmc, "--hold B", "clamped");
  ASSERT_EQ(clamped.result.exit_code, 0) << clamped.result.err;
  const std::vector<double> written = b_words(clamped.output);
  EXPECT_FALSE(written.empty());
  for (const double b : written) EXPECT_TRUE(programmed.count(b)) << "B" << b << " is not the program's";
  EXPECT_LE(json_number(clamped.result.out, "error_after_um"), 1.0) << clamped.result.out;
  EXPECT_EQ(run_command(ccomp() + " verify " + sample("programs/face-b0-b90.ngc") + " " +
                        shell_quote(dir + "/clamped.ngc") + " -m " + shell_quote(kHmc) +
                        " --tool-table " + sample("tools.tbl"))
                .exit_code,
            0);

  // The model's key does what the option does.
  std::string model = read_file(kHmc);
  const std::string axis = "B: {type: rotary}";
  ASSERT_NE(model.find(axis), std::string::npos);
  model.replace(model.find(axis), axis.size(), "B: {type: rotary, hold: indexing}");
  write_file(dir + "/indexing.yaml", model);
  const JobRun keyed = compensate(dir, "face-b0-b90.ngc", dir + "/indexing.yaml", "", "keyed");
  ASSERT_EQ(keyed.result.exit_code, 0) << keyed.result.err;
  EXPECT_EQ(b_words(keyed.output), written);
}

struct BadHold {
  const char* name;
  std::string from, to;  ///< replaced in the sample model; empty: --hold `option` instead
  std::string option;
  int exit_code;
  const char* says;
};

class BadHolds : public testing::TestWithParam<BadHold> {};

TEST_P(BadHolds, AreRefusedByName) {
  const BadHold& c = GetParam();
  const std::string dir = temp_dir(std::string("bad_hold_") + c.name);
  std::string model = read_file(kHmc);
  if (!c.from.empty()) model.replace(model.find(c.from), c.from.size(), c.to);
  write_file(dir + "/m.yaml", model);
  const JobRun r = compensate(dir, "pocket-xy.ngc", dir + "/m.yaml", c.option, "out");
  EXPECT_EQ(r.result.exit_code, c.exit_code) << r.result.err;
  EXPECT_NE(r.result.err.find(c.says), std::string::npos) << r.result.err;
  EXPECT_FALSE(fs::exists(dir + "/out.ngc"));
}

INSTANTIATE_TEST_SUITE_P(
    HeldAxes, BadHolds,
    testing::Values(BadHold{"unknown_mode", "B: {type: rotary}", "B: {type: rotary, hold: sideways}", "", 5,
                            "axis B: hold 'sideways' is none of auto, clamped (or indexing), free"},
                    BadHold{"linear_axis", "X: {type: linear,", "X: {type: linear, hold: clamped,", "", 5,
                            "axis X: hold is for a rotary axis"},
                    BadHold{"option_linear", "", "", "--hold X", 2, "'X' is not a rotary axis of the machine"},
                    BadHold{"option_mode", "", "", "--hold B=loose", 2, "'loose' is none of auto, clamped"}),
    [](const testing::TestParamInfo<BadHold>& p) { return std::string(p.param.name); });

}  // namespace
}  // namespace ccomp::test
