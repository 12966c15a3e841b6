// The guards on their own: limits (an arc's extremes too), the correction bound, the
// digits' rounding, and warnings said once.
#include "compensate/job_guards.hpp"

#include <gtest/gtest.h>

#include <numbers>
#include <string>
#include <vector>

#include "error_of.hpp"
#include "job_runner.hpp"

namespace ccomp::compensate {
namespace {

model::MachineModel limited_machine() {
  model::MachineModel m = test::sample_machine("zero");
  for (model::AxisSpec& a : m.axes)
    if (a.letter == 'X' || a.letter == 'Y') a.min = -100, a.max = 100;
  return m;
}

/// A counter-clockwise arc about (cx, 0) from (cx + 20, -40) to (cx + 20, 40), radius 44.7:
/// it passes x = cx + 44.7 between its ends.
gcode::Motion arc_about(double cx, const gcode::Offsets& offsets) {
  gcode::Motion m;
  m.kind = gcode::MotionKind::arc;
  m.start = {cx + 20, -40, 0};
  m.end = {cx + 20, 40, 0};
  m.arc.center_first = cx;
  m.arc.center_second = 0;
  m.arc.turns = 1;
  m.offsets = &offsets;
  m.line = 7;
  return m;
}

TEST(JobGuards, AnArcIsCheckedAtTheExtremesItPassesNotOnlyAtItsEnds) {
  const model::MachineModel m = limited_machine();
  const gcode::Offsets offsets;
  EXPECT_NO_THROW(check_limits(arc_about(50, offsets), m, "p.ngc"));  // reaches x = 94.7
  const gcode::Motion beyond = arc_about(60, offsets);                // ends at x = 80, reaches 104.7
  const Error e = test::error_of([&] { check_limits(beyond, m, "p.ngc"); }, "an arc beyond X's limit");
  EXPECT_EQ(e.kind(), ErrorKind::safety);
  EXPECT_EQ(e.where().line, 7U);
  EXPECT_NE(e.message().find("axis X would go to 104.72"), std::string::npos) << e.message();
  // With the block's text, the refusal points at where the block starts, as every error
  // about a whole block does (no word of it is the one at fault).
  const Error shown = test::error_of([&] { check_limits(beyond, m, "p.ngc", "  G2 X80 Y0 I30 J0"); }, "beyond");
  EXPECT_EQ(shown.where().column, 3U);
  EXPECT_NE(format_error(shown).find("p.ngc:7:3: refused: axis X"), std::string::npos) << format_error(shown);
  EXPECT_NE(format_error(shown).find("\n    ^"), std::string::npos) << format_error(shown);
}

TEST(JobGuards, TheToolOffsetCountsAgainstTheLimits) {
  const model::MachineModel m = limited_machine();
  gcode::Offsets offsets;
  offsets.tool = {15, 0, 0};
  gcode::Motion move;
  move.kind = gcode::MotionKind::feed;
  move.end = {90, 0, 0};
  move.offsets = &offsets;
  EXPECT_EQ(test::error_of([&] { check_limits(move, m, "p.ngc"); }, "90 + 15 beyond 100").kind(), ErrorKind::safety);
}

TEST(JobGuards, ACorrectionBeyondTheModelsBoundIsRefusedAtItsLine) {
  model::MachineModel m = limited_machine();
  m.max_correction = 0.05;
  JobOptions options;
  JobReport report;
  JobGuards guards(m, options, report, "p.ngc");
  MoveReport move;
  move.max_correction = 0.04;
  move.max_deviation_before = 0.03;
  guards.account(move, gcode::Units::mm, 3, "G1 X1");
  EXPECT_EQ(report.compensated_moves, 1U);
  EXPECT_DOUBLE_EQ(report.max_error_before, 0.03);
  move.max_correction = 0.06;
  const Error e = test::error_of([&] { guards.account(move, gcode::Units::mm, 4, "G1 X2"); }, "0.06 > 0.05");
  EXPECT_EQ(e.kind(), ErrorKind::safety);
  EXPECT_EQ(e.where().line, 4U);
  EXPECT_EQ(report.compensated_moves, 1U);
}

TEST(JobGuards, DecimalsThatTakeTheWholeToleranceAreRefusedAndAQuarterIsWarnedOnce) {
  const model::MachineModel m = limited_machine();  // 6 linear axes: sqrt(6) / 2 places
  JobOptions options;
  std::vector<std::string> warnings;
  options.warning = [&](const std::string& w, std::uint32_t) { warnings.push_back(w); };
  options.decimals = 3;  // 0.5e-3 * sqrt(6) = 1.2 um > 1 um
  JobReport report;
  JobGuards refused(m, options, report, "p.ngc");
  EXPECT_EQ(test::error_of([&] { refused.account({}, gcode::Units::mm, 1, "G1"); }, "3 decimals").kind(),
            ErrorKind::usage);
  options.decimals = -1;  // 4 decimals: 0.12 um, under a quarter of 1 um; 5 in inch: 0.3 um, over it
  JobGuards guards(m, options, report, "p.ngc");
  guards.account({}, gcode::Units::mm, 1, "G1");
  EXPECT_TRUE(warnings.empty());
  guards.account({}, gcode::Units::inch, 2, "G1");
  guards.account({}, gcode::Units::inch, 3, "G1");
  EXPECT_EQ(warnings.size(), 1U);
}

TEST(JobGuards, AnUnhiddenReversalIsWarnedOncePerAxis) {
  const model::MachineModel m = limited_machine();
  JobOptions options;
  std::vector<std::uint32_t> lines;
  options.warning = [&](const std::string&, std::uint32_t line) { lines.push_back(line); };
  JobReport report;
  JobGuards guards(m, options, report, "p.ngc");
  MoveReport move;
  move.unhidden_reversals = {Axis::X};
  guards.account(move, gcode::Units::mm, 5, "G1 X1");
  guards.account(move, gcode::Units::mm, 6, "G1 X0");
  move.unhidden_reversals = {Axis::X, Axis::Y};
  guards.account(move, gcode::Units::mm, 7, "G1 X1 Y1");
  EXPECT_EQ(lines, (std::vector<std::uint32_t>{5, 7}));
}

}  // namespace
}  // namespace ccomp::compensate
