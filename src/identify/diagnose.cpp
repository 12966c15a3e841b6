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
using detail::term_name;

/// A candidate is suggested when the chi-square falls by this much (five sigma) beyond
/// what noise and its scan would give.
constexpr double kSignificance = 25.0;
/// The residual holds structure when its rms is above this many noise floors (the loop's
/// own end: a model at the noise leaves at most this).
constexpr double kStructure = 1.3;
/// A variable the residual is uneven along: a bin's rms this many times the rms everywhere.
constexpr double kUneven = 1.2;

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

/// A scored candidate: its suggestion, and the value and coefficients it was scored at.
struct Scored {
  Suggestion suggestion;
  double value = 0.0;
  Eigen::VectorXd coefficients;
  double gain = 0.0;  // mm^2: the fall in the sum of squares where it was fitted
};

/// The refitted model's residual and what its free parameters can absorb.
struct Projector {
  Eigen::VectorXd r;  // residual, orthogonal to the base columns
  Eigen::MatrixXd A;  // the base's columns (the refit's design matrix), scaled to unit length: n x m
  Eigen::MatrixXd W;  // m x k: A W is an orthonormal basis of the combinations the data identify

  /// A^T C over some rows (C has a row per one of them): the base's rows gathered a block at
  /// a time, never a copy of A on each probe's rows (rows x m per probe was much of check's
  /// memory on a large file).
  [[nodiscard]] Eigen::MatrixXd At_on_rows(const std::vector<Eigen::Index>& rows, const Eigen::MatrixXd& C) const {
    constexpr Eigen::Index kBlock = 256;
    Eigen::MatrixXd AtC = Eigen::MatrixXd::Zero(A.cols(), C.cols());
    if (A.cols() == 0) return AtC;
    Eigen::MatrixXd gathered(kBlock, A.cols());
    const auto n = static_cast<Eigen::Index>(rows.size());
    for (Eigen::Index first = 0; first < n; first += kBlock) {
      const Eigen::Index count = std::min(kBlock, n - first);
      for (Eigen::Index i = 0; i < count; ++i) gathered.row(i) = A.row(rows[static_cast<std::size_t>(first + i)]);
      AtC.noalias() += gathered.topRows(count).transpose() * C.middleRows(first, count);
    }
    return AtC;
  }

  /// The sum of squares of column c (A^T c given) that the base cannot absorb.
  [[nodiscard]] double left_over(const Eigen::Ref<const Eigen::VectorXd>& c,
                                 const Eigen::Ref<const Eigen::VectorXd>& Atc) const {
    const Eigen::VectorXd Utc = W.transpose() * Atc;
    return c.squaredNorm() - Utc.squaredNorm();
  }

  /// The fall in the sum of squares when columns C join the base fit, and their
  /// coefficients. C is given on some rows (a probe's), `r_rows` is the residual there
  /// and `AtC` is A^T C over the same rows (m x C.cols()). U = A W is never formed: what
  /// the base absorbs of C is W^T (A^T C), and A^T C is one product for many candidates.
  double gain(const Eigen::Ref<const Eigen::MatrixXd>& C, const Eigen::Ref<const Eigen::VectorXd>& r_rows,
              const Eigen::Ref<const Eigen::MatrixXd>& AtC, Eigen::VectorXd* coefficients) const {
    return gain_of_sums(C.transpose() * C, C.transpose() * r_rows, AtC, coefficients);
  }

  /// The same from the sums over the rows: C^T C, C^T r and A^T C (fixed_sums.hpp).
  double gain_of_sums(const Eigen::MatrixXd& CtC, const Eigen::VectorXd& b,
                      const Eigen::Ref<const Eigen::MatrixXd>& AtC, Eigen::VectorXd* coefficients) const {
    const Eigen::Index k = CtC.cols();
    const Eigen::MatrixXd UtC = W.transpose() * AtC;
    const Eigen::MatrixXd N = CtC - UtC.transpose() * UtC;
    // Columns scaled to unit diagonal; a column the base already spans gains nothing.
    Eigen::VectorXd d = N.diagonal().cwiseMax(0.0).cwiseSqrt();
    for (Eigen::Index j = 0; j < k; ++j)
      if (!(d[j] > 1e-9 * std::sqrt(std::max(CtC(j, j), 1e-300)))) return 0.0;
    const Eigen::MatrixXd Ns = d.cwiseInverse().asDiagonal() * N * d.cwiseInverse().asDiagonal();
    const Eigen::VectorXd bs = b.cwiseQuotient(d);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Ns);
    // Columns that are nearly one another once the base is out: the candidate is not one effect.
    if (eig.eigenvalues().minCoeff() < 1e-6) return 0.0;
    const Eigen::VectorXd xs =
        eig.eigenvectors() * (eig.eigenvectors().transpose() * bs).cwiseQuotient(eig.eigenvalues());
    if (coefficients) *coefficients = xs.cwiseQuotient(d);
    return bs.dot(xs);
  }
};

