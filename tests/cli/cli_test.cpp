// The command line as shop scripts and CAM hooks use it: files in and out, streams, exit
// codes that mean something, and no half-written output on failure.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <regex>

#include <filesystem>

#include "sample_models.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

namespace fs = std::filesystem;

std::string zero() {
  return shell_quote(source_dir() + "/samples/machines/zero.yaml");
}

/// The output without ccomp's header line.
std::string without_header(const std::string& text) {
  const auto at = text.find("(ccomp ");
  if (at == std::string::npos) return text;
  const auto end = text.find('\n', at);
  return text.substr(0, at) + text.substr(end + 1);
}

constexpr const char* kProgram = "G21 G90\nG0 X1 Y2 (start)\r\nG1 x 3.000 F100\n\nM2\n";

TEST(Cli, MainJobWritesTheProgramBackWithAHeader) {
  const std::string dir = temp_dir("cli_main");
  write_file(dir + "/in.nc", kProgram);
  const CommandResult r = run_command(ccomp() + " " + dir + "/in.nc -m " + zero() + " -o " + dir + "/out.nc");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string out = read_file(dir + "/out.nc");
  EXPECT_EQ(without_header(out), kProgram);
  EXPECT_NE(out.find("(ccomp "), std::string::npos);
  EXPECT_NE(out.find("sha256:"), std::string::npos);
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find(".ccomp-"), std::string::npos) << "temporary file left behind";
}

TEST(Cli, StreamsFromStdinToStdout) {
  const CommandResult r = run_command(ccomp() + " - -m " + zero() + " -o -", kProgram);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(without_header(r.out), kProgram);
}

TEST(Cli, ProgramErrorsNamePositionAndLeaveThePreviousOutput) {
  const std::string dir = temp_dir("cli_error");
  write_file(dir + "/in.nc", "G0 X1\nG1 X2 F100 G0\nM2\n");
  write_file(dir + "/out.nc", "previous output\n");
  const CommandResult r = run_command(ccomp() + " " + dir + "/in.nc -m " + zero() + " -o " + dir + "/out.nc");
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("in.nc:2:12: error: two G codes used from the same modal group"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("G1 X2 F100 G0\n             ^"), std::string::npos) << r.err;
  EXPECT_EQ(read_file(dir + "/out.nc"), "previous output\n");
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find(".ccomp-"), std::string::npos) << "temporary file left behind";
}

TEST(Cli, RefusesToCompensateTwice) {
  const std::string dir = temp_dir("cli_twice");
  write_file(dir + "/in.nc", kProgram);
  ASSERT_EQ(run_command(ccomp() + " " + dir + "/in.nc -m " + zero() + " -o " + dir + "/once.nc").exit_code, 0);
  const CommandResult again = run_command(ccomp() + " " + dir + "/once.nc -m " + zero() + " -o " + dir + "/twice.nc");
  EXPECT_EQ(again.exit_code, 7) << again.err;
  EXPECT_NE(again.err.find("already compensated"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir + "/twice.nc"));
  EXPECT_EQ(run_command(ccomp() + " " + dir + "/once.nc -m " + zero() + " -o " + dir + "/twice.nc --force").exit_code,
            0);
}

