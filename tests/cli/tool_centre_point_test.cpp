// Five-axis programs as the command line takes them: a program written for tool-centre-point
// control is refused where it would be compensated or measured, at the code that switches
// it on (exit 4), and read as it is where nothing depends on its coordinates (a trace, the
// zero model); verify and predict report the tool's direction beside the tip and verify
// judges it against its angular tolerance.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <string>

#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

std::string five_axis_model() {
  return source_dir() + "/samples/machines/vmc-xyzac-trunnion.yaml";
}

/// A program that switches TCP on at its second line, in a dialect, and where the refusal
/// must point.
struct TcpCase {
  const char* name;
  const char* dialect;
  const char* second_line;  ///< the line that switches TCP on
  const char* code;         ///< as the message names it
  int column;
};

void PrintTo(const TcpCase& c, std::ostream* os) {
  *os << c.name;
}

class ToolCentrePoint : public testing::TestWithParam<TcpCase> {};

TEST_P(ToolCentrePoint, IsRefusedAtTheCodeThatSwitchesItOn) {
  const TcpCase& c = GetParam();
  const std::string dir = temp_dir(std::string("tcp_") + c.name);
  const std::string program = dir + "/tcp.ngc";
  write_file(program, fmt::format("G21 G90 G94 G17\n{}\nG0 X10 Y5 Z20 A10 C30\nG1 X20 F500\nM2\n", c.second_line));
  const std::string dialect = std::string(" --dialect ") + c.dialect;
  const std::string where = fmt::format("tcp.ngc:2:{}: error: {} switches to ", c.column, c.code);
  const CommandResult job = run_command(shell_quote(ccomp_binary()) + " " + program + " -m " + five_axis_model() +
                                        dialect + " -o " + dir + "/out.ngc");
  EXPECT_EQ(job.exit_code, 4) << job.err;
  EXPECT_NE(job.err.find(where), std::string::npos) << job.err;
  EXPECT_NE(job.err.find("joint-coordinate programs only"), std::string::npos) << job.err;
  // predict and verify follow the tip through the joints: they would measure another path.
  const CommandResult predicted =
      run_command(shell_quote(ccomp_binary()) + " predict " + program + " -m " + five_axis_model() + dialect);
  EXPECT_EQ(predicted.exit_code, 4) << predicted.err;
  EXPECT_NE(predicted.err.find(where), std::string::npos) << predicted.err;
  const CommandResult verified = run_command(shell_quote(ccomp_binary()) + " verify " + program + " " + program +
                                             " -m " + five_axis_model() + dialect);
  EXPECT_EQ(verified.exit_code, 4) << verified.err;
  EXPECT_NE(verified.err.find(where), std::string::npos) << verified.err;
}

INSTANTIATE_TEST_SUITE_P(Modes, ToolCentrePoint,
                         testing::Values(TcpCase{"LinuxcncSwitchkinsM428", "linuxcnc", "M428 ;TCP:xyzac", "M428", 1},
                                         TcpCase{"LinuxcncUserKinematicsM430", "linuxcnc", "G54 M430", "M430", 5},
                                         TcpCase{"FanucG43_4", "fanuc", "G43.4 H1", "G43.4", 1},
                                         TcpCase{"FanucG43_5", "fanuc", "T1 M6 G43.5 H1", "G43.5", 7},
                                         TcpCase{"LinuxcncG43_4", "linuxcnc", "G43.4 H1", "G43.4", 1},
                                         TcpCase{"HeidenhainM128InIso", "fanuc", "M128", "M128", 1}),
                         [](const auto& param_info) { return std::string(param_info.param.name); });

