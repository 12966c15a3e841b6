// verify's search for the fraction of a turning piece nearest an executed point
// (src/compensate/nearest_fraction.hpp), against the fraction found by bisection on the
// derivative of the distance in long double: on a piece whose tip moves millimetres, and on
// one whose tip stands nearly still at 300 mm from the origin while the tool turns (a TCP
// move pivoting about the tip), where the rounding of the coordinates sets how near any
// search can come and the steps must stop where they stop shrinking.
#include "compensate/nearest_fraction.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace ccomp::compensate {
namespace {

/// A tip path: an arc of `radius` (mm) about `centre` in the XY plane, `sweep` rad long,
/// with a rise; `target` is off it by `off` (mm) towards the centre at fraction `meant`.
struct TipArc {
  Eigen::Vector3d centre{300.0, -120.0, 80.0};
  double radius = 40.0, sweep = 0.2, rise = 0.5;
  [[nodiscard]] Eigen::Vector3d at(double f) const {
    const double a = sweep * f;
    return centre + Eigen::Vector3d(radius * std::cos(a), radius * std::sin(a), rise * f);
  }
  [[nodiscard]] Eigen::Vector3d target(double meant, double off) const {
    Eigen::Vector3d p = at(meant);
    const double a = sweep * meant;
    return p - off * Eigen::Vector3d(std::cos(a), std::sin(a), 0.0);
  }
  /// d/df of |g - target|^2 / 2 in long double.
  [[nodiscard]] long double derivative(long double f, const Eigen::Vector3d& t) const {
    const long double a = static_cast<long double>(sweep) * f, r = radius, s = sweep;
    const long double gx = centre.x() + r * std::cos(a) - t.x(), gy = centre.y() + r * std::sin(a) - t.y(),
                      gz = centre.z() + static_cast<long double>(rise) * f - t.z();
    return gx * (-r * s * std::sin(a)) + gy * (r * s * std::cos(a)) + gz * static_cast<long double>(rise);
  }
  /// The nearest fraction by bisection on the derivative (one minimum in [0, 1] here).
  [[nodiscard]] double exact(const Eigen::Vector3d& t) const {
    long double lo = 0, hi = 1;
    for (int k = 0; k < 200; ++k) {
      const long double mid = (lo + hi) / 2;
      (derivative(mid, t) < 0 ? lo : hi) = mid;
    }
    return static_cast<double>((lo + hi) / 2);
  }
};

struct Case {
  const char* name;
  double radius, sweep, rise, off, meant;
  double turn;       ///< rad the tool turns over the piece
  double tolerance;  ///< of the fraction found against the exact one
  int most_steps;    ///< Gauss-Newton steps taken at most
};

class NearestFractionCases : public ::testing::TestWithParam<Case> {};

TEST_P(NearestFractionCases, FindsTheExactFractionAndStopsWhereTheStepsStopShrinking) {
  const Case& c = GetParam();
  TipArc arc;
  arc.radius = c.radius, arc.sweep = c.sweep, arc.rise = c.rise;
  const Eigen::Vector3d target = arc.target(c.meant, c.off);
  NearestFractionOptions o;
  o.turn = c.turn;
  const std::optional<NearestFraction> found =
      nearest_fraction(c.meant + 0.01, target, [&](double f) { return arc.at(f); }, o);
  ASSERT_TRUE(found.has_value());
  const double exact = arc.exact(target);
  EXPECT_NEAR(found->fraction, exact, c.tolerance) << c.name;
  // The tool's direction at the fraction found, off the exact one's by at most:
  EXPECT_LT(std::abs(found->fraction - exact) * c.turn, 1e-8) << c.name << ": rad";
  EXPECT_LE(found->steps, c.most_steps) << c.name;
}

INSTANTIATE_TEST_SUITE_P(
    Pieces, NearestFractionCases,
    ::testing::Values(
        // A tip moving 8 mm while the tool turns 2 degrees: to the last bits, in a few steps.
        Case{"moving_tip", 40.0, 0.2, 0.5, 0.8e-3, 0.37, 0.035, 1e-12, 4},
        // A tip moving 2.6 um while the tool turns 3 degrees, 50 nm off: the rounding of
        // coordinates of 300 mm makes steps of about 1e-10 of the fraction, never 1e-12.
        // The old rule ran all 12 steps here.
        Case{"standing_tip", 0.013, 0.2, 0.0, 5e-5, 0.6, 0.05, 1e-7, 4},
        // The same tip exactly on its path.
        Case{"standing_tip_on_path", 0.013, 0.2, 0.0, 0.0, 0.3, 0.05, 1e-7, 4}),
    [](const ::testing::TestParamInfo<Case>& param) { return std::string(param.param.name); });

TEST(NearestFraction, AStandingCurveHasNoFraction) {
  const Eigen::Vector3d still(300.0, -120.0, 80.0);
  EXPECT_FALSE(nearest_fraction(0.5, Eigen::Vector3d(301.0, -120.0, 80.0), [&](double) { return still; }));
}

// A tip moving 2.6 nm over the piece, the point 1 um off it: the tip cannot say where
// along the piece the point is. Asked for only what is within reach, the search says so
// (verify then takes the direction's nearest); asked anyway, it lands where its
// wandering ends.
TEST(NearestFraction, ATargetFartherThanTheCurveMovesIsBeyondReach) {
  TipArc arc;
  arc.radius = 0.013, arc.sweep = 2e-4, arc.rise = 0.0;
  const Eigen::Vector3d target = arc.target(0.4, 1e-3);
  NearestFractionOptions o;
  o.only_within_reach = true;
  EXPECT_FALSE(nearest_fraction(0.4, target, [&](double f) { return arc.at(f); }, o));
  // Within reach, the same search answers: 50 pm off a path of 2.6 nm.
  EXPECT_TRUE(nearest_fraction(0.4, arc.target(0.4, 5e-8), [&](double f) { return arc.at(f); }, o));
}

TEST(NearestFraction, ATargetBeyondTheEndGivesTheEnd) {
  TipArc arc;
  const std::optional<NearestFraction> found =
      nearest_fraction(0.5, arc.at(1.3), [&](double f) { return arc.at(f); });
  ASSERT_TRUE(found);
  EXPECT_EQ(found->fraction, 1.0);
}

}  // namespace
}  // namespace ccomp::compensate
