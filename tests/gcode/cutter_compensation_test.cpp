// Cutter radius compensation (G41/G42) as LinuxCNC's rs274 computes it, on shapes whose
// offset path is known by hand: the entry move, inside corners pulled back to where the two
// offsets meet, outside corners gone round on an arc about the corner, the move after G40,
// and what rs274 refuses. (tests/gcode/rs274_differential_test.cpp holds ccomp to rs274
// itself on thousands of generated profiles.)
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "rs274_differential.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

using gcode::MotionKind;

std::vector<std::array<double, 2>> xy_ends(const RunResult& r) {
  std::vector<std::array<double, 2>> ends;
  for (const auto& m : r.motions) ends.push_back({m.motion.end[0], m.motion.end[1]});
  return ends;
}

void expect_ends(const RunResult& r, const std::vector<std::array<double, 2>>& expected) {
  ASSERT_FALSE(r.error) << format_error(*r.error);
  const auto ends = xy_ends(r);
  ASSERT_EQ(ends.size(), expected.size());
  for (std::size_t k = 0; k < ends.size(); ++k) {
    EXPECT_NEAR(ends[k][0], expected[k][0], 1e-9) << "motion " << k;
    EXPECT_NEAR(ends[k][1], expected[k][1], 1e-9) << "motion " << k;
  }
}

std::string refusal(const std::string& program) {
  const RunResult r = run_program(program);
  EXPECT_TRUE(r.error) << "accepted: " << program;
  if (!r.error) return "";
  EXPECT_GT(r.error->where().line, 0U);
  return r.error->message();
}

TEST(CutterCompensation, InsideCornersArePulledBackToWhereTheOffsetsMeet) {
  // A 2 mm tool left of a path turning left: every corner is inside.
  const RunResult r =
      run_program("G21 G17 G90 F100\nG0 X0 Y0\nG41.1 D2\nG1 X10 Y0\nG1 X10 Y10\nG1 X0 Y10\nG40\nG1 X-5 Y10\nM2\n");
  // The entry ends one radius left of its end, then each end is pulled back along its line
  // to the next offset line; G40 leaves the last where its offset put it.
  expect_ends(r, {{0, 0}, {9, 1}, {9, 9}, {0, 9}, {-5, 10}});
  EXPECT_EQ(r.motions[4].motion.start[1], 9.0) << "the move after G40 leaves from the tool";
}

TEST(CutterCompensation, OutsideCornersAreGoneRoundOnAnArcAboutTheCorner) {
  const RunResult r = run_program("G21 G17 G90 F100\nG0 X0 Y0\nG42.1 D2\nG1 X10 Y0\nG1 X10 Y10\nG40\nG1 X20 Y10\nM2\n");
  expect_ends(r, {{0, 0}, {10, -1}, {11, 0}, {11, 10}, {20, 10}});
  const gcode::Motion& corner = r.motions[2].motion;
  EXPECT_EQ(corner.kind, MotionKind::arc);
  EXPECT_NEAR(corner.arc.center_first, 10.0, 1e-12);
  EXPECT_NEAR(corner.arc.center_second, 0.0, 1e-12);
  EXPECT_EQ(corner.arc.turns, 1) << "right of the path, an outside corner turns counter-clockwise";
}

TEST(CutterCompensation, ANegativeDiameterOffsetsToTheOtherSide) {
  const RunResult r = run_program("G21 G17 G90 F100\nG0 X0 Y0\nG41.1 D-2\nG1 X10 Y0\nG40\nG1 X20 Y0\nM2\n");
  expect_ends(r, {{0, 0}, {10, -1}, {20, 0}});
}

