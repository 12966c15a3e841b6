// The bound of the error field's bending along a straight move against the forward model
// itself: for random models of every form and random short moves, the actual tip never
// leaves its chord by more than the bound; and where no bound holds, there is none.
#include "ccomp/model/variation_bound.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "ccomp/axis.hpp"
#include "ccomp/model/model_file.hpp"
#include "random_terms.hpp"
#include "sample_models.hpp"

namespace ccomp::model {
namespace {

/// The largest distance of the actual tip from its chord, sampled along the move a -> b.
double measured_chord_deviation(const ForwardModel& m, const ChainQ& a, const ChainQ& b, const Conditions& c) {
  ForwardData d(m);
  auto tip = [&](double t) {
    forward(m, d, a + t * (b - a), c, false);
    return Eigen::Vector3d(d.actual);
  };
  const Eigen::Vector3d at_a = tip(0.0), at_b = tip(1.0);
  double worst = 0.0;
  for (int k = 1; k < 64; ++k) {
    const double t = k / 64.0;
    worst = std::max(worst, (tip(t) - (at_a + t * (at_b - at_a))).norm());
  }
  return worst;
}

/// |e(b) - e(a)|, e the tip's error (actual - nominal).
double measured_error_change(const ForwardModel& m, const ChainQ& a, const ChainQ& b, const Conditions& c) {
  ForwardData d(m);
  auto error = [&](const ChainQ& q) {
    forward(m, d, q, c, false, Evaluate::both);
    return Eigen::Vector3d(d.actual - d.nominal);
  };
  return (error(b) - error(a)).norm();
}

TEST(VariationBound, HoldsAlongShortMovesForEveryForm) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  const std::string chain = test::with_limits(test::kHmcChain, 600.0) + "terms:\n";
  for (const std::string form : {"polynomial", "table", "periodic", "reversal", "thermal", "warmup", "scale_expansion",
                                 "cross_axis", "location"}) {
    const MachineModel mm =
        parse_machine_model(chain + test::random_terms(form, rng) + test::random_terms(form, rng), form + ".yaml");
    const ForwardModel m(mm);
    Conditions c;
    c.time = 1500;
    c.temperatures = {26.0, 34.0};
    for (double& s : c.directions) s = u(rng) > 0 ? 1.0 : -1.0;
    const VariationBound bound(m, c);
    int bounded = 0;
    double tightest = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 120; ++k) {
      ChainQ a = ChainQ::Zero();
      for (int i = 0; i < 3; ++i) a[i] = 500 * u(rng);
      if (k % 2 == 0) a[k % 3] = 250.0 * std::round(2 * u(rng));  // on a table's knot
      a[4] = 3.0 * u(rng);                                        // B, rad
      a[kToolLengthIndex] = 100.0;
      const Eigen::Vector3d direction = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
      const double length = std::pow(10.0, -2.0 + 2.5 * (u(rng) + 1) / 2);  // 0.01 .. 3 mm
      ChainQ b = a;
      b.head<3>() += length * direction;
      b.head<3>() -= 0.5 * length * direction;  // centred on a
      a.head<3>() -= 0.5 * length * direction;
      if (k % 3 == 0) b[4] += 2e-6;  // B turned by a correction
      EXPECT_GE(bound.error_change(a, b), measured_error_change(m, a, b, c)) << form << ": move " << k;
      const double limit = bound.chord_deviation(a, b);
      if (!std::isfinite(limit)) continue;
      ++bounded;
      const double measured = measured_chord_deviation(m, a, b, c);
      EXPECT_LE(measured, limit) << form << ": move " << k << " of " << length << " mm";
      if (measured > 1e-9) tightest = std::min(tightest, limit / measured);
    }
    EXPECT_EQ(bounded, 120) << form << ": every short move of a model with limits has a bound";
    // Not a bound so loose it would never let a move through: within 1000x somewhere.
    if (std::isfinite(tightest)) {
      EXPECT_LT(tightest, 1000.0) << form;
    }
  }
}

