// The forward model through a parsed model file: signs of the ISO error motions, the Abbe
// effect of the tool length. Its Jacobians are checked in tests/jacobian_suite_test.cpp.
#include "ccomp/model/forward.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>

#include "ccomp/error.hpp"
#include "ccomp/model/model_file.hpp"
#include "sample_models.hpp"

namespace ccomp::model {
namespace {

const char* const kChain = test::kHmcChain;

ForwardData at(const ForwardModel& m, double x, double y, double z, double b_deg, double L, bool jacobians = false,
               const Conditions& c = {}) {
  ForwardData d(m);
  ChainQ q = ChainQ::Zero();
  q << x, y, z, 0, b_deg * M_PI / 180, 0, 0, 0, 0, L;
  forward(m, d, q, c, jacobians);
  return d;
}

// Fuzzing (tools/fuzz.sh model): a model without terms has no parameters, and the key of
// what was last evaluated was compared and copied from their null data() (clang's UBSan:
// null passed to memcmp/memcpy; GCC's, in tools/sanitize.sh, does not check those calls).
TEST(Forward, AModelWithoutTermsHasNoError) {
  const ForwardModel m(parse_machine_model("name: m\naxes: {X: {}}\n", "m.yaml"));
  ASSERT_EQ(m.parameter_count(), 0U);
  ForwardData d(m);
  for (double x : {0.0, 0.0, 12.5}) {
    ChainQ q = ChainQ::Zero();
    q[0] = x;
    forward(m, d, q, {}, true);
    EXPECT_EQ(deviation(d), Eigen::Vector3d::Zero()) << x;
  }
}

TEST(Forward, ErrorMotionsShowWithTheirIsoSign) {
  for (const char* term : {"{name: EXX, value: 10}", "{name: EYY, value: 10}", "{name: EZZ, value: 10}"}) {
    const MachineModel mm = parse_machine_model(std::string(kChain) + "terms:\n  - " + term + "\n", "m.yaml");
    const ForwardModel m(mm);
    const Eigen::Vector3d d = deviation(at(m, 120, -40, 30, 0, 100));
    const int axis = term[8] - 'X';
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(d[k], k == axis ? 0.010 : 0.0, 1e-12) << term << " component " << k;
  }
}

TEST(Forward, PitchOfTheSpindleHeadActsThroughTheToolLength) {
  // EAY: the Y carriage pitches about X by 20 urad; the tool tip, L below the head's
  // frame origin along -Z, moves in Y by 20 urad x L (the Abbe arm).
  const MachineModel mm = parse_machine_model(std::string(kChain) + "terms:\n  - {name: EAY, value: 20}\n", "m.yaml");
  const ForwardModel m(mm);
  for (double L : {0.0, 100.0, 250.0}) {
    const Eigen::Vector3d d = deviation(at(m, 0, 0, 0, 0, L));
    EXPECT_NEAR(d.y(), 20e-6 * L, 1e-12) << L;
    EXPECT_NEAR(d.x(), 0.0, 1e-12);
  }
}

TEST(Forward, NominalIsTheProgramPointOnTheRotatedTable) {
  const MachineModel mm = parse_machine_model(kChain, "m.yaml");
  const ForwardModel m(mm);
  // At B = 0 the tool tip sits at (x, y, z + 400 - L) in the table frame: the table moves
  // -x and -z, the tool hangs L below the head and the B centre is 400 mm off.
  const ForwardData d0 = at(m, 10, 20, 30, 0, 100);
  EXPECT_LT((d0.nominal - Eigen::Vector3d(10, 20, 330)).norm(), 1e-12);
  EXPECT_LT((d0.actual - d0.nominal).norm(), 1e-15) << "no terms, no error";
  // B = 90 deg about -Y turns that point (v) into (v.z, v.y, -v.x) in the table frame.
  const ForwardData d90 = at(m, 10, 20, 30, 90, 0);
  EXPECT_LT((d90.nominal - Eigen::Vector3d(430, 20, -10)).norm(), 1e-12);
}

TEST(Forward, LostMotionIsTheAxisOwnPositioningReversal) {
  const MachineModel mm = parse_machine_model(std::string(kChain) + R"(terms:
  - {name: EXX, variable: vx, form: reversal, reversal: -6 um}
  - {name: EYX, variable: vx, form: reversal, reversal: 2 um}
  - {name: EZY, variable: vy, form: reversal, reversal: 1 um}
  - {name: EBB, variable: vb, form: reversal, unit: urad, reversal: -20}
)",
                                              "m.yaml");
  const ForwardModel m(mm);
  EXPECT_NEAR(m.lost_motion()[0], 0.006, 1e-15);
  EXPECT_EQ(m.lost_motion()[1], 0.0) << "EZY is a straightness of Y, not its positioning";
  EXPECT_NEAR(m.lost_motion()[4], 20e-6, 1e-18);
  EXPECT_TRUE(m.reads_approach(0));
  EXPECT_TRUE(m.reads_approach(1));
  EXPECT_FALSE(m.reads_approach(2));
  // Negative reversal: approaching upward the tool falls 3 um short (ISO 230-2's B is the
  // upward mean minus the downward one).
  Conditions up, down;
  up.directions[0] = 1;
  down.directions[0] = -1;
  EXPECT_NEAR(deviation(at(m, 10, 0, 0, 0, 100, false, up)).x(), -0.003, 1e-12);
  EXPECT_NEAR(deviation(at(m, 10, 0, 0, 0, 100, false, down)).x(), 0.003, 1e-12);
}

TEST(Forward, AnyFormInAnApproachSwitchesAsAReversalDoes) {
  // EXX as a polynomial in vx is a constant and a reversal: its switch is X's lost motion.
  // An angular switch counts in reversal_size() as seen 500 mm out.
  const MachineModel mm = parse_machine_model(std::string(kChain) + R"(terms:
  - {name: EXX, variable: vx, form: polynomial, unit: um, coefficients: [1, -3]}
  - {name: EAY, variable: vy, form: table, unit: urad, at: [-1, 1], values: [-4, 6]}
)",
                                              "m.yaml");
  const ForwardModel m(mm);
  EXPECT_NEAR(m.lost_motion()[0], 0.006, 1e-15);
  EXPECT_NEAR(m.reversal_size()[0], 0.006, 1e-15);
  EXPECT_EQ(m.lost_motion()[1], 0.0) << "EAY is a pitch of Y, not its positioning";
  EXPECT_NEAR(m.reversal_size()[1], 10e-6 * 500, 1e-15);
  EXPECT_TRUE(m.reads_approach(0) && m.reads_approach(1));
  Conditions up, down;
  up.directions[0] = 1;
  down.directions[0] = -1;
  EXPECT_NEAR(deviation(at(m, 10, 0, 0, 0, 100, false, up)).x(), -0.002, 1e-12);
  EXPECT_NEAR(deviation(at(m, 10, 0, 0, 0, 100, false, down)).x(), 0.004, 1e-12);
}