/// The base model refitted to the data and what its free parameters can absorb, with the
/// probes' columns: one pass over the data, with a model that has the probes as terms
/// (zero: its predictions are the refit's), gives the base's columns and the probes' alike.
Projector refitted_base(const model::ForwardModel& model, const MeasurementSet& data, std::vector<Probe>& probes,
                        const FitOptions& fit_options, Diagnosis& out) {
  out.refit = fit(model, data, fit_options);
  model::MachineModel probing = model.machine();
  const std::size_t first = probing.terms.size();
  for (const Probe& p : probes) {
    model::ErrorTermSpec t;
    t.name = t.iso = term_name(p.component, p.link, true);
    t.link = p.link;
    t.component = p.component;
    t.placement = p.placement;
    t.parameters = Eigen::VectorXd::Zero(1);
    t.parameter_unit = {1.0};
    probing.terms.push_back(t);
  }
  const model::ForwardModel f(probing);
  std::vector<std::size_t> columns = free_parameters(model);  // the base's terms keep their offsets in f
  const auto m = static_cast<Eigen::Index>(columns.size());
  for (std::size_t k = 0; k < probes.size(); ++k) columns.push_back(f.parameter_offset(first + k));
  Eigen::VectorXd parameters = model_parameters(f);
  parameters.head(out.refit.all_parameters.size()) = out.refit.all_parameters;
  Projector base;
  {
    Eigen::MatrixXd J;
    design_matrix(f, parameters, data, columns, base.r, &J);
    for (std::size_t k = 0; k < probes.size(); ++k) probes[k].g = J.col(m + static_cast<Eigen::Index>(k));
    // The base's columns are J's first m: dropping the probes' in place (a shrinking realloc
    // of the column-major storage) rather than copying, which held J and A at once.
    J.conservativeResize(Eigen::NoChange, m);
    base.A = std::move(J);
  }
  if (base.A.cols() > 0) {
    // What the base absorbs is what its fit could determine: columns in physical scales,
    // directions whose effect at that size is above the noise (fit.hpp).
    const Eigen::VectorXd physical = physical_scales(model, data);
    for (Eigen::Index j = 0; j < base.A.cols(); ++j)
      base.A.col(j) *= physical[static_cast<Eigen::Index>(columns[static_cast<std::size_t>(j)])];
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(normal_matrix(base.A));
    const double largest = std::sqrt(std::max(eig.eigenvalues().maxCoeff(), 0.0));
    const double seen = std::max(3.0 * out.refit.noise, 1e-9 * largest);
    std::vector<Eigen::Index> kept;
    for (Eigen::Index k = 0; k < eig.eigenvalues().size(); ++k)
      if (std::sqrt(std::max(eig.eigenvalues()[k], 0.0)) > seen) kept.push_back(k);
    base.W.resize(base.A.cols(), static_cast<Eigen::Index>(kept.size()));
    for (std::size_t c = 0; c < kept.size(); ++c)
      base.W.col(static_cast<Eigen::Index>(c)) =
          eig.eigenvectors().col(kept[c]) / std::sqrt(eig.eigenvalues()[kept[c]]);
    // The refit's residual, made exactly orthogonal to what the base absorbs.
    const Eigen::VectorXd absorbed = base.W * (base.W.transpose() * (base.A.transpose() * base.r));
    base.r -= base.A * absorbed;
  } else {
    base.W.resize(0, 0);
  }
  // What the user sees is the refit's own rms (what `fit` reports), not the projection's:
  // the fit holds changes the noise does not support, the projection takes them.
  out.rms_refit = out.refit.rms_after;
  return base;
}