TEST(Cli, RefusesAxesTheMachineLacks) {
  const std::string dir = temp_dir("cli_axes");
  write_file(dir + "/xyz.yaml", "name: three-axis\naxes: {X: {}, Y: {}, Z: {}}\n");
  write_file(dir + "/in.nc", "G0 X1\nG0 A90\nM2\n");
  const CommandResult r = run_command(ccomp() + " " + dir + "/in.nc -m " + dir + "/xyz.yaml -o " + dir + "/out.nc");
  EXPECT_EQ(r.exit_code, 7);
  EXPECT_NE(r.err.find("in.nc:2:4: refused: the program uses axis A"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/out.nc"));
  // A lone letter (Fanuc, Mazak: ignored) names no axis the program moves.
  write_file(dir + "/lone.nc", "G0 X1 A\nM2\n");
  EXPECT_EQ(run_command(ccomp() + " " + dir + "/lone.nc -m " + dir + "/xyz.yaml -o " + dir + "/lone-out.nc" +
                        " --dialect fanuc")
                .exit_code,
            0);
}

TEST(Cli, ExitCodesForUsageModelAndIo) {
  const std::string dir = temp_dir("cli_codes");
  write_file(dir + "/in.nc", kProgram);
  write_file(dir + "/bad.yaml", "name: x\naxes: {X: {min: 3, max: 1}}\n");
  EXPECT_EQ(run_command(ccomp() + " " + dir + "/in.nc -o " + dir + "/o.nc").exit_code, 2);  // no model
  EXPECT_EQ(run_command(ccomp() + " " + dir + "/in.nc -m " + zero()).exit_code, 2);         // no output
  EXPECT_EQ(run_command(ccomp() + " --no-such-flag").exit_code, 2);
  EXPECT_EQ(run_command(ccomp() + " " + dir + "/in.nc -m " + dir + "/bad.yaml -o -").exit_code, 5);
  EXPECT_EQ(run_command(ccomp() + " " + dir + "/missing.nc -m " + zero() + " -o -").exit_code, 6);
  const CommandResult help = run_command(ccomp() + " --help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("Exit codes"), std::string::npos);
  EXPECT_NE(help.out.find("7   refused"), std::string::npos);
}

TEST(Cli, InPlaceKeepsABackup) {
  const std::string dir = temp_dir("cli_inplace");
  write_file(dir + "/part.nc", kProgram);
  const CommandResult r = run_command(ccomp() + " " + dir + "/part.nc -m " + zero() + " --in-place");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_file(dir + "/part.nc.orig"), kProgram);
  EXPECT_EQ(without_header(read_file(dir + "/part.nc")), kProgram);
}

TEST(Cli, BatchWithOutDirAndJobsReportsEveryFailure) {
  const std::string dir = temp_dir("cli_batch");
  fs::create_directories(dir + "/in");
  for (int i = 0; i < 6; ++i) write_file(fmt::format("{}/in/p{}.nc", dir, i), kProgram);
  write_file(dir + "/in/broken.nc", "G0 X1\nG2 X2 F1\nM2\n");
  std::string inputs;
  for (const auto& e : fs::directory_iterator(dir + "/in")) {
    inputs += ' ';
    inputs += e.path().string();
  }
  const CommandResult r = run_command(ccomp() + inputs + " -m " + zero() + " --out-dir " + dir + "/out -j 3");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("broken.nc:2"), std::string::npos) << r.err;
  for (int i = 0; i < 6; ++i)
    EXPECT_EQ(without_header(read_file(dir + "/out/p" + std::to_string(i) + ".nc")), kProgram) << i;
  EXPECT_FALSE(fs::exists(dir + "/out/broken.nc"));
}

TEST(Cli, FilterProgressLinesOnRequest) {
  std::string big;
  for (int i = 0; i < 2000; ++i) big += "G1 X" + std::to_string(i) + " F100\n";
  const CommandResult r = run_command(ccomp() + " - -m " + zero() + " -o - --progress", big + "M2\n");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("FILTER_PROGRESS=0\n"), std::string::npos);
  EXPECT_NE(r.err.find("FILTER_PROGRESS=100\n"), std::string::npos);
  EXPECT_EQ(run_command(ccomp() + " - -m " + zero() + " -o -", "G0 X1\nM2\n").err.find("FILTER_PROGRESS"),
            std::string::npos);
}

TEST(Cli, TracePrintsCanonicalCalls) {
  const CommandResult r = run_command(ccomp() + " trace -", "G21 G0 X1\nG1 Y2 F10\nM2\n");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("STRAIGHT_TRAVERSE(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)"), std::string::npos);
  EXPECT_NE(r.out.find("STRAIGHT_FEED(1.0000, 2.0000, 0.0000, 0.0000, 0.0000, 0.0000)"), std::string::npos);
}

}  // namespace
}  // namespace ccomp::test