TEST(ToolCentrePoint, TheSwitchBackAndATraceAreNotRefused) {
  const std::string dir = temp_dir("tcp_read");
  const std::string program = dir + "/switch.ngc";
  // M429 is LinuxCNC's switch back to identity kinematics: joint coordinates, as ccomp reads.
  write_file(program, "G21 G90 G94\nM429\nG0 X10 Y5 Z20 A10 C30\nG1 X20 F500\nM2\n");
  EXPECT_EQ(
      run_command(shell_quote(ccomp_binary()) + " " + program + " -m " + five_axis_model() + " -o " + dir + "/out.ngc")
          .exit_code,
      0);
  // The LinuxCNC corpus' TCP program: a trace shows what the interpreter reads...
  const std::string boat = source_dir() + "/tests/data/corpus/programs/boat-xyzbc.ngc";
  const CommandResult trace = run_command(shell_quote(ccomp_binary()) + " trace " + boat + " --tool-table " +
                                          source_dir() + "/samples/tools.tbl");
  EXPECT_EQ(trace.exit_code, 0) << trace.err;
  // ... and compensating it on a machine with errors is refused at its M428, where it was
  // read as joint coordinates before.
  const CommandResult job =
      run_command(shell_quote(ccomp_binary()) + " " + boat + " -m " + five_axis_model() + " -o " + dir + "/boat.ngc");
  EXPECT_EQ(job.exit_code, 4) << job.err;
  EXPECT_NE(job.err.find("boat-xyzbc.ngc:2:1: error: M428 switches to LinuxCNC's switchable kinematics"),
            std::string::npos)
      << job.err;
}

TEST(ToolDirection, VerifyReportsAndJudgesIt) {
  const std::string dir = temp_dir("tool_direction");
  const std::string program = source_dir() + "/samples/programs/five-axis-xyzac.ngc";
  const std::string tools = " --tool-table " + source_dir() + "/samples/tools.tbl";
  const std::string out = dir + "/out.ngc";
  ASSERT_EQ(run_command(shell_quote(ccomp_binary()) + " " + program + " -m " + five_axis_model() + tools + " -o " +
                        out + " -q")
                .exit_code,
            0);
  const std::string verify =
      shell_quote(ccomp_binary()) + " verify " + program + " " + out + " -m " + five_axis_model() + tools;
  const CommandResult json = run_command(verify + " --json");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  auto number = [&](const std::string& field) {
    const auto at = json.out.find("\"" + field + "\": ");
    EXPECT_NE(at, std::string::npos) << field;
    return std::stod(json.out.substr(at + field.size() + 4));
  };
  const double left = number("orientation_max_urad");
  EXPECT_GT(left, 0.0);
  EXPECT_NEAR(number("angular_tolerance_urad"), 100.0, 1e-9) << "the tolerance (1 um) over 10 mm";
  const CommandResult text = run_command(verify);
  EXPECT_NE(text.out.find(fmt::format("tool direction off by {:.1f} urad at most", left)), std::string::npos)
      << text.out;
  // Under what is left: refused (7), the message at the worst line, the verdict in the JSON.
  const std::string strict = fmt::format(" --angular-tolerance {:.6f}", 0.5 * left);
  const CommandResult refused = run_command(verify + strict);
  EXPECT_EQ(refused.exit_code, 7) << refused.err;
  EXPECT_NE(refused.err.find("more than the angular tolerance of"), std::string::npos) << refused.err;
  const CommandResult refused_json = run_command(verify + strict + " --json");
  EXPECT_EQ(refused_json.exit_code, 7);
  EXPECT_NE(refused_json.out.find("\"passed\": false"), std::string::npos) << refused_json.out;
  // The uncompensated program tilts the tool further than the output leaves it.
  const CommandResult before =
      run_command(shell_quote(ccomp_binary()) + " predict " + program + " -m " + five_axis_model() + tools + " --json");
  ASSERT_EQ(before.exit_code, 0) << before.err;
  const auto at = before.out.find("\"orientation_max_urad\": ");
  ASSERT_NE(at, std::string::npos);
  EXPECT_GT(std::stod(before.out.substr(at + 24)), left) << before.out;
  // Not an angle: a usage error.
  EXPECT_EQ(run_command(verify + " --angular-tolerance -3").exit_code, 2);
}

}  // namespace
}  // namespace ccomp::test
