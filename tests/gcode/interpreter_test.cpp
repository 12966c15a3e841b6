// What the interpreter makes of motion, offsets and modal state. Positions are checked in
// the machine frame (work offsets applied), in mm and degrees.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <tuple>

#include "ccomp/gcode/dialect.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

using gcode::MotionKind;

RunResult ok(const std::string& program, const gcode::InterpreterOptions& o = {}) {
  RunResult r = run_program(program, o);
  EXPECT_FALSE(r.error) << (r.error ? format_error(*r.error) : "");
  return r;
}

std::string refused(const std::string& program, const gcode::InterpreterOptions& o = {}) {
  RunResult r = run_program(program, o);
  EXPECT_TRUE(r.error) << "accepted: " << program;
  return r.error ? r.error->message() : "";
}

TEST(Interpreter, UnitsAndDistanceModes) {
  const RunResult r = ok("G20 G0 X1\nG91 X1\nG21 X1\nG90 Y2\nM2\n");
  ASSERT_EQ(r.motions.size(), 4U);
  EXPECT_DOUBLE_EQ(r.motions[0].motion.end[0], 25.4);
  EXPECT_DOUBLE_EQ(r.motions[1].motion.end[0], 50.8);
  EXPECT_DOUBLE_EQ(r.motions[2].motion.end[0], 51.8);
  EXPECT_DOUBLE_EQ(r.motions[3].motion.end[1], 2.0);
  EXPECT_EQ(r.motions[3].motion.kind, MotionKind::traverse);
}

TEST(Interpreter, WorkOffsetsG92G52AndG53) {
  const RunResult r = ok("G10 L2 P2 X10 Y20\nG55 G0 X1 Y1\nG92 X0 Y0\nG0 X1\nG92.1\nG52 X5\nG0 X0\nG53 G0 X0 Y0\nM2\n");
  ASSERT_EQ(r.motions.size(), 4U);
  EXPECT_DOUBLE_EQ(r.motions[0].motion.end[0], 11.0);  // G55 origin 10 + 1
  EXPECT_DOUBLE_EQ(r.motions[1].motion.end[0], 12.0);  // G92 made (11,21) read (0,0)
  EXPECT_DOUBLE_EQ(r.motions[2].motion.end[0], 15.0);  // G52 shifts G55 by 5
  EXPECT_DOUBLE_EQ(r.motions[3].motion.end[0], 0.0);   // G53: machine coordinates
  EXPECT_EQ(r.motions[3].motion.source, gcode::MotionSource::machine_coordinates);
}

TEST(Interpreter, ToolLengthOffsetMovesTheControlledPointNotTheMachine) {
  gcode::InterpreterOptions o;
  o.tools.tools[1] = gcode::ToolEntry{1, 1, {0, 0, 100.0}, 10.0, ""};
  const RunResult r = ok("T1 M6\nG43 H1\nG0 Z0\nG49\nG0 Z0\nM2\n", o);
  ASSERT_EQ(r.motions.size(), 2U);
  EXPECT_DOUBLE_EQ(r.motions[0].offsets.tool[2], 100.0);
  EXPECT_DOUBLE_EQ(r.motions[0].motion.end[2], 0.0);       // controlled point at the program's Z0
  EXPECT_DOUBLE_EQ(r.motions[0].motion.start[2], -100.0);  // machine did not move at G43
  EXPECT_NE(refused("G43 H7\nM2\n").find("tool 7"), std::string::npos);
}