namespace ccomp::test {
namespace {

TEST(Cli, RefusesMovesBeyondTheAxisLimits) {
  const std::string dir = temp_dir("cli_limits");
  write_file(dir + "/m.yaml",
             "name: small\naxes: {X: {min: -100, max: 100}, Y: {min: -100, max: 100}, Z: {min: -200, max: 0}}\n");
  write_file(dir + "/tools.tbl", "T1 P1 Z150\n");
  // Inside: corners at +-90. The arc from (90,0) round to (0,90) bulges to X=90 only.
  write_file(dir + "/ok.nc", "G21 F100\nG0 X90 Y0 Z-10\nG3 X0 Y90 I-90 J0\nM2\n");
  // A full circle of radius 90 about (20,0) reaches X=110: the endpoints alone look fine.
  write_file(dir + "/arc.nc", "G21 F100\nG0 X-70 Y0 Z-10\nG2 X-70 Y0 I90 J0\nM2\n");
  // Z-10 is inside [-200, 0]; with a 150 mm tool offset the machine's Z goes to +140.
  write_file(dir + "/tool.nc", "G21\nT1 M6\nG43 H1\nG0 Z-10\nM2\n");
  const std::string base = shell_quote(ccomp_binary()) + " -m " + dir + "/m.yaml --tool-table " + dir + "/tools.tbl ";
  EXPECT_EQ(run_command(base + dir + "/ok.nc -o " + dir + "/ok.out").exit_code, 0);
  const CommandResult arc = run_command(base + dir + "/arc.nc -o " + dir + "/arc.out");
  EXPECT_EQ(arc.exit_code, 7);
  EXPECT_NE(arc.err.find("arc.nc:3:1: refused: axis X would go to 110.0000"), std::string::npos) << arc.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/arc.out"));
  const CommandResult tool = run_command(base + dir + "/tool.nc -o " + dir + "/tool.out");
  EXPECT_EQ(tool.exit_code, 7);
  EXPECT_NE(tool.err.find("axis Z would go to 140.0000"), std::string::npos) << tool.err;
}

}  // namespace
}  // namespace ccomp::test

namespace ccomp::test {
namespace {

const std::string kThermalModel = std::string(kVmcChain) + R"(max_correction: 0.05 mm
terms:
  - {name: EZZ, variable: T_spindle, form: thermal, coefficient: 3, unit: um}
)";

TEST(Cli, RefusesAThermalTermWithoutItsSensorReading) {
  const std::string dir = temp_dir("cli_sensor");
  write_file(dir + "/m.yaml", kThermalModel);
  write_file(dir + "/in.nc", "G21 G0 X10 Y10 Z10\nG1 X20 F100\nM30\n");
  const std::string base = shell_quote(ccomp_binary()) + " " + dir + "/in.nc -m " + dir + "/m.yaml -o " + dir;
  // A reading the user forgot is a usage error (exit 2), as every other sensor mistake.
  const CommandResult missing = run_command(base + "/out.nc");
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("--sensor spindle=VALUE (term EZZ depends on sensor 'spindle')"),
            std::string::npos)
      << missing.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/out.nc"));
  // With the reading: 30 degC is 10 K above the reference, 30 um of Z growth to take out.
  const CommandResult given = run_command(base + "/out.nc --sensor spindle=30");
  ASSERT_EQ(given.exit_code, 0) << given.err;
  EXPECT_NE(read_file(dir + "/out.nc").find("Z9.9700"), std::string::npos) << read_file(dir + "/out.nc");
  // 30 degC more is 90 um: beyond the model's 0.05 mm bound.
  const CommandResult hot = run_command(base + "/hot.nc --sensor spindle=50");
  EXPECT_EQ(hot.exit_code, 7);
  EXPECT_NE(hot.err.find("beyond the model's bound"), std::string::npos) << hot.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/hot.nc"));
  const CommandResult unknown = run_command(base + "/x.nc --sensor nozzle=30");
  EXPECT_EQ(unknown.exit_code, 2) << "an unknown sensor is a usage error";
  EXPECT_NE(unknown.err.find("machine 'test-vmc' has no sensor of that name (its sensors: spindle)"), std::string::npos)
      << unknown.err;
  EXPECT_EQ(run_command(base + "/x.nc --sensor spindle=30 --sensor spindle=31").exit_code, 2) << "read twice";
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.nc"));
}

}  // namespace
}  // namespace ccomp::test

