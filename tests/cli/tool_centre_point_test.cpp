// Five-axis programs as the command line takes them: a program written for tool-centre-point
// control is followed by the job, verify and predict, arcs included (what is not followed
// under TCP yet is refused at its line, exit 4); verify and predict report the tool's direction beside the
// tip and verify judges it against its angular tolerance.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

std::string five_axis_model() {
  return source_dir() + "/samples/machines/vmc-xyzac-trunnion.yaml";
}

/// A program that switches TCP on at its second line, in a dialect.
struct TcpCase {
  const char* name;
  const char* dialect;
  const char* second_line;  ///< the line that switches TCP on
};

void PrintTo(const TcpCase& c, std::ostream* os) {
  *os << c.name;
}

const std::string kTools = " --tool-table " + source_dir() + "/samples/tools.tbl";

class ToolCentrePoint : public testing::TestWithParam<TcpCase> {};

// Each code that switches TCP on is followed: the job compensates the program (its moves
// split where the rotary axes turn, written as TCP words under the same code), and verify
// passes the output against the program, both followed through the model's perfect machine.
TEST_P(ToolCentrePoint, IsFollowedByTheJobVerifyAndPredict) {
  const TcpCase& c = GetParam();
  const std::string dir = temp_dir(std::string("tcp_") + c.name);
  const std::string program = dir + "/tcp.ngc", out = dir + "/out.ngc";
  write_file(program, fmt::format("G21 G90 G94 G17\n{}\nG0 X10 Y5 Z20 A10 C30\nG1 X40 Y-10 A25 C75 F500\nM2\n",
                                  c.second_line));
  const std::string options = std::string(" -m ") + five_axis_model() + " --dialect " + c.dialect + kTools;
  const CommandResult job = run_command(shell_quote(ccomp_binary()) + " " + program + options + " -o " + out + " -q");
  ASSERT_EQ(job.exit_code, 0) << job.err;
  const std::string written = read_file(out);
  EXPECT_NE(written.find(std::string("\n") + c.second_line + "\n"), std::string::npos) << written;
  EXPECT_GT(std::count(written.begin(), written.end(), '\n'), 7) << "the turning move in pieces\n" << written;
  const CommandResult verified =
      run_command(shell_quote(ccomp_binary()) + " verify " + program + " " + out + options);
  EXPECT_EQ(verified.exit_code, 0) << verified.err << verified.out;
  const CommandResult predicted = run_command(shell_quote(ccomp_binary()) + " predict " + program + options);
  EXPECT_EQ(predicted.exit_code, 0) << predicted.err;
}

INSTANTIATE_TEST_SUITE_P(Modes, ToolCentrePoint,
                         testing::Values(TcpCase{"LinuxcncSwitchkinsM428", "linuxcnc", "M428 G43 H1"},
                                         TcpCase{"FanucG43_4", "fanuc", "G43.4 H1"},
                                         TcpCase{"LinuxcncG43_4", "linuxcnc", "G43.4 H1"},
                                         TcpCase{"HeidenhainM128InIso", "fanuc", "M128 G43 H1"},
                                         TcpCase{"SiemensTraoriAxesLinear", "siemens", "T1 M6 D1 ORIMKS ORIAXES TRAORI"},
                                         TcpCase{"SiemensTraoriGreatCircle", "siemens", "T1 M6 D1 TRAORI"}),
                         [](const auto& param_info) { return std::string(param_info.param.name); });

/// What is not followed under TCP yet, refused (exit 4) at its line and column.
struct Unfollowed {
  const char* name;
  const char* dialect;
  const char* program;
  const char* where;  ///< "line:column: error: " and the message's start
};

void PrintTo(const Unfollowed& c, std::ostream* os) {
  *os << c.name;
}

class NotFollowedUnderTcp : public testing::TestWithParam<Unfollowed> {};