TEST(Interpreter, ArcCentresInEveryPlane) {
  // Quarter circles of radius 10 about the origin, G17/G18/G19, IJK and R forms.
  const RunResult r =
      ok("G21 F100\nG0 X10 Y0 Z0\nG17 G3 X0 Y10 I-10 J0\nG0 X10 Y0 Z0\nG18 G2 X0 Z10 R10\n"
         "G0 X0 Y10 Z0\nG19 G3 Y0 Z10 J-10 K0\nM2\n");
  ASSERT_EQ(r.motions.size(), 6U);
  const auto& a = r.motions[1].motion;
  EXPECT_EQ(a.kind, MotionKind::arc);
  EXPECT_NEAR(a.arc.center_first, 0.0, 1e-12);
  EXPECT_NEAR(a.arc.center_second, 0.0, 1e-12);
  EXPECT_EQ(a.arc.turns, 1);
  const auto& b = r.motions[3].motion;  // G18: first axis Z, second X
  EXPECT_EQ(b.arc.plane, gcode::Plane::zx);
  EXPECT_NEAR(b.arc.center_first, 0.0, 1e-9);
  EXPECT_NEAR(b.arc.center_second, 0.0, 1e-9);
  EXPECT_EQ(b.arc.turns, -1);
  const auto& c = r.motions[5].motion;
  EXPECT_EQ(c.arc.plane, gcode::Plane::yz);
  EXPECT_NEAR(c.arc.center_first, 0.0, 1e-12);
  EXPECT_NEAR(c.arc.center_second, 0.0, 1e-12);
}

TEST(Interpreter, RFormatPicksTheShortOrLongArc) {
  const RunResult r = ok("F1 G0 X0 Y0\nG2 X10 Y0 R5\nG0 X0 Y0\nG2 X10 Y10 R-10\nG0 X0 Y0\nG2 X10 Y10 R10\nM2\n");
  EXPECT_NEAR(r.motions[1].motion.arc.center_first, 5.0, 1e-9);  // a semicircle
  EXPECT_NEAR(r.motions[1].motion.arc.center_second, 0.0, 1e-9);
  // chord (0,0)-(10,10), r 10: centres (0,10) and (10,0); clockwise short arc about (10,0)
  EXPECT_NEAR(r.motions[5].motion.arc.center_first, 10.0, 1e-9);
  EXPECT_NEAR(r.motions[5].motion.arc.center_second, 0.0, 1e-9);
  EXPECT_NEAR(r.motions[3].motion.arc.center_first, 0.0, 1e-9);  // R<0: the long way
  EXPECT_NEAR(r.motions[3].motion.arc.center_second, 10.0, 1e-9);
}

TEST(Interpreter, HelixTurnsAndAbsoluteCentres) {
  const RunResult r = ok("F1 G0 X10 Y0 Z0\nG3 X10 Y0 Z-3 I-10 J0 P3\nG90.1 G2 X0 Y10 I0 J0 Z-4\nM2\n");
  EXPECT_EQ(r.motions[1].motion.arc.turns, 3);
  EXPECT_DOUBLE_EQ(r.motions[1].motion.end[2], -3.0);
  EXPECT_NEAR(r.motions[2].motion.arc.center_first, 0.0, 1e-12);
  EXPECT_EQ(r.motions[2].motion.arc.turns, -1);
}

TEST(Interpreter, ArcErrorsAsLinuxcncWords) {
  EXPECT_NE(refused("F1 G2 X1\nM2\n").find("R, I, J and K words all missing"), std::string::npos);
  EXPECT_NE(refused("F1 G0 X0 Y0\nG2 X10 I4\nM2\n").find("radius to end of arc differs"), std::string::npos);
  EXPECT_NE(refused("F1 G0 X0 Y0\nG2 X10 R4\nM2\n").find("too small"), std::string::npos);
  EXPECT_NE(refused("G1 X1\nM2\n").find("zero feed rate"), std::string::npos);
  EXPECT_NE(refused("G93 G1 X1\nM2\n").find("inverse time"), std::string::npos);
}

TEST(Interpreter, BlockErrorsNameTheWord) {
  RunResult r = run_program("G0 G1 X1 F1\nM2\n");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error->message().find("same modal group"), std::string::npos);
  EXPECT_EQ(r.error->where().column, 4U);
  r = run_program("G0 X1\nG12.3 X2\nM2\n");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error->message().find("unknown G code G12.3"), std::string::npos);
  EXPECT_EQ(r.error->where().line, 2U);
  EXPECT_NE(refused("G0 X1 X2\nM2\n").find("multiple X words"), std::string::npos);
  EXPECT_NE(refused("G0 X1 M3 M4\nM2\n").find("same modal group"), std::string::npos);
  EXPECT_NE(refused("G61 R1\nM2\n").find("R word with no G code"), std::string::npos);
}