/// Each probe's rows (where its column is not zero), and the base on them.
void probe_rows(const Projector& base, Eigen::Index n, std::vector<Probe>& probes) {
  for (Probe& p : probes) {
    const double largest = p.g.cwiseAbs().maxCoeff();
    for (Eigen::Index i = 0; i < n; ++i)
      if (std::abs(p.g[i]) > 1e-9 * largest) p.rows.push_back(i);
    if (static_cast<Eigen::Index>(p.rows.size()) == n) continue;  // every row: the base's own A and r serve
    p.r_rows.resize(static_cast<Eigen::Index>(p.rows.size()));
    for (std::size_t i = 0; i < p.rows.size(); ++i) p.r_rows[static_cast<Eigen::Index>(i)] = base.r[p.rows[i]];
  }
}

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
  Projector base = refitted_base(model, data, probes, refit_options, out);
  probe_rows(base, n, probes);
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

  // Candidates with a scan (a period, a time constant): a coarse pass, then the best
  // values weighed exactly, a few at a time in one product.
  auto score_scanned = [&](const Candidate& c) -> std::optional<Scored> {
    const Probe& p = probes[c.probe];
    if (p.rows.empty()) return std::nullopt;
    const bool all_rows = static_cast<Eigen::Index>(p.rows.size()) == n;
    const Eigen::VectorXd& r_rows = all_rows ? base.r : p.r_rows;
    // The exact gains at `values`; the coefficients at the first of them into `x`.
    auto exact_gains = [&](const std::vector<double>& values, Eigen::VectorXd* x) {
      const int bc = c.basis_count;
      Eigen::MatrixXd C(static_cast<Eigen::Index>(p.rows.size()), static_cast<Eigen::Index>(values.size()) * bc);
      for (std::size_t v = 0; v < values.size(); ++v)
        candidate_columns(c, p, data, values[v], false, C.middleCols(static_cast<Eigen::Index>(v) * bc, bc));
      const Eigen::MatrixXd AtC = all_rows ? Eigen::MatrixXd(base.A.transpose() * C) : base.At_on_rows(p.rows, C);
      std::vector<double> gains(values.size());
      for (std::size_t v = 0; v < values.size(); ++v) {
        const Eigen::Index first = static_cast<Eigen::Index>(v) * bc;
        gains[v] = base.gain(C.middleCols(first, bc), r_rows, AtC.middleCols(first, bc), v == 0 ? x : nullptr);
      }
      return gains;
    };
    // The coarse gains' eight best local peaks weighed exactly; only they compete (the
    // coarse gains elsewhere are not comparable).
    auto keep_exact_peaks = [&](const std::vector<double>& values, std::vector<double>& gains) {
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
    };
    // Evenly in frequency for periods (each step shifts the phase at the far end by the
    // same amount), in log for time constants, in value for places.
    std::vector<double> values(static_cast<std::size_t>(c.scan_points)), gains(values.size());
    for (std::size_t k = 0; k < values.size(); ++k) {
      const double f = static_cast<double>(k) / static_cast<double>(values.size() - 1);
      switch (c.scan_spacing) {
        case Candidate::Spacing::frequency:
          values[k] = 1.0 / (1.0 / c.scan_from + f * (1.0 / c.scan_to - 1.0 / c.scan_from));
          break;
        case Candidate::Spacing::logarithmic:
          values[k] = c.scan_from * std::pow(c.scan_to / c.scan_from, f);
          break;
        case Candidate::Spacing::linear:
          values[k] = c.scan_from + f * (c.scan_to - c.scan_from);
          break;
      }
    }
    if (c.scan_spacing == Candidate::Spacing::frequency && c.phase_variable) {
      // A long frequency scan's coarse pass leaves out what the base absorbs (cheap);
      // its eight best local peaks are then weighed exactly. The frequencies are evenly
      // spaced, so each row's (cos, sin) steps by one rotation per frequency.
      std::vector<double> phase_variable(p.rows.size()), g(p.rows.size());
      for (std::size_t i = 0; i < p.rows.size(); ++i) {
        phase_variable[i] = c.phase_variable(data.observations[static_cast<std::size_t>(p.rows[i])]);
        g[i] = p.g[p.rows[i]];
      }
      gains = coarse_periodic_gains(phase_variable, g, r_rows, 1.0 / values[0], 1.0 / values[1] - 1.0 / values[0],
                                    values.size());
      keep_exact_peaks(values, gains);
    } else if (c.scan_spacing == Candidate::Spacing::linear) {
      // A place along an axis (a local defect): the coarse pass weighs each place by its
      // column's correlation with the residual alone (a bell is local: what the base
      // absorbs of it is small), and its eight best local peaks are then weighed exactly.
      // The rows by their place, so that each scanned place reads only the rows it reaches.
      std::vector<std::pair<double, Eigen::Index>> by_place;
      for (const Eigen::Index row : p.rows)
        by_place.emplace_back(c.phase_variable(data.observations[static_cast<std::size_t>(row)]), row);
      std::sort(by_place.begin(), by_place.end());
      for (std::size_t k = 0; k < values.size(); ++k) {
        double cr = 0.0, cc = 0.0;
        auto it = std::lower_bound(by_place.begin(), by_place.end(), std::pair{values[k] - c.reach, Eigen::Index{-1}});
        for (; it != by_place.end() && it->first <= values[k] + c.reach; ++it) {
          const Eigen::Index row = it->second;
          const double column = p.g[row] * c.basis(data.observations[static_cast<std::size_t>(row)], 0, values[k]);
          cr += column * base.r[row];
          cc += column * column;
        }
        gains[k] = cc > 0 ? cr * cr / cc : 0.0;
      }
      keep_exact_peaks(values, gains);
    } else {
      gains = exact_gains(values, nullptr);
    }
    const auto top = static_cast<std::size_t>(std::max_element(gains.begin(), gains.end()) - gains.begin());
    // Refining moves the peak by less than half a step, which raises its gain by a
    // quarter at most: a candidate that could not pass with twice its gain is not
    // refined (it is not suggested either way).
    const double trials = static_cast<double>(values.size());
    const auto parameters = static_cast<double>(c.basis_count + 1);
    if (2.0 * gains[top] / sigma2 - parameters - 2.0 * std::log(trials) <= kSignificance) return std::nullopt;
    // Refine between the neighbours on a grid, three times narrower each round, and put
    // the peak on the parabola through the best point and its neighbours.
    double lo = values[top > 0 ? top - 1 : top], hi = values[top + 1 < values.size() ? top + 1 : top];
    if (lo > hi) std::swap(lo, hi);
    constexpr int kGrid = 12;
    std::vector<double> grid(kGrid), grid_gains;
    std::size_t best = 0;
    for (int round = 0; round < 3; ++round) {
      for (int j = 0; j < kGrid; ++j) grid[static_cast<std::size_t>(j)] = lo + (hi - lo) * j / (kGrid - 1);
      grid_gains = exact_gains(grid, nullptr);
      best = static_cast<std::size_t>(std::max_element(grid_gains.begin(), grid_gains.end()) - grid_gains.begin());
      lo = grid[best > 0 ? best - 1 : best], hi = grid[std::min<std::size_t>(best + 1, kGrid - 1)];
    }
    double value = grid[best];
    if (best > 0 && best + 1 < kGrid) {
      const double bend = grid_gains[best - 1] - 2 * grid_gains[best] + grid_gains[best + 1];
      if (bend < 0) value += 0.5 * (grid[1] - grid[0]) * (grid_gains[best - 1] - grid_gains[best + 1]) / bend;
    }
    // The gain and coefficients there, and the uncertainty from the curvature of the sum
    // of squares (a chi-square rise of 1).
    // A place along an axis is as precise at 0 as anywhere: its step is the scan's range's.
    const double h = c.scan_spacing == Candidate::Spacing::linear || value == 0.0
                         ? 1e-4 * std::abs(c.scan_to - c.scan_from)
                         : 1e-4 * std::abs(value);
    Eigen::VectorXd x;
    const std::vector<double> last = exact_gains({value, value + h, value - h}, &x);
    const double curvature = (2 * last[0] - last[1] - last[2]) / (h * h);
    const double uncertainty = curvature > 0 ? std::sqrt(2.0 * sigma2 / curvature) : 0.0;
    return suggestion(c, value, last[0], x, uncertainty, trials);
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
