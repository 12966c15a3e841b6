#include "ccomp/identify/fit.hpp"
#include "ccomp/identify/fit_caveats.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string_view>

#include "ccomp/error.hpp"
#include "ccomp/identify/check.hpp"
#include "ccomp/identify/next_measurement.hpp"
#include "ccomp/identify/physical_scale.hpp"
#include "ccomp/util/parallel.hpp"

namespace ccomp::identify {

using model::TermForm;

std::string parameter_label(const model::ErrorTermSpec& t, std::size_t k) {
  const std::string& n = t.iso;
  switch (t.shape.form) {
    case TermForm::constant:
      return n;
    case TermForm::polynomial:
      return fmt::format("{}.a{}", n, k);
    case TermForm::table:
      return fmt::format("{}.value[{}]", n, k);
    case TermForm::periodic:
      return k == 0 ? n + ".period" : fmt::format("{}.{}{}", n, k % 2 ? 'a' : 'b', (k + 1) / 2);
    case TermForm::reversal:
      return t.shape.order_primary == 0 ? n + ".reversal" : fmt::format("{}.reversal{}", n, k);
    case TermForm::thermal_linear:
      return fmt::format("{}.k_{}", n, t.primary.text);
    case TermForm::thermal_warmup:
      return k == 0 ? n + ".amplitude" : n + ".time_constant";
    case TermForm::bump:
      return n + (k == 0 ? ".amplitude" : k == 1 ? ".at" : ".width");
    case TermForm::scale_expansion:
      return n + ".alpha";
    case TermForm::cross_axis: {
      const auto order = static_cast<std::size_t>(t.shape.order);
      return fmt::format("{}.c{}{}", n, k / order, k % order + 1);
    }
  }
  return fmt::format("{}[{}]", n, k);
}

namespace {

/// Whether a term is the straightness of a linear axis as a polynomial of its position
/// (EYX of x) whose slope is where the axis' line lies, carried by a squareness the model
/// has free: its own line's (EC0X: X's line turned toward y gives the same column), or,
/// where the reference frame fixes this line (Z's line is its primary axis, Y's lies in its
/// Z-Y plane), the other line's that makes the same angle (EXZ's by EB0X, EYZ's by EA0Y,
/// EXY's by EC0X). Without that squareness free the slope stays the straightness'.
bool slope_is_a_location(const model::MachineModel& mm, const model::ErrorTermSpec& t) {
  if (t.shape.form != TermForm::polynomial || t.placement != model::ErrorPlacement::motion || t.component >= 3 ||
      t.primary.kind != model::VariableKind::axis)
    return false;
  for (const auto* chain : {&mm.workpiece_chain, &mm.tool_chain})
    for (const model::LinkSpec& l : *chain) {
      if (l.name != t.link || !l.axis || l.tool) continue;
      const model::AxisSpec* a = mm.axis(*l.axis);
      const std::size_t letter = std::string_view("XYZABCUVW").find(*l.axis);
      const int along = static_cast<int>(letter % 3);  // U V W travel along X Y Z
      if ((a && a->type == model::AxisType::rotary) || letter != t.primary.index || along == t.component) return false;
      const int about = 3 + (3 - along - t.component);  // the line turned toward the straightness' direction
      // Where the reference frame fixes this line's turn (Z's line is its primary axis, Y's
      // lies in its Z-Y plane), the angle between the two lines is the other line's
      // squareness: Z toward x is EB0X, Z toward y is EA0Y, Y toward x is EC0X.
      std::string carrier = t.link;
      int carried = about;
      const bool frame_fixed = model::frame_fixes_line_turn(*l.axis, about);
      if (frame_fixed) {
        const char other = (*l.axis == 'Z' && about == 3) ? 'Y' : 'X';
        carrier.clear();
        for (const auto* side : {&mm.workpiece_chain, &mm.tool_chain})
          for (const model::LinkSpec& k : *side)
            if (k.axis && *k.axis == other) carrier = k.name;
      }
      for (const model::ErrorTermSpec& s : mm.terms)
        if (s.free && !carrier.empty() && s.link == carrier && s.placement == model::ErrorPlacement::location &&
            s.component == carried)
          return true;
      return false;
    }
  return false;
}

}  // namespace

std::vector<std::size_t> free_parameters(const model::ForwardModel& model) {
  std::vector<std::size_t> free;
  const model::MachineModel& mm = model.machine();
  for (std::size_t t = 0; t < mm.terms.size(); ++t) {
    const model::ErrorTermSpec& term = mm.terms[t];
    if (!term.free) continue;
    const bool slope_is_location = slope_is_a_location(mm, term);
    for (Eigen::Index k = 0; k < term.parameters.size(); ++k) {
      // A period is a property of the mechanism (a screw's pitch, 360 deg of a table):
      // fitted only when the file says so (discovery scans it instead).
      if (term.shape.form == TermForm::periodic && k == 0 && !term.free_period) continue;
      // A straightness is the deviation from its axis' line (docs/error-model.md Ref 4: against its
      // least-squares line); the line's slope is where the line lies: the squareness, or
      // nothing where the reference frame defines it.
      if (slope_is_location && k == 1) continue;
      free.push_back(model.parameter_offset(t) + static_cast<std::size_t>(k));
    }
  }
  return free;
}

Eigen::VectorXd model_parameters(const model::ForwardModel& model) {
  Eigen::VectorXd p(static_cast<Eigen::Index>(model.parameter_count()));
  for (std::size_t t = 0; t < model.machine().terms.size(); ++t)
    p.segment(static_cast<Eigen::Index>(model.parameter_offset(t)), model.machine().terms[t].parameters.size()) =
        model.machine().terms[t].parameters;
  return p;
}

namespace {

double rms(const Eigen::VectorXd& r) {
  return r.size() ? std::sqrt(r.squaredNorm() / static_cast<double>(r.size())) : 0.0;
}

std::vector<double> rms_by_source(const Eigen::VectorXd& r, const MeasurementSet& data) {
  std::vector<double> sum(data.sources.size(), 0.0), count(data.sources.size(), 0.0);
  for (std::size_t i = 0; i < data.observations.size(); ++i) {
    sum[data.observations[i].source] += r[static_cast<Eigen::Index>(i)] * r[static_cast<Eigen::Index>(i)];
    count[data.observations[i].source] += 1;
  }
  for (std::size_t s = 0; s < sum.size(); ++s) sum[s] = count[s] > 0 ? std::sqrt(sum[s] / count[s]) : 0.0;
  return sum;
}

/// Readings beyond 5 robust sigmas (the median absolute residual's) of the rest, when they
/// are under 1% of the rows: many of them is a missing effect, not spikes.
std::vector<FitReport::Outlier> outliers_of(const Eigen::VectorXd& r, const MeasurementSet& data) {
  if (r.size() < 20) return {};
  Eigen::VectorXd a = r.cwiseAbs();
  std::nth_element(a.data(), a.data() + a.size() / 2, a.data() + a.size());
  const double sigma = 1.4826 * a[a.size() / 2];
  std::vector<FitReport::Outlier> out;
  for (Eigen::Index i = 0; i < r.size(); ++i)
    if (std::abs(r[i]) > 5.0 * sigma && std::abs(r[i]) > 1e-9) {
      const Observation& o = data.observations[static_cast<std::size_t>(i)];
      out.push_back({o.file, o.row, r[i]});
    }
  if (static_cast<double>(out.size()) > 0.01 * static_cast<double>(r.size())) return {};
  std::sort(out.begin(), out.end(),
            [](const auto& x, const auto& y) { return std::abs(x.residual) > std::abs(y.residual); });
  return out;
}

}  // namespace

void design_matrix(const model::ForwardModel& model, const Eigen::VectorXd& parameters, const MeasurementSet& data,
                   const std::vector<std::size_t>& free, Eigen::VectorXd& r, Eigen::MatrixXd* J) {
  const auto n = static_cast<Eigen::Index>(data.observations.size());
  r.resize(n);
  if (J) J->resize(n, static_cast<Eigen::Index>(free.size()));
  // Rows are independent: each piece of them on a thread, with its own scratch.
  util::for_each_piece(data.observations.size(), util::hardware_threads(), [&](std::size_t begin, std::size_t end) {
    model::ForwardData d(model);
    d.set_parameters(parameters);
    // J's rows gathered a few at a time and stored as a block: a row written straight
    // into the column-major J touches one cache line (and page) per column.
    constexpr Eigen::Index kChunk = 64;
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows(J ? kChunk : 0, J ? J->cols() : 0);
    Eigen::Index chunk_begin = static_cast<Eigen::Index>(begin);
    for (auto i = static_cast<Eigen::Index>(begin); i < static_cast<Eigen::Index>(end); ++i) {
      const Observation& o = data.observations[static_cast<std::size_t>(i)];
      model::forward(model, d, o.q, MeasurementSet::conditions(o), J != nullptr);
      const Eigen::Matrix3d& R = d.nominal_chain.oMp.R;  // table frame -> machine axes
      r[i] = o.value - o.direction.dot(R * (d.actual - d.nominal));
      if (!J) continue;
      const Eigen::RowVector3d nR = o.direction.transpose() * R;
      for (std::size_t j = 0; j < free.size(); ++j)
        rows(i - chunk_begin, static_cast<Eigen::Index>(j)) =
            nR * d.J_parameters.col(static_cast<Eigen::Index>(free[j]));
      if (i - chunk_begin + 1 == kChunk || i + 1 == static_cast<Eigen::Index>(end)) {
        J->middleRows(chunk_begin, i - chunk_begin + 1) = rows.topRows(i - chunk_begin + 1);
        chunk_begin = i + 1;
      }
    }
  });
}

namespace {
constexpr std::size_t kRowBlocks = 8;
/// A change the data support moves the predictions by more than this many noise sigmas:
/// the test a fit's step directions and its final changes both pass.
constexpr double kSignificant = 3.0;
/// A direction the data determine: one physical scale along it moves the predictions by
/// more than one noise sigma (its uncertainty is below one physical scale). Whether the
/// change found along it is kept is the 3-sigma test above, at the end.
constexpr double kDeterminable = 1.0;
/// A fitted change beyond this many physical scales is refused (FitReport::refusals).
Eigen::Index block_begin(Eigen::Index rows, std::size_t b) {
  return rows * static_cast<Eigen::Index>(b) / static_cast<Eigen::Index>(kRowBlocks);
}

/// The sum over the fixed row blocks of block(begin, count), computed on the cores and
/// added in block order: the same sums on any machine, whatever its core count.
template <class Block>
Eigen::MatrixXd sum_over_row_blocks(Eigen::Index rows, Eigen::Index out_rows, Eigen::Index out_cols, Block block) {
  std::vector<Eigen::MatrixXd> part(kRowBlocks);
  util::for_each_index(kRowBlocks, util::hardware_threads(), [&](std::size_t b) {
    const Eigen::Index begin = block_begin(rows, b), end = block_begin(rows, b + 1);
    // An empty block adds nothing (and Eigen's product kernels divide by its size).
    part[b] = end > begin ? block(begin, end - begin) : Eigen::MatrixXd::Zero(out_rows, out_cols);
  });
  Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(out_rows, out_cols);
  for (const Eigen::MatrixXd& p : part) sum += p;
  return sum;
}

}  // namespace

Eigen::MatrixXd normal_matrix(const Eigen::MatrixXd& A, const Eigen::VectorXd* weights) {
  const Eigen::MatrixXd lower =
      sum_over_row_blocks(A.rows(), A.cols(), A.cols(), [&](Eigen::Index begin, Eigen::Index count) {
        Eigen::MatrixXd N = Eigen::MatrixXd::Zero(A.cols(), A.cols());
        if (weights)
          N.selfadjointView<Eigen::Lower>().rankUpdate(
              (weights->segment(begin, count).cwiseSqrt().asDiagonal() * A.middleRows(begin, count)).transpose());
        else
          N.selfadjointView<Eigen::Lower>().rankUpdate(A.middleRows(begin, count).transpose());
        return N;
      });
  return lower.selfadjointView<Eigen::Lower>();
}

Eigen::MatrixXd transpose_product(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  return sum_over_row_blocks(A.rows(), A.cols(), B.cols(), [&](Eigen::Index begin, Eigen::Index count) {
    return Eigen::MatrixXd(A.middleRows(begin, count).transpose() * B.middleRows(begin, count));
  });
}

Eigen::VectorXd residuals(const model::ForwardModel& model, const Eigen::VectorXd& parameters,
                          const MeasurementSet& data) {
  Eigen::VectorXd r;
  design_matrix(model, parameters, data, {}, r, nullptr);
  return r;
}

model::MachineModel without_free_spans(model::MachineModel machine) {
  for (model::ErrorTermSpec& t : machine.terms)
    if (t.free) t.span.reset();
  return machine;
}

namespace {

/// Whether a fitted term of this form is held beyond where it was fitted (see fitted_spans()).
bool grows_beyond_its_data(TermForm form) {
  return form == TermForm::polynomial || form == TermForm::cross_axis || form == TermForm::thermal_linear ||
         form == TermForm::scale_expansion;
}

}  // namespace

std::optional<double> variable_value(const model::Variable& v, const Observation& o) {
  switch (v.kind) {
    case model::VariableKind::axis:
      return o.q[static_cast<Eigen::Index>(v.index)];
    case model::VariableKind::tool_length:
      return o.q[static_cast<Eigen::Index>(model::kToolLengthIndex)];
    case model::VariableKind::temperature:
      return v.index < o.temperatures.size() ? o.temperatures[v.index] : 20.0;
    case model::VariableKind::time:
      return o.time;
    case model::VariableKind::direction:
    case model::VariableKind::none:
      return std::nullopt;
  }
  return std::nullopt;
}

std::vector<std::optional<model::TermSpan>> fitted_spans(const model::MachineModel& machine,
                                                         const MeasurementSet& data) {
  std::vector<std::optional<model::TermSpan>> spans(machine.terms.size());
  for (std::size_t t = 0; t < machine.terms.size(); ++t) {
    const model::ErrorTermSpec& term = machine.terms[t];
    if (!term.free || !grows_beyond_its_data(term.shape.form)) continue;
    double low = std::numeric_limits<double>::infinity(), high = -low;
    for (const Observation& o : data.observations)
      if (const std::optional<double> v = variable_value(term.primary, o)) low = std::min(low, *v), high = std::max(high, *v);
    if (low < high) spans[t] = model::TermSpan{low, high};
  }
  return spans;
}

std::string nothing_identifiable(const FitReport& report) {
  if (report.parameters.empty() || report.rank > 0) return {};
  return fmt::format(
      "nothing identifiable above the noise floor: none of the {} free parameters moves the predictions by more than "
      "3 noise sigmas ({:.3f} um) over these {} readings; measure a longer stroke, more targets, more runs or both "
      "directions",
      report.parameters.size(), kSignificant * report.noise * 1e3, report.observations);
}

FitReport fit(const model::ForwardModel& model, const MeasurementSet& data, const FitOptions& options,
              Linearization* at_fit) {
  const model::MachineModel& mm = model.machine();
  FitReport report;
  report.observations = data.observations.size();
  Eigen::VectorXd p = model_parameters(model);
  const std::vector<std::size_t> free = free_parameters(model);
  if (data.observations.size() < free.size())
    throw Error(ErrorKind::data,
                fmt::format("{} readings cannot determine {} free parameters: a fit needs at least as many readings "
                            "(measure more, or free fewer terms)",
                            data.observations.size(), free.size()),
                SourceLocation{data.files.empty() ? std::string() : data.files.front(), 0, 0});
  for (std::size_t index : free) {
    std::size_t t = 0;
    while (t + 1 < mm.terms.size() && model.parameter_offset(t + 1) <= index) ++t;
    const std::size_t k = index - model.parameter_offset(t);
    report.parameters.push_back({index, t, parameter_label(mm.terms[t], k), p[static_cast<Eigen::Index>(index)],
                                 p[static_cast<Eigen::Index>(index)], 0.0, true});
  }
  // Weights per observation: the source's, times the robust loss's.
  const auto n = static_cast<Eigen::Index>(data.observations.size());
  Eigen::VectorXd source_weight = Eigen::VectorXd::Ones(n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (const auto& [label, w] : options.source_weights)
      if (data.sources[data.observations[static_cast<std::size_t>(i)].source] == label) source_weight[i] = w;
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  design_matrix(model, p, data, free, r, free.empty() ? nullptr : &J);
  report.rms_before = rms(r);
  report.source_rms_before = rms_by_source(r, data);
  const auto m = static_cast<Eigen::Index>(free.size());
  Eigen::VectorXd weight = source_weight;
  auto cost = [&](const Eigen::VectorXd& res) { return (weight.cwiseSqrt().asDiagonal() * res).squaredNorm(); };
  // Where the fit starts, to end no worse: the plain weighted least squares, whatever loss.
  const Eigen::VectorXd start_p = p, start_r = r;
  auto plain_cost = [&](const Eigen::VectorXd& res) {
    return (source_weight.cwiseSqrt().asDiagonal() * res).squaredNorm();
  };
  // Each parameter in its physical scale (10 um, 10 urad, over the variable's reach): a
  // direction is determined when moving one scale along it changes the predictions by more
  // than the noise would (3 sigma), not when its column merely has a length.
  const Eigen::VectorXd physical = physical_scales(model, data);
  report.noise = noise_floor(data, r).value;
  // A period, a time constant, a bump's place and width: what the shape of a term is, whose
  // column is zero while its amplitudes are (decided again once they have moved).
  auto is_shape = [&](Eigen::Index j) {
    const FittedParameter& fp = report.parameters[static_cast<std::size_t>(j)];
    const model::ErrorTermSpec& t = mm.terms[fp.term];
    const std::size_t k = fp.index - model.parameter_offset(fp.term);
    return (t.shape.form == TermForm::periodic && k == 0) || (t.shape.form == TermForm::thermal_warmup && k == 1) ||
           (t.shape.form == TermForm::bump && k >= 1);
  };
  // A parameter the data do not see on its own (a spindle's yaw when every tool tip sits on
  // its axis) is held exactly: it takes no part in any step. (Not a period or a time
  // constant whose amplitude is still zero: those are decided once the amplitudes move.)
  std::vector<Eigen::Index> blind;
  if (m > 0) {
    Eigen::VectorXd effect(m);
    for (Eigen::Index j = 0; j < m; ++j)
      effect[j] = std::sqrt(source_weight.dot(J.col(j).cwiseAbs2())) *
                  physical[static_cast<Eigen::Index>(free[static_cast<std::size_t>(j)])];
    for (Eigen::Index j = 0; j < m; ++j) {
      if (!is_shape(j) &&
          !(effect[j] > std::max(kSignificant * report.noise, options.rank_tolerance * effect.maxCoeff())))
        blind.push_back(j);
    }
  }
  Eigen::VectorXd scale = Eigen::VectorXd::Ones(m), column_norm = Eigen::VectorXd::Zero(m);
  Eigen::MatrixXd V;
  Eigen::VectorXd sigma;
  std::vector<bool> identified_direction;
  Eigen::MatrixXd subspace;      // the identified directions (scaled coordinates), columns
  bool jacobian_current = true;  // J is at p (a converged last step or a revert moves p on)
  // A period or time constant whose column was zero when the rank was decided (its
  // amplitudes were zero): blind then, decided again once they have moved.
  auto has_blind_shape = [&] {
    for (Eigen::Index j = 0; j < m; ++j) {
      if (is_shape(j) && column_norm[j] == 0.0) return true;
    }
    return false;
  };
  double lambda = 0.0;  // Levenberg-Marquardt damping, relative to the largest singular value squared
  for (int iteration = 0; iteration < options.max_iterations && m > 0; ++iteration) {
    report.iterations = iteration + 1;
    if (options.progress)
      options.progress(static_cast<double>(iteration) / static_cast<double>(options.max_iterations));
    if (options.loss == Loss::huber && iteration > 0) {
      // Robust scale from the median absolute residual; rows beyond 1.345 of it count linearly.
      Eigen::VectorXd a = r.cwiseAbs();
      std::nth_element(a.data(), a.data() + a.size() / 2, a.data() + a.size());
      const double s = std::max(1.4826 * a[a.size() / 2], 1e-12);
      for (Eigen::Index i = 0; i < n; ++i)
        weight[i] = source_weight[i] * std::min(1.0, 1.345 * s / std::max(std::abs(r[i]), 1e-300));
    }
    // Columns scaled to unit length, so the singular values compare parameters of any unit.
    // What the data determine is decided from the start, and once more after the first
    // step if a period or a time constant was blind then (until its amplitudes move):
    // deciding again every iteration lets combinations at the threshold drift in and fit
    // noise.
    const bool blind_shape = iteration == 1 && has_blind_shape();
    const bool decide = iteration == 0 || blind_shape;
    if (decide)
      for (Eigen::Index j = 0; j < m; ++j) {
        column_norm[j] = std::sqrt(weight.dot(J.col(j).cwiseAbs2()));
        scale[j] = 1.0 / physical[static_cast<Eigen::Index>(free[static_cast<std::size_t>(j)])];
      }
    // A = sqrt(W) J S^-1 is never formed (a copy of the whole design matrix): its normal
    // matrix and gradient come from J and are scaled after.
    const bool unit_weights = (weight.array() == 1.0).all();
    Eigen::MatrixXd N = scale.cwiseInverse().asDiagonal() * normal_matrix(J, unit_weights ? nullptr : &weight) *
                        scale.cwiseInverse().asDiagonal();
    Eigen::VectorXd g = (J.transpose() * weight.cwiseProduct(r)).cwiseQuotient(scale);
    for (const Eigen::Index j : blind) {  // held: no part in the normal equations
      N.row(j).setZero();
      N.col(j).setZero();
      g[j] = 0.0;
      column_norm[j] = 0.0;
    }
    if (decide) {
      // Descending singular values and their right singular vectors.
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(N);
      sigma = eig.eigenvalues().cwiseMax(0.0).cwiseSqrt().reverse();
      V = eig.eigenvectors().rowwise().reverse();
      const double largest = sigma.size() ? sigma[0] : 0.0;
      identified_direction.assign(static_cast<std::size_t>(m), false);
      std::vector<Eigen::Index> kept;
      for (Eigen::Index k = 0; k < m; ++k)
        if (sigma[k] > std::max(kDeterminable * report.noise, options.rank_tolerance * largest) && sigma[k] > 0) {
          identified_direction[static_cast<std::size_t>(k)] = true;
          kept.push_back(k);
        }
      subspace.resize(m, static_cast<Eigen::Index>(kept.size()));
      for (std::size_t c = 0; c < kept.size(); ++c) subspace.col(static_cast<Eigen::Index>(c)) = V.col(kept[c]);
    }
    // No direction above the noise floor (a short stroke, few targets, one run): nothing
    // to step along, and nothing to decompose (Eigen's solver of an empty matrix faults).
    if (subspace.cols() == 0) {
      report.converged = true;
      break;
    }
    // Levenberg-Marquardt within the identified subspace: where the cost does not fall,
    // the weak directions are damped first (lambda), not the whole step (a period far
    // from its start is not quadratic).
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> reduced(subspace.transpose() * N * subspace);
    const Eigen::VectorXd mu = reduced.eigenvalues().cwiseMax(0.0);
    const Eigen::MatrixXd Q = subspace * reduced.eigenvectors();
    const Eigen::VectorXd Qg = Q.transpose() * g;
    const double largest = mu.size() ? mu.maxCoeff() : 0.0;
    const double before = cost(r);
    // Only directions whose step gains more than the noise would (chi-square by 9, the
    // test the end of the fit applies before keeping a change) are stepped along. The
    // rest is noise: there the least-squares step is long (noise over a small singular
    // value), the model is no longer linear that far out, and the full step fails and is
    // damped back over several passes over the data, only to be reverted at the end.
    // The noise: what the linear model leaves after the full step (from a poor start the
    // residual now is mostly model error, and would hide real effects).
    const Eigen::VectorXd direction_gain =
        (mu.array() > 0).select(Qg.cwiseAbs2().cwiseQuotient(mu.cwiseMax(1e-300)), 0.0);
    const double noise2 = std::max(before - direction_gain.sum(), 0.0) /
                          std::max(1.0, static_cast<double>(n) - static_cast<double>(subspace.cols()));
    Eigen::VectorXd stepped_Qg = Qg;
    // What the step would gain on the local linear model. Below what counts as
    // convergence (see below) no trial is worth its pass over the data: at the optimum
    // every trial fails, and each costs one.
    double predicted_gain = 0.0;
    for (Eigen::Index k = 0; k < mu.size(); ++k) {
      if (direction_gain[k] > kSignificant * kSignificant * noise2)
        predicted_gain += direction_gain[k];
      else
        stepped_Qg[k] = 0.0;
    }
    auto step_for = [&](double damping) {
      const Eigen::VectorXd step = Q * stepped_Qg.cwiseQuotient((mu.array() + damping).max(1e-300).matrix());
      return Eigen::VectorXd(step.cwiseQuotient(scale));
    };
    if (predicted_gain <= before / static_cast<double>(n) + 1e-30) {
      // From a least-squares optimum (a model a plain fit wrote) nothing moves before the
      // robust weights are in: they come at the next iteration.
      if (options.loss == Loss::huber && iteration == 0) continue;
      report.converged = true;
      break;
    }
    // What the step with a damping gains on the linear model.
    auto linear_gain = [&](double damping) {
      const Eigen::ArrayXd y = stepped_Qg.array() / (mu.array() + damping).max(1e-300);
      return (y * (2.0 * stepped_Qg.array() - mu.array() * y)).sum();
    };
    Eigen::VectorXd trial_p = p, trial_r;
    bool improved = false;
    double damping = 0.0;
    for (int attempt = 0; attempt < 24; ++attempt) {
      damping = lambda * largest;
      Eigen::VectorXd dp = step_for(damping);
      for (const Eigen::Index j : blind) dp[j] = 0.0;  // exactly: not even the rounding of Q
      trial_p = p;
      for (Eigen::Index j = 0; j < m; ++j)
        trial_p[static_cast<Eigen::Index>(free[static_cast<std::size_t>(j)])] += dp[j];
      design_matrix(model, trial_p, data, free, trial_r, nullptr);
      if (cost(trial_r) <= before) {
        improved = true;
        lambda = std::max(lambda * 0.1, 1e-12);
        break;
      }
      lambda = lambda > 0 ? lambda * 10.0 : 1e-8;
    }
    if (!improved) {
      report.converged = true;
      break;
    }
    const double after = cost(trial_r);
    p = trial_p;
    r = std::move(trial_r);
    // Converged when an iteration gains less than one reading's noise variance (chi-square
    // by 1, what a single parameter's one-sigma change is worth): what is left to gain is
    // not information the data hold. (A hundredth, as before, spent five more iterations
    // at an optimum damping weak directions into place, each a design matrix.)
    const double chi1 = before / static_cast<double>(n) + 1e-30;
    // Also converged when the step took (nearly) all the linear model promised and the
    // cost fell by what it predicted, to one noise variance: the model is linear over
    // the step, so a further step would gain less than that (and the design matrix for
    // it is half a fit's time). Not with a robust loss: its weights move each step.
    const double taken = linear_gain(damping);
    const bool linear = options.loss == Loss::least_squares && taken >= predicted_gain - chi1 &&
                        std::abs((before - after) - taken) <= chi1 && !has_blind_shape();
    if (before - after <= chi1 || linear) {
      report.converged = true;
      jacobian_current = false;  // not needed for another step: built only if asked for
      break;
    }
    design_matrix(model, p, data, free, r, &J);
  }
  if (m == 0) report.converged = true;
  // Never fit noise: a combination whose change moves the predictions by no more than the
  // noise would (3 sigma) is not supported by the data, and goes back to where it was.
  // Strong effects pass easily; a nearly invisible parameter (a yaw whose arm is zero)
  // would otherwise take any value the noise suggests.
  if (m > 0 && !identified_direction.empty()) {
    const double dof0 = std::max(1.0, static_cast<double>(n) - static_cast<double>(m));
    const double noise = std::sqrt((weight.cwiseSqrt().asDiagonal() * r).squaredNorm() / dof0);
    Eigen::VectorXd change(m);
    for (Eigen::Index j = 0; j < m; ++j)
      change[j] = (p[static_cast<Eigen::Index>(free[static_cast<std::size_t>(j)])] -
                   report.parameters[static_cast<std::size_t>(j)].before) *
                  scale[j];
    const Eigen::VectorXd c = V.transpose() * change;
    Eigen::VectorXd kept = Eigen::VectorXd::Zero(m);
    bool reverted = false;
    for (Eigen::Index k = 0; k < m; ++k) {
      if (!identified_direction[static_cast<std::size_t>(k)]) continue;
      if (sigma[k] * std::abs(c[k]) > kSignificant * noise)
        kept[k] = c[k], ++report.significant;
      else
        reverted = true;
    }
    if (reverted) {
      // Linear reasoning: a nonlinear parameter (a period) far from where it started may
      // not come back along a straight line. Keep the fit if reverting costs more than
      // the noise allows for what was reverted.
      Eigen::VectorXd back_p = p, back_r;
      const Eigen::VectorXd back = (V * kept).cwiseQuotient(scale);
      for (Eigen::Index j = 0; j < m; ++j)
        back_p[static_cast<Eigen::Index>(free[static_cast<std::size_t>(j)])] =
            report.parameters[static_cast<std::size_t>(j)].before + back[j];
      design_matrix(model, back_p, data, free, back_r, nullptr);
      const auto identifiable =
          static_cast<std::size_t>(std::count(identified_direction.begin(), identified_direction.end(), true));
      const auto reverted_count = static_cast<double>(identifiable - report.significant);
      if (cost(back_r) - cost(r) <= kSignificant * kSignificant * noise * noise * std::max(1.0, reverted_count)) {
        p = back_p;
        r = back_r;
        jacobian_current = false;
      } else {
        report.significant = identifiable;
      }
    }
  }
  bool unheld = false;
  for (const Eigen::Index j : blind) {  // held, to the bit (a revert's rounding included)
    const auto index = static_cast<Eigen::Index>(free[static_cast<std::size_t>(j)]);
    unheld = unheld || p[index] != start_p[index];
    p[index] = start_p[index];
  }
  if (unheld) {
    r = residuals(model, p, data);
    jacobian_current = false;
  }
  // Every accepted step lowered the cost; the revert of what the noise does not support
  // may raise it a little. A fit never ends worse than it started: then nothing moves.
  // (With the robust loss a move that lowers its own cost may raise the plain one: judged
  // by its own loss, each of its steps already lowered it.)
  if ((options.loss == Loss::least_squares && !(plain_cost(r) <= plain_cost(start_r))) || !p.allFinite()) {
    p = start_p;
    r = start_r;
    jacobian_current = false;
    report.significant = 0;
  }
  report.all_parameters = p;
  report.rms_after = rms(r);
  if (at_fit) {
    if (!jacobian_current) design_matrix(model, p, data, free, r, m > 0 ? &J : nullptr);
    at_fit->residuals = r;
    at_fit->jacobian = std::move(J);
  }
  report.max_after = r.size() ? r.cwiseAbs().maxCoeff() : 0.0;
  report.outliers = outliers_of(r, data);
  report.source_rms_after = rms_by_source(r, data);
  report.singular_values = sigma;
  // Identifiability, in words, and the uncertainty of what was identified.
  std::size_t rank = 0;
  for (bool b : identified_direction) rank += b ? 1 : 0;
  report.rank = rank;
  report.condition_number = rank > 0 ? sigma[0] / sigma[static_cast<Eigen::Index>(rank - 1)] : 0.0;
  const double dof = static_cast<double>(n) - static_cast<double>(rank);
  const double s2 = dof > 0 ? (weight.cwiseSqrt().asDiagonal() * r).squaredNorm() / dof : 0.0;
  for (Eigen::Index j = 0; j < m; ++j) {
    FittedParameter& fp = report.parameters[static_cast<std::size_t>(j)];
    fp.after = p[static_cast<Eigen::Index>(fp.index)];
    // Determined on its own when its unit vector (scaled) has next to nothing in the
    // directions the data cannot see: up to 1% of it there.
    double var = 0.0, unseen = 0.0;
    for (Eigen::Index k = 0; k < m; ++k) {
      if (identified_direction[static_cast<std::size_t>(k)])
        var += V(j, k) * V(j, k) / (sigma[k] * sigma[k]);
      else
        unseen += V(j, k) * V(j, k);
    }
    fp.uncertainty = std::sqrt(s2 * var) / scale[j];
    fp.identified = unseen <= 1e-4;
  }
  report.covariance_factor.setZero(m, m);
  for (Eigen::Index k = 0; k < m; ++k) {
    const bool seen = identified_direction[static_cast<std::size_t>(k)];
    // In physical scales; a direction the data know to about a scale no worse than one
    // they do not know at all (the residual's rms may exceed the noise floor it was judged on).
    const double sd = seen ? std::min(1.0, std::sqrt(s2) / sigma[k]) : 1.0;
    report.covariance_factor.row(k) = (sd * V.col(k).cwiseQuotient(scale)).transpose();
  }
  // A value far beyond what a machine plausibly has is what the data cannot say (a blind
  // direction, a wrong unit, a diverging fit), never a measurement: refused, named.
  for (const FittedParameter& fp : report.parameters) {
    const double plausible = physical[static_cast<Eigen::Index>(fp.index)];
    if (std::abs(fp.after - fp.before) > kImplausibleScales * plausible)
      report.refusals.push_back(
          fmt::format("{} moved by {:.4g} (internal units), {:.0f} times its physical scale {:.4g}", fp.label,
                      fp.after - fp.before, std::abs(fp.after - fp.before) / plausible, plausible));
  }
  {
    double largest = 0.0;
    std::uint32_t row = 0;
    for (std::size_t i = 0; i < data.observations.size(); ++i) {
      const double predicted = std::abs(data.observations[i].value - r[static_cast<Eigen::Index>(i)]);
      if (predicted > largest) largest = predicted, row = data.observations[i].row;
    }
    if (largest > mm.max_correction)
      report.refusals.push_back(
          fmt::format("the fitted model predicts {:.4g} mm at row {}, beyond the model's max_correction of {:.4g} mm",
                      largest, row, mm.max_correction));
  }
  if (std::string nothing = nothing_identifiable(report); !nothing.empty()) report.refusals.push_back(std::move(nothing));
  // In words: parameters the data do not see at all, then the combinations they cannot
  // separate or that the data do not support above the noise.
  std::string unseen;
  for (Eigen::Index j = 0; j < m; ++j)
    if (column_norm[j] <= 1e-12 * column_norm.maxCoeff())
      unseen += (unseen.empty() ? "" : ", ") + report.parameters[static_cast<std::size_t>(j)].label;
  if (!unseen.empty())
    report.unidentifiable.push_back(
        fmt::format("{}: no effect above 3 noise sigmas on these measurements; left as they were", unseen));
  for (Eigen::Index k = 0; k < m; ++k) {
    if (identified_direction[static_cast<std::size_t>(k)]) continue;
    std::vector<std::pair<double, std::size_t>> members;
    for (Eigen::Index j = 0; j < m; ++j)
      if (std::abs(V(j, k)) > 0.1 && column_norm[j] > 1e-12 * column_norm.maxCoeff())
        members.emplace_back(-std::abs(V(j, k)), static_cast<std::size_t>(j));
    std::sort(members.begin(), members.end());
    if (members.empty()) continue;
    if (members.size() > 6) members.resize(6);
    std::string combination;
    for (const auto& [w, j] : members)
      combination += fmt::format("{}{:+.2f} {}", combination.empty() ? "" : " ", V(static_cast<Eigen::Index>(j), k),
                                 report.parameters[j].label);
    // What would separate them: the two heaviest members of different terms.
    const auto parameter_of = [&](std::size_t j) {
      const FittedParameter& fp = report.parameters[j];
      return TermParameter{fp.term, fp.index - model.parameter_offset(fp.term)};
    };
    std::string measure;
    const TermParameter first = parameter_of(members.front().second);
    for (const auto& [w, j] : members)
      if (report.parameters[j].term != first.term) {
        measure = separating_parameters(mm, first, parameter_of(j));
        break;
      }
    if (measure.empty())
      measure = fmt::format("readings over more of the range its variable spans, or closer together, which show "
                            "the shape of {}'s error",
                            mm.terms[first.term].name);
    report.unidentifiable.push_back(
        fmt::format("{}: the data cannot separate these (relative singular value {:.1e}); "
                    "this combination is left as it was; to separate them: {}",
                    combination, sigma[0] > 0 ? sigma[k] / sigma[0] : 0.0, measure));
  }
  if (options.progress) options.progress(1.0);
  return report;
}

}  // namespace ccomp::identify
