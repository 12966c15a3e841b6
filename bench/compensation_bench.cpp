// Speed of the compensation core: the inverse (points/s) and the forward model with its
// Jacobians, on the full 46-term sample HMC.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "ccomp/compensate/inverse.hpp"
#include "ccomp/model/forward.hpp"

namespace {

const ccomp::model::ForwardModel& model() {
  static const ccomp::model::MachineModel m =
      ccomp::model::load_machine_model(CCOMP_SOURCE_DIR "/samples/machines/hmc-xyzb.yaml");
  static const ccomp::model::ForwardModel f(m);
  return f;
}

std::vector<ccomp::model::ChainQ> poses(int n) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<ccomp::model::ChainQ> out;
  for (int i = 0; i < n; ++i) {
    ccomp::model::ChainQ q = ccomp::model::ChainQ::Zero();
    q << 400 * u(rng), 350 * u(rng), 300 * u(rng), 0, 3 * u(rng), 0, 0, 0, 0, 100;
    out.push_back(q);
  }
  return out;
}

ccomp::model::Conditions conditions() {
  ccomp::model::Conditions c;
  c.temperatures = {24, 23, 31};
  c.time = 3600;
  return c;
}

void Inverse(benchmark::State& state) {
  const auto& m = model();
  const ccomp::compensate::InverseProblem problem(m);
  ccomp::model::ForwardData d(m);
  const auto qs = poses(1000);
  const auto c = conditions();
  std::size_t i = 0;
  for (auto _ : state) {
    const auto r = ccomp::compensate::solve_inverse(m, problem, d, qs[i++ % qs.size()], c);
    benchmark::DoNotOptimize(r.q);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(Inverse)->Unit(benchmark::kMicrosecond);

/// The inverse as the job uses it: points 0.05 mm apart along a finishing pass, solved
/// through one workspace (a Jacobian reused and updated along the path, solutions predicted).
void InverseAlongAPath(benchmark::State& state) {
  const auto& m = model();
  const ccomp::compensate::InverseProblem problem(m);
  ccomp::model::ForwardData d(m);
  ccomp::compensate::InverseWorkspace ws;
  const auto c = conditions();
  std::size_t i = 0;
  for (auto _ : state) {
    const double s = 0.05 * static_cast<double>(i++ % 16000);  // 800 mm, then back to the start
    ccomp::model::ChainQ q = ccomp::model::ChainQ::Zero();
    q << -400 + s, 20, -1 + 0.3 * std::sin(s / 40), 0, 0, 0, 0, 0, 0, 100;
    const auto r = ccomp::compensate::solve_inverse(m, problem, d, q, c, {}, nullptr, &ws);
    benchmark::DoNotOptimize(r.q);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
  state.counters["jacobians_per_point"] =
      static_cast<double>(ws.jacobian_evaluations) / static_cast<double>(std::max<std::int64_t>(state.iterations(), 1));
}
BENCHMARK(InverseAlongAPath)->Unit(benchmark::kMicrosecond);

void ForwardWithJacobians(benchmark::State& state) {
  const auto& m = model();
  ccomp::model::ForwardData d(m);
  const auto qs = poses(1000);
  const auto c = conditions();
  std::size_t i = 0;
  for (auto _ : state) {
    ccomp::model::forward(m, d, qs[i++ % qs.size()], c, state.range(0) != 0);
    benchmark::DoNotOptimize(d.actual);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(ForwardWithJacobians)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