TEST(Interpreter, CannedCycleDrillsEachHoleWithStickyValues) {
  const RunResult r = ok("G21 F100 G0 X0 Y0 Z10\nG99 G81 X1 Y1 Z-2 R1\nX2\nG80\nM2\n");
  // per hole: XY at old Z, down to R, feed to Z, back to R (G99)
  std::vector<std::array<double, 3>> ends;
  for (const auto& m : r.motions) ends.push_back({m.motion.end[0], m.motion.end[1], m.motion.end[2]});
  const std::vector<std::array<double, 3>> expected = {{0, 0, 10}, {1, 1, 10}, {1, 1, 1},  {1, 1, -2},
                                                       {1, 1, 1},  {2, 1, 1},  {2, 1, -2}, {2, 1, 1}};
  EXPECT_EQ(ends, expected);
  EXPECT_EQ(r.motions[3].motion.kind, MotionKind::feed);
  EXPECT_EQ(r.motions[3].motion.source, gcode::MotionSource::canned_cycle);
}

TEST(Interpreter, ARunOfCycleBlocksKeepsItsInitialLevel) {
  // rs274: a G91 R counts from the level where the run of cycle blocks began, however the
  // blocks come (here a subprogram repeated), and every hole after the first is reached at
  // the clearance level.
  const RunResult r = ok("G21 G90 F10 G0 X0 Y0 Z10\nM98 P1 L3\nG80 G90\nM30\nO1\nG91 G99 G81 X10 Z-5 R-2.5\nM99\n");
  std::vector<double> bottoms;
  for (const auto& m : r.motions)
    if (m.motion.kind == MotionKind::feed) bottoms.push_back(m.motion.end[2]);
  EXPECT_EQ(bottoms, (std::vector<double>{2.5, 2.5, 2.5})) << "R 7.5 each time, not 2.5 below the last R";
  const RunResult g98 = ok("G21 G90 F100 G0 X0 Y0 Z10\nG99 G81 X1 Y1 Z-2 R2\nG98 X10 R3\nG80\nM2\n");
  ASSERT_GE(g98.motions.size(), 7U);
  EXPECT_EQ(g98.motions[5].motion.end[0], 10.0);
  EXPECT_EQ(g98.motions[5].motion.end[2], 10.0) << "to the next hole at the initial level (G98)";
}

TEST(Interpreter, AMainProgramMayNotRunIntoItsSubprograms) {
  // LinuxCNC refuses a Fanuc-style main program without M2, M30 or % before its subprograms.
  const RunResult r = run_program("G21\nG0 X1\nM98 P100\nO100\nG0 X2\nM99\n");
  ASSERT_TRUE(r.error);
  EXPECT_EQ(r.error->where().line, 4U);
  EXPECT_NE(r.error->message().find("runs into subprogram O100"), std::string::npos) << r.error->message();
  EXPECT_EQ(ok("G21\nG0 X1\nM98 P100\nM30\nO100\nG0 X2\nM99\n").motions.size(), 2U);
}

TEST(Interpreter, TappingOutsideXYFeedsAlongThePlaneNormal) {
  // G18: Y is the cycle axis. (LinuxCNC's own output permutes this; see the suite test.)
  const RunResult r = ok("G21 F100 S100 M3 G18 G0 X0 Y5 Z0\nG98 G84 X1 Z2 Y-1 R1\nG80\nM2\n");
  ASSERT_GE(r.motions.size(), 5U);
  const auto& feed_down = r.motions[3].motion;
  EXPECT_EQ(feed_down.kind, MotionKind::feed);
  EXPECT_DOUBLE_EQ(feed_down.end[0], 1.0);
  EXPECT_DOUBLE_EQ(feed_down.end[1], -1.0);
  EXPECT_DOUBLE_EQ(feed_down.end[2], 2.0);
  EXPECT_DOUBLE_EQ(r.motions[4].motion.end[1], 5.0);  // fed back out to the initial level
}