TEST(VariationBound, ErrorSlopesSumToTheErrorChange) {
  // error_change() is linear in each variable's travel: its slopes, times each travel,
  // add up to it (with a rounding term of their own) for any move, turning or not.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  const std::string chain = test::with_limits(test::kHmcChain, 600.0) + "terms:\n";
  for (const std::string form : {"polynomial", "periodic", "cross_axis", "location", "scale_expansion"}) {
    const MachineModel mm = parse_machine_model(chain + test::random_terms(form, rng), form + ".yaml");
    const ForwardModel m(mm);
    Conditions c;
    c.temperatures = {26.0, 34.0};
    const VariationBound bound(m, c);
    const VariationBound::ErrorSlopes slopes = bound.error_slopes(100.0);
    for (int k = 0; k < 20; ++k) {
      ChainQ a = ChainQ::Zero(), b = a;
      a[kToolLengthIndex] = b[kToolLengthIndex] = 100.0;
      for (int i = 0; i < 5; ++i) a[i] = 300 * u(rng), b[i] = a[i] + 0.5 * u(rng);
      const double exact = bound.error_change(a, b), summed = slopes.change(a, b);
      EXPECT_GE(summed, exact) << form << ": move " << k;
      EXPECT_LE(summed, exact * (1 + 1e-12) + slopes.rounding) << form << ": move " << k;
    }
  }
}

/// |e(q, b) - e(q, a)|: the tip's error at q, the approach directions changed from a to b.
double measured_direction_change(const ForwardModel& m, const ChainQ& q, Conditions c, const AxisArray<double>& a,
                                 const AxisArray<double>& b) {
  ForwardData d(m);
  auto error = [&](const AxisArray<double>& directions) {
    c.directions = directions;
    forward(m, d, q, c, false, Evaluate::both);
    return Eigen::Vector3d(d.actual - d.nominal);
  };
  return (error(b) - error(a)).norm();
}

TEST(VariationBound, BoundsWhatTheErrorSwitchesAsTheApproachChanges) {
  // At one point the approach changes (an axis reversed, or part of its play taken up): the
  // tip's error moves by no more than direction_change() (with error_change()'s rounding,
  // as the two are used together), and by a fair share of it: the bound is not vacuous.
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> u(-1, 1);
  const std::string chain = test::with_limits(test::kHmcChain, 600.0) + "terms:\n";
  std::vector<std::pair<std::string, MachineModel>> models;
  for (int n = 0; n < 3; ++n)
    models.emplace_back(
        "reversal " + std::to_string(n),
        parse_machine_model(chain + test::random_terms("reversal", rng) + test::random_terms("polynomial", rng) +
                                test::random_terms("reversal", rng),
                            "reversal.yaml"));
  // Every form a direction may take (docs/machine-model.md): an order-1 polynomial (here an
  // angle), a linear table at -1 and 1, and a location that follows an approach.
  models.emplace_back(
      "direction forms",
      parse_machine_model(chain +
                              "  - {name: EAY, variable: vy, form: polynomial, unit: urad, coefficients: [0.5, 2.0]}\n"
                              "  - {name: EZX, variable: vx, form: table, interpolation: linear, at: [-1, 1], "
                              "values: [-0.4, 0.6]}\n"
                              "  - {name: EC0X, variable: vz, form: reversal, unit: urad, reversal: 3}\n"
                              "  - {name: EX0B, variable: vb, form: reversal, reversal: 2}\n",
                          "directions.yaml"));
  models.emplace_back("sample HMC",
                      load_machine_model(std::string(CCOMP_SOURCE_DIR) + "/samples/machines/hmc-xyzb.yaml"));
  for (const auto& [name, mm] : models) {
    const ForwardModel m(mm);
    Conditions c;
    c.time = 3600;
    c.temperatures = {24.0, 23.0, 31.0};
    const VariationBound bound(m, c);
    double tightest = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 200; ++k) {
      ChainQ q = ChainQ::Zero();
      for (int i = 0; i < 3; ++i) q[i] = 400 * u(rng);
      q[4] = 3.0 * u(rng);
      q[kToolLengthIndex] = 100.0;
      AxisArray<double> a{}, b{};
      for (std::size_t i = 0; i < a.size(); ++i) {
        a[i] = u(rng) > 0 ? 1.0 : -1.0;
        // reversed, part of the play taken up, or as it was
        b[i] = k % 3 == 0 ? -a[i] : k % 3 == 1 ? std::clamp(a[i] + 0.3 * u(rng), -1.0, 1.0) : a[i];
      }
      if (k % 3 == 2) b[static_cast<std::size_t>(k) % 5] *= -1.0;  // one axis reversed
      const double measured = measured_direction_change(m, q, c, a, b);
      const double limit = bound.direction_change(a, b, 100.0);
      EXPECT_LE(measured, limit + bound.error_change(q, q)) << name << ": point " << k;
      if (measured > 1e-9) tightest = std::min(tightest, limit / measured);
    }
    EXPECT_LT(tightest, 10.0) << name;
    AxisArray<double> same{};
    same.fill(0.25);
    EXPECT_EQ(bound.direction_change(same, same, 100.0), 0.0) << name;
  }
}

