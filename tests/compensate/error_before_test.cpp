// The report's error before: a probe whose error cannot raise the maximum (by the bound of
// the error's change since the probe before it) is not evaluated, and the maximum over a
// program stays exactly what evaluating every probe gives.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <new>

#include "ccomp/axis.hpp"
#include "ccomp/compensate/compensator.hpp"
#include "ccomp/model/machine.hpp"
#include "ccomp/model/model_file.hpp"

namespace ccomp::compensate {
namespace {

/// What a finishing pass's probes give, each taken exactly and with the bound.
struct Pass {
  double all = 0.0, skipping = 0.0;  ///< the maximum, every probe evaluated; the same skipping
  int probes = 0, evaluated = 0, approach_changes = 0;
};

/// Rows 0.05 mm apart in X, stepping 2 mm in Y at each row's end, on the sample HMC; the
/// approach turns with the row, and Y's is `y(k)` at a row's k-th probe. Every probe taken
/// with the bound must be at least its error, and below the maximum so far where bounded.
Pass finishing_pass(int rows, double (*y)(int)) {
  const model::MachineModel mm =
      model::load_machine_model(std::string(CCOMP_SOURCE_DIR) + "/samples/machines/hmc-xyzb.yaml");
  const model::ForwardModel m(mm);
  CompensationOptions o;
  o.conditions.time = 3600;
  o.conditions.temperatures = {24.0, 23.0, 31.0};
  Compensator every(m, o), bounded(m, o);
  Pass pass;
  AxisArray<double> last{};
  for (int row = 0; row < rows; ++row) {
    const double direction = row % 2 == 0 ? 1.0 : -1.0;
    for (int k = 0; k <= 400; ++k, ++pass.probes) {
      ErrorProbe p;
      p.nominal = model::ChainQ::Zero();
      p.nominal << -10 + direction * (k * 0.05 - 10), -20 + 2 * row, -0.3 + 1e-4 * k, 0, 0, 0, 0, 0, 0, 100;
      p.directions = {direction, y(k), -1, 0, 1, 0, 0, 0, 0};
      pass.approach_changes += p.directions != last;
      last = p.directions;
      model::ForwardData d(m);
      model::forward(m, d, p.nominal, o.conditions, false, model::Evaluate::nominal);
      p.tip = d.nominal;
      const double exact = every.error_at(p);
      const double taken = bounded.error_at(p, pass.skipping);
      if (taken == exact)
        ++pass.evaluated;
      else
        EXPECT_LE(taken, pass.skipping) << "a bounded probe may not raise the maximum";
      EXPECT_GE(taken, exact) << "a bound below the error at probe " << pass.probes;
      pass.all = std::max(pass.all, exact);
      pass.skipping = std::max(pass.skipping, taken);
    }
  }
  return pass;
}

TEST(ErrorBefore, TheMaximumIsExactWhileMostProbesAreBounded) {
  const Pass pass = finishing_pass(20, [](int) { return 1.0; });
  EXPECT_EQ(pass.skipping, pass.all);
  EXPECT_LT(pass.evaluated, pass.probes / 4) << "most probes of a finishing pass are bounded below the maximum";
}

TEST(ErrorBefore, ProbesAcrossAnApproachChangeAreBoundedToo) {
  // Along the rows, Y barely moves: its correction's travel turns it every few moves, and
  // its play is taken up whole or in part. The probes after such a change are bounded by
  // what the change can switch (VariationBound::direction_change), not evaluated each time,
  // and the maximum is still exactly that of evaluating them all.
  const Pass pass = finishing_pass(10, [](int k) { return k % 6 < 3 ? 1.0 : k % 6 == 3 ? 0.4 : -1.0; });
  EXPECT_EQ(pass.skipping, pass.all);
  EXPECT_GT(pass.approach_changes, pass.probes / 4);
  EXPECT_LT(pass.evaluated, pass.probes / 4) << "a probe after an approach change is bounded as any other";
}

TEST(ErrorBefore, TheChainsZeroIsAPointLikeAnyOther) {
  // Nominal tips are remembered by chain values; a remembered slot never filled must not
  // stand for the chain's zero (machine zero, no tool length): its error there is the
  // model's, micrometres, not the distance to a tip at the origin.
  const model::MachineModel mm =
      model::load_machine_model(std::string(CCOMP_SOURCE_DIR) + "/samples/machines/vmc-xyz.yaml");
  const model::ForwardModel m(mm);
  // Built in zeroed memory, as a fresh heap page is: what an uninitialised slot would hold.
  alignas(Compensator) static unsigned char storage[sizeof(Compensator)];
  std::memset(storage, 0, sizeof storage);
  Compensator* c = new (storage) Compensator(m, CompensationOptions{});
  const model::ChainQ zero = model::ChainQ::Zero();
  model::ForwardData d(m);
  model::forward(m, d, zero, CompensationOptions{}.conditions, false, model::Evaluate::both);
  EXPECT_NEAR(c->error_at(zero), (d.actual - d.nominal).norm(), 1e-12);
  EXPECT_LT(c->error_at(zero), 0.01);
  c->~Compensator();
}

}  // namespace
}  // namespace ccomp::compensate
