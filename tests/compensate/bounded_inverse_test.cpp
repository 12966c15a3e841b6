// The inverse's shortcut along a path (InverseOptions::bound): a point accepted without
// evaluating the model, or an evaluated iterate left standing, must land within the bound
// it reports, and that bound within the caller's tolerance, for models of every form and for the sample machine;
// checked against a fresh evaluation of the model at the accepted axis values. Where the model gives no bound, every
// point is evaluated.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <regex>
#include <sstream>

#include "ccomp/axis.hpp"
#include "ccomp/compensate/inverse.hpp"
#include "ccomp/kinematics/pose.hpp"
#include "ccomp/model/model_file.hpp"
#include "ccomp/model/variation_bound.hpp"
#include "job_runner.hpp"
#include "random_terms.hpp"
#include "sample_models.hpp"

namespace ccomp::compensate {
namespace {

constexpr double kTolerance = 1e-4;  // mm: what the compensation at 1 um allows a point

/// A finishing path in even steps of `step` mm: rows of 20 mm along X with a bent Z, a step
/// over in Y between them (the approach of X turns round), a tool change and a table index
/// on the way. `zigzag`: every third point steps back a step and a half, so that points
/// fall between the last two solved and behind them.
model::ChainQ path_point(int k, double step, AxisArray<double>& directions, bool zigzag = false) {
  const int per_row = static_cast<int>(std::lround(20.0 / step));
  const int row = k / per_row, along = k % per_row;
  const double s = (along - (zigzag && along % 3 == 2 ? 1.5 : 0.0)) * step;
  const double x = row % 2 == 0 ? -10.0 + s : -10.0 + (per_row - 1) * step - s;
  directions[0] = row % 2 == 0 ? 1.0 : -1.0;
  model::ChainQ q = model::ChainQ::Zero();
  q << x, 30.0 + 0.5 * row, -20.0 + 0.5 * std::sin(0.1 * x) * std::cos(0.07 * row), 0, k < 1600 ? 0.0 : 0.4, 0, 0, 0, 0,
      k < 1000 ? 100.0 : 140.0;
  return q;
}

struct Outcome {
  int bounded = 0, points = 0;
  int standing = 0;          ///< evaluated, and left where the residual is within a tenth of the tolerance
  double worst_share = 0.0;  ///< the largest true residual over its bound
};

/// Solves the path with the shortcut and checks each point against a fresh evaluation.
Outcome solve_path(const model::ForwardModel& m, const model::Conditions& conditions, double step,
                   const std::string& label, bool zigzag = false) {
  const InverseProblem problem(m);
  model::ForwardData d(m), check(m), nominal(m);
  model::Conditions c = conditions;
  const model::VariationBound bound(m, c);
  InverseOptions options;
  options.bound = &bound;
  options.bounded_tolerance = kTolerance;
  InverseWorkspace ws;
  Outcome out;
  for (int k = 0; k < 2400; ++k, ++out.points) {
    const model::ChainQ q = path_point(k, step, c.directions, zigzag);
    model::forward(m, nominal, q, c);
    const InverseResult r = solve_inverse(m, problem, d, q, c, options, nullptr, &ws);
    if (!r.converged) {
      ADD_FAILURE() << label << ": point " << k << " did not converge";
      break;
    }
    model::forward(m, check, r.q, c);
    const double position = (check.actual - nominal.nominal).norm();
    if (r.evaluated && r.residual_bound <= 1e-6) {  // converged
      EXPECT_LT(position, 1e-6) << label << ": point " << k;
      continue;
    }
    ++(r.evaluated ? out.standing : out.bounded);
    // What the rotary residual left turns the tip through, at most the bound's lever.
    const Eigen::Vector3d axis = nominal.R_nominal.transpose() * problem.rotary_directions.front();
    const Eigen::Vector3d omega = kinematics::so3_log(nominal.R_nominal.transpose() * check.R_actual);
    const double turned = bound.lever(q, q) * std::abs(axis.dot(omega));
    EXPECT_LE(position + turned, r.residual_bound * (1 + 1e-9)) << label << ": point " << k;
    EXPECT_LE(r.residual_bound, r.evaluated ? 0.1 * kTolerance : kTolerance) << label << ": point " << k;
    EXPECT_NEAR((r.position_residual - (check.actual - nominal.nominal)).norm(), 0.0, r.residual_bound)
        << label << ": the extrapolated residual, point " << k;
    EXPECT_EQ(r.q[9], q[9]) << label << ": point " << k;
    out.worst_share = std::max(out.worst_share, (position + turned) / r.residual_bound);
  }
  EXPECT_EQ(ws.bounded_points, static_cast<std::size_t>(out.bounded)) << label;
  return out;
}

TEST(BoundedInverse, PointsAcceptedOnTheBoundLandWithinItForEveryForm) {
  std::mt19937 rng(23);
  const std::string chain = test::with_limits(test::kHmcChain, 600.0) + "terms:\n";
  for (const std::string form : {"polynomial", "table", "periodic", "reversal", "thermal", "warmup", "scale_expansion",
                                 "cross_axis", "location"}) {
    const model::MachineModel mm = model::parse_machine_model(
        chain + test::random_terms(form, rng) + test::random_terms(form, rng), form + ".yaml");
    const model::ForwardModel m(mm);
    model::Conditions c;
    c.time = 1500;
    c.temperatures = {26.0, 34.0};
    // Every form lets points of a fine path through; the coarser one may not (a table's
    // knots, a short period).
    EXPECT_GT(solve_path(m, c, 0.02, form + " at 0.02 mm").bounded, 0) << form;
    solve_path(m, c, 0.1, form + " at 0.1 mm");
    EXPECT_GT(solve_path(m, c, 0.02, form + " zigzag at 0.02 mm", true).bounded, 0) << form;
  }
}

TEST(BoundedInverse, TheSampleMachinesFinishingPathSkipsMostEvaluations) {
  const model::MachineModel mm =
      model::load_machine_model(std::string(CCOMP_SOURCE_DIR) + "/samples/machines/hmc-xyzb.yaml");
  const model::ForwardModel m(mm);
  model::Conditions c;
  c.time = 3600;
  c.temperatures = {24.0, 23.0, 31.0};
  const Outcome fine = solve_path(m, c, 0.05, "hmc-xyzb at 0.05 mm");
  // Most points of a fine path go through, and the bound is not so loose that the truth
  // never comes near it.
  EXPECT_GT(fine.bounded, fine.points / 2);
  EXPECT_GT(fine.worst_share, 0.1);
  // Some evaluated points stand without another evaluation; none off the path.
  EXPECT_GT(fine.standing, 0);
  // Steps of 2 mm: the error field bends too much between them for any to go through.
  const Outcome coarse = solve_path(m, c, 2.0, "hmc-xyzb at 2 mm");
  EXPECT_EQ(coarse.bounded, 0);
}

TEST(BoundedInverse, NoBoundNoShortcut) {
  // A polynomial of X on an X without limits: the field has no bound, every point is solved.
  const model::MachineModel mm = model::parse_machine_model(
      std::string(test::kHmcChain) + "terms:\n  - {name: EXX, form: polynomial, coefficients: [0, 0, 1e-3]}\n",
      "unlimited.yaml");
  const model::ForwardModel m(mm);
  model::Conditions c;
  c.temperatures = {20.0, 20.0};
  const Outcome none = solve_path(m, c, 0.05, "unlimited");
  EXPECT_EQ(none.bounded, 0);
  EXPECT_EQ(none.standing, 0);
}

TEST(BoundedInverse, TheJobsPointsStayWithinATenthOfTheToleranceOfExactSolves) {
  // A finishing pass through the job with the sample HMC, with the shortcut (the default)
  // and --exact: the shortcut changes what is written, by at most a tenth of the tolerance
  // at every coordinate (here one unit of the fourth decimal), and adds no line.
  const model::MachineModel mm = test::sample_machine("hmc-xyzb");
  std::string program = "G21 G90 G94 G54\nT1 M6\nG43 H1\nF1500\nG0 X0 Y0 Z5\nG1 Z-1\n";
  for (int row = 0; row < 3; ++row)
    for (int k = 0; k <= 300; ++k) {
      const double x = (row % 2 == 0 ? k : 300 - k) * 0.05, y = row * 0.4;
      char line[80];
      std::snprintf(line, sizeof line, "G1 X%.4f Y%.4f Z%.4f\n", x, y,
                    -1.0 + 0.5 * std::sin(0.1 * x) * std::cos(0.07 * y));
      program += line;
    }
  program += "G0 Z50\nM30\n";
  JobOptions o;
  o.time = 3600;
  o.sensors = {{"bed", 24.0}, {"column", 23.0}, {"spindle", 31.0}};
  const std::string fast = test::compensate(program, mm, o);
  o.exact = true;
  const std::string exact = test::compensate(program, mm, o);
  EXPECT_NE(fast, exact) << "the shortcut took no point";
  std::istringstream a(fast), b(exact);
  std::string la, lb;
  const std::regex number("([A-Z])(-?[0-9]+\\.?[0-9]*)");
  int lines = 0, moved = 0;
  while (std::getline(a, la)) {
    ASSERT_TRUE(std::getline(b, lb)) << "the shortcut added line " << lines + 1 << ": " << la;
    ++lines;
    if (la == lb) continue;
    ++moved;
    ASSERT_EQ(std::regex_replace(la, number, "$1"), std::regex_replace(lb, number, "$1")) << la << " | " << lb;
    for (std::sregex_iterator i(la.begin(), la.end(), number), j(lb.begin(), lb.end(), number);
         i != std::sregex_iterator() && j != std::sregex_iterator(); ++i, ++j)
      EXPECT_LE(std::abs(std::stod((*i)[2]) - std::stod((*j)[2])), 1e-4 + 1e-12) << la << " | " << lb;
  }
  EXPECT_FALSE(std::getline(b, lb)) << "--exact wrote more lines";
  EXPECT_GT(moved, 0);
}

}  // namespace
}  // namespace ccomp::compensate