TEST(Forward, PlayIsTakenUpOverTheLostMotion) {
  const MachineModel mm = parse_machine_model(std::string(kChain) + R"(terms:
  - {name: EXX, variable: vx, form: reversal, reversal: -6 um}
  - {name: EZY, variable: vy, form: reversal, reversal: 1 um}
)",
                                              "m.yaml");
  const ForwardModel m(mm);
  auto travel = [&](Conditions& c, double dx, double dy) {
    ChainQ a = ChainQ::Zero(), b = ChainQ::Zero();
    b[0] = dx;
    b[1] = dy;
    take_up_play(m, c, a, b);
  };
  Conditions c;
  c.directions[0] = -1;
  travel(c, 0.003, 0);  // half the lost motion: half-way through the play
  EXPECT_NEAR(c.directions[0], 0.0, 1e-12);
  travel(c, -0.0015, 0);  // a small move back only eats into the play again
  EXPECT_NEAR(c.directions[0], -0.5, 1e-12);
  travel(c, 0.1, 0);
  EXPECT_EQ(c.directions[0], 1.0) << "stops at +1";
  // Y has no lost motion of its own: it switches as soon as it moves, not for a rounding.
  travel(c, 0, -1e-7);
  EXPECT_EQ(c.directions[1], 0.0);
  travel(c, 0, -1e-4);
  EXPECT_EQ(c.directions[1], -1.0);
  // The tool does not move while the play is taken up: the command's travel and the
  // reversal's change cancel.
  Conditions before, after;
  before.directions[0] = -1;
  after.directions[0] = -1;
  ChainQ from = ChainQ::Zero(), to = ChainQ::Zero();
  from[0] = 50;
  to[0] = 50.004;
  take_up_play(m, after, from, to);
  const double tip_before = at(m, 50, 0, 0, 0, 100, false, before).actual.x();
  const double tip_after = at(m, 50.004, 0, 0, 0, 100, false, after).actual.x();
  EXPECT_NEAR(tip_after, tip_before, 1e-12);
}

