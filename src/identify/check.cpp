#include "ccomp/identify/check.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <utility>
#include <tuple>

#include "ccomp/identify/fit.hpp"

namespace ccomp::identify {

CheckReport check(const model::ForwardModel& model, const MeasurementSet& data) {
  CheckReport report;
  const Eigen::VectorXd r = residuals(model, model.machine().terms.empty() ? Eigen::VectorXd() : [&] {
    Eigen::VectorXd p(static_cast<Eigen::Index>(model.parameter_count()));
    for (std::size_t t = 0; t < model.machine().terms.size(); ++t)
      p.segment(static_cast<Eigen::Index>(model.parameter_offset(t)), model.machine().terms[t].parameters.size()) =
          model.machine().terms[t].parameters;
    return p;
  }(), data);
  report.observations = data.observations.size();
  report.residual = r;
  report.sources.resize(data.sources.size());
  for (std::size_t s = 0; s < data.sources.size(); ++s) report.sources[s].source = data.sources[s];
  double sum2 = 0.0;
  for (std::size_t i = 0; i < data.observations.size(); ++i) {
    const Observation& o = data.observations[i];
    const double e = r[static_cast<Eigen::Index>(i)];
    sum2 += e * e;
    SourceResidual& s = report.sources[o.source];
    ++s.observations;
    s.rms += e * e;
    s.max = std::max(s.max, std::abs(e));
    if (std::abs(e) > report.max)
      report.max = std::abs(e), report.worst_row = o.row, report.worst_file = data.files[o.file];
  }
  for (SourceResidual& s : report.sources)
    s.rms = s.observations ? std::sqrt(s.rms / static_cast<double>(s.observations)) : 0.0;
  report.rms = data.observations.empty() ? 0.0 : std::sqrt(sum2 / static_cast<double>(data.observations.size()));
  const NoiseFloor noise = noise_floor(data, r);
  report.noise_floor = noise.value;
  report.noise_method = noise.method;
  return report;
}

namespace {

/// rad: the longest rotary step a run's second differences take (30 degrees: a once- or
/// twice-a-turn error then leaves under a quarter, resp. under its whole amplitude).
constexpr double kLongestRotaryStep = 30.0 * std::numbers::pi / 180.0;

/// Readings a, b, c along one run: a line (the steps along one direction, one way), or the
/// rotary axes stepping one way with the linear axes following smoothly (a point on the
/// table kept under the probe as it turns: its positions lie on a circle), the time moving
/// with them. Their steps h1, h2 along it (mm, rad), or none. ISO 230-2's irregular targets
/// space them unevenly; the combination below cancels a straight line whatever the steps.
std::optional<std::pair<double, double>> run_steps(const Observation& a, const Observation& b, const Observation& c) {
  const model::ChainQ step1 = b.q - a.q, step2 = c.q - b.q;
  const auto turn1 = step1.segment<3>(3), turn2 = step2.segment<3>(3);
  const bool turning = turn1.norm() > 0 || turn2.norm() > 0;
  model::ChainQ travel1 = step1, travel2 = step2;
  if (turning) travel1.segment<3>(3).setZero(), travel2.segment<3>(3).setZero();
  const double h1 = turning ? turn1.norm() : step1.norm(), h2 = turning ? turn2.norm() : step2.norm();
  if (!(h1 > 0 && h2 > 0) || h2 > 3 * h1 || h1 > 3 * h2) return std::nullopt;
  // A turn of a quarter of a revolution is no step a smooth error cancels over: the table's
  // own once-a-turn error leaves twice its amplitude in the second difference at 90 degrees.
  if (turning && std::max(h1, h2) > kLongestRotaryStep) return std::nullopt;
  if (std::abs((c.time - b.time) * h1 - (b.time - a.time) * h2) > 1e-6 * (1.0 + std::abs(c.time)) * (h1 + h2))
    return std::nullopt;
  if (!turning) {
    if ((step2 / h2 - step1 / h1).norm() > 1e-6) return std::nullopt;
  } else {
    if ((turn2 / h2 - turn1 / h1).norm() > 1e-6) return std::nullopt;
    // On a circle turned by d, the steps' directions differ by d (up to 0.5 rad).
    if ((travel2 / h2 - travel1 / h1).norm() > 0.5 * travel1.norm() / h1 + 1e-6) return std::nullopt;
  }
  return std::pair{h1, h2};
}

}  // namespace

NoiseFloor noise_floor(const MeasurementSet& data, const Eigen::VectorXd& r) {
  NoiseFloor report;
  // Repeated points: the same position (to 1 um), direction, approach and conditions.
  using Key = std::tuple<long long, long long, long long, long long, long long, long long, long long, long long,
                         long long, long long, long long>;
  std::map<Key, std::vector<double>> groups;
  for (std::size_t i = 0; i < data.observations.size(); ++i) {
    const Observation& o = data.observations[i];
    auto k = [](double v, double unit) { return static_cast<long long>(std::llround(v / unit)); };
    // Every rotary axis (a trunnion's A as well as a table's B) and its approach.
    groups[Key{k(o.q[0], 1e-3), k(o.q[1], 1e-3), k(o.q[2], 1e-3), k(o.q[3], 1e-8), k(o.q[4], 1e-8), k(o.q[5], 1e-8),
               k(o.q[static_cast<Eigen::Index>(model::kToolLengthIndex)], 1e-3),
               k(o.direction.x() + 2 * o.direction.y() + 4 * o.direction.z(), 1e-6),
               k(o.directions[0] + 3 * o.directions[1] + 9 * o.directions[2] + 27 * o.directions[3] +
                     81 * o.directions[4] + 243 * o.directions[5],
                 1.0),
               k(o.time, 1.0), static_cast<long long>(o.source)}]
        .push_back(r[static_cast<Eigen::Index>(i)]);
  }
  double pooled = 0.0, dof = 0.0;
  for (const auto& [key, values] : groups) {
    if (values.size() < 2) continue;
    double mean = 0.0;
    for (double v : values) mean += v;
    mean /= static_cast<double>(values.size());
    for (double v : values) pooled += (v - mean) * (v - mean);
    dof += static_cast<double>(values.size() - 1);
  }
  if (dof >= 10) {
    report.value = std::sqrt(pooled / dof);
    report.method = "repeated points";
    return report;
  }
  // Second differences of residuals at evenly spaced points along a run (a laser line, a
  // row of a grid, a sphere probed at even angles of a rotary axis): a smooth model error
  // nearly cancels in them, independent noise of sigma leaves sigma * sqrt(6). Each
  // source's readings along one direction and one approach are a series of their own; in
  // it, a reading's run is the nearest lag (readings of several points interleaved, as
  // spheres probed in turn at each angle) whose steps are even.
  constexpr std::size_t kLags = 8;
  std::map<std::tuple<std::uint32_t, long long, long long>, std::vector<std::size_t>> series;
  std::vector<double> seconds;
  for (std::size_t i = 0; i < data.observations.size(); ++i) {
    const Observation& o = data.observations[i];
    const long long direction = std::llround((o.direction.x() + 3 * o.direction.y() + 9 * o.direction.z()) * 1e6);
    long long approach = 0;
    for (std::size_t a = 0, weight = 1; a < 6; ++a, weight *= 3) approach += o.directions[a] * static_cast<long long>(weight);
    std::vector<std::size_t>& last = series[{o.source, direction, approach}];  // up to 2 kLags previous readings
    for (std::size_t lag = 1; lag <= kLags && 2 * lag <= last.size(); ++lag) {
      const std::size_t a = last[last.size() - 2 * lag], b = last[last.size() - lag];
      const auto h = run_steps(data.observations[a], data.observations[b], o);
      if (!h) continue;
      // h2 r_a - (h1 + h2) r_b + h1 r_c: zero on a straight line, sigma times the norm of
      // its weights for noise (sqrt(6) h for even steps).
      const auto [h1, h2] = *h;
      const double second = h2 * r[static_cast<Eigen::Index>(a)] - (h1 + h2) * r[static_cast<Eigen::Index>(b)] +
                            h1 * r[static_cast<Eigen::Index>(i)];
      seconds.push_back(std::abs(second) / std::sqrt(h1 * h1 + h2 * h2 + (h1 + h2) * (h1 + h2)));
      break;
    }
    if (last.size() == 2 * kLags) last.erase(last.begin());
    last.push_back(i);
  }
  // The median, not the mean: where the error bends sharply (a table turning) the second
  // difference is not noise, and those few places must not set the floor.
  if (seconds.size() >= 10) {
    std::nth_element(seconds.begin(), seconds.begin() + static_cast<std::ptrdiff_t>(seconds.size() / 2), seconds.end());
    report.value = 1.4826 * seconds[seconds.size() / 2];
    report.method = "second differences along lines";
  } else {
    report.method = "none: no repeated points and no evenly spaced lines in the data";
  }
  return report;
}

}  // namespace ccomp::identify
