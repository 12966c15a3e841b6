// Speed of the compensation core: the inverse (points/s) and the forward model with its
// Jacobians, on the full 46-term sample HMC, and with laser tables of X Y Z added.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "ccomp/compensate/inverse.hpp"
#include "ccomp/model/forward.hpp"
#include "ccomp/model/model_file.hpp"

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

/// The sample HMC with cubic laser tables of `knots` values added to EXX, EYY and EZZ:
/// a table's cost must not grow with its length once its spline is solved.
ccomp::model::MachineModel with_laser_tables(int knots) {
  std::ifstream in(CCOMP_SOURCE_DIR "/samples/machines/hmc-xyzb.yaml");
  std::stringstream text;
  text << in.rdbuf();
  for (const char* name : {"EXX", "EYY", "EZZ"}) {
    text << "  - {name: " << name << ", form: table, interpolation: cubic, unit: um, at: [";
    for (int k = 0; k < knots; ++k) text << (k ? ", " : "") << -500.0 + 1000.0 * k / (knots - 1);
    text << "], values: [";
    for (int k = 0; k < knots; ++k) text << (k ? ", " : "") << 2.0 * std::sin(0.7 * k);
    text << "]}\n";
  }
  return ccomp::model::parse_machine_model(text.str(), "hmc-with-laser-tables");
}

void ForwardWithLaserTables(benchmark::State& state) {
  const ccomp::model::MachineModel mm = with_laser_tables(static_cast<int>(state.range(0)));
  const ccomp::model::ForwardModel m(mm);
  ccomp::model::ForwardData d(m);
  const auto qs = poses(1000);
  const auto c = conditions();
  std::size_t i = 0;
  for (auto _ : state) {
    ccomp::model::forward(m, d, qs[i++ % qs.size()], c);
    benchmark::DoNotOptimize(d.actual);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(ForwardWithLaserTables)->Arg(11)->Arg(41)->Arg(201)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