TEST(VariationBound, AStretchedMovesChordBoundGrowsNoFasterThanTheSquare) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1, 1);
  const std::string chain = test::with_limits(test::kHmcChain, 600.0) + "terms:\n";
  for (const std::string form : {"polynomial", "table", "periodic", "cross_axis", "reversal", "location"}) {
    const MachineModel mm = parse_machine_model(chain + test::random_terms(form, rng), form + ".yaml");
    const ForwardModel m(mm);
    Conditions c;
    c.temperatures = {26.0, 34.0};
    for (double& s : c.directions) s = u(rng) > 0 ? 1.0 : -1.0;
    const VariationBound bound(m, c);
    for (int k = 0; k < 20; ++k) {
      ChainQ a = ChainQ::Zero();
      for (int i = 0; i < 3; ++i) a[i] = 300 * u(rng);
      a[4] = 2.0 * u(rng);
      a[kToolLengthIndex] = 100.0;
      ChainQ b = a;
      for (int i = 0; i < 3; ++i) b[i] += 0.05 * u(rng);
      b[4] += 1e-7 * u(rng);
      const double limit = bound.stretch_limit(a, b), chord = bound.chord_deviation(a, b);
      ASSERT_GE(limit, 1.0) << form;
      for (const double stretch : {1.5, 3.0, 10.0, 40.0}) {
        if (stretch >= limit) continue;
        const double stretched = bound.chord_deviation(a, a + stretch * (b - a));
        EXPECT_TRUE(std::isfinite(stretched)) << form << ": move " << k << " stretched " << stretch;
        EXPECT_LE(stretched, stretch * stretch * chord * (1 + 1e-12)) << form << ": move " << k;
      }
    }
  }
}

TEST(VariationBound, NoneWhereTheFieldIsUnbounded) {
  ChainQ a = ChainQ::Zero(), b = a;
  a[kToolLengthIndex] = b[kToolLengthIndex] = 100.0;
  b[0] = 12.0;
  const Conditions c{0.0, {20.0, 20.0}, {}};
  {  // a polynomial of X on an X without limits grows without bound
    const MachineModel mm = parse_machine_model(
        std::string(test::kHmcChain) + "terms:\n  - {name: EXX, form: polynomial, coefficients: [0, 0, 1e-3]}\n",
        "unlimited.yaml");
    const ForwardModel m(mm);
    EXPECT_TRUE(std::isinf(VariationBound(m, c).chord_deviation(a, b)));
  }
  {  // a move over more than one knot of a table
    const MachineModel mm = parse_machine_model(test::with_limits(test::kHmcChain, 600.0) +
                                                    "terms:\n  - {name: EXX, form: table, at: [-20, -10, 0, 10, 20], "
                                                    "values: [0, 3, -2, 4, 1]}\n",
                                                "table.yaml");
    const ForwardModel m(mm);
    const VariationBound bound(m, c);
    EXPECT_TRUE(std::isinf(bound.chord_deviation(a, b))) << "12 mm over knots 10 mm apart";
    b[0] = 8.0;
    EXPECT_TRUE(std::isfinite(bound.chord_deviation(a, b)));
    EXPECT_GE(bound.chord_deviation(a, b), measured_chord_deviation(m, a, b, c));
  }
  {  // constant errors do not bend a move of the linear axes at all
    const MachineModel mm = parse_machine_model(
        test::with_limits(test::kHmcChain, 600.0) + "terms:\n  - {name: EBX, value: 20}\n  - {name: EXZ, value: 5}\n",
        "constant.yaml");
    const ForwardModel m(mm);
    EXPECT_LT(VariationBound(m, c).chord_deviation(a, b), 1e-9);  // what rounding leaves
  }
}