namespace ccomp::test {
namespace {

TEST(Cli, PredictAndVerifyProveTheSample) {
  const std::string dir = temp_dir("cli_verify");
  const std::string model = source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml";
  const std::string tools = " --tool-table " + source_dir() + "/samples/tools.tbl";
  const std::string program = source_dir() + "/samples/programs/pocket-xy.ngc";
  ASSERT_EQ(
      run_command(shell_quote(ccomp_binary()) + " " + program + " -m " + model + tools + " -o " + dir + "/out.ngc -q")
          .exit_code,
      0);
  const CommandResult predicted =
      run_command(shell_quote(ccomp_binary()) + " predict " + program + " -m " + model + tools);
  ASSERT_EQ(predicted.exit_code, 0) << predicted.err;
  const CommandResult verified =
      run_command(shell_quote(ccomp_binary()) + " verify " + program + " " + dir + "/out.ngc -m " + model + tools);
  ASSERT_EQ(verified.exit_code, 0) << verified.err;
  auto max_um = [](const std::string& text) { return std::stod(text.substr(text.find(" max ") + 5)); };
  EXPECT_GT(max_um(predicted.out), 5.0) << predicted.out;  // 9.6 um with program zero on the B centre
  EXPECT_LT(max_um(verified.out), 1.0 + 0.1) << verified.out;

  // A script reads the verdict from the exit code: more than the tolerance is refused...
  const CommandResult strict = run_command(shell_quote(ccomp_binary()) + " verify " + program + " " + dir +
                                           "/out.ngc --tolerance 0.0001 -m " + model + tools);
  EXPECT_EQ(strict.exit_code, 7) << strict.err;
  EXPECT_NE(strict.err.find("more than the tolerance of 0.10 um"), std::string::npos) << strict.err;
  // A tolerance just under what is left: the message shows the digits that differ.
  const CommandResult exact = run_command(shell_quote(ccomp_binary()) + " verify " + program + " " + dir +
                                          "/out.ngc --json -m " + model + tools);
  const double left_um = std::stod(exact.out.substr(exact.out.find("\"max_um\": ") + 10));
  // Halfway between what is left and the low end of what prints as it to two decimals.
  const double shown = std::round(left_um * 100.0) / 100.0, tolerance_um = 0.5 * (left_um + shown - 0.005);
  const CommandResult barely =
      run_command(shell_quote(ccomp_binary()) + " verify " + program + " " + dir + "/out.ngc --tolerance " +
                  fmt::format("{:.9f}", tolerance_um * 1e-3) + " -m " + model + tools);
  ASSERT_EQ(barely.exit_code, 7) << barely.err;
  std::smatch said;
  ASSERT_TRUE(std::regex_search(barely.err, said,
                                std::regex("the contour error left, ([0-9.]+) um, is more than the tolerance of "
                                           "([0-9.]+) um")))
      << barely.err;
  EXPECT_EQ(fmt::format("{:.2f}", left_um), fmt::format("{:.2f}", tolerance_um)) << "the case is one of rounding";
  EXPECT_NE(said[1].str(), said[2].str()) << barely.err;
  EXPECT_NEAR(std::stod(said[1]), left_um, 5e-4 + 1e-12) << barely.err;  // to its last printed digit
  // A model without a chain (the zero model) would put every point at the origin: refused.
  for (const char* command : {" predict ", " verify "}) {
    const std::string second = std::string(command) == " verify " ? program + " " : "";
    const CommandResult chainless = run_command(shell_quote(ccomp_binary()) + command + program + " " + second +
                                                "-m " + source_dir() + "/samples/machines/zero.yaml" + tools);
    EXPECT_EQ(chainless.exit_code, 5) << chainless.err;
    EXPECT_NE(chainless.err.find("has no kinematic chain"), std::string::npos) << chainless.err;
  }
  // ... and so is an output that stops short (a post-processor that wrote half a file).
  const std::string whole = read_file(dir + "/out.ngc");
  write_file(dir + "/half.ngc", whole.substr(0, whole.size() / 2));
  const CommandResult half =
      run_command(shell_quote(ccomp_binary()) + " verify " + program + " " + dir + "/half.ngc -m " + model + tools);
  EXPECT_EQ(half.exit_code, 7) << half.err;
  EXPECT_NE(half.err.find("half.ngc leaves"), std::string::npos) << half.err;
  EXPECT_NE(half.err.find("of the original's cuts uncut"), std::string::npos) << half.err;
}

}  // namespace
}  // namespace ccomp::test