TEST_P(NotFollowedUnderTcp, IsRefusedAtItsLine) {
  const Unfollowed& c = GetParam();
  const std::string dir = temp_dir(std::string("tcp_refused_") + c.name);
  const std::string program = dir + "/tcp.ngc";
  write_file(program, c.program);
  const CommandResult job = run_command(shell_quote(ccomp_binary()) + " " + program + " -m " + five_axis_model() +
                                        " --dialect " + c.dialect + kTools + " -o " + dir + "/out.ngc");
  EXPECT_EQ(job.exit_code, 4) << job.err;
  EXPECT_NE(job.err.find(std::string("tcp.ngc:") + c.where), std::string::npos) << job.err;
}

INSTANTIATE_TEST_SUITE_P(
    Constructs, NotFollowedUnderTcp,
    testing::Values(
        Unfollowed{"UserKinematicsM430", "linuxcnc", "G21 G90\nG54 M430\nG0 X10 A10\nM2\n",
                   "2:5: error: M430 switches to LinuxCNC's switchable kinematics: the user kinematics"},
        Unfollowed{"AngleWordsUnderG43_5", "fanuc", "G21 G90\nT1 M6 G43.5 H1\nG0 X10 A10\nM2\n",
                   "3:8: error: under G43.5 the rotary axes follow the tool's direction (I J K)"},
        Unfollowed{"G43_5FromTheSingularPose", "fanuc", "G21 G90\nT1 M6 G43.5 H1\nG0 X10 Z20 I0.5 J0 K0.866025\nM2\n",
                   "3:1: error: from the singular pose two sets of rotary angles"},
        Unfollowed{"AnOffsetFromThePosition", "fanuc", "G21 G90 G17\nG43.4 H1\nG0 X10 Y0 Z20 A10\nG92 X0\nM2\n",
                   "4:1: error: an offset set from the position (G92, G10 L20) under tool centre point control"},
        Unfollowed{"SiemensOriaxesUnderOriwks", "siemens",
                   "G71 G90\nT1 M6\nORIAXES TRAORI\nG0 X10 Y0 Z20 A10\nG1 X20 A15 F500\nM30\n",
                   "5:8: error: a rotary axis turns under TRAORI: ORIWKS and ORIAXES disagree"},
        Unfollowed{"SiemensDirectionVectorWithoutTraori", "siemens", "G71\nT1 M6\nG1 X10 A3=0 B3=0 C3=1 F500\nM30\n",
                   "3:8: error: A3= B3= C3= give the tool's direction under TRAORI only"},
        Unfollowed{"ACannedCycle", "fanuc", "G21 G90 G17\nG43.4 H1\nG0 X10 Y0 Z20\nG81 X20 Y5 Z-5 R2 F100\nG80\nM2\n",
                   "4:1: error: a canned cycle, G28/G30 or G53 under tool centre point control"}),
    [](const auto& param_info) { return std::string(param_info.param.name); });

// Arcs under TCP (I J K and R, the tool tilting and C turning along the first): the control
// moves the tip along them in the part; the job writes each as G1 lines (its own line a G1,
// its centre words gone) and verify finds them within the tolerance of the arcs.
TEST(ToolCentrePoint, AnArcIsFollowedAndWrittenAsLines) {
  const std::string dir = temp_dir("tcp_arc");
  const std::string program = dir + "/arc.ngc", out = dir + "/out.ngc";
  write_file(program,
             "G21 G90 G17\nG43.4 H1\nG0 X10 Y0 Z20 A10 C0\nG2 X20 Y10 I10 J0 A20 C30 F500\nG3 X30 Y0 R10\nG1 X35\n"
             "G49\nM2\n");
  const std::string options = " -m " + five_axis_model() + " --dialect fanuc" + kTools;
  const CommandResult job = run_command(shell_quote(ccomp_binary()) + " " + program + options + " -o " + out + " -q");
  ASSERT_EQ(job.exit_code, 0) << job.err;
  std::string written = read_file(out);
  written.erase(0, written.find('\n') + 1);  // ccomp's header
  EXPECT_GT(std::count(written.begin(), written.end(), '\n'), 100) << written;
  EXPECT_FALSE(std::regex_search(written, std::regex(R"((G0?[23]|[IJR]-?[0-9.]+)\b)"))) << "an arc word left\n"
                                                                                     << written;
  const auto own = written.find("\nG1 X", written.find("G0 X"));
  EXPECT_NE(own, std::string::npos) << "the arc's own line a G1\n" << written;
  const CommandResult verified =
      run_command(shell_quote(ccomp_binary()) + " verify " + program + " " + out + options);
  EXPECT_EQ(verified.exit_code, 0) << verified.err << verified.out;
}

