// Five-axis compensation held to a reference machine written apart from ccomp's model code
// (tests/support/reference_five_axis.hpp): a trunnion table (XYZAC, C on A) with each location
// and motion error alone and all together. The model file is this test's description of the
// reference in ccomp's terms (its chain offsets from the reference's geometry, its linear
// terms moved from machine positions to program ones through the work offset); a program
// sweeping A through 0 (the singular pose, where the tool runs along C's line) is compensated
// point by point as the job does, and each corrected pose is run on the reference.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "ccomp/compensate/inverse.hpp"
#include "ccomp/model/model_file.hpp"
#include "reference_five_axis.hpp"

namespace ccomp::compensate {
namespace {

using test::FiveAxisWords;
using test::ReferenceTrunnion;

constexpr double kRadPerDeg = std::numbers::pi / 180.0;
constexpr double kToolLength = 120.0;

std::string vec(const Eigen::Vector3d& v) {
  std::ostringstream out;
  out.precision(17);
  out << "[" << v.x() << " mm, " << v.y() << " mm, " << v.z() << " mm]";
  return out.str();
}

/// Positioning errors of the linear axes on the reference (mm, of the machine position):
/// slope and curvature of each.
struct LinearErrors {
  double slope = 0.0, curvature = 0.0;
};

/// A polynomial term of `name` (um, of the program's coordinate) equal to the reference's
/// error at the machine position the work offset `shift` away.
std::string moved_polynomial(const char* name, const LinearErrors& e, double shift) {
  std::ostringstream out;
  out.precision(17);
  out << "  - {name: " << name << ", form: polynomial, unit: um, coefficients: ["
      << 1e3 * (e.slope * shift + e.curvature * shift * shift) << ", " << 1e3 * (e.slope + 2 * e.curvature * shift)
      << ", " << 1e3 * e.curvature << "]}\n";
  return out.str();
}

/// One error of the reference, as the test sets it there and writes it in the model.
struct TrunnionError {
  const char* name;
  void (*set)(ReferenceTrunnion&);
  std::string term;  ///< the model's line(s), given the reference (for the linear axes' shift)
  std::string (*terms)(const ReferenceTrunnion&) = nullptr;
};

constexpr LinearErrors kX{12e-6, -1.5e-8}, kY{-9e-6, 2e-8}, kZ{7e-6, 1e-8};
constexpr double kAaHarmonic = 14e-6, kCcHarmonic = -11e-6;  // rad, first harmonic amplitudes (sine)

std::vector<TrunnionError> trunnion_errors() {
  return {
      {"EY0A", [](ReferenceTrunnion& r) { r.EY0A = 0.012; }, "  - {name: EY0A, value: 12, unit: um}\n"},
      {"EZ0A", [](ReferenceTrunnion& r) { r.EZ0A = -0.008; }, "  - {name: EZ0A, value: -8, unit: um}\n"},
      {"EB0A", [](ReferenceTrunnion& r) { r.EB0A = 15e-6; }, "  - {name: EB0A, value: 15, unit: urad}\n"},
      {"EC0A", [](ReferenceTrunnion& r) { r.EC0A = -10e-6; }, "  - {name: EC0A, value: -10, unit: urad}\n"},
      {"EX0C", [](ReferenceTrunnion& r) { r.EX0C = -0.009; }, "  - {name: EX0C, value: -9, unit: um}\n"},
      {"EY0C", [](ReferenceTrunnion& r) { r.EY0C = 0.007; }, "  - {name: EY0C, value: 7, unit: um}\n"},
      {"EA0C", [](ReferenceTrunnion& r) { r.EA0C = 12e-6; }, "  - {name: EA0C, value: 12, unit: urad}\n"},
      {"EB0C", [](ReferenceTrunnion& r) { r.EB0C = -9e-6; }, "  - {name: EB0C, value: -9, unit: urad}\n"},
      {"EAA",
       [](ReferenceTrunnion& r) { r.EAA = [](double a) { return kAaHarmonic * std::sin(a * kRadPerDeg); }; },
       "  - {name: EAA, form: periodic, period: 360 deg, unit: urad, harmonics: [[0, 14]]}\n"},
      {"ECC",
       [](ReferenceTrunnion& r) { r.ECC = [](double c) { return kCcHarmonic * std::sin(c * kRadPerDeg); }; },
       "  - {name: ECC, form: periodic, period: 360 deg, unit: urad, harmonics: [[0, -11]]}\n"},
      {"EXX",
       [](ReferenceTrunnion& r) { r.EXX = [](double m) { return kX.slope * m + kX.curvature * m * m; }; }, "",
       [](const ReferenceTrunnion& r) { return moved_polynomial("EXX", kX, r.work_offset().x()); }},
      {"EYY",
       [](ReferenceTrunnion& r) { r.EYY = [](double m) { return kY.slope * m + kY.curvature * m * m; }; }, "",
       [](const ReferenceTrunnion& r) { return moved_polynomial("EYY", kY, r.work_offset().y()); }},
      {"EZZ",
       [](ReferenceTrunnion& r) { r.EZZ = [](double m) { return kZ.slope * m + kZ.curvature * m * m; }; }, "",
       [](const ReferenceTrunnion& r) { return moved_polynomial("EZZ", kZ, r.work_offset().z()); }},
  };
}

/// The reference in ccomp's terms: the table base moved by X and Y, the trunnion and its
/// table at their centres, the program origin a fixed link on the C table; the head's Z
/// carries the tool from where its tip meets the program origin at machine zero.
std::string trunnion_chain(const ReferenceTrunnion& r) {
  return R"(
name: reference-trunnion
axes: {X: {}, Y: {}, Z: {}, A: {type: rotary}, C: {type: rotary}}
max_correction: 1 mm
chain:
  workpiece:
    - {link: Y, axis: Y, direction: [0, -1, 0]}
    - {link: X, axis: X, direction: [-1, 0, 0]}
    - {link: A, axis: A, direction: [-1, 0, 0], offset: )" +
         vec(r.a_centre) + R"(}
    - {link: C, axis: C, direction: [0, 0, -1], offset: )" +
         vec(r.c_from_a) + R"(}
    - {link: part, offset: )" +
         vec(r.origin_from_c) + R"(}
  tool:
    - {link: Z, axis: Z, direction: [0, 0, 1], offset: )" +
         vec(r.a_centre + r.c_from_a + r.origin_from_c) + R"(}
    - {link: tool, tool_length: [0, 0, -1]}
terms:
)";
}

/// A five-axis finishing pass: the tool tilts from A -35 to A 40 degrees through A 0 while C
/// turns 210 degrees and the tip runs over the part; then a stretch at A 0 itself, C turning.
std::vector<FiveAxisWords> sweep() {
  std::vector<FiveAxisWords> points;
  const int n = 300;
  for (int k = 0; k <= n; ++k) {
    const double s = static_cast<double>(k) / n;
    points.push_back({-40 + 90 * s, 30 * std::sin(3 * s), 25 - 20 * s, -35 + 75 * s, -60 + 210 * s});
  }
  for (int k = 0; k <= 60; ++k) points.push_back({50.0 - k, -10 + 0.5 * k, 5, 0.0, 150 - 2.0 * k});
  return points;
}

model::ChainQ chain_of(const FiveAxisWords& w) {
  model::ChainQ q = model::ChainQ::Zero();
  q << w.x, w.y, w.z + kToolLength, w.a * kRadPerDeg, 0, w.c * kRadPerDeg, 0, 0, 0, kToolLength;
  return q;
}

FiveAxisWords words_of(const model::ChainQ& q) {
  return {q[0], q[1], q[2] - kToolLength, q[3] / kRadPerDeg, q[5] / kRadPerDeg};
}

/// How far A stands from the singular pose (A 0) where the tool's direction is held to the
/// full tolerance: within it the rotary axes turn the tool by sin(A) per radian of C, and
/// the damped solve leaves part of that direction as it is (the share kSingularDamping
/// allows), reported.
constexpr double kAwayFromSingular = 2.0;  // deg

struct Landing {
  double tip = 0.0;        ///< mm: the worst tip error on the reference
  double direction = 0.0;  ///< rad: the worst tool direction error, |A| beyond kAwayFromSingular
  double near_singular = 0.0;  ///< rad: the same within it
  /// rad: how much worse the tool's direction is than without compensation, at worst (<= 0:
  /// never worse)
  double made_worse = -1.0;
  double reported = 0.0;                   ///< rad: the worst orientation error the solve reported
  double rotary_correction = 0.0;          ///< rad: the largest change of A or C
  double direction_left_unreported = 0.0;  ///< rad: the reference's direction error less the reported one
  int unconverged = 0;
};

double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

Landing compensate_on(const ReferenceTrunnion& reference, const std::string& terms) {
  const model::MachineModel mm = model::parse_machine_model(trunnion_chain(reference) + terms, "trunnion.yaml");
  const model::ForwardModel m(mm);
  const InverseProblem problem(m);
  EXPECT_EQ(problem.orientation, OrientationEquations::tool_direction);
  model::ForwardData d(m);
  InverseWorkspace ws;
  Landing out;
  for (const FiveAxisWords& w : sweep()) {
    const model::ChainQ q = chain_of(w);
    const InverseResult r = solve_inverse(m, problem, d, q, {}, {}, nullptr, &ws);
    if (!r.converged) {
      ++out.unconverged;
      continue;
    }
    const test::PartPose meant = reference.nominal(w, kToolLength);
    const test::PartPose got = reference.actual(words_of(r.q), kToolLength);
    const double direction = angle_between(meant.axis, got.axis);
    const double uncompensated = angle_between(meant.axis, reference.actual(w, kToolLength).axis);
    out.tip = std::max(out.tip, (got.tip - meant.tip).norm());
    double& worst = std::abs(w.a) >= kAwayFromSingular ? out.direction : out.near_singular;
    worst = std::max(worst, direction);
    out.made_worse = std::max(out.made_worse, direction - uncompensated);
    out.reported = std::max(out.reported, r.orientation_error.norm());
    out.direction_left_unreported =
        std::max(out.direction_left_unreported, std::abs(direction - r.orientation_error.norm()));
    out.rotary_correction = std::max({out.rotary_correction, std::abs(r.q[3] - q[3]), std::abs(r.q[5] - q[5])});
  }
  return out;
}

/// Every pose within 1 um of its tip, its tool direction within 10 urad away from A 0 and
/// never worse than uncompensated near it; what is left there is what the solve reported,
/// and no rotary axis is corrected by more than 1 mrad (no flip, no absurd correction).
void expect_lands(const Landing& l, const char* what) {
  EXPECT_EQ(l.unconverged, 0) << what;
  EXPECT_LT(l.tip, 1e-3) << what;
  EXPECT_LT(l.direction, 10e-6) << what;
  EXPECT_LT(l.made_worse, 0.1e-6) << what;
  EXPECT_LT(l.direction_left_unreported, 0.1e-6) << what << ": what is left is what is reported";
  EXPECT_LT(l.rotary_correction, 1e-3) << what;
}

class TrunnionTable : public testing::TestWithParam<TrunnionError> {};

TEST_P(TrunnionTable, EachErrorAloneLandsWithinAMicrometreAndTenMicroradians) {
  ReferenceTrunnion reference;
  GetParam().set(reference);
  const std::string terms = GetParam().terms ? GetParam().terms(reference) : GetParam().term;
  expect_lands(compensate_on(reference, terms), GetParam().name);
}

INSTANTIATE_TEST_SUITE_P(Errors, TrunnionTable, testing::ValuesIn(trunnion_errors()),
                         [](const auto& param_info) { return std::string(param_info.param.name); });

TEST(TrunnionTable, AllErrorsTogetherLandWithinAMicrometreAndTenMicroradians) {
  ReferenceTrunnion reference;
  std::string terms;
  for (const TrunnionError& e : trunnion_errors()) {
    e.set(reference);
    terms += e.terms ? e.terms(reference) : e.term;
  }
  const Landing l = compensate_on(reference, terms);
  expect_lands(l, "all");
  EXPECT_GT(l.near_singular, 10e-6) << "C's tilt at A 0 is beyond any small correction: this checks it is reported";
}

}  // namespace
}  // namespace ccomp::compensate