namespace ccomp::test {
namespace {

TEST(Cli, DecimalsAsToldAndRefusedWhenTooCoarseForTheTolerance) {
  const std::string dir = temp_dir("cli_decimals");
  const std::string base = shell_quote(ccomp_binary()) + " " + source_dir() + "/samples/programs/pocket-xy.ngc -m " +
                           source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml --tool-table " + source_dir() +
                           "/samples/tools.tbl -o " + dir;
  // Three decimals may take 0.87 um of the 1 um: warned of, and the verdict measures what
  // they cost (just over the tolerance here): written, exit 1.
  const CommandResult three = run_command(base + "/three.ngc --decimals 3");
  EXPECT_EQ(three.exit_code, 1) << three.err;
  EXPECT_NE(three.err.find("warning: coordinates written to 3 decimals in mm"), std::string::npos) << three.err;
  EXPECT_NE(three.err.find("more than the tolerance of 1.00 um; the output is written"), std::string::npos)
      << three.err;
  EXPECT_TRUE(std::regex_search(read_file(dir + "/three.ngc"), std::regex(R"(\nG0 X-30\.\d{3} Y-19\.\d{3} Z5\.\d{3}\s)")))
      << read_file(dir + "/three.ngc");
  const CommandResult two = run_command(base + "/two.ngc --decimals 2");
  EXPECT_EQ(two.exit_code, 2);
  EXPECT_NE(two.err.find("error: --decimals 2: coordinates written to 2 decimals in mm may put the tool up to 8.66 um"),
            std::string::npos)
      << two.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/two.ngc"));
  EXPECT_EQ(run_command(base + "/ten.ngc --decimals 10").exit_code, 2);
}

}  // namespace
}  // namespace ccomp::test

namespace ccomp::test {
namespace {

TEST(Cli, FlattenWritesTheBoltCircleAsItRuns) {
  // stdbc.nc drills eight holes by a subprogram called with L#2 (Fanuc M98), turning A
  // 45 degrees in G91 after each; flattened, its lines each run once.
  const std::string dir = temp_dir("cli_flatten");
  const std::string base = shell_quote(ccomp_binary()) + " " + corpus_dir() + "/programs/stdbc.nc -m " + source_dir() +
                           "/samples/machines/zero.yaml --dialect fanuc --tool-table " + source_dir() +
                           "/tests/data/corpus-tools.tbl -o " + dir + "/out.nc";
  const CommandResult r = run_command(base + " --flatten");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string out = read_file(dir + "/out.nc");
  for (const char* gone : {"M98", "M99", "#", "O0011"}) EXPECT_EQ(out.find(gone), std::string::npos) << gone;
  std::size_t turns = 0;
  for (auto at = out.find("G91 A45.0"); at != std::string::npos; at = out.find("G91 A45.0", at + 1)) ++turns;
  EXPECT_EQ(turns, 3U * 8U) << "eight holes for each of the spot drill, the drill and the tap\n" << out;
  // `ccomp flatten` prints the same program: what the job compensated (here: nothing).
  const CommandResult printed = run_command(shell_quote(ccomp_binary()) + " flatten - --dialect fanuc --tool-table " +
                                                source_dir() + "/tests/data/corpus-tools.tbl",
                                            read_file(corpus_dir() + "/programs/stdbc.nc"));
  ASSERT_EQ(printed.exit_code, 0) << printed.err;
  EXPECT_EQ(printed.out, without_header(out));
}

}  // namespace
}  // namespace ccomp::test