/// One scratch kept over a sequence of evaluations of the HMC chain with `terms`, and the
/// point and conditions the sequence starts from.
struct KeptScratch {
  explicit KeptScratch(const std::string& terms)
      : model(parse_machine_model(std::string(kChain) + "terms:" + terms, "m.yaml")), kept(model) {
    q << 120, -40, 30, 0, 0.3, 0, 0, 0, 0, 100;
    c.temperatures = {22, 25};
  }
  ForwardModel model;
  ForwardData kept;
  ChainQ q = ChainQ::Zero();
  Conditions c;
};

TEST(Forward, TermsOffTheAxesFollowTheConditionsAndParameters) {
  // Terms that depend on no axis (thermal drifts, reversals, constants) keep their values
  // between evaluations while the conditions and parameters stand still. One scratch
  // evaluated over a sequence of changes must give what a fresh one gives at each step.
  KeptScratch scratch(R"(
  - {name: EXX, form: polynomial, unit: um, coefficients: [1, 0.02]}
  - {name: EX0X, variable: T_bed, form: thermal, unit: um, coefficient: 3}
  - {name: EZ0Z, variable: t, form: warmup, amplitude: 12 um, time_constant: 1800 s}
  - {name: EXX, variable: vx, form: reversal, reversal: -6 um}
  - {name: EYY, variable: y, form: scale_expansion, temperature: T_spindle, coefficient: 11e-6, reference: 20}
  - {name: EZY, variable: y, form: periodic, period: 5 mm, unit: um, harmonics: [[1.5, 0.5]]}
  - {name: EYX, form: table, interpolation: cubic, unit: um, at: [-200, 0, 150, 300], values: [1, -2, 0.5, 3]}
)");
  auto& [m, kept, q, c] = scratch;
  c.time = 600;
  auto same_as_fresh = [&](const std::string& step) {
    forward(m, kept, q, c);
    ForwardData fresh(m);
    fresh.set_parameters(kept.parameters());
    forward(m, fresh, q, c);
    EXPECT_EQ(kept.actual, fresh.actual) << step;
    return kept.actual;
  };
  Eigen::Vector3d last = same_as_fresh("first");
  auto changed = [&](const std::string& step) {
    const Eigen::Vector3d now = same_as_fresh(step);
    EXPECT_NE(now, last) << step << " must change the tip";
    last = now;
  };
  c.temperatures[0] = 23.5;
  changed("bed temperature");
  c.time = 1200;
  changed("time");
  c.directions[0] = 1;
  changed("X's approach");
  kept.edit_parameters()[0] += 1e-4;  // EXX's constant
  changed("a parameter of a term on an axis");
  kept.edit_parameters()[m.parameter_offset(1)] *= 2;  // the bed drift's coefficient
  changed("a parameter of a term off the axes");
  kept.edit_parameters()[m.parameter_offset(5) + 1] += 1e-4;  // EZY's first cosine, at an unchanged Y
  changed("a parameter of a periodic term (evaluated apart, its value kept while Y stands still)");
  kept.edit_parameters()[m.parameter_offset(6) + 2] += 1e-4;  // a value of EYX's cubic table
  changed("a value of a cubic table (its spline solved anew)");
  Eigen::VectorXd other = kept.parameters();
  other[m.parameter_offset(6)] += 1e-4;  // another of the table's values, set whole
  kept.set_parameters(other);
  changed("parameters set whole");
  const std::uint64_t revision = kept.parameters_revision();
  kept.set_parameters(other);
  EXPECT_EQ(kept.parameters_revision(), revision) << "the same parameters set again are no change";
  forward(m, kept, q, c, true);  // an evaluation with Jacobians keeps no key
  kept.edit_parameters()[m.parameter_offset(6) + 1] -= 2e-4;
  changed("a table value after an evaluation with Jacobians");
  q[1] += 1;
  changed("Y");
  c.temperatures[1] = 30;
  changed("spindle temperature (scale expansion, on the axes)");
  (void)same_as_fresh("again, unchanged");
}

