#include "ccomp/compensate/trust.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <random>

#include "ccomp/axis.hpp"
#include "ccomp/constants.hpp"

namespace ccomp::compensate {
namespace {


std::size_t chain_index(char axis) {
  return axis == 'L' ? model::kToolLengthIndex : kAxisLetters.find(axis);
}

/// A pose's value of a coverage axis as the file writes it (mm, deg; a whole turn's modulo 360).
double coverage_value(const model::AxisCoverage& c, const model::ChainQ& q) {
  double v = q[static_cast<Eigen::Index>(chain_index(c.axis))];
  if (c.rotary) v /= kRadPerDeg;
  const bool whole_turn = c.rotary && !c.bins.empty() && c.bins.front().from == 0.0 && c.bins.back().to == 360.0;
  if (whole_turn) v -= 360.0 * std::floor(v / 360.0);
  return v;
}

std::size_t bin_of(const model::AxisCoverage& c, double v) {
  if (c.bins.empty()) return 0;
  const double from = c.bins.front().from, to = c.bins.back().to;
  const double f = (v - from) / (to - from) * static_cast<double>(c.bins.size());
  return static_cast<std::size_t>(std::clamp(f, 0.0, static_cast<double>(c.bins.size()) - 0.5));
}

/// Standard normal draws from a fixed seed: the same bound for the same program and model
/// on every machine (std::normal_distribution's algorithm is the library's own).
class Normal {
 public:
  double operator()() {
    if (spare_) {
      spare_ = false;
      return second_;
    }
    const double u1 = (static_cast<double>(engine_()) + 1.0) / 4294967297.0;
    const double u2 = static_cast<double>(engine_()) / 4294967296.0;
    const double r = std::sqrt(-2.0 * std::log(u1));
    second_ = r * std::sin(2 * std::numbers::pi * u2);
    spare_ = true;
    return r * std::cos(2 * std::numbers::pi * u2);
  }

