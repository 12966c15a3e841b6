#include "ccomp/identify/fit_information.hpp"

#include <algorithm>
#include <cmath>
#include <array>
#include <map>
#include <set>

#include "ccomp/axis.hpp"
#include "ccomp/constants.hpp"

namespace ccomp::identify {
namespace {

/// A reading's value of chain variable `index` as the file writes it: mm, deg.
double value_of(const Observation& o, std::size_t index, bool rotary) {
  const double v = o.q[static_cast<Eigen::Index>(index)];
  return rotary ? v / kRadPerDeg : v;
}

/// The bins' edges of one variable: `bins` equal stretches of [from, to].
std::vector<model::CoverageBin> empty_bins(double from, double to, int bins) {
  std::vector<model::CoverageBin> out;
  for (int k = 0; k < bins; ++k)
    out.push_back({from + (to - from) * k / bins, from + (to - from) * (k + 1) / bins, {}});
  return out;
}

model::AxisCoverage coverage_along(const MeasurementSet& data, char letter, std::size_t index, bool rotary,
                                   double limit_min, double limit_max) {
  model::AxisCoverage c;
  c.axis = letter;
  c.rotary = rotary;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Observation& o : data.observations) {
    const double v = value_of(o, index, rotary);
    lo = std::min(lo, v), hi = std::max(hi, v);
  }
  if (data.observations.empty()) lo = hi = 0.0;
  c.from = lo, c.to = hi;
  // A turn that may go all the way round is binned over the turn; a limited one (a
  // trunnion) and a linear axis over its limits, else over the data.
  const bool whole_turn = rotary && !(std::isfinite(limit_min) && std::isfinite(limit_max) && limit_max - limit_min < 360);
  double from = whole_turn ? 0.0 : (std::isfinite(limit_min) ? limit_min : lo);
  double to = whole_turn ? 360.0 : (std::isfinite(limit_max) ? limit_max : hi);
  if (!(to > from)) from -= 0.5, to += 0.5;
  c.bins = empty_bins(from, to, letter == 'L' ? kToolLengthBins : rotary ? kRotaryBins : kLinearBins);
  std::vector<std::map<std::uint32_t, std::size_t>> counts(c.bins.size());
  std::vector<std::set<std::array<long, 3>>> places(c.bins.size());
  for (const Observation& o : data.observations) {
    double v = value_of(o, index, rotary);
    if (whole_turn) v = v - 360.0 * std::floor(v / 360.0);
    const double f = (v - from) / (to - from) * static_cast<double>(c.bins.size());
    const auto k = static_cast<std::size_t>(std::clamp(f, 0.0, static_cast<double>(c.bins.size()) - 0.5));
    ++counts[k][o.source];
    places[k].insert({std::lround(o.q[0]), std::lround(o.q[1]), std::lround(o.q[2])});
  }
  for (std::size_t k = 0; k < c.bins.size(); ++k) {
    for (const auto& [source, n] : counts[k]) c.bins[k].readings.emplace_back(data.sources[source], n);
    c.bins[k].points = places[k].size();
  }
  return c;
}

}  // namespace

std::vector<model::AxisCoverage> coverage_of(const model::MachineModel& machine, const MeasurementSet& data) {
  std::vector<model::AxisCoverage> out;
  for (const model::AxisSpec& a : machine.axes)
    out.push_back(coverage_along(data, a.letter, a.index(), a.type == model::AxisType::rotary, a.min,
                                 a.max));
  out.push_back(coverage_along(data, 'L', model::kToolLengthIndex, false, -std::numeric_limits<double>::infinity(),
                               std::numeric_limits<double>::infinity()));
  return out;
}

model::FitInformation fit_information(const model::ForwardModel& model, const MeasurementSet& data,
                                      const FitReport& report) {
  model::FitInformation info;
  info.observations = report.observations;
  info.noise = report.noise;
  // What the fit leaves beyond the noise: a missing effect, which no covariance holds.
  info.excess = std::sqrt(std::max(0.0, report.rms_after * report.rms_after - report.noise * report.noise));
  for (const FittedParameter& p : report.parameters)
    info.parameters.push_back({p.term, p.index - model.parameter_offset(p.term), p.label});
  info.covariance_factor = report.covariance_factor;
  info.coverage = coverage_of(model.machine(), data);
  return info;
}

}  // namespace ccomp::identify