TEST(VariationBound, IsTightForOneTermAtItsMostBent) {
  // Each case: one term, a move where it bends most; the bound is reached within a factor 2.
  struct Case {
    const char* term;
    double x, length;
  };
  const Case cases[] = {
      // a lead screw's error, 5 um over a 4 mm pitch: most curved at its crest, x = 0
      {"{name: EXX, form: periodic, period: 4 mm, harmonics: [[5, 0]]}", 0.0, 0.4},
      // the X carriage pitching 1 urad more per mm: the pitch acts through an arm X itself
      // lengthens, so the tip bends by 2 eps' r' although eps is a straight line
      {"{name: EBX, form: polynomial, unit: urad, coefficients: [0, 1]}", 100.0, 3.0},
  };
  const Conditions c{0.0, {20.0, 20.0}, {}};
  for (const Case& k : cases) {
    const MachineModel mm =
        parse_machine_model(test::with_limits(test::kHmcChain, 600.0) + "terms:\n  - " + k.term + "\n", "one.yaml");
    const ForwardModel m(mm);
    ChainQ a = ChainQ::Zero();
    a[kToolLengthIndex] = 100.0;
    a[0] = k.x - k.length / 2;
    ChainQ b = a;
    b[0] = k.x + k.length / 2;
    const double limit = VariationBound(m, c).chord_deviation(a, b), measured = measured_chord_deviation(m, a, b, c);
    EXPECT_LE(measured, limit) << k.term;
    EXPECT_GE(measured, 0.5 * limit) << k.term;
  }
  // The error's change: the pitch acting through its arm (100 mm here).
  const MachineModel mm = parse_machine_model(test::with_limits(test::kHmcChain, 600.0) +
                                                  "terms:\n  - {name: EBX, form: polynomial, unit: urad, "
                                                  "coefficients: [0, 1]}\n",
                                              "pitch.yaml");
  const ForwardModel m(mm);
  ChainQ a = ChainQ::Zero();
  a[kToolLengthIndex] = 100.0;
  ChainQ b = a;
  b[0] = 1.0;
  const double change = VariationBound(m, c).error_change(a, b), measured = measured_error_change(m, a, b, c);
  EXPECT_GE(change, measured);
  EXPECT_LE(change, 50 * measured);  // the lever bound: all strokes and offsets, 2900 mm here
}

TEST(VariationBound, LetsTheSampleMachinesFinishingMovesThrough) {
  // The compensation accepts a piece without a check when the bound is below a tenth of
  // the tolerance: at 1 um, a finishing program's 0.05 mm moves must pass on the full HMC.
  const MachineModel mm = load_machine_model(std::string(CCOMP_SOURCE_DIR) + "/samples/machines/hmc-xyzb.yaml");
  const ForwardModel m(mm);
  Conditions c;
  c.time = 3600;
  c.temperatures = {24.0, 23.0, 31.0};
  const VariationBound bound(m, c);
  ChainQ a = ChainQ::Zero();
  a << 120, -80, 40, 0, 0.3, 0, 0, 0, 0, 100;
  ChainQ b = a;
  b[0] += 0.05, b[2] -= 0.002, b[4] += 1e-7;
  EXPECT_LT(bound.chord_deviation(a, b), 1e-4 - 1e-6);
  EXPECT_GE(bound.chord_deviation(a, b), measured_chord_deviation(m, a, b, c));
}

}  // namespace
}  // namespace ccomp::model