 private:
  std::mt19937 engine_{20261128u};
  bool spare_ = false;
  double second_ = 0.0;
};

std::string readings_text(const std::map<std::string, std::size_t>& readings) {
  if (readings.empty()) return "nothing measured there";
  std::string s;
  for (const auto& [source, n] : readings) s += fmt::format("{}{} ({} readings)", s.empty() ? "" : ", ", source, n);
  return "only " + s + " measured there";
}

/// The thin stretches of one axis the program runs in: each run of consecutive thin bins
/// (model::is_thin), from the first bin of it the program visits to the last ("B 120-270:
/// only sphere (6 readings) measured there").
void thin_stretches(const model::AxisCoverage& c, const std::vector<bool>& visited, std::vector<std::string>& out) {
  std::size_t fullest = 0;
  for (const model::CoverageBin& b : c.bins) fullest = std::max(fullest, b.total());
  const auto n = c.bins.size();
  std::vector<bool> thin(n);
  for (std::size_t k = 0; k < n; ++k) thin[k] = model::is_thin(c.bins[k], fullest);
  // A whole turn's run may go over 360: start after a bin that is not thin.
  const bool whole_turn = c.rotary && n > 0 && c.bins.front().from == 0.0 && c.bins.back().to == 360.0;
  std::size_t start = 0;
  if (whole_turn) {
    while (start < n && thin[start]) ++start;
    if (start == n) start = 0;
  }
  for (std::size_t i = 0; i < n;) {
    if (!thin[(start + i) % n]) {
      ++i;
      continue;
    }
    std::size_t first = n, last = n;  // the visited bins of this run, in steps from `start`
    std::size_t end = i;
    for (; end < n && thin[(start + end) % n]; ++end)
      if (visited[(start + end) % n]) {
        if (first == n) first = end;
        last = end;
      }
    if (first != n) {
      std::map<std::string, std::size_t> readings;
      for (std::size_t j = first; j <= last; ++j)
        for (const auto& [source, count] : c.bins[(start + j) % n].readings) readings[source] += count;
      out.push_back(fmt::format("{} {:g}-{:g}: {}", c.axis, c.bins[(start + first) % n].from,
                                c.bins[(start + last) % n].to, readings_text(readings)));
    }
    i = end;
  }
}

}  // namespace

TrustGauge::TrustGauge(const model::ForwardModel& model, std::optional<model::FitInformation> info)
    : model_(model), info_(std::move(info)) {
  if (info_)
    for (const model::AxisCoverage& c : info_->coverage) {
      visited_.emplace_back(c.bins.size(), false);
      low_.push_back(std::numeric_limits<double>::infinity());
      high_.push_back(-std::numeric_limits<double>::infinity());
    }
}

void TrustGauge::add(const model::ChainQ& q, const model::Conditions& conditions, std::uint32_t line) {
  const auto& info = info_;
  if (!info) return;
  for (std::size_t a = 0; a < info->coverage.size(); ++a) {
    const model::AxisCoverage& c = info->coverage[a];
    const double v = coverage_value(c, q);
    if (!c.bins.empty()) visited_[a][bin_of(c, v)] = true;
    low_[a] = std::min(low_[a], v), high_[a] = std::max(high_[a], v);
  }
  if (seen_++ % stride_ != 0) return;
  kept_.push_back({q, conditions, line});
  if (kept_.size() >= 2 * kKeptPoses) {  // every second dropped; from now on every second taken
    for (std::size_t k = 0; k < kKeptPoses; ++k) kept_[k] = std::move(kept_[2 * k]);
    kept_.resize(kKeptPoses);
    stride_ *= 2;
  }
}

ProgramTrust TrustGauge::result() const {
  ProgramTrust t;
  const auto& info = info_;
  if (!info) return t;
  t.known = true;
  t.points = seen_;
  t.excess = info->excess;
  // Each fitted parameter's place in the model's parameter vector.
  std::vector<Eigen::Index> columns;
  for (const model::FittedParameterRef& p : info->parameters)
    columns.push_back(static_cast<Eigen::Index>(model_.parameter_offset(p.term) + p.index));
  const Eigen::MatrixXd& F = info->covariance_factor;  // rows u_k
  // Draws of the parameters' error: F^T z, z standard normal.
  Normal normal;
  Eigen::MatrixXd z(F.rows(), kSamples);
  for (Eigen::Index i = 0; i < z.size(); ++i) z.data()[i] = normal();
  const Eigen::MatrixXd draws = F.transpose() * z;  // parameters x samples
  Eigen::VectorXd worst_of_draw = Eigen::VectorXd::Zero(kSamples);
  double worst_sd = -1.0;
  model::ForwardData data(model_);
  Eigen::MatrixXd G(3, static_cast<Eigen::Index>(columns.size()));
  for (const Kept& k : kept_) {
    model::forward(model_, data, k.q, k.conditions, true);
    for (std::size_t j = 0; j < columns.size(); ++j)
      G.col(static_cast<Eigen::Index>(j)) = data.J_parameters.col(columns[j]);
    const Eigen::MatrixXd errors = G * draws;  // 3 x samples: the tip's error of each draw here
    worst_of_draw = worst_of_draw.cwiseMax(errors.colwise().norm().transpose());
    const double sd = (G * F.transpose()).norm();  // sqrt of the trace of the covariance here
    if (sd > worst_sd) worst_sd = sd, t.worst_line = k.line;
  }
  std::vector<double> sorted(worst_of_draw.data(), worst_of_draw.data() + worst_of_draw.size());
  std::sort(sorted.begin(), sorted.end());
  const double mean = worst_of_draw.size() ? worst_of_draw.mean() : 0.0;
  const double q95 = sorted.empty() ? 0.0 : sorted[static_cast<std::size_t>(0.95 * static_cast<double>(sorted.size() - 1))];
  // What the fit left beyond the noise (an effect the model lacks) is there too, of its size.
  t.expected_after = std::sqrt(mean * mean + t.excess * t.excess);
  t.after_bound = q95 + 1.96 * t.excess;
  for (std::size_t a = 0; a < info->coverage.size(); ++a) {
    const model::AxisCoverage& c = info->coverage[a];
    if (!(low_[a] <= high_[a])) continue;
    if (!c.rotary) {
      const double margin = 0.01 * std::max(c.to - c.from, 1.0);
      if (low_[a] < c.from - margin || high_[a] > c.to + margin)
        t.extrapolation.push_back(fmt::format("{} {:.6g}..{:.6g}: beyond the measured {:.6g}..{:.6g}", c.axis, low_[a],
                                              high_[a], c.from, c.to));
    }
    if (!c.bins.empty()) thin_stretches(c, visited_[a], t.extrapolation);
  }
  return t;
}

std::string trust_text(const ProgramTrust& t) {
  if (!t.known) return "no fit information: bound unknown";
  std::string s = fmt::format("expected after {:.2f} um, 95% bound {:.2f} um (largest uncertainty at line {})",
                              t.expected_after * 1e3, t.after_bound * 1e3, t.worst_line);
  if (t.excess > 0) s += fmt::format("; {:.2f} um of it the fit's residual beyond the noise", 1.96 * t.excess * 1e3);
  if (!t.extrapolation.empty()) {
    s += "; extrapolation: ";
    for (std::size_t k = 0; k < t.extrapolation.size(); ++k) s += (k ? "; " : "") + t.extrapolation[k];
  }
  return s;
}

}  // namespace ccomp::compensate