TEST(CutterCompensation, ArcsRunAtTheirRadiusLessOrMoreTheTools) {
  // Left of a counter-clockwise arc the tool is inside it: radius 10 - 1.
  const RunResult r =
      run_program("G21 G17 G90 F100\nG0 X0 Y-5\nG41.1 D2\nG1 X10 Y0\nG3 X20 Y10 I0 J10\nG40\nG1 X20 Y20\nM2\n");
  ASSERT_FALSE(r.error) << format_error(*r.error);
  const gcode::Motion& arc = r.motions.back().motion.kind == MotionKind::arc ? r.motions.back().motion
                                                                             : r.motions[r.motions.size() - 2].motion;
  EXPECT_EQ(arc.kind, MotionKind::arc);
  EXPECT_NEAR(arc.end[0], 19.0, 1e-9);
  EXPECT_NEAR(arc.end[1], 10.0, 1e-9);
  EXPECT_NEAR(arc.arc.center_first, 10.0, 1e-12);
  EXPECT_NEAR(arc.arc.center_second, 10.0, 1e-12);
}

TEST(CutterCompensation, WhatRs274RefusesIsRefusedAtTheBlock) {
  EXPECT_NE(
      refusal("G21 F100\nG0 X0 Y0\nG41.1 D20\nG1 X5\nM2\n").find("entry move is not greater than the tool radius"),
      std::string::npos);
  // An inside corner after a line shorter than the corner pulls it back.
  EXPECT_NE(refusal("G21 F100\nG0 X0 Y0\nG41.1 D2\nG1 X10\nG1 Y0.5\nG1 X0\nM2\n").find("without gouging"),
            std::string::npos);
  EXPECT_NE(refusal("G21 F100\nG0 X0 Y0\nG41.1 D4\nG1 X10\nG3 X12 Y2 I0 J2\nM2\n").find("tool radius not less"),
            std::string::npos);
  EXPECT_NE(refusal("G21 F100\nG41.1\nM2\n").find("D word"), std::string::npos);
  EXPECT_NE(refusal("G21 F100\nG19\nG41.1 D2\nM2\n").find("XY and XZ planes"), std::string::npos);
  EXPECT_NE(refusal("G21 F100\nG41.1 D2\nG42.1 D2\nM2\n").find("already on"), std::string::npos);
  EXPECT_NE(refusal("G21 F100\nG41 D7\nM2\n").find("not in the tool table"), std::string::npos);
  EXPECT_NE(refusal("G21 F100\nG41 D1.5\nM2\n").find("whole number"), std::string::npos);
  // Fuzzing (tools/fuzz.sh gcode): a D beyond any int was converted to int, which is
  // undefined; it is a bad tool number.
  EXPECT_NE(refusal("G21 F100\nG41 D88888888888888888888\nM2\n").find("bad tool number"), std::string::npos);
  const std::string on = "G21 F100\nG0 X0 Y0\nG41.1 D2\nG1 X10\n";
  EXPECT_NE(refusal(on + "G53 G1 X20\nM2\n").find("G53"), std::string::npos);
  EXPECT_NE(refusal(on + "G18\nM2\n").find("change planes"), std::string::npos);
  EXPECT_NE(refusal(on + "T1 M6\nM2\n").find("change tools"), std::string::npos);
  EXPECT_NE(refusal(on + "G43.1 Z1\nM2\n").find("tool length"), std::string::npos);
  EXPECT_NE(refusal(on + "G92 X0\nM2\n").find("axis offsets"), std::string::npos);
  EXPECT_NE(refusal(on + "G10 L2 P1 X1\nM2\n").find("active coordinate system"), std::string::npos);
  EXPECT_NE(refusal(on + "G55\nM2\n").find("coordinate systems"), std::string::npos);
  EXPECT_NE(refusal(on + "G81 X1 Y1 Z-1 R1\nM2\n").find("canned cycle"), std::string::npos);
  EXPECT_NE(refusal(on + "G38.2 Y5\nM2\n").find("probe"), std::string::npos);
  EXPECT_NE(refusal(on + "G40\nG2 X20 Y0 R10\nM2\n").find("must be straight"), std::string::npos);
}

