// Input that used to hang, write without end or turn silently into other numbers: each is
// refused with its position and exit 3, by the main job and by trace alike.
#include <gtest/gtest.h>

#include <filesystem>

#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

struct Runaway {
  const char* name;
  std::string program;
  const char* words;  ///< in the error
  int line = 3;       ///< where the error points
};
void PrintTo(const Runaway& r, std::ostream* os) {
  *os << r.name;
}

std::string digits(int count) {
  return "1" + std::string(static_cast<std::size_t>(count), '0');
}

class RunawayInput : public ::testing::TestWithParam<Runaway> {};

TEST_P(RunawayInput, IsRefusedByTheMainJobAndByTrace) {
  const std::string dir = temp_dir(std::string("runaway_") + GetParam().name);
  write_file(dir + "/part.nc", "G21 G90\nG0 X0 Y0 Z0\n" + GetParam().program + "M2\n");
  const std::string part = shell_quote(dir + "/part.nc");
  const std::string model = shell_quote(source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml");
  for (const std::string& command :
       {shell_quote(ccomp_binary()) + " " + part + " -m " + model + " -q -o " + shell_quote(dir + "/out.nc"),
        shell_quote(ccomp_binary()) + " trace " + part + " > /dev/null"}) {
    const CommandResult r = run_command("timeout 60 " + command);
    EXPECT_EQ(r.exit_code, 3) << command << "\n" << r.err;
    EXPECT_NE(r.err.find(GetParam().words), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("part.nc:" + std::to_string(GetParam().line) + ":"), std::string::npos)
        << "positioned: " << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(dir + "/out.nc"));
}

INSTANTIATE_TEST_SUITE_P(
    Cli, RunawayInput,
    ::testing::Values(
        // Above the largest double: was dropped, the line written as a bare G1.
        Runaway{"number_beyond_range", "G1 X" + digits(320) + " F100\n", "beyond any machine's range"},
        Runaway{"number_beyond_range_in_an_expression", "G1 X[" + digits(320) + "+1] F100\n",
                "beyond any machine's range"},
        // LinuxCNC reads X1e999 as X1 and E999, and refuses an E no code uses.
        Runaway{"exponent", "G1 X1e999 F100\n", "E word with no G code that uses it"},
        // An endless loop that never moves: ran for ever.
        Runaway{"loop_without_motion", "#1=0\nO100 while [1]\n#1=[#1+1]\nO100 endwhile\n", "without a move", 4},
        // Written out turn by turn without end.
        Runaway{"arc_turns", "G2 X0 Y0 I5 J0 P100000000 F100\n", "turns"}),
    [](const auto& test) { return std::string(test.param.name); });

// A UTF-8 byte-order mark (Windows editors) is not text of the program: read past, kept.
TEST(Input, AByteOrderMarkIsReadPastAndKept) {
  const std::string dir = temp_dir("bom");
  write_file(dir + "/part.nc", "\xEF\xBB\xBFG21 G90\nG0 X0 Y0 Z0\nG1 X10 F100\nM2\n");
  const CommandResult r =
      run_command(shell_quote(ccomp_binary()) + " " + shell_quote(dir + "/part.nc") + " -m " +
                  shell_quote(source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml") + " -q -o -");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.rfind("\xEF\xBB\xBF(ccomp ", 0), 0U) << "the mark first, then the header";
  EXPECT_NE(r.out.find("\nG21 G90\n"), std::string::npos);
  // And the header is still seen: a second run is refused as double compensation.
  write_file(dir + "/once.nc", r.out);
  EXPECT_EQ(run_command(shell_quote(ccomp_binary()) + " " + shell_quote(dir + "/once.nc") + " -m " +
                        shell_quote(source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml") + " -q -o -")
                .exit_code,
            7);
  EXPECT_EQ(r.out.find("G1 X10 F100"), std::string::npos) << "compensated";
}

// Errors with no word to point at still carry a column: where the block starts.
TEST(Input, ErrorsWithoutAWordPointAtTheBlock) {
  const std::string dir = temp_dir("columns");
  for (const std::string& program :
       {std::string("  O<nowhere> call\n"), std::string("  #1=[1/0]\n"), std::string("  G2 X10 Y0 I3 J0 F100\n")}) {
    write_file(dir + "/part.nc", "G21 G90 G17\nG0 X0 Y0 Z0\n" + program + "M2\n");
    const CommandResult r = run_command(shell_quote(ccomp_binary()) + " trace " + shell_quote(dir + "/part.nc"));
    EXPECT_EQ(r.exit_code, 3) << program;
    const auto at = r.err.find("part.nc:3:");
    ASSERT_NE(at, std::string::npos) << program << r.err;
    EXPECT_GE(std::stoi(r.err.substr(at + 10)), 3) << "a column: " << r.err;
  }
}

// An (ABORT, ...) stops a trace, which shows what the interpreter does; the main job says it
// and goes on (the condition around an abort reads the machine's state, which ccomp only
// simulates). It was honoured by trace and passed over in silence by the main job.
TEST(Input, AnAbortStopsATraceAndIsSaidByTheMainJob) {
  const std::string dir = temp_dir("abort");
  write_file(dir + "/part.nc", "G21 G90\nG0 X0 Y0 Z0\n(abort, the fixture is not clamped)\nG1 X10 F100\nM2\n");
  const std::string part = shell_quote(dir + "/part.nc");
  const CommandResult trace = run_command(shell_quote(ccomp_binary()) + " trace " + part);
  EXPECT_EQ(trace.exit_code, 3);
  EXPECT_NE(trace.err.find("part.nc:3:1: error: (ABORT)"), std::string::npos) << trace.err;
  EXPECT_NE(trace.err.find("the fixture is not clamped"), std::string::npos) << trace.err;
  const CommandResult job =
      run_command(shell_quote(ccomp_binary()) + " " + part + " -m " +
                  shell_quote(source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml") + " -q -o -");
  EXPECT_EQ(job.exit_code, 0) << job.err;
  EXPECT_NE(job.err.find("part.nc:3: warning: (ABORT,"), std::string::npos) << job.err;
  EXPECT_NE(job.err.find("the fixture is not clamped) reached"), std::string::npos) << job.err;
}

// Cutter compensation's exit rule is LinuxCNC's, after a move made with the offset on.
TEST(Input, AnArcAfterG40IsRefusedOnlyWhereLinuxcncRefusesIt) {
  const std::string dir = temp_dir("g40");
  const std::string model = shell_quote(source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml");
  auto run = [&](const std::string& program, const std::string& dialect) {
    write_file(dir + "/part.nc", "G21 G90 G17\nG0 X-20 Y-20 Z0\n" + program + "M2\n");
    return run_command(shell_quote(ccomp_binary()) + " trace " + shell_quote(dir + "/part.nc") + " --dialect " +
                       dialect)
        .exit_code;
  };
  EXPECT_EQ(run("G41.1 D2\nG1 X0 Y0 F100\nG40\nG2 X10 Y0 I5 J0\n", "linuxcnc"), 3);
  EXPECT_EQ(run("G41.1 D2\nG40\nG2 X-10 Y-20 I5 J0 F100\n", "linuxcnc"), 0) << "no move was made with the offset on";
  EXPECT_EQ(run("G41.1 D2\nG1 X0 Y0 F100\nG40\nG1 X5\nG2 X10 Y0 I2.5 J0\n", "linuxcnc"), 0);
  EXPECT_EQ(run("G41.1 D2\nG1 X0 Y0 F100\nG40\nG2 X10 Y0 I5 J0\n", "fanuc"), 0);
}

}  // namespace
}  // namespace ccomp::test
