#include "scanners.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <utility>

namespace ccomp::identify::detail {
namespace {

using Spacing = Candidate::Spacing;

/// A sinusoid's gain (the fall in the sum of squares when its cos and sin columns g cos,
/// g sin join, leaving out what the base absorbs) at `count` evenly spaced frequencies
/// f0 + k df of `variable`, for the residual r. Each row's (cos, sin) turns by one
/// rotation per frequency. Rows are taken a block at a time through all frequencies: the
/// block stays in the first-level cache, the rows are read from memory once.
std::vector<double> coarse_periodic_gains(const std::vector<double>& variable, const std::vector<double>& g,
                                          const Eigen::VectorXd& r, double f0, double df, std::size_t count) {
  const auto rows = static_cast<Eigen::Index>(variable.size());
  Eigen::ArrayXd cs(rows), sn(rows), step_c(rows), step_s(rows), gr(rows), g2(rows);
  for (Eigen::Index i = 0; i < rows; ++i) {
    const double v = variable[static_cast<std::size_t>(i)], gi = g[static_cast<std::size_t>(i)];
    cs[i] = std::cos(2 * std::numbers::pi * v * f0), sn[i] = std::sin(2 * std::numbers::pi * v * f0);
    step_c[i] = std::cos(2 * std::numbers::pi * v * df), step_s[i] = std::sin(2 * std::numbers::pi * v * df);
    gr[i] = gi * r[i];
    g2[i] = gi * gi;
  }
  // Per frequency: g r cos, g r sin, g^2 cos^2, g^2 cos sin, g^2 sin^2, summed.
  std::vector<std::array<double, 5>> sums(count, std::array<double, 5>{});
  constexpr Eigen::Index kBlock = 256;
  Eigen::ArrayXd turned(kBlock);
  for (Eigen::Index begin = 0; begin < rows; begin += kBlock) {
    const Eigen::Index size = std::min(kBlock, rows - begin);
    auto c = cs.segment(begin, size), s = sn.segment(begin, size);
    const auto sc = step_c.segment(begin, size), ss = step_s.segment(begin, size);
    const auto w = gr.segment(begin, size), w2 = g2.segment(begin, size);
    auto t = turned.head(size);
    for (std::size_t k = 0; k < count; ++k) {
      std::array<double, 5>& sum = sums[k];
      sum[0] += (w * c).sum(), sum[1] += (w * s).sum();
      sum[2] += (w2 * c.square()).sum(), sum[3] += (w2 * c * s).sum(), sum[4] += (w2 * s.square()).sum();
      t = c * sc - s * ss;
      s = s * sc + c * ss;
      c = t;
    }
  }
  std::vector<double> gains(count);
  for (std::size_t k = 0; k < count; ++k) {
    const auto& [b0, b1, n00, n01, n11] = sums[k];
    const double det = n00 * n11 - n01 * n01;
    gains[k] = det > 1e-12 * n00 * n11 ? (n11 * b0 * b0 - 2 * n01 * b0 * b1 + n00 * b1 * b1) / det : 0.0;
  }
  return gains;
}

/// A scan under way: the candidate, its probe's rows and the residual on them.
struct Scan {
  const Candidate& c;
  const Probe& p;
  const ScanContext& context;
  bool all_rows;
  const Eigen::VectorXd& r_rows;

  /// The exact gains at `values`; the coefficients at the first of them into `x`, a few
  /// values at a time in one product.
  std::vector<double> exact_gains(const std::vector<double>& values, Eigen::VectorXd* x) const {
    const Projector& base = context.base;
    const int bc = c.basis_count;
    Eigen::MatrixXd C(static_cast<Eigen::Index>(p.rows.size()), static_cast<Eigen::Index>(values.size()) * bc);
    for (std::size_t v = 0; v < values.size(); ++v)
      candidate_columns(c, p, context.data, values[v], false, C.middleCols(static_cast<Eigen::Index>(v) * bc, bc));
    const Eigen::MatrixXd AtC = all_rows ? Eigen::MatrixXd(base.A.transpose() * C) : base.At_on_rows(p.rows, C);
    std::vector<double> gains(values.size());
    for (std::size_t v = 0; v < values.size(); ++v) {
      const Eigen::Index first = static_cast<Eigen::Index>(v) * bc;
      gains[v] = base.gain(C.middleCols(first, bc), r_rows, AtC.middleCols(first, bc), v == 0 ? x : nullptr);
    }
    return gains;
  }