TEST(Forward, AnEvaluationKeepsTheLinksWhoseInputsStoodStill) {
  // Along a program's points most links keep their errors: an evaluation sums and poses a
  // link again only where an axis its terms read moved or an approach they read changed,
  // a carriage's polynomials as one. At every step of a sequence moving one thing at a time
  // it must give what evaluating every term alone gives (the Jacobians' path: another order
  // of the same sums, so to 1e-12 mm), and each step must move the tip.
  KeptScratch scratch(R"(
  - {name: EXX, form: polynomial, unit: um, coefficients: [1, 0.02, -1.5e-5]}
  - {name: EYX, form: polynomial, unit: um, coefficients: [0, 0, 2.0e-5]}
  - {name: EBX, form: polynomial, unit: urad, coefficients: [3, 0.015]}
  - {name: EXX, form: periodic, period: 10 mm, unit: um, harmonics: [[1.8, -0.9]]}
  - {name: EXX, variable: vx, form: reversal, reversal: -4 um}
  - {name: EAY, form: polynomial, unit: urad, coefficients: [4, 0.018]}
  - {name: EZY, form: polynomial, unit: um, coefficients: [0, 0, 1.1e-5]}
  - {name: EYY, variable: vy, form: reversal, reversal: -3 um}
  - {name: ECZ, form: cross_axis, other: x, unit: urad, coefficients: [[0.01, 0], [0, 1.0e-7]]}
  - {name: EZZ, form: table, interpolation: cubic, unit: um, at: [-200, 0, 150, 300], values: [1, -2, 0.5, 3]}
  - {name: EBB, form: periodic, period: 360 deg, unit: urad, harmonics: [[15, -10]]}
  - {name: EX0S, variable: T_spindle, form: thermal, unit: um, coefficient: 3}
  - {name: EC0X, value: 25, unit: urad}
  - {name: EXS, variable: L, form: polynomial, unit: um, coefficients: [0, 0.01]}
)");
  auto& [m, kept, q, c] = scratch;
  Eigen::Vector3d last;
  auto step = [&](const std::string& what, bool moves = true) {
    forward(m, kept, q, c);
    ForwardData alone(m);
    alone.set_parameters(kept.parameters());
    forward(m, alone, q, c, true);
    EXPECT_LT((kept.actual - alone.actual).norm(), 1e-12) << what;
    EXPECT_LT((kept.R_actual - alone.R_actual).norm(), 1e-15) << what;
    if (moves) {
      EXPECT_NE(kept.actual, last) << what << " must move the tip";
    }
    last = kept.actual;
  };
  step("first", false);
  q[0] += 0.05;
  step("X (its carriage's polynomials, lead screw, Z's cross-axis term)");
  q[1] += 1e-5;
  step("Y by a correction's size");
  q[2] -= 0.3;
  step("Z (its table)");
  q[4] += 1e-6;
  step("B");
  c.directions[1] = -0.4;
  step("Y's approach (a play being taken up) alone");
  c.directions[0] = 1;
  q[0] += 0.05;
  step("X's approach and X");
  c.temperatures[1] = 27;
  step("the spindle's temperature");
  kept.edit_parameters()[m.parameter_offset(1) + 2] *= 2;  // EYX's square term
  step("a polynomial's coefficient");
  q[9] += 10;
  step("the tool length (the spindle's term in it)");
}

