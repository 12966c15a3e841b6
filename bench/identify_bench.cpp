// Speed of identification: a fit of 100,000 observations with 300 free parameters, and the
// diagnosis of the whole candidate library on the same data. Prints seconds for each
// (targets: under 2 s and 5 s on this project's 2-core machines).
//   ccomp_bench_identify [observations] [parameters-per-motion]
#include <fmt/format.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <random>
#include <string>

#include "ccomp/identify/diagnose.hpp"
#include "ccomp/identify/fit.hpp"
#include "ccomp/model/model_file.hpp"

namespace {

/// The sample HMC's axes and chains (everything before its terms), to which the bench
/// adds terms of its own.
std::string sample_chain() {
  std::ifstream in(CCOMP_SOURCE_DIR "/samples/machines/hmc-xyzb-geometric.yaml");
  std::string text, line;
  while (std::getline(in, line) && line != "terms:") text += line + "\n";
  return text + "terms:\n";
}

/// The 18 error motions of X, Y, Z as laser-run tables of `knots` values each, and the 12
/// table errors as harmonics: 18 knots + 12 x 2 parameters, all free.
std::string model_text(int knots, double scale) {
  std::string text = sample_chain();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  const char* axes = "XYZ";
  for (int a = 0; a < 3; ++a)
    for (const char* c : {"X", "Y", "Z", "A", "B", "C"}) {
      const double stroke = a == 1 ? 450 : 500;
      std::string at, values;
      for (int k = 0; k < knots; ++k) {
        at += fmt::format("{}{:.3f}", k ? ", " : "", -stroke + 2 * stroke * k / (knots - 1));
        values += fmt::format("{}{:.3f}", k ? ", " : "", scale * 5 * u(rng));
      }
      text += fmt::format("  - {{name: E{}{}, form: table, at: [{}], values: [{}], unit: {}, fit: true}}\n", c, axes[a],
                          at, values, std::string("XYZ").find(c[0]) != std::string::npos ? "um" : "urad");
    }
  for (const char* c : {"X", "Y", "Z", "A", "C", "B"})
    for (int h = 1; h <= 2; ++h)
      text += fmt::format(
          "  - {{name: E{}B, form: periodic, period: {} deg, unit: {}, harmonics: [[{:.2f}, {:.2f}]], fit: true}}\n", c,
          360 / h, std::string("XYZ").find(c[0]) != std::string::npos ? "um" : "urad", scale * 3 * u(rng),
          scale * 3 * u(rng));
  return text;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  const int observations = argc > 1 ? std::atoi(argv[1]) : 100000;
  const int knots = argc > 2 ? std::atoi(argv[2]) : 15;
  const ccomp::model::MachineModel truth = ccomp::model::parse_machine_model(model_text(knots, 1.0), "truth");
  const ccomp::model::MachineModel start = ccomp::model::parse_machine_model(model_text(knots, 0.0), "start");
  const ccomp::model::ForwardModel t(truth), s(start);
  // Readings at random points, directions and table angles, 0.2 um of noise.
  ccomp::identify::MeasurementSet data;
  data.files = {"bench"};
  data.sources = {"random"};
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1, 1);
  std::normal_distribution<double> noise(0, 0.0002);
  ccomp::model::ForwardData d(t);
  for (int i = 0; i < observations; ++i) {
    ccomp::identify::Observation o;
    o.q << 480 * u(rng), 430 * u(rng), 480 * u(rng), 0, 3.1 * u(rng), 0, 0, 0, 0, 100 + 100 * u(rng);
    o.q[2] += o.q[9];
    o.direction = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    o.value = ccomp::identify::predict(t, d, o) + noise(rng);
    o.row = static_cast<std::uint32_t>(i + 2);
    data.observations.push_back(o);
  }
  fmt::print("identification, {} observations, {} free parameters:\n", observations,
             ccomp::identify::free_parameters(s).size());
  auto t0 = std::chrono::steady_clock::now();
  const ccomp::identify::FitReport r = ccomp::identify::fit(s, data);
  fmt::print("  fit       {:7.2f} s  ({} iterations, rms {:.3f} -> {:.3f} um, {} combinations identified)\n",
             seconds_since(t0), r.iterations, r.rms_before * 1e3, r.rms_after * 1e3, r.rank);
  t0 = std::chrono::steady_clock::now();
  const ccomp::identify::Diagnosis g = ccomp::identify::diagnose(t, data);
  fmt::print("  diagnose  {:7.2f} s  ({} candidates, {} suggested, noise floor {:.3f} um)\n", seconds_since(t0),
             g.candidates_tried, g.suggestions.size(), g.noise * 1e3);
  return 0;
}
