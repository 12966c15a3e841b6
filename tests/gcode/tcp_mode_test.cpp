// Tool centre point codes as the interpreter takes them (gcode/tcp_mode.hpp): followed, each
// motion says whether its words are the tip in the part; refused at the code; or read as any
// code (a trace). G43.4 is G43's group: G43 and G49 end it, as they end each other; LinuxCNC's
// M428 and Heidenhain's M128 are switches of their own, which only M429 and M129 undo.
#include <gtest/gtest.h>

#include <array>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "ccomp/error.hpp"
#include "ccomp/gcode/interpreter.hpp"
#include "ccomp/gcode/tool_table.hpp"

namespace ccomp::gcode {
namespace {

class TcpFlags : public CanonSink {
 public:
  void motion(const Motion& m) override { tcp.push_back(m.tcp); }
  std::vector<bool> tcp;
};

InterpreterOptions options_for(const char* dialect, TcpCodes tcp) {
  InterpreterOptions o;
  o.dialect = *dialect_named(dialect);
  std::istringstream table("T1 P1 Z100.0 D10.0\n");
  o.tools = read_tool_table(table, "t.tbl");
  o.tcp = tcp;
  return o;
}

std::vector<bool> flags(const std::string& program, const char* dialect) {
  LineSource source = LineSource::from_string(program, "t.ngc");
  TcpFlags sink;
  Interpreter(options_for(dialect, TcpCodes::follow)).run(source, sink);
  return sink.tcp;
}

TEST(TcpModes, G43_4IsOnUntilItsGroupSaysOtherwise) {
  EXPECT_EQ(flags("G43.4 H1\nG0 X1 A5\nG1 X2 F100\nG43 H1\nG1 X3\nG43.4 H1\nG1 X4\nG49\nG1 X5\nM2\n", "fanuc"),
            (std::vector<bool>{true, true, false, true, false}));
}

TEST(TcpModes, M128IsOnUntilM129AndG43LeavesIt) {
  EXPECT_EQ(flags("M128\nG43 H1\nG0 X1 A5\nG49\nG1 X2 F100\nM129\nG1 X3\nM2\n", "fanuc"),
            (std::vector<bool>{true, true, false}));
}

TEST(TcpModes, M428IsOnUntilM429AndG49LeavesIt) {
  EXPECT_EQ(flags("M428\nG43 H1\nG0 X1 A5\nG49\nG1 X2 F100\nM429\nG1 X3\nM2\n", "linuxcnc"),
            (std::vector<bool>{true, true, false}));
}

TEST(TcpModes, G43_4TakesG43sOffsetAndShareItsGroup) {
  LineSource source = LineSource::from_string("G43.4 H1\nG0 Z0\nM2\n", "t.ngc");
  Interpreter interpreter(options_for("fanuc", TcpCodes::follow));
  TcpFlags sink;
  interpreter.run(source, sink);
  EXPECT_DOUBLE_EQ(interpreter.offsets().tool[2], 100.0);
  LineSource both = LineSource::from_string("G43.4 G43 H1\nM2\n", "t.ngc");
  try {
    Interpreter(options_for("fanuc", TcpCodes::follow)).run(both, sink);
    FAIL() << "two codes of one group accepted";
  } catch (const Error& e) {
    EXPECT_NE(e.message().find("same modal group"), std::string::npos) << e.message();
  }
}

void expect_refused(const std::string& program, const char* dialect, TcpCodes tcp, const std::string& message,
                    int column) {
  LineSource source = LineSource::from_string(program, "t.ngc");
  TcpFlags sink;
  try {
    Interpreter(options_for(dialect, tcp)).run(source, sink);
    FAIL() << program << " accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::unsupported) << e.message();
    EXPECT_NE(e.message().find(message), std::string::npos) << e.message();
    EXPECT_EQ(e.where().line, 1U);
    EXPECT_EQ(e.where().column, static_cast<std::uint32_t>(column));
  }
}

TEST(TcpModes, WhatIsNotFollowedIsRefusedAtTheCode) {
  // (G43.5 without the caller's kinematics for directions: tcp_direction unset.)
  expect_refused("T1 M6 G43.5 H1\nM2\n", "fanuc", TcpCodes::follow, "G43.5 gives the tool's direction as I J K", 7);
  expect_refused("G54 M430\nM2\n", "linuxcnc", TcpCodes::follow, "M430 switches to", 5);
  // Refusing: every switch.
  expect_refused("M428\nM2\n", "linuxcnc", TcpCodes::refuse, "M428 switches to", 1);
  expect_refused("M128\nM2\n", "fanuc", TcpCodes::refuse, "M128 switches to", 1);
  expect_refused("G43.4 H1\nM2\n", "fanuc", TcpCodes::refuse, "G43.4 switches to", 1);
  // Read as any code (a trace): the M codes pass, G43.4 has no group there.
  expect_refused("G43.4 H1\nM2\n", "fanuc", TcpCodes::pass, "G43.4 switches to", 1);
  LineSource source = LineSource::from_string("M428\nG0 X1\nM429\nM2\n", "t.ngc");
  TcpFlags sink;
  Interpreter(options_for("linuxcnc", TcpCodes::pass)).run(source, sink);
  EXPECT_EQ(sink.tcp, std::vector<bool>{false});
}

// Where TCP switches, the interpreter goes on from where the machine is in the other
// coordinates, as the caller's kinematics give it: an axis a block does not name stays there.
TEST(TcpModes, ASwitchCarriesThePositionIntoTheOtherCoordinates) {
  InterpreterOptions o = options_for("fanuc", TcpCodes::follow);
  std::vector<bool> switches;
  o.tcp_switch = [&switches](const Axes& p, const Offsets&, bool to_tcp) {
    switches.push_back(to_tcp);
    Axes q = p;
    q[0] += to_tcp ? 1000.0 : -1000.0;  // a TCP point's X: 1000 beyond the axis'
    return q;
  };
  struct Starts : CanonSink {
    void motion(const Motion& m) override { x.push_back({m.start[0], m.end[0]}); }
    std::vector<std::pair<double, double>> x;
  } sink;
  LineSource source =
      LineSource::from_string("G0 X5 Z10 A30\nG43.4 H1\nG1 Z20 F100\nG49\nG0 Z50\nM128\nG0 Y1\nM2\n", "t.ngc");
  Interpreter(o).run(source, sink);
  EXPECT_EQ(switches, (std::vector<bool>{true, false, true}));
  ASSERT_EQ(sink.x.size(), 4U);
  EXPECT_EQ(sink.x[1], (std::pair<double, double>{1005.0, 1005.0})) << "under TCP from the converted point";
  EXPECT_EQ(sink.x[2], (std::pair<double, double>{5.0, 5.0})) << "back where the axis was";
  EXPECT_EQ(sink.x[3], (std::pair<double, double>{1005.0, 1005.0}));
}

// G43.5: the block's I J K (a component left out is 0) go to the caller's kinematics, whose
// angles the move ends at; the direction stays where a block gives none; each move says it
// turns the direction on a great circle and gives it as I J K; G49 ends it.
TEST(TcpModes, G43_5TakesTheAnglesForItsDirectionFromTheCaller) {
  InterpreterOptions o = options_for("fanuc", TcpCodes::follow);
  std::vector<std::array<double, 3>> asked;
  o.tcp_direction = [&asked](const std::array<double, 3>& d, const Axes& p, const Offsets&) -> std::optional<Axes> {
    asked.push_back(d);
    if (d[2] < 0) return std::nullopt;  // pointing down: none this machine takes
    Axes q = p;
    q[3] = 100 * d[0], q[5] = 100 * d[1];  // angles the test can recognise
    return q;
  };
  struct Moves : CanonSink {
    void motion(const Motion& m) override { moves.push_back(m); }
    std::vector<Motion> moves;
  } sink;
  LineSource source = LineSource::from_string(
      "G43.5 H1\nG0 X1 Z50 I0.5 K0.8\nG1 X2 J0.25 K1 F100\nG1 X3\nG49\nG1 X4\nM2\n", "t.ngc");
  Interpreter(o).run(source, sink);
  EXPECT_EQ(asked, (std::vector<std::array<double, 3>>{{0.5, 0, 0.8}, {0, 0.25, 1}}));
  ASSERT_EQ(sink.moves.size(), 4U);
  EXPECT_DOUBLE_EQ(sink.moves[0].end[3], 50.0);
  EXPECT_DOUBLE_EQ(sink.moves[1].end[3], 0.0);
  EXPECT_DOUBLE_EQ(sink.moves[1].end[5], 25.0);
  EXPECT_DOUBLE_EQ(sink.moves[2].end[5], 25.0) << "no I J K: the direction, and the angles, stay";
  for (std::size_t k = 0; k < 3; ++k) EXPECT_TRUE(sink.moves[k].tcp && sink.moves[k].direction_words == DirectionWords::ijk && sink.moves[k].tcp_great_circle);
  EXPECT_FALSE(sink.moves[3].tcp || sink.moves[3].direction_words != DirectionWords::none);
  // A direction the machine cannot take, an angle word and an arc are refused at the line.
  for (const char* program : {"G43.5 H1\nG0 X1 I0 J0 K-1\nM2\n", "G43.5 H1\nG0 X1 A5\nM2\n",
                              "G43.5 H1\nG0 X1\nG2 X2 Y1 I1 J0 F100\nM2\n"}) {
    LineSource refused = LineSource::from_string(program, "t.ngc");
    Moves ignored;
    try {
      Interpreter(o).run(refused, ignored);
      FAIL() << program;
    } catch (const Error& e) {
      EXPECT_GE(e.where().line, 2U) << e.message();
    }
  }
}

TEST(TcpModes, TwoSwitchesOnOneLineAreRefused) {
  LineSource source = LineSource::from_string("M428 M429\nM2\n", "t.ngc");
  TcpFlags sink;
  try {
    Interpreter(options_for("linuxcnc", TcpCodes::follow)).run(source, sink);
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(e.message().find("two tool-centre-point switches on one line"), std::string::npos) << e.message();
    EXPECT_EQ(e.where().column, 6U);
  }
}

}  // namespace
}  // namespace ccomp::gcode