TEST(Forward, ALocationErrorOnAnAxisIsRefused) {
  // A location is a constant (its pose is set once for the conditions); the model file
  // makes only constants locations, and a model built otherwise is refused by name.
  MachineModel mm = parse_machine_model(std::string(kChain) + R"(terms:
  - {name: EXX, form: polynomial, unit: um, coefficients: [1, 0.02]}
)",
                                        "m.yaml");
  mm.terms[0].placement = ErrorPlacement::location;
  try {
    const ForwardModel m(mm);
    FAIL() << "a location on an axis was taken";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("EXX"), std::string::npos) << e.what();
  }
}

TEST(Forward, PeriodicTermsOfOneVariableAndPeriodShareAPhaseWhileThePeriodsMatch) {
  // The table's once-per-turn error motions (EXB, EZB) share one phase with EBB; the worm
  // wheel's 4-degree EBB, and X's lead screw, have their own. Along a sweep of B every
  // point gives what evaluating each term alone gives (the Jacobians' path), and once a fit
  // moves one period the sharing stops.
  const MachineModel mm = parse_machine_model(std::string(kChain) + R"(terms:
  - {name: EBB, form: periodic, period: 360 deg, unit: urad, harmonics: [[15, -10], [6, 4]]}
  - {name: EXX, form: periodic, period: 10 mm, unit: um, harmonics: [[1.8, -0.9]]}
  - {name: EXB, form: periodic, period: 360 deg, unit: um, harmonics: [[4, 2]]}
  - {name: EBB, form: periodic, period: 4 deg, unit: urad, harmonics: [[3, -2]]}
  - {name: EZB, form: periodic, period: 360 deg, unit: um, harmonics: [[-3, 5]]}
  - {name: EYX, variable: b, form: periodic, period: 360 deg, unit: um, harmonics: [[0.5, 0.2]]}
)",
                                              "m.yaml");
  const ForwardModel m(mm);
  const auto& slots = m.slots();
  EXPECT_EQ(slots[0].phase_source, -1);
  EXPECT_EQ(slots[1].phase_source, -1) << "another variable";
  EXPECT_EQ(slots[2].phase_source, 0);
  EXPECT_EQ(slots[3].phase_source, -1) << "another period";
  EXPECT_EQ(slots[4].phase_source, 0);
  EXPECT_EQ(slots[5].phase_source, -1) << "on a link before the source's: evaluated before it";
  ForwardData swept(m);
  auto sweep = [&](const std::string& what) {
    for (int k = 0; k < 200; ++k) {
      ChainQ q = ChainQ::Zero();
      q << 120 + 0.05 * k, -40, 30, 0, 0.3 + 1e-4 * k + (k % 50 == 0 ? 0.7 : 0.0), 0, 0, 0, 0, 100;
      forward(m, swept, q, {}, false);
      ForwardData alone(m);
      alone.set_parameters(swept.parameters());
      forward(m, alone, q, {}, true);
      ASSERT_LT((swept.actual - alone.actual).norm(), 1e-12) << what << ", point " << k;
    }
  };
  sweep("shared");
  EXPECT_EQ(swept.phases[4].c1, swept.phases[0].c1);
  swept.edit_parameters()[static_cast<Eigen::Index>(m.parameter_offset(4))] *= 1.001;  // EZB's period, fitted
  sweep("EZB's period moved");
  EXPECT_NE(swept.phases[4].period, swept.phases[0].period);
}

}  // namespace
}  // namespace ccomp::model
