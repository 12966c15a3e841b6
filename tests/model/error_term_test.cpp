// What each term form must do by definition. Its derivatives, with respect to its variables
// and to each parameter, are checked with every other Jacobian in tests/jacobian_suite_test.cpp.
#include "ccomp/model/error_term.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "term_shapes.hpp"

namespace ccomp::model {
namespace {

using test::cross;
using test::shape;
using test::table;
using test::vec;

TEST(TermForms, TablesPassThroughTheirValuesAndHoldOutside) {
  for (Interpolation i : {Interpolation::linear, Interpolation::cubic}) {
    const TermShape s = table(i);
    const Eigen::VectorXd y = vec({0.001, -0.002, 0.0, 0.003, 0.001, -0.004});
    for (std::size_t k = 0; k < s.knots.size(); ++k)
      EXPECT_NEAR(evaluate(s, y, {s.knots[k], 0}).value, y[static_cast<Eigen::Index>(k)], 1e-15);
    EXPECT_NEAR(evaluate(s, y, {1000.0, 0}).value, -0.004, 1e-15);
    EXPECT_EQ(evaluate(s, y, {1000.0, 0}).d_primary, 0.0);
  }
}

TEST(TermForms, CubicTableIsTheNaturalSpline) {
  // A long laser table with uneven knots: the spline must be twice continuously
  // differentiable at every interior knot, straight at both ends, and reproduce a
  // straight line exactly (a natural spline does); its weights must sum to one.
  TermShape s = table(Interpolation::cubic);
  s.knots.clear();
  Eigen::VectorXd y(61), line(61);
  for (Eigen::Index k = 0; k < 61; ++k) {
    s.knots.push_back(-600.0 + 20.0 * static_cast<double>(k) + (k % 3 == 1 ? 7.0 : 0.0));
    y[k] = 0.003 * std::sin(0.9 * static_cast<double>(k)) + 1e-5 * s.knots.back();
    line[k] = 0.002 - 3e-6 * s.knots.back();
  }
  auto at = [&](double v) { return evaluate(s, y, {v, 0}); };
  const double e = 1e-4;
  auto curvature = [&](double v) { return (at(v + e).d_primary - at(v - e).d_primary) / (2 * e); };
  for (std::size_t k = 1; k + 1 < s.knots.size(); ++k) {
    const double x = s.knots[k];
    EXPECT_NEAR(at(x - 1e-7).d_primary, at(x + 1e-7).d_primary, 1e-10) << "slope jumps at knot " << k;
    EXPECT_NEAR(curvature(x - 2 * e), curvature(x + 2 * e), 2e-8) << "curvature jumps at knot " << k;
  }
  EXPECT_NEAR(curvature(s.knots.front() + 2 * e), 0.0, 1e-8);
  EXPECT_NEAR(curvature(s.knots.back() - 2 * e), 0.0, 1e-8);
  for (double v : {-583.3, -1.0, 77.7, 591.0}) {
    EXPECT_NEAR(evaluate(s, line, {v, 0}).value, 0.002 - 3e-6 * v, 1e-15) << v;
    EXPECT_NEAR(evaluate(s, y, {v, 0}, true).d_parameters.sum(), 1.0, 1e-12) << v;
  }
}

TEST(TermForms, PeriodicRepeatsReversalSplitsThermalStartsAtZero) {
  const TermShape p = shape(TermForm::periodic, 2);
  const Eigen::VectorXd pp = vec({6.0, 0.003, -0.001, 0.0005, 0.0002});
  EXPECT_NEAR(evaluate(p, pp, {1.7, 0}).value, evaluate(p, pp, {1.7 + 6.0 * 7, 0}).value, 1e-12);
  const Eigen::VectorXd r = vec({0.008});
  EXPECT_NEAR(
      evaluate(shape(TermForm::reversal), r, {1, 0}).value - evaluate(shape(TermForm::reversal), r, {-1, 0}).value,
      0.008, 1e-15);
  EXPECT_EQ(evaluate(shape(TermForm::thermal_warmup), vec({0.02, 600}), {0, 0}).value, 0.0);
  EXPECT_NEAR(evaluate(shape(TermForm::thermal_warmup), vec({0.02, 600}), {1e6, 0}).value, 0.02, 1e-12);
  EXPECT_EQ(evaluate(shape(TermForm::thermal_linear), vec({0.001}), {20.0, 0}).value, 0.0);
}

TEST(TermForms, PeriodicTurnedFromItsLastPhaseEqualsAFreshEvaluation) {
  // A term's scratch keeps a phase whose sine is exact and turns from there for nearby
  // points (steps of 0.05 mm on a 10 mm screw, a B angle corrected by microradians, and a
  // jump): every value must be what a fresh evaluation gives, to a few ulps.
  const TermShape p = shape(TermForm::periodic, 3);
  const Eigen::VectorXd pp = vec({10.0, 0.003, -0.001, 0.0005, 0.0002, -0.0004, 0.0001});
  TermValue kept;
  double v = -412.0;
  for (int k = 0; k < 2000; ++k) {
    v += k == 1000 ? 37.7 : (k % 7 == 0 ? 1e-6 : 0.05);
    evaluate(p, pp, {v, 0}, false, kept);
    const TermValue fresh = evaluate(p, pp, {v, 0});
    ASSERT_NEAR(kept.value, fresh.value, 1e-17) << "at " << v;
    ASSERT_NEAR(kept.d_primary, fresh.d_primary, 1e-16) << "at " << v;
  }
}

TEST(TermForms, PeriodicValueAloneIsWhatEvaluateGivesBitwise) {
  // The forward model's loop takes periodic_value(); the fit and the Jacobians evaluate():
  // along the same points, with scratches of their own, the values must be the same bits.
  const TermShape p = shape(TermForm::periodic, 3);
  const Eigen::VectorXd pp = vec({10.0, 0.003, -0.001, 0.0005, 0.0002, -0.0004, 0.0001});
  TermValue by_evaluate, by_value;
  double v = 87.0;
  for (int k = 0; k < 2000; ++k) {
    v -= k == 700 ? 120.3 : (k % 5 == 0 ? 3e-7 : 0.05);
    evaluate(p, pp, {v, 0}, false, by_evaluate);
    ASSERT_EQ(periodic_value(pp.data(), 3, v, by_value), by_evaluate.value) << "at " << v;
  }
}

}  // namespace
}  // namespace ccomp::model
