// Solving on its own: arcs as chords within half the tolerance, a rapid as its end.
#include "compensate/move_solver.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "ccomp/compensate/machine_coordinates.hpp"
#include "job_runner.hpp"

namespace ccomp::compensate {
namespace {

gcode::ArcGeometry circle(double r, double sweep) {
  gcode::ArcGeometry g;
  g.r_start = g.r_end = r;
  g.sweep = sweep;
  return g;
}

double sagitta(double r, double sweep, std::size_t n) {
  return r * (1.0 - std::cos(sweep / static_cast<double>(n) / 2.0));
}

TEST(MoveSolver, AnArcTakesTheFewestChordsWithinTheTolerance) {
  for (const double r : {0.5, 10.0, 250.0})
    for (const double sweep : {0.1, std::numbers::pi, 2 * std::numbers::pi, 20 * std::numbers::pi})
      for (const double tolerance : {0.0005, 0.001, 0.01}) {
        const std::size_t n = arc_chord_count(circle(r, sweep), tolerance);
        EXPECT_LE(sagitta(r, sweep, n), tolerance * (1 + 1e-12)) << r << " " << sweep << " " << tolerance;
        if (n > 1) {
          EXPECT_GT(sagitta(r, sweep, n - 1), tolerance) << r << " " << sweep << " " << tolerance;
        }
      }
  EXPECT_EQ(arc_chord_count(circle(0.0005, 2 * std::numbers::pi), 0.001), 1U);  // smaller than the tolerance
}

class MoveSolverTest : public ::testing::Test {
 protected:
  MoveSolverTest() : forward_(test::sample_machine("hmc-xyzb-geometric")), solver_(forward_, {}) {
    offsets_.tool = {0, 0, 100.0};
  }
  model::ForwardModel forward_;
  MoveSolver solver_;
  gcode::Offsets offsets_;
};

TEST_F(MoveSolverTest, ARapidIsItsCompensatedEnd) {
  gcode::Motion m;
  m.kind = gcode::MotionKind::traverse;
  m.start = {0, 0, -100};
  m.end = {100, 50, -120};
  m.offsets = &offsets_;
  MoveReport report;
  std::vector<CompensatedPoint> points;
  solver_.solve(m, offsets_, report, points);
  ASSERT_EQ(points.size(), 1U);
  const model::ChainQ nominal = compensate::chain_of(m.end, offsets_);
  EXPECT_GT((points[0].q - nominal).norm(), 1e-6);
  EXPECT_LT((points[0].q - nominal).norm(), forward_.machine().max_correction);
}

TEST_F(MoveSolverTest, AFullCircleComesAsChordsAndReportsTheirSagitta) {
  gcode::Motion m;
  m.kind = gcode::MotionKind::arc;
  m.start = {40, 0, -100};
  m.end = m.start;
  m.arc.center_first = 0;
  m.arc.center_second = 0;
  m.arc.turns = 1;
  m.offsets = &offsets_;
  MoveReport report;
  std::vector<CompensatedPoint> points;
  solver_.solve(m, offsets_, report, points);
  const std::size_t chords = arc_chord_count(gcode::arc_geometry(m), 0.0005);
  EXPECT_GE(points.size(), chords);  // each chord's end, and what a split adds
  EXPECT_DOUBLE_EQ(points.back().s, 1.0);
  EXPECT_GE(report.max_deviation_after, sagitta(40, 2 * std::numbers::pi, chords));
  EXPECT_LT(report.max_deviation_after, 0.001);
  EXPECT_LT((points.back().q - compensate::chain_of(m.end, offsets_)).norm(), forward_.machine().max_correction);
}

}  // namespace
}  // namespace ccomp::compensate
