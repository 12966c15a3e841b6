#include "ccomp/identify/diagnose.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <functional>
#include <map>
#include <numbers>
#include <optional>
#include <utility>

#include "aliasing.hpp"
#include "candidates.hpp"
#include "ccomp/error.hpp"
#include "ccomp/identify/check.hpp"
#include "ccomp/identify/fit.hpp"
#include "ccomp/identify/next_measurement.hpp"
#include "ccomp/identify/physical_scale.hpp"
#include "ccomp/model/machine.hpp"
#include "ccomp/model/model_file.hpp"
#include "ccomp/util/interval.hpp"
#include "ccomp/util/parallel.hpp"
#include "fixed_sums.hpp"
#include "held_out.hpp"
#include "origin_shift.hpp"
#include "projector.hpp"
#include "scanners.hpp"

namespace ccomp::identify {
namespace {

using detail::axes_of;
using detail::axis_name;
using detail::axis_value;
using detail::AxisInfo;
using detail::Candidate;
using detail::candidate_columns;
using detail::candidate_library;
using detail::Probe;
using detail::kSignificance;
using detail::Projector;
using detail::term_name;

/// The residual holds structure when its rms is above this many noise floors (the loop's
/// own end: a model at the noise leaves at most this).
constexpr double kStructure = 1.3;
/// A variable the residual is uneven along: a bin's rms this many times the rms everywhere.
constexpr double kUneven = 1.2;


/// A scored candidate: its suggestion, and the value and coefficients it was scored at.
struct Scored {
  Suggestion suggestion;
  double value = 0.0;
  Eigen::VectorXd coefficients;
  double gain = 0.0;  // mm^2: the fall in the sum of squares where it was fitted
};




/// The residual's rms in eight bins along every variable that varies (bins of ten readings
/// or more), each with its ratio to the rms everywhere, largest ratio first.
std::vector<Region> residual_bins(const MeasurementSet& data, const std::vector<AxisInfo>& axes,
                                  const Eigen::VectorXd& r, double overall) {
  const auto n = static_cast<Eigen::Index>(data.observations.size());
  std::vector<Region> bins;
  auto add_bins = [&](const std::string& variable, auto get) {
    util::Interval range;
    for (const Observation& o : data.observations)
      if (const double v = get(o); !std::isnan(v)) range.add(v);
    if (!(range.width() > 0)) return;
    const double lo = range.lo, hi = range.hi;
    constexpr int kBins = 8;
    std::vector<double> sum(kBins, 0.0), count(kBins, 0.0);
    for (Eigen::Index i = 0; i < n; ++i) {
      const Observation& o = data.observations[static_cast<std::size_t>(i)];
      if (std::isnan(get(o))) continue;  // a sensor this reading's file does not have
      const int bin = std::min(kBins - 1, static_cast<int>((get(o) - lo) / (hi - lo) * kBins));
      sum[static_cast<std::size_t>(bin)] += r[i] * r[i];
      count[static_cast<std::size_t>(bin)] += 1;
    }
    // Against the rms everywhere, or the bins' median if higher: where only some readings
    // vary along the variable (a laser line along Y among readings at one y), their bins all
    // stand above the rest alike, which says which readings, not where.
    std::vector<double> rms(kBins, -1.0), seen;
    for (std::size_t b = 0; b < rms.size(); ++b)
      if (count[b] >= 10) rms[b] = std::sqrt(sum[b] / count[b]), seen.push_back(rms[b]);
    if (seen.empty() || !(overall > 0)) return;
    std::nth_element(seen.begin(), seen.begin() + static_cast<std::ptrdiff_t>(seen.size() / 2), seen.end());
    const double reference = std::max(overall, seen[seen.size() / 2]);
    for (int b = 0; b < kBins; ++b) {
      const auto bi = static_cast<std::size_t>(b);
      if (rms[bi] < 0) continue;
      bins.push_back({variable, lo + (hi - lo) * b / kBins, lo + (hi - lo) * (b + 1) / kBins, rms[bi],
                      rms[bi] / reference});
    }
  };
  for (const AxisInfo& a : axes) add_bins(axis_name(a.index), [&a](const Observation& o) { return axis_value(o, a); });
  add_bins("L", [](const Observation& o) { return o.q[static_cast<Eigen::Index>(model::kToolLengthIndex)]; });
  add_bins("t", [](const Observation& o) { return o.time; });
  for (std::size_t s = 0; s < data.sensors.size(); ++s)
    add_bins("T_" + data.sensors[s],
             [s](const Observation& o) { return s < o.temperatures.size() ? o.temperatures[s] : std::nan(""); });
  std::stable_sort(bins.begin(), bins.end(), [](const Region& a, const Region& b) { return a.ratio > b.ratio; });
  return bins;
}

/// Where the residual concentrates: bins at 1.5 times the rms everywhere and 3 noise sigmas.
std::vector<Region> residual_regions(const std::vector<Region>& bins, double noise) {
  std::vector<Region> regions;
  for (const Region& g : bins)
    if (g.ratio > 1.5 && g.rms > 3 * noise && regions.size() < 8) regions.push_back(g);
  return regions;
}

/// Whether the candidate's coefficients make its term larger on the data than a machine's
/// could be (physical_scale.hpp): a nearly blind combination that the noise can push to
/// any size. Each basis function's part counts on its own.
bool implausible(const Candidate& c, const Probe& p, const MeasurementSet& data, const Scored& scored) {
  const double plausible = p.component < 3 ? kPlausibleTranslation : kPlausibleRotation;
  for (int k = 0; k < c.basis_count; ++k) {
    double largest = 0.0;
    for (const Eigen::Index row : p.rows)
      largest = std::max(largest, std::abs(c.basis(data.observations[static_cast<std::size_t>(row)], k, scored.value)));
    if (std::abs(scored.coefficients[k]) * largest > kImplausibleScales * plausible) return true;
  }
  return false;
}

/// Above this share of base directions per reading a projection's rms is not a fit's.
constexpr double kProjectionShare = 0.005;

/// The suggestion's rms and residual from a fit of the model with its spec.
void refit_with(const model::ForwardModel& model, const MeasurementSet& data, const FitOptions& options,
                Suggestion& s) {
  try {
    // The data's sensors, in the data's order, so a suggested sensor reads its own column.
    model::MachineModel machine = model.machine();
    machine.sensors = data.sensors;
    const model::ForwardModel with(model::with_terms(std::move(machine), {s.spec}, "suggestion"));
    const FitReport r = fit(with, data, options);
    if (!r.refusals.empty() || !std::isfinite(r.rms_after)) return;
    s.rms_after = r.rms_after;
    s.residual = residuals(with, r.all_parameters, data);
    s.refitted = true;
  } catch (const Error&) {
    // A spec the fit refuses keeps the projection's figures.
  }
}

/// The rms of the residual without the refit's outliers (spikes are not structure).
double rms_without_outliers(const Diagnosis& d, const MeasurementSet& data) {
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < data.observations.size(); ++i) {
    const Observation& o = data.observations[i];
    if (std::any_of(d.refit.outliers.begin(), d.refit.outliers.end(),
                    [&](const FitReport::Outlier& x) { return x.file == o.file && x.row == o.row; }))
      continue;
    sum += d.residual[static_cast<Eigen::Index>(i)] * d.residual[static_cast<Eigen::Index>(i)], ++count;
  }
  return count ? std::sqrt(sum / static_cast<double>(count)) : 0.0;
}

/// The residual's structure beyond the noise when no candidate explains it, in words
/// (`d.residual` is the refit's; `bins` its rms along each variable, largest first).
std::string unexplained_structure(const Diagnosis& d, const MeasurementSet& data, const std::vector<Region>& bins) {
  if (!d.skipped.empty() || !(rms_without_outliers(d, data) > kStructure * d.noise)) return {};
  // The variables along which it is most uneven, and its largest bin.
  std::string along;
  std::vector<std::string> seen;
  for (const Region& g : bins)
    if (g.ratio > kUneven && seen.size() < 2 && std::find(seen.begin(), seen.end(), g.variable) == seen.end()) {
      along += (seen.empty() ? " along " : " and ") + g.variable;
      seen.push_back(g.variable);
    }
  std::string text = fmt::format("unexplained structure{}: rms {:.3f} um against a noise floor of {:.3f} um", along,
                                 d.rms_refit * 1e3, d.noise * 1e3);
  if (!seen.empty())
    text += fmt::format(", largest at {} {:.4g}..{:.4g} (rms {:.3f} um)", bins.front().variable, bins.front().from,
                        bins.front().to, bins.front().rms * 1e3);
  else
    text += ", even along every variable";
  if (!d.refit.outliers.empty())
    text += fmt::format(" (and {} outlier reading(s), left out of this)", d.refit.outliers.size());
  if (d.unproven > 0)
    text +=
        fmt::format("; {} candidate(s) lowered it where fitted but did not predict the readings left out", d.unproven);
  if (d.implausible > 0)
    text += fmt::format("; {} would need values beyond {:g} times a machine's (a combination the data barely see)",
                        d.implausible, kImplausibleScales);
  return text + ": no effect in the library is proven; a shape to look for, not a name";
}

}  // namespace