// G43.5 (the tool's direction as I J K, Fanuc's TCP type 2): the job writes the compensated
// tip and direction as X Y Z I J K (no angle words), verify passes it, and the model without
// error gives the program back byte for byte.
TEST(ToolCentrePoint, AG43_5ProgramIsFollowedAndWrittenAsDirections) {
  const std::string dir = temp_dir("tcp_g43_5");
  const std::string program = dir + "/g43_5.ngc", out = dir + "/out.ngc", zero = dir + "/zero.ngc";
  std::string text = "G21 G90 G17 G94\nG0 A20 C90\nG43.5 H1\nG0 X30 Y0 Z60 I0.342020 J0 K0.939693\nG1 Z10 F600\n";
  for (int k = 1; k <= 12; ++k) {
    const double phi = 7.5 * k * std::numbers::pi / 180, tilt = (20 + k) * std::numbers::pi / 180;
    text += fmt::format("X{:.4f} Y{:.4f} I{:.6f} J{:.6f} K{:.6f}\n", 30 * std::cos(phi), 30 * std::sin(phi),
                        std::sin(tilt) * std::cos(phi), std::sin(tilt) * std::sin(phi), std::cos(tilt));
  }
  text += "G0 Z60\nG49\nM2\n";
  write_file(program, text);
  const std::string options = " -m " + five_axis_model() + " --dialect fanuc" + kTools;
  const CommandResult job = run_command(shell_quote(ccomp_binary()) + " " + program + options + " -o " + out + " -q");
  ASSERT_EQ(job.exit_code, 0) << job.err;
  const std::string written = read_file(out);
  const std::string under = written.substr(written.find("G43.5"));
  EXPECT_EQ(under.find_first_of("ABC"), std::string::npos) << written;
  EXPECT_GT(std::count(under.begin(), under.end(), 'K'), 12) << written;
  EXPECT_NE(written, read_file(program));
  const CommandResult verified = run_command(shell_quote(ccomp_binary()) + " verify " + program + " " + out + options);
  EXPECT_EQ(verified.exit_code, 0) << verified.err << verified.out;
  const CommandResult unchanged =
      run_command(shell_quote(ccomp_binary()) + " " + program + " -m " + source_dir() +
                  "/samples/machines/zero.yaml --dialect fanuc" + kTools + " -o " + zero + " -q");
  ASSERT_EQ(unchanged.exit_code, 0) << unchanged.err;
  std::string back = read_file(zero);
  back.erase(0, back.find('\n') + 1);
  EXPECT_EQ(back, text);
  // The same program for a Sinumerik (TRAORI in its basic settings, the direction as
  // A3= B3= C3=): the very words the G43.5 one gets, in Siemens' addresses.
  std::string siemens = std::regex_replace(text, std::regex("G43.5 H1"), "D1 TRAORI");
  siemens = std::regex_replace(siemens, std::regex("G49"), "TRAFOOF");
  siemens = std::regex_replace(siemens, std::regex(" I"), " A3=");
  siemens = std::regex_replace(siemens, std::regex(" J"), " B3=");
  siemens = std::regex_replace(siemens, std::regex(" K"), " C3=");
  siemens = std::regex_replace(siemens, std::regex("G21 G90 G17 G94"), "G71 G90 G17 G94\nT1 M6");
  write_file(dir + "/traori.mpf", siemens);
  const CommandResult traori = run_command(shell_quote(ccomp_binary()) + " " + dir + "/traori.mpf -m " +
                                           five_axis_model() + " --dialect siemens" + kTools + " -o " + dir +
                                           "/traori_out.mpf -q");
  ASSERT_EQ(traori.exit_code, 0) << traori.err << siemens;
  auto words_under_tcp = [](std::string program, const char* on) {
    program = program.substr(program.find(on));
    program = std::regex_replace(program, std::regex("A3="), "I");
    program = std::regex_replace(program, std::regex("B3="), "J");
    program = std::regex_replace(program, std::regex("C3="), "K");
    // Each line's words in letter order (where an added word goes differs by dialect).
    std::vector<std::vector<std::string>> lines;
    const std::regex word(R"([XYZIJK]-?[0-9.]+)");
    std::istringstream in(program);
    for (std::string line; std::getline(in, line);) {
      std::vector<std::string> words;
      for (auto it = std::sregex_iterator(line.begin(), line.end(), word); it != std::sregex_iterator(); ++it)
        words.push_back((*it)[0].str());
      std::sort(words.begin(), words.end());
      if (!words.empty()) lines.push_back(words);
    }
    return lines;
  };
  EXPECT_EQ(words_under_tcp(read_file(dir + "/traori_out.mpf"), "TRAORI"), words_under_tcp(written, "G43.5"));
}

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
  const CommandResult trace = run_command(shell_quote(ccomp_binary()) + " trace " + boat + kTools);
  EXPECT_EQ(trace.exit_code, 0) << trace.err;
  // ... and compensating it follows its M428: on the XYZAC sample it stops at its B word, an
  // axis of the machine it was posted for.
  const CommandResult job =
      run_command(shell_quote(ccomp_binary()) + " " + boat + " -m " + five_axis_model() + kTools + " -o " + dir + "/boat.ngc");
  EXPECT_EQ(job.exit_code, 7) << job.err;
  EXPECT_NE(job.err.find("boat-xyzbc.ngc:11:21: refused: the program uses axis B"), std::string::npos) << job.err;
}