TEST(Interpreter, PeckDrillingRetractsAboveEachPeck) {
  const RunResult r = ok("G21 F100 G0 X0 Y0 Z10\nG98 G73 X0 Y0 Z-3 R2 Q1.2\nG80\nM2\n");
  std::vector<double> z;
  for (const auto& m : r.motions) z.push_back(m.motion.end[2]);
  const std::vector<double> expected = {10,   10,           2,    0.8,          0.8 + 0.254, -0.4, -0.4 + 0.254,
                                        -1.6, -1.6 + 0.254, -2.8, -2.8 + 0.254, -3,          10};
  ASSERT_EQ(z.size(), expected.size());
  for (std::size_t i = 0; i < z.size(); ++i) EXPECT_NEAR(z[i], expected[i], 1e-12) << i;
}

TEST(Interpreter, CannedCycleRefusals) {
  EXPECT_NE(refused("F1 G81 X0 Y0 Z1 R0\nM2\n").find("R value"), std::string::npos);
  EXPECT_NE(refused("F1 G81 X0 Y0 Z-1\nM2\n").find("R word missing"), std::string::npos);
  EXPECT_NE(refused("F1 G81 X0 Y0 Z-1 R0 A9\nM2\n").find("canned cycle"), std::string::npos);
}

// Fuzzing (tools/fuzz.sh gcode): L repeats and pecks were unbounded. An L of 1e20 went to
// int (undefined); a Q too small to change the depth (Z of -1e20, Q0.0000001) pecked for ever.
TEST(Interpreter, RunawayCannedCyclesAreRefused) {
  const std::string repeats = refused("G21 G91 F10 G0 Z5\nG81 X0.001 Z-1 R1 L40000\nM2\n");
  EXPECT_NE(repeats.find("G81 makes more than 100000 moves"), std::string::npos) << repeats;
  const std::string pecks = refused("G21 F10 G0 X0 Y0 Z5\nG83 X1 Z-2 R0 Q0.00002\nM2\n");
  EXPECT_NE(pecks.find("G83 makes more than 100000 moves"), std::string::npos) << pecks;
  const RunResult huge_l = run_program("G21 G91 F10 G0 Z5\nG81 X1 Z-1 R1 L100000000000000000000\nM2\n");
  ASSERT_TRUE(huge_l.error);
  EXPECT_NE(huge_l.error->message().find("repeats: more than 100000"), std::string::npos);
  EXPECT_EQ(huge_l.error->where().line, 2U);
  EXPECT_EQ(huge_l.error->where().column, 15U) << "at the L word";
  const RunResult absorbed = run_program("G21 F10 G0 X0 Y0 Z5\nG83 X1 Z-100000000000000000000 R1 Q0.0000001\nM2\n");
  ASSERT_TRUE(absorbed.error) << "the peck depth never changes";
  EXPECT_EQ(absorbed.error->where().line, 2U);
  // What real programs do stays: 799 pecks (3 moves each), and 1000 holes (3 each).
  EXPECT_EQ(ok("G21 F10 G0 X0 Y0 Z5\nG83 X1 Z-100 R0 Q0.125\nM2\n").motions.size(), 3U + 799U * 3U + 2U);
  EXPECT_EQ(ok("G21 G91 F10 G0 Z5\nG81 X1 Z-1 R1 L1000\nM2\n").motions.size(), 2U + 1000U * 3U);
}

