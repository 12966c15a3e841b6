#include "ccomp/identify/check.hpp"

#include <algorithm>
#include <cmath>
#include <map>
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
  // Second differences of residuals at evenly spaced points along a line (a laser run, a
  // row of a grid): a smooth model error nearly cancels in them, independent noise of
  // sigma leaves sigma * sqrt(6). Each source's readings along one direction and one
  // approach are a series of their own.
  struct Series {
    std::vector<std::size_t> last;  // up to the two previous observations
  };
  std::map<std::tuple<std::uint32_t, long long, long long>, Series> series;
  std::vector<double> seconds;
  for (std::size_t i = 0; i < data.observations.size(); ++i) {
    const Observation& o = data.observations[i];
    const long long direction = std::llround((o.direction.x() + 3 * o.direction.y() + 9 * o.direction.z()) * 1e6);
    const long long approach =
        std::llround(o.directions[0] + 3 * o.directions[1] + 9 * o.directions[2] + 27 * o.directions[4]);
    Series& s = series[{o.source, direction, approach}];
    if (s.last.size() == 2) {
      const Observation& a = data.observations[s.last[0]];
      const Observation& b = data.observations[s.last[1]];
      const model::ChainQ step1 = b.q - a.q, step2 = o.q - b.q;
      const bool even = step1.norm() > 0 && (step2 - step1).norm() <= 1e-6 * (1.0 + step1.norm()) &&
                        std::abs(o.time - 2 * b.time + a.time) <= 1e-6 * (1.0 + std::abs(o.time));
      if (even) {
        const double second = r[static_cast<Eigen::Index>(s.last[0])] - 2 * r[static_cast<Eigen::Index>(s.last[1])] +
                              r[static_cast<Eigen::Index>(i)];
        seconds.push_back(std::abs(second));
      }
      s.last.erase(s.last.begin());
    }
    s.last.push_back(i);
  }
  // The median, not the mean: where the error bends sharply (a table turning) the second
  // difference is not noise, and those few places must not set the floor.
  if (seconds.size() >= 10) {
    std::nth_element(seconds.begin(), seconds.begin() + static_cast<std::ptrdiff_t>(seconds.size() / 2), seconds.end());
    report.value = 1.4826 * seconds[seconds.size() / 2] / std::sqrt(6.0);
    report.method = "second differences along lines";
  } else {
    report.method = "none: no repeated points and no evenly spaced lines in the data";
  }
  return report;
}

}  // namespace ccomp::identify