// A move under TCP to a point far beyond the machine: a positioned refusal, not a split
// without end (the split itself is bounded: tcp_kinematics_test.cpp).
TEST(ToolCentrePoint, AMoveToAHugePointIsRefusedAtItsLine) {
  const std::string dir = temp_dir("tcp_huge");
  const std::string program = dir + "/huge.ngc";
  write_file(program, "G21 G90\nG43.4 H1\nG0 X0 Y0 Z20 A0 C0\nG1 X100000000000000 A10 F100\nM2\n");
  const CommandResult job = run_command(shell_quote(ccomp_binary()) + " " + program + " -m " + five_axis_model() +
                                        " --dialect fanuc" + kTools + " -o " + dir + "/out.ngc");
  EXPECT_EQ(job.exit_code, 7) << job.err;
  EXPECT_NE(job.err.find("huge.ngc:4:1: refused: axis X would go to"), std::string::npos) << job.err;
}

// TCP switched off where the rotary axes stand at A30 C270: the retract after G49 names Z
// alone and moves Z alone (the axes stay where the TCP pass left them, not at the TCP
// point's numbers read as the axes', some 40 mm away).
TEST(ToolCentrePoint, ASwitchOffAtAnAngleKeepsTheAxesWhereTheyAre) {
  const std::string dir = temp_dir("tcp_switch_off");
  std::string text = read_file(source_dir() + "/samples/programs/five-axis-tcp-xyzac.ngc");
  const auto g49 = text.find("G49\n");
  ASSERT_NE(g49, std::string::npos);
  text.insert(g49 + 4, "G0 Z100\n");
  const std::string program = dir + "/switch.ngc", out = dir + "/out.ngc";
  write_file(program, text);
  const std::string options = " -m " + five_axis_model() + " --dialect fanuc" + kTools;
  const CommandResult job = run_command(shell_quote(ccomp_binary()) + " " + program + options + " -o " + out + " -q");
  ASSERT_EQ(job.exit_code, 0) << job.err;
  const std::string written = read_file(out);
  const auto retract = written.find("\nG0 Z100");
  ASSERT_NE(retract, std::string::npos) << written;
  const std::string line = written.substr(retract + 1, written.find('\n', retract + 1) - retract - 1);
  EXPECT_EQ(line.find('X'), std::string::npos) << line;
  EXPECT_EQ(line.find('Y'), std::string::npos) << line;
  const CommandResult verified = run_command(shell_quote(ccomp_binary()) + " verify " + program + " " + out + options);
  EXPECT_EQ(verified.exit_code, 0) << verified.err << verified.out;
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