/// The shift of the readings' program zero that the residual holds beyond what the base's
/// free parameters absorb, where significant and larger than kSmallestOriginShift.
std::optional<OriginMisfit> origin_misfit(const model::ForwardModel& model, const MeasurementSet& data,
                                          const Projector& base, const Diagnosis& out, double sse0, double sigma2) {
  const Eigen::MatrixXd all = detail::origin_shift_columns(model, out.refit.all_parameters, data);
  // Only the axes along which the data place the origin, once the base has taken what it
  // can, to within kOriginResolution (a shift along the B line moves nothing of a B error's
  // lever: its column is all but absorbed, and its coefficient would be noise).
  const Eigen::MatrixXd At_all = transpose_product(base.A, all);
  std::vector<Eigen::Index> seen;
  for (Eigen::Index axis = 0; axis < 3; ++axis)
    if (std::sqrt(std::max(base.left_over(all.col(axis), At_all.col(axis)), 0.0)) * detail::kOriginResolution >
        std::sqrt(sigma2))
      seen.push_back(axis);
  if (seen.empty()) return std::nullopt;
  Eigen::MatrixXd C(all.rows(), static_cast<Eigen::Index>(seen.size()));
  for (std::size_t k = 0; k < seen.size(); ++k) C.col(static_cast<Eigen::Index>(k)) = all.col(seen[k]);
  Eigen::VectorXd coefficients;
  const double gain = base.gain(C, base.r, transpose_product(base.A, C), &coefficients);
  if (!(gain > 0) || coefficients.size() != C.cols()) return std::nullopt;
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < seen.size(); ++k) shift[seen[k]] = coefficients[static_cast<Eigen::Index>(k)];
  const auto n = static_cast<double>(data.observations.size());
  OriginMisfit m;
  m.shift = shift;
  const auto k = static_cast<double>(seen.size());
  m.rms_before = out.refit.rms_after;
  m.rms_after = std::sqrt(std::max(sse0 - gain, 0.0) / n);
  m.bic_delta = n * std::log(std::max(sse0 - gain, 1e-300) / std::max(sse0, 1e-300)) + k * std::log(n);
  m.significance = gain / sigma2 - k;
  if (!(m.significance > kSignificance) || !(m.bic_delta < -10.0) || shift.norm() < detail::kSmallestOriginShift)
    return std::nullopt;
  return m;
}