// Fuzzing (tools/fuzz.sh gcode): a T word of 100 digits was converted to int (undefined);
// M61's Q and an arc's P turns went the same way. Each is refused at its word.
TEST(Interpreter, ToolNumbersAndTurnsBeyondIntAreRefusedAtTheirWord) {
  const std::string big = "100000000000000000000";  // 1e20, in digits: G-code has no exponent
  for (const auto& [program, words, column] :
       {std::tuple{"T" + big + " M6\nM2\n", "bad tool number T", 1U},
        std::tuple{"M61 Q" + big + "\nM2\n", "bad tool number Q", 5U},
        std::tuple{"G21 G17 G2 X1 Y0 I0.5 P" + big + " F1\nM2\n", "P value for arc turns", 23U}}) {
    const RunResult r = run_program(program);
    ASSERT_TRUE(r.error) << program;
    EXPECT_NE(r.error->message().find(words), std::string::npos) << r.error->message();
    EXPECT_EQ(r.error->where().line, 1U);
    EXPECT_EQ(r.error->where().column, column) << program;
  }
  EXPECT_FALSE(run_program("T2147483647 M6\nM61 Q7\nM2\n").error);
}

TEST(Interpreter, FanucDialectReturnsToG0AfterG80) {
  gcode::InterpreterOptions o;
  o.dialect = *gcode::dialect_named("fanuc");
  const RunResult r = ok("G0 X0 Y0 Z5 F10\nG81 X1 Z-1 R1\nG80\nX3\nG53 Z0\nM30\n", o);
  EXPECT_EQ(r.motions.back().motion.kind, MotionKind::traverse);
  EXPECT_EQ(r.motions.back().motion.source, gcode::MotionSource::machine_coordinates);
  EXPECT_DOUBLE_EQ(r.motions[r.motions.size() - 2].motion.end[0], 3.0);
  EXPECT_NE(refused("G0 X0 Y0 Z5 F10\nG81 X1 Z-1 R1\nG80\nX3\nM30\n").find("G80"), std::string::npos)
      << "LinuxCNC: G80 leaves no motion mode";
}

TEST(Interpreter, RotatedCoordinateSystem) {
  const RunResult r = ok("G10 L2 P1 X10 Y0 R90\nG54 G0 X1 Y0\nM2\n");
  ASSERT_EQ(r.motions.size(), 1U);
  EXPECT_NEAR(r.motions[0].motion.end[0], 10.0, 1e-12);  // +X of the program is +Y of the machine
  EXPECT_NEAR(r.motions[0].motion.end[1], 1.0, 1e-12);
}

TEST(Interpreter, InverseTimeFeedIsKeptPerBlock) {
  const RunResult r = ok("G0 X0 Y0 A0\nG93 G1 X10 A90 F2\nX20 A180 F4\nG94 F100 G1 X0\nM2\n");
  ASSERT_EQ(r.motions.size(), 4U);
  EXPECT_EQ(r.motions[1].motion.feed_mode, gcode::FeedMode::inverse_time);
  EXPECT_DOUBLE_EQ(r.motions[1].motion.feed, 2.0);
  EXPECT_DOUBLE_EQ(r.motions[2].motion.feed, 4.0);
  EXPECT_DOUBLE_EQ(r.motions[2].motion.end[3], 180.0);
  EXPECT_EQ(r.motions[3].motion.feed_mode, gcode::FeedMode::units_per_minute);
}

TEST(Interpreter, ProbeMovesWarn) {
  const RunResult r = ok("F10 G38.2 Z-5\nM2\n");
  ASSERT_EQ(r.motions.size(), 1U);
  EXPECT_EQ(r.motions[0].motion.kind, MotionKind::probe);
  ASSERT_EQ(r.warnings.size(), 1U);
}

TEST(Interpreter, ProgramEndsAtM2AndTheClosingPercent) {
  EXPECT_EQ(ok("G0 X1\nM2\nG0 X2\n").motions.size(), 1U);
  EXPECT_EQ(ok("%\nG0 X1\n%\nG0 X2\n").motions.size(), 1U);
  EXPECT_EQ(ok("/G0 X1\nG0 X2\n").motions.size(), 2U) << "block delete is off by default, as in rs274";
  gcode::InterpreterOptions o;
  o.block_delete = true;
  EXPECT_EQ(ok("/G0 X1\nG0 X2\n", o).motions.size(), 1U);
}

}  // namespace
}  // namespace ccomp::test