  /// The coarse gains' eight best local peaks weighed exactly; only they compete (the
  /// coarse gains elsewhere are not comparable).
  void keep_exact_peaks(const std::vector<double>& values, std::vector<double>& gains) const {
    std::vector<std::pair<double, std::size_t>> peaks;
    for (std::size_t k = 0; k < gains.size(); ++k)
      if ((k == 0 || gains[k] >= gains[k - 1]) && (k + 1 == gains.size() || gains[k] >= gains[k + 1]))
        peaks.emplace_back(-gains[k], k);
    std::sort(peaks.begin(), peaks.end());
    if (peaks.size() > 8) peaks.resize(8);
    std::vector<double> peak_values;
    for (const auto& peak : peaks) peak_values.push_back(values[peak.second]);
    const std::vector<double> exact = exact_gains(peak_values, nullptr);
    for (std::size_t i = 0; i < peaks.size(); ++i) gains[peaks[i].second] = exact[i];
    for (std::size_t k = 0; k < gains.size(); ++k)
      if (std::none_of(peaks.begin(), peaks.end(), [k](const auto& peak) { return peak.second == k; }))
        gains[k] = -1.0;
  }
};

/// One spacing of the scanned values: the value at a fraction f of the scan, and the
/// coarse pass that weighs all of them.
struct Scanner {
  double (*value_at)(const Candidate& c, double f);
  std::vector<double> (*coarse_gains)(const Scan& scan, const std::vector<double>& values);
};

/// Periods: evenly in frequency, so that each step shifts the phase at the far end by the
/// same amount.
double frequency_value(const Candidate& c, double f) {
  return 1.0 / (1.0 / c.scan_from + f * (1.0 / c.scan_to - 1.0 / c.scan_from));
}

/// A long frequency scan's coarse pass leaves out what the base absorbs (cheap); its eight
/// best local peaks are then weighed exactly. The frequencies are evenly spaced, so each
/// row's (cos, sin) steps by one rotation per frequency. Without a phase variable, exactly.
std::vector<double> frequency_gains(const Scan& scan, const std::vector<double>& values) {
  if (!scan.c.phase_variable) return scan.exact_gains(values, nullptr);
  const Probe& p = scan.p;
  std::vector<double> phase_variable(p.rows.size()), g(p.rows.size());
  for (std::size_t i = 0; i < p.rows.size(); ++i) {
    phase_variable[i] = scan.c.phase_variable(scan.context.data.observations[static_cast<std::size_t>(p.rows[i])]);
    g[i] = p.g[p.rows[i]];
  }
  std::vector<double> gains = coarse_periodic_gains(phase_variable, g, scan.r_rows, 1.0 / values[0],
                                                    1.0 / values[1] - 1.0 / values[0], values.size());
  scan.keep_exact_peaks(values, gains);
  return gains;
}

/// Time constants: evenly in log, weighed exactly (a short scan).
double logarithmic_value(const Candidate& c, double f) { return c.scan_from * std::pow(c.scan_to / c.scan_from, f); }

std::vector<double> exact_gains(const Scan& scan, const std::vector<double>& values) {
  return scan.exact_gains(values, nullptr);
}

/// Places along an axis: evenly.
double linear_value(const Candidate& c, double f) { return c.scan_from + f * (c.scan_to - c.scan_from); }

/// A local defect: the coarse pass weighs each place by its column's correlation with the
/// residual alone (a bell is local: what the base absorbs of it is small), and its eight
/// best local peaks are then weighed exactly. The rows by their place, so that each scanned
/// place reads only the rows it reaches.
std::vector<double> place_gains(const Scan& scan, const std::vector<double>& values) {
  const Candidate& c = scan.c;
  const Probe& p = scan.p;
  const MeasurementSet& data = scan.context.data;
  std::vector<std::pair<double, Eigen::Index>> by_place;
  for (const Eigen::Index row : p.rows)
    by_place.emplace_back(c.phase_variable(data.observations[static_cast<std::size_t>(row)]), row);
  std::sort(by_place.begin(), by_place.end());
  std::vector<double> gains(values.size());
  for (std::size_t k = 0; k < values.size(); ++k) {
    double cr = 0.0, cc = 0.0;
    auto it = std::lower_bound(by_place.begin(), by_place.end(), std::pair{values[k] - c.reach, Eigen::Index{-1}});
    for (; it != by_place.end() && it->first <= values[k] + c.reach; ++it) {
      const Eigen::Index row = it->second;
      const double column = p.g[row] * c.basis(data.observations[static_cast<std::size_t>(row)], 0, values[k]);
      cr += column * scan.context.base.r[row];
      cc += column * column;
    }
    gains[k] = cc > 0 ? cr * cr / cc : 0.0;
  }
  scan.keep_exact_peaks(values, gains);
  return gains;
}

/// In Spacing's order.
constexpr std::array<Scanner, 3> kScanners{{
    {frequency_value, frequency_gains},
    {logarithmic_value, exact_gains},
    {linear_value, place_gains},
}};

const Scanner& scanner(Spacing spacing) { return kScanners[static_cast<std::size_t>(spacing)]; }

}  // namespace

std::optional<ScanOutcome> scan(const Candidate& c, const ScanContext& context) {
  const Probe& p = context.probes[c.probe];
  if (p.rows.empty()) return std::nullopt;
  const bool all_rows = static_cast<Eigen::Index>(p.rows.size()) == context.base.r.size();
  const Scan s{c, p, context, all_rows, all_rows ? context.base.r : p.r_rows};
  const Scanner& by = scanner(c.scan_spacing);
  std::vector<double> values(static_cast<std::size_t>(c.scan_points));
  for (std::size_t k = 0; k < values.size(); ++k)
    values[k] = by.value_at(c, static_cast<double>(k) / static_cast<double>(values.size() - 1));
  const std::vector<double> gains = by.coarse_gains(s, values);
  const auto top = static_cast<std::size_t>(std::max_element(gains.begin(), gains.end()) - gains.begin());
  // Refining moves the peak by less than half a step, which raises its gain by a quarter
  // at most: a candidate that could not pass with twice its gain is not refined (it is not
  // suggested either way).
  const double sigma2 = context.sigma2;
  const double trials = static_cast<double>(values.size());
  const auto parameters = static_cast<double>(c.basis_count + 1);
  if (2.0 * gains[top] / sigma2 - parameters - 2.0 * std::log(trials) <= kSignificance) return std::nullopt;
  // Refine between the neighbours on a grid, three times narrower each round, and put the
  // peak on the parabola through the best point and its neighbours.
  double lo = values[top > 0 ? top - 1 : top], hi = values[top + 1 < values.size() ? top + 1 : top];
  if (lo > hi) std::swap(lo, hi);
  constexpr int kGrid = 12;
  std::vector<double> grid(kGrid), grid_gains;
  std::size_t best = 0;
  for (int round = 0; round < 3; ++round) {
    for (int j = 0; j < kGrid; ++j) grid[static_cast<std::size_t>(j)] = lo + (hi - lo) * j / (kGrid - 1);
    grid_gains = s.exact_gains(grid, nullptr);
    best = static_cast<std::size_t>(std::max_element(grid_gains.begin(), grid_gains.end()) - grid_gains.begin());
    lo = grid[best > 0 ? best - 1 : best], hi = grid[std::min<std::size_t>(best + 1, kGrid - 1)];
  }
  ScanOutcome out;
  out.value = grid[best];
  if (best > 0 && best + 1 < kGrid) {
    const double bend = grid_gains[best - 1] - 2 * grid_gains[best] + grid_gains[best + 1];
    if (bend < 0) out.value += 0.5 * (grid[1] - grid[0]) * (grid_gains[best - 1] - grid_gains[best + 1]) / bend;
  }
  // The gain and coefficients there, and the uncertainty from the curvature of the sum of
  // squares (a chi-square rise of 1). A place along an axis is as precise at 0 as
  // anywhere: its step is the scan's range's.
  const double value = out.value;
  const double h = c.scan_spacing == Spacing::linear || value == 0.0 ? 1e-4 * std::abs(c.scan_to - c.scan_from)
                                                                       : 1e-4 * std::abs(value);
  const std::vector<double> last = s.exact_gains({value, value + h, value - h}, &out.coefficients);
  const double curvature = (2 * last[0] - last[1] - last[2]) / (h * h);
  out.gain = last[0];
  out.uncertainty = curvature > 0 ? std::sqrt(2.0 * sigma2 / curvature) : 0.0;
  out.trials = trials;
  return out;
}

}  // namespace ccomp::identify::detail
