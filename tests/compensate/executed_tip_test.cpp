// verify's shortcut on short moves: the tip on the chord between a move's ends is within
// the nanometre it promises of the model's tip at every fraction, and it is taken only
// where the bound allows and the play stands still.
#include "compensate/executed_tip.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "ccomp/model/model_file.hpp"
#include "ccomp/model/variation_bound.hpp"
#include "sample_models.hpp"

namespace ccomp::test {
namespace {

using compensate::ExecutedTip;
using model::ChainQ;

/// Y's straightness along X (a slope and a slight bow), Z's, X's lead screw and Y's
/// backlash on a VMC of 500 mm strokes: a 0.05 mm move bends by far less than a nanometre.
model::MachineModel vmc() {
  return model::parse_machine_model(with_limits(kVmcChain, 500) + R"(
terms:
  - {name: EYX, form: polynomial, coefficients: [0, 0.2, 1e-4]}
  - {name: EZX, form: polynomial, coefficients: [1, -0.05]}
  - {name: EXX, form: periodic, period: 20 mm, harmonics: [[0.5, 0.2]]}
  - {name: EYY, variable: vy, form: reversal, reversal: -4 um}
)",
                                    "vmc.yaml");
}

ChainQ at(double x, double y, double z) {
  ChainQ q = ChainQ::Zero();
  q.head<3>() << x, y, z;
  return q;
}

Eigen::Vector3d model_tip(const model::ForwardModel& m, const ChainQ& q, const model::Conditions& c) {
  model::ForwardData d(m);
  model::forward(m, d, q, c, false, model::Evaluate::actual);
  return d.actual;
}

Eigen::Vector3d nominal_tip(const model::ForwardModel& m, const ChainQ& q) {
  model::ForwardData d(m);
  model::forward(m, d, q, {}, false, model::Evaluate::nominal);
  return d.nominal;
}

TEST(ExecutedTip, OnAShortMovesChordItIsWithinANanometreOfTheModelAtEveryFraction) {
  const model::MachineModel mm = vmc();
  const model::ForwardModel m(mm);
  ExecutedTip tip(m, {});
  model::Conditions c;
  c.directions[1] = 1.0;  // Y approached from below, its play taken up
  // Short moves along a wavy line, one after the other, as a finishing pass cuts.
  for (int k = 0; k < 40; ++k) {
    const ChainQ a = at(0.05 * k, 0.1, 0.01 * std::sin(0.3 * k));
    const ChainQ b = at(0.05 * (k + 1), 0.1, 0.01 * std::sin(0.3 * (k + 1)));
    ASSERT_TRUE(tip.start_move(a, b, c, k % 2 == 0)) << "move " << k;
    EXPECT_EQ(tip.on_chord(0.0), model_tip(m, a, c)) << "its ends are the model's own";
    EXPECT_EQ(tip.on_chord(1.0), model_tip(m, b, c));
    for (int j = 1; j < 16; ++j) {
      const double t = j / 16.0;
      EXPECT_LE((tip.on_chord(t) - model_tip(m, a + t * (b - a), c)).norm(), ExecutedTip::kChordBound)
          << "move " << k << " at " << t;
      // predict's nominal tip: exactly affine along a move of the linear axes alone
      if (k % 2 == 0) {
        EXPECT_LE((tip.nominal_on_chord(t) - nominal_tip(m, a + t * (b - a))).norm(), 1e-12);
      }
    }
  }
}

TEST(ExecutedTip, ALongMoveOrOneThatTakesUpPlayIsEvaluatedPointByPoint) {
  const model::MachineModel mm = vmc();
  const model::ForwardModel m(mm);
  ExecutedTip tip(m, {});
  model::Conditions c;
  c.directions[1] = 1.0;
  // 40 mm across X's 20 mm lead-screw period and Y's bow: micrometres off its chord.
  EXPECT_FALSE(tip.start_move(at(60, 0, 0), at(100, 0.5, 0), c));
  // Short, but Y turns round: its play changes along the move, and the error with it.
  EXPECT_FALSE(tip.start_move(at(1, 0.1, 0), at(1.05, 0.09, 0), c));
  EXPECT_FALSE(tip.on_chord());
  // The same move with Y's play already the other way is straight and steady.
  c.directions[1] = -1.0;
  EXPECT_TRUE(tip.start_move(at(1, 0.1, 0), at(1.05, 0.09, 0), c));
  tip.other_move();
  EXPECT_FALSE(tip.on_chord());
  // 2 mm through X's lead screw bends by more than the nanometre: point by point too.
  const model::VariationBound bound(m, {});
  EXPECT_GT(bound.chord_deviation(at(1, 0.1, 0), at(3, 0.1, 0)), ExecutedTip::kChordBound);
  EXPECT_FALSE(tip.start_move(at(1, 0.1, 0), at(3, 0.1, 0), c));
}

TEST(ExecutedTip, AKeptEndIsTheModelsForTheApproachItIsAskedFor) {
  // The same move twice, Y's play one way, then the other: Y's backlash term reads it, so
  // the end kept from the first is not the second's.
  const model::MachineModel mm = vmc();
  const model::ForwardModel m(mm);
  ExecutedTip tip(m, {});
  model::Conditions up, down;
  up.directions[1] = 1.0, down.directions[1] = -1.0;
  const ChainQ a = at(5, 0.1, 0), b = at(5.05, 0.1, 0);
  ASSERT_TRUE(tip.start_move(a, b, up));
  ASSERT_TRUE(tip.start_move(b, a, down));
  EXPECT_EQ(tip.on_chord(0.0), model_tip(m, b, down));
  EXPECT_EQ(tip.on_chord(1.0), model_tip(m, a, down));
  EXPECT_GT((model_tip(m, b, down) - model_tip(m, b, up)).norm(), 1e-3) << "the backlash shows";
  // X's approach no term reads: it may change, and the kept end serves.
  model::Conditions down_x = down;
  down_x.directions[0] = -1.0;
  ASSERT_TRUE(tip.start_move(a, b, down_x));
  EXPECT_EQ(tip.on_chord(0.0), model_tip(m, a, down_x));
}

TEST(ExecutedTip, PredictsNominalTipIsOnTheChordOnlyWhereNoRotaryAxisTurns) {
  // The HMC's table turning by a nanoradian: the actual tip is still within the bound of
  // its chord, but the nominal one is not affine in the turn; a tool length that changes
  // is a translation, affine.
  const model::MachineModel mm = model::parse_machine_model(with_limits(kHmcChain, 500) + "terms: []\n", "hmc.yaml");
  const model::ForwardModel m(mm);
  ExecutedTip tip(m, {});
  const model::Conditions c;
  ChainQ a = at(1, 2, 3), turned = at(1.05, 2, 3), longer = at(1.05, 2, 3);
  turned[4] = 1e-9;
  longer[static_cast<Eigen::Index>(model::kToolLengthIndex)] = 0.01;
  EXPECT_TRUE(tip.start_move(a, turned, c));
  EXPECT_FALSE(tip.start_move(a, turned, c, true));
  ASSERT_TRUE(tip.start_move(a, longer, c, true));
  for (int j = 1; j < 16; ++j)
    EXPECT_LE((tip.nominal_on_chord(j / 16.0) - nominal_tip(m, a + (j / 16.0) * (longer - a))).norm(), 1e-12);
}

}  // namespace
}  // namespace ccomp::test