TEST(CutterCompensation, TheProgrammedPathCarriesTheToolCentresSettledMoves) {
  // For the main job: each programmed move, once the next settles its corner, with the
  // tool centre's move under it.
  gcode::InterpreterOptions o;
  o.cutter_path = gcode::CutterPath::programmed;
  const RunResult r =
      run_program("G21 G17 G90 F100\nG0 X0 Y0\nG41.1 D2\nG1 X10 Y0\nG1 X10 Y10\nG40\nG1 X-5 Y10\nM2\n", o);
  ASSERT_FALSE(r.error) << format_error(*r.error);
  ASSERT_EQ(r.motions.size(), 4U);
  const gcode::Motion& first = r.motions[1].motion;
  EXPECT_EQ(first.end[0], 10.0);
  EXPECT_EQ(first.end[1], 0.0);
  EXPECT_TRUE(first.offset);
  EXPECT_NEAR(first.tool_end[0], 9.0, 1e-9) << "pulled back by the inside corner";
  EXPECT_NEAR(first.tool_end[1], 1.0, 1e-9);
  const gcode::Motion& exit = r.motions[3].motion;
  EXPECT_TRUE(exit.offset);
  EXPECT_NEAR(exit.tool_start[0], 9.0, 1e-9);
  EXPECT_NEAR(exit.tool_start[1], 10.0, 1e-9);
}

/// Where the tool centre is after each motion: the motion's end, or under the control's
/// offset the tool centre's settled end.
std::vector<gcode::Axes> tool_path(const RunResult& r) {
  std::vector<gcode::Axes> ends;
  for (const auto& m : r.motions)
    ends.push_back(m.motion.offset && m.motion.radius_compensation ? m.motion.tool_end : m.motion.end);
  return ends;
}

bool same_point(const gcode::Axes& a, const gcode::Axes& b) {
  for (std::size_t i = 0; i < gcode::kAxisCount; ++i)
    if (std::abs(a[i] - b[i]) > 1e-9) return false;
  return true;
}

TEST(CutterCompensation, TheThreeWaysOfReportingItAgreeOnGeneratedProfiles) {
  // The offset path as rs274 issues it (trace), block by block (--resolve-cutter-comp) and
  // under the programmed path (the main job): the same tool path and the same refusals,
  // on the differential fuzzer's programs (profiles under G41/G42 among the rest).
  int with_offset = 0;
  for (unsigned seed = 1; seed <= 150; ++seed) {
    const std::string program = generated_program(seed, 60);
    gcode::InterpreterOptions o;
    o.tools.tools[1] = gcode::ToolEntry{1, 1, {0, 0, 12.7}, 6.35, ""};
    o.tools.tools[2] = gcode::ToolEntry{2, 2, {0, 0, 31.75}, 12.7, ""};
    const RunResult trace = run_program(program, o);
    o.cutter_path = gcode::CutterPath::tool_centre_by_block;
    const RunResult by_block = run_program(program, o);
    o.cutter_path = gcode::CutterPath::programmed;
    const RunResult programmed = run_program(program, o);
    ASSERT_EQ(trace.error.has_value(), by_block.error.has_value()) << "seed " << seed;
    ASSERT_EQ(trace.error.has_value(), programmed.error.has_value())
        << "seed " << seed << "\n"
        << (programmed.error ? format_error(*programmed.error) : format_error(*trace.error));
    if (trace.error) {
      EXPECT_EQ(trace.error->message(), programmed.error->message()) << "seed " << seed;
      EXPECT_EQ(trace.error->where().line, programmed.error->where().line) << "seed " << seed;
    }
    const auto ends = tool_path(trace), block_ends = tool_path(by_block), under = tool_path(programmed);
    ASSERT_EQ(ends.size(), block_ends.size()) << "seed " << seed;
    for (std::size_t k = 0; k < ends.size(); ++k) ASSERT_TRUE(same_point(ends[k], block_ends[k])) << "seed " << seed;
    // The programmed path leaves out the control's corner arcs: its tool centre's ends come
    // in the same order.
    std::size_t at = 0;
    for (const gcode::Axes& e : under) {
      while (at < ends.size() && !same_point(ends[at], e)) ++at;
      ASSERT_LT(at, ends.size()) << "seed " << seed << ": a tool centre end the offset path does not reach";
      ++at;
    }
    for (const auto& m : programmed.motions) with_offset += m.motion.offset ? 1 : 0;
  }
  EXPECT_GT(with_offset, 500) << "moves under the offset compared";
}

}  // namespace
}  // namespace ccomp::test