namespace ccomp::test {
namespace {

TEST(Cli, VerifyMeetsTheToleranceInTheHeaderAndWarnsOfAnotherModel) {
  const std::string dir = temp_dir("cli_verify_header");
  const std::string machines = source_dir() + "/samples/machines/";
  const std::string tools = " --tool-table " + source_dir() + "/samples/tools.tbl";
  const std::string program = source_dir() + "/samples/programs/pocket-xy.ngc";
  const std::string ccomp = shell_quote(ccomp_binary());
  ASSERT_EQ(run_command(ccomp + " " + program + " -m " + machines + "vmc-xyz.yaml" + tools +
                        " --tolerance 0.005 -q -o " + dir + "/out.ngc")
                .exit_code,
            0);
  EXPECT_NE(read_file(dir + "/out.ngc").find(" at 5 um; "), std::string::npos);
  const std::string verify = ccomp + " verify " + program + " " + dir + "/out.ngc" + tools + " -m " + machines;
  // Compensated to 5 um, it is held to 5 um unless told otherwise.
  const CommandResult as_made = run_command(verify + "vmc-xyz.yaml");
  EXPECT_EQ(as_made.exit_code, 0) << as_made.err << as_made.out;
  const CommandResult stricter = run_command(verify + "vmc-xyz.yaml --tolerance 0.001");
  EXPECT_EQ(stricter.exit_code, 7) << stricter.err;
  // Checked against another machine's model, it says so.
  const CommandResult other = run_command(verify + "vmc-xyza-trunnion.yaml");
  EXPECT_NE(other.err.find("warning: compensated with another model"), std::string::npos) << other.err;
  EXPECT_EQ(as_made.err.find("another model"), std::string::npos) << as_made.err;
}

TEST(Cli, ToleranceThatIsNotMillimetresSaysSo) {
  const std::string dir = temp_dir("cli_tolerance");
  write_file(dir + "/p.ngc", "G21 G90\nG0 X1 Y2\nG1 X3 F100\nM2\n");
  const std::string ccomp = shell_quote(ccomp_binary());
  const std::string model = " -m " + source_dir() + "/samples/machines/vmc-xyz.yaml ";
  const std::string compensate = ccomp + " " + dir + "/p.ngc" + model + "-o " + dir + "/out.ngc --tolerance ";
  const std::string verify = ccomp + " verify " + dir + "/p.ngc " + dir + "/out.ngc" + model + "--tolerance ";
  const std::pair<std::string, std::string> refused[] = {
      {"0", "the value must be more than 0 mm"},      {"-0.001", "the value must be more than 0 mm"},
      {"inf", "'inf' is not a finite number"},        {"0.001x", "unknown unit 'x'"},
      {"1", "a number without a unit is mm here, and 1 mm is not a plausible compensation tolerance (up to 0.1 mm); "
            "did you mean 1um?"},
  };
  for (const std::string& command : {compensate, verify}) {
    for (const auto& [value, says] : refused) {
      const CommandResult r = run_command(command + "'" + value + "'");
      EXPECT_EQ(r.exit_code, 2) << command << value;
      const std::string headline = r.err.substr(0, r.err.find('\n'));
      EXPECT_NE(headline.find("error: --tolerance " + value + ": " + says), std::string::npos) << r.err;
      EXPECT_LT(headline.size(), 300U) << "a short message, not CLI11's range as a 300-digit double: " << r.err;
    }
  }
  // A number of mm, or a length with its unit, passes the check (and reaches the run: its
  // header names it in um).
  EXPECT_EQ(run_command(compensate + "0.002").exit_code, 0);
  EXPECT_NE(read_file(dir + "/out.ngc").find(" at 2 um; "), std::string::npos) << read_file(dir + "/out.ngc");
  EXPECT_EQ(run_command(verify + "0.002").exit_code, 0);
  EXPECT_EQ(run_command(compensate + "1um").exit_code, 0);
  EXPECT_NE(read_file(dir + "/out.ngc").find(" at 1 um; "), std::string::npos) << read_file(dir + "/out.ngc");
}

}  // namespace
}  // namespace ccomp::test