std::string scanned_value_text(const Suggestion& s) {
  if (!(s.period > 0) && s.form != "bump") return {};
  const bool warm_up = s.form == "exponential";
  const std::string unit = warm_up                                                  ? "s"
                           : s.variable.find_first_of("abc") == 0 ? "deg"
                                                                    : "mm";
  const std::string what = warm_up ? "time constant" : s.form == "bump" ? "at" : "period";
  if (s.form == "harmonic") return fmt::format("{} {:.6g} {}", what, s.period, unit);
  return fmt::format("{} {:.6g} +- {:.2g} {}", what, s.period, s.period_uncertainty, unit);
}

Diagnosis diagnose(const model::ForwardModel& model, const MeasurementSet& data, const DiagnoseOptions& options) {
  const model::MachineModel& mm = model.machine();
  Diagnosis out;
  const auto n = static_cast<Eigen::Index>(data.observations.size());
  if (n == 0) return out;
  // Too few readings to refit the model: no diagnosis, said (the model as it is against the
  // data is still worth reading; `fit` refuses such data).
  if (const std::size_t free = free_parameters(model).size(); data.observations.size() < free) {
    out.skipped = fmt::format(
        "{} readings cannot determine the model's {} free parameters: no refit, no "
        "diagnosis (measure more, or free fewer terms)",
        data.observations.size(), free);
    return out;
  }
  out.noise = options.noise > 0 ? options.noise : check(model, data).noise_floor;

  const std::vector<AxisInfo> axes = axes_of(mm, data);
  std::vector<Probe> probes;
  const std::vector<Candidate> candidates = candidate_library(mm, data, axes, probes);
  out.candidates_tried = candidates.size();
  FitOptions refit_options = options.fit;
  if (options.progress) refit_options.progress = [&options](double done) { options.progress(0.3 * done); };
  Projector base = detail::refitted_base(model, data, probes, refit_options, out);
  detail::probe_rows(base, n, probes);
  const double sse0 = base.r.squaredNorm();
  const double rms_projected = std::sqrt(sse0 / static_cast<double>(n));
  // Without a noise floor from the data's structure, the refitted residual stands in for
  // it: an upper bound, so fewer effects pass, never more.
  if (!(out.noise > 0)) out.noise = rms_projected;
  const double sigma2 = std::max(out.noise * out.noise, 1e-18);

  // A candidate's suggestion from its best value (a period, a time constant), the gain
  // there and its coefficients.
  auto suggestion = [&](const Candidate& c, double value, double gain, const Eigen::VectorXd& x, double uncertainty,
                        double trials) -> std::optional<Scored> {
    if (!(gain > 0)) return std::nullopt;
    Suggestion s;
    s.effect = c.effect, s.error = c.error, s.term = c.term, s.variable = c.variable, s.form = c.form;
    s.period = c.scan_points > 0 || c.form == "harmonic" ? value : 0.0;
    s.period_uncertainty = uncertainty;
    s.rms_before = rms_projected;  // like with like for the tests below; the refit's own is shown
    const double sse1 = std::max(sse0 - gain, 0.0);
    s.rms_after = std::sqrt(sse1 / static_cast<double>(n));
    const auto k = static_cast<double>(c.basis_count + (c.scan_points > 0 ? 1 : 0));
    s.bic_delta = static_cast<double>(n) * std::log(std::max(sse1, 1e-300) / std::max(sse0, 1e-300)) +
                  k * std::log(static_cast<double>(n));
    // Against the noise floor: the fall in chi-square, less what the parameters and the
    // scan would win from noise alone (2 ln(trials) for the look-elsewhere effect).
    s.significance = gain / sigma2 - k - 2.0 * std::log(trials);
    s.yaml = "  - " + c.yaml(x, value);
    s.spec = c.yaml(x, value);
    if (c.lattice_step > 0 && s.period > 0) {
      s.aliases = detail::aliases_of(s.period, c.lattice_step, c.shortest_period);
      if (!s.aliases.empty())
        s.aliasing = detail::aliasing_text(s.period, c.lattice_step, s.aliases, c.period_unit, c.settling_run);
    }
    return Scored{std::move(s), value, x, gain};
  };

  // Candidates without a scan: what the base absorbs of all their columns in one pass over
  // the data, a block of rows at a time (their columns over every row would be n x F),
  // instead of a pass over the base's columns per candidate.
  std::vector<Eigen::Index> fixed_column(candidates.size(), -1);
  Eigen::Index fixed_columns = 0;
  for (std::size_t i = 0; i < candidates.size(); ++i)
    if (candidates[i].scan_points == 0 && !probes[candidates[i].probe].rows.empty())
      fixed_column[i] = fixed_columns, fixed_columns += candidates[i].basis_count;
  const detail::FixedSums fixed =
      detail::fixed_sums(candidates, probes, fixed_column, fixed_columns, data, base.A, base.r, options.threads);
  auto score_fixed = [&](std::size_t i) {
    const Candidate& c = candidates[i];
    Eigen::VectorXd x;
    const double gain = base.gain_of_sums(fixed.CtC[i], fixed.Ctr.segment(fixed_column[i], c.basis_count),
                                          fixed.AtC.middleCols(fixed_column[i], c.basis_count), &x);
    return suggestion(c, c.period, gain, x, 0.0, 1.0);
  };

  // Candidates with a scan (a period, a time constant, a place): scanned (scanners.hpp).
  const detail::ScanContext scanning{base, probes, data, sigma2};
  auto score_scanned = [&](const Candidate& c) -> std::optional<Scored> {
    const std::optional<detail::ScanOutcome> o = detail::scan(c, scanning);
    if (!o) return std::nullopt;
    return suggestion(c, o->value, o->gain, o->coefficients, o->uncertainty, o->trials);
  };

  // Scanned candidates first: they are the long ones, and the threads take indices in order.
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < candidates.size(); ++i)
    if (candidates[i].scan_points > 0) order.push_back(i);
  for (std::size_t i = 0; i < candidates.size(); ++i)
    if (fixed_column[i] >= 0) order.push_back(i);
  std::vector<std::optional<Scored>> results(candidates.size());
  std::atomic<std::size_t> candidates_scored{0};
  util::for_each_index(order.size(), options.threads, [&](std::size_t j) {
    const std::size_t i = order[j];
    results[i] = fixed_column[i] >= 0 ? score_fixed(i) : score_scanned(candidates[i]);
    if (options.progress)
      options.progress(0.3 + 0.6 * static_cast<double>(++candidates_scored) / static_cast<double>(order.size()));
  });
  // Significant: the chi-square falls by 25 (five sigma) beyond what noise and the scan
  // would give, the information criterion agrees, and the rms falls by 3% at least.
  std::vector<std::size_t> kept;  // candidates
  for (std::size_t i = 0; i < results.size(); ++i)
    if (const Suggestion* s = results[i] ? &results[i]->suggestion : nullptr;
        s && s->significance > kSignificance && s->bic_delta < -10.0 && s->rms_after < 0.97 * s->rms_before)
      kept.push_back(i);
  std::stable_sort(kept.begin(), kept.end(), [&](std::size_t a, std::size_t b) {
    return results[a]->suggestion.bic_delta < results[b]->suggestion.bic_delta;
  });
  // Proven: the effect also predicts readings it was not fitted to (held_out.hpp), by
  // five sigma against the noise. Weighed in the order of the information criterion until
  // enough are proven.
  for (const std::size_t i : kept) {
    if (out.suggestions.size() == static_cast<std::size_t>(options.max_suggestions)) break;
    const Candidate& c = candidates[i];
    Scored& scored = *results[i];
    Suggestion& s = scored.suggestion;
    if (implausible(c, probes[c.probe], data, scored)) {
      ++out.implausible;
      continue;
    }
    Eigen::MatrixXd C = Eigen::MatrixXd::Zero(n, c.basis_count);
    candidate_columns(c, probes[c.probe], data, scored.value, true, C);
    // The columns less what the base's free parameters take of them.
    Eigen::MatrixXd C_free = C;
    if (base.A.cols() > 0) C_free -= base.A * (base.W * (base.W.transpose() * transpose_product(base.A, C)));
    const detail::HeldOut held = detail::held_out_gain(C_free, base.r, data);
    s.held_out = held.gain / std::max(held.fitted_gain, 1e-300);
    s.held_out_by = held.by == detail::HeldOutBy::source ? "source" : "block";
    if (!(held.gain / sigma2 > kSignificance)) {
      ++out.unproven;
      continue;
    }
    s.rank = static_cast<int>(out.suggestions.size() + 1);
    // The residual with the effect added: what its terms take, less what the base's free
    // parameters had taken of it (the linear fit of both, whose rms is rms_after).
    s.residual = base.r - C_free * scored.coefficients;
    s.rms_before = out.rms_refit;
    out.suggestions.push_back(std::move(s));
  }
  // What is scored is what is suggested: where the model has many free parameters for the
  // readings, the projection takes the noise along every direction the base could move,
  // while a fit holds what the noise does not support; the rms after is then the fit's of
  // the model with the spec, as `fit --add` would write it.
  // (The ties are read first, off the projection's residuals, all alike.)
  out.ties = find_ties(out.suggestions, base.r);
  if (static_cast<double>(base.W.cols()) > kProjectionShare * static_cast<double>(n))
    for (Suggestion& s : out.suggestions) refit_with(model, data, options.fit, s);

  out.origin_misfit = origin_misfit(model, data, base, out, sse0, sigma2);
  const std::vector<Region> bins = residual_bins(data, axes, base.r, rms_projected);
  out.regions = residual_regions(bins, out.noise);
  out.residual = std::move(base.r);
  if (out.suggestions.empty()) out.unexplained = unexplained_structure(out, data, bins);
  if (options.progress) options.progress(1.0);
  return out;
}

}  // namespace ccomp::identify