namespace ccomp::test {
namespace {

// A shop's G54 given on the command line: the output's header records it, verify and
// predict measure the program where it ran without being told again, and told another
// origin they measure another machine's cut.
TEST(Cli, TheWorkOffsetTravelsWithTheOutput) {
  const std::string dir = temp_dir("cli_work_offset");
  const std::string model = " -m " + source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml";
  const std::string tools = " --tool-table " + source_dir() + "/samples/tools.tbl";
  const std::string program = source_dir() + "/samples/programs/face-b0-b90.ngc";
  const std::string ccomp = shell_quote(ccomp_binary());
  const std::string shop = " --work-offset G54=X-35,Y20,Z-330";
  const CommandResult made = run_command(ccomp + " " + program + model + tools + shop + " -q -o " + dir + "/out.ngc");
  ASSERT_EQ(made.exit_code, 0) << made.err;
  EXPECT_NE(read_file(dir + "/out.ngc").find("; work offsets G54 X-35 Y20 Z-330)"), std::string::npos);
  auto max_um = [](const std::string& json) { return std::stod(json.substr(json.find("\"max_um\": ") + 10)); };
  const std::string verify = ccomp + " verify " + program + " " + dir + "/out.ngc" + model + tools + " --json";
  const CommandResult as_made = run_command(verify);
  EXPECT_EQ(as_made.exit_code, 0) << as_made.err;
  EXPECT_LT(max_um(as_made.out), 1.0 + 0.1);
  const CommandResult told_again = run_command(verify + shop);
  EXPECT_EQ(max_um(told_again.out), max_um(as_made.out)) << "the header's G54 is the option's";
  const CommandResult elsewhere = run_command(verify + " --work-offset G54=X0,Y0,Z-400");
  EXPECT_NE(max_um(elsewhere.out), max_um(as_made.out)) << "another origin is another cut";
  EXPECT_NE(elsewhere.err.find("warning: compensated with G54 X-35 Y20 Z-330, measured with --work-offset's G54 X0 Y0 "
                               "Z-400"),
            std::string::npos)
      << elsewhere.err;
  EXPECT_EQ(as_made.err.find("warning"), std::string::npos) << as_made.err;
  const CommandResult off_machine = run_command(ccomp + " " + source_dir() + "/samples/programs/pocket-xy.ngc -m " +
                                                source_dir() + "/samples/machines/vmc-xyz.yaml" + tools +
                                                " --work-offset G54=B90 -o -");
  EXPECT_EQ(off_machine.exit_code, 2) << off_machine.err;
  EXPECT_NE(off_machine.err.find("the machine has no B axis"), std::string::npos) << off_machine.err;
  const std::string predict = ccomp + " predict " + program + model + tools + " --json";
  EXPECT_NE(max_um(run_command(predict + shop).out), max_um(run_command(predict).out))
      << "predict measures the program where it runs";
  const CommandResult bad = run_command(ccomp + " " + program + model + tools + " --work-offset G54=X1,X2 -o -");
  EXPECT_EQ(bad.exit_code, 2) << bad.err;
  EXPECT_NE(bad.err.find("axis X is given twice"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace ccomp::test
