#include "fit_stages.hpp"

#include <fmt/format.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "ccomp/error.hpp"
#include "ccomp/identify/check.hpp"
#include "ccomp/identify/next_measurement.hpp"
#include "ccomp/identify/physical_scale.hpp"
#include "ccomp/model/term_forms.hpp"
#include "symmetric_eigen.hpp"

namespace ccomp::identify::fit_stages {

std::size_t Directions::rank() const {
  return static_cast<std::size_t>(std::count(identified.begin(), identified.end(), true));
}

double Workspace::cost(const Eigen::VectorXd& residuals) const {
  return (weight.cwiseSqrt().asDiagonal() * residuals).squaredNorm();
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

/// The term whose parameters hold the model's parameter `index`.
std::size_t term_of_parameter(const model::ForwardModel& model, std::size_t index) {
  std::size_t t = 0;
  while (t + 1 < model.machine().terms.size() && model.parameter_offset(t + 1) <= index) ++t;
  return t;
}

}  // namespace

Problem pose(const model::ForwardModel& model, const MeasurementSet& data, const FitOptions& options) {
  Problem problem{model, data, options, free_parameters(model), {}, {}, {}};
  if (data.observations.size() < problem.free.size())
    throw Error(ErrorKind::data,
                fmt::format("{} readings cannot determine {} free parameters: a fit needs at least as many readings "
                            "(measure more, or free fewer terms)",
                            data.observations.size(), problem.free.size()),
                SourceLocation{data.files.empty() ? std::string() : data.files.front(), 0, 0});
  const auto n = static_cast<Eigen::Index>(data.observations.size());
  problem.source_weight = Eigen::VectorXd::Ones(n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (const auto& [label, w] : options.source_weights)
      if (data.sources[data.observations[static_cast<std::size_t>(i)].source] == label) problem.source_weight[i] = w;
  problem.physical = physical_scales(model, data);
  for (const std::size_t index : problem.free) {
    const std::size_t t = term_of_parameter(model, index);
    problem.shape.push_back(
        model::term_form(model.machine().terms[t].shape.form).shapes_only(index - model.parameter_offset(t)));
  }
  return problem;
}

void open(const Problem& problem, Workspace& ws, FitReport& report) {
  const model::ForwardModel& model = problem.model;
  const MeasurementSet& data = problem.data;
  report.observations = data.observations.size();
  ws.p = model_parameters(model);
  for (const std::size_t index : problem.free) {
    const std::size_t t = term_of_parameter(model, index);
    const std::size_t k = index - model.parameter_offset(t);
    const double value = ws.p[static_cast<Eigen::Index>(index)];
    report.parameters.push_back({index, t, parameter_label(model.machine().terms[t], k), value, value, 0.0, true});
  }
  design_matrix(model, ws.p, data, problem.free, ws.r, problem.free.empty() ? nullptr : &ws.J);
  report.rms_before = rms(ws.r);
  report.source_rms_before = rms_by_source(ws.r, data);
  // Where the fit starts, to end no worse: the plain weighted least squares, whatever loss.
  ws.start_p = ws.p, ws.start_r = ws.r;
  ws.weight = problem.source_weight;
  const Eigen::Index m = problem.unknowns();
  ws.scale = Eigen::VectorXd::Ones(m), ws.column_norm = Eigen::VectorXd::Zero(m);
  report.noise = noise_floor(data, ws.r).value;
}

void hold_blind(const Problem& problem, double noise, Workspace& ws) {
  const Eigen::Index m = problem.unknowns();
  if (m == 0) return;
  // Each parameter in its physical scale (10 um, 10 urad, over the variable's reach): it
  // is seen when moving one scale changes the predictions by more than the noise would
  // (3 sigma), not when its column merely has a length.
  Eigen::VectorXd effect(m);
  for (Eigen::Index j = 0; j < m; ++j)
    effect[j] = std::sqrt(problem.source_weight.dot(ws.J.col(j).cwiseAbs2())) * problem.physical[problem.model_index(j)];
  for (Eigen::Index j = 0; j < m; ++j)
    if (!problem.shape[static_cast<std::size_t>(j)] &&
        !(effect[j] > std::max(kSignificant * noise, problem.options.rank_tolerance * effect.maxCoeff())))
      ws.blind.push_back(j);
}

namespace {

/// A shape whose column was zero when the rank was decided (its amplitudes were zero):
/// blind then, decided again once they have moved.
bool has_blind_shape(const Problem& problem, const Workspace& ws) {
  for (Eigen::Index j = 0; j < problem.unknowns(); ++j)
    if (problem.shape[static_cast<std::size_t>(j)] && ws.column_norm[j] == 0.0) return true;
  return false;
}

/// Huber's weights from the robust scale (the median absolute residual's): rows beyond
/// 1.345 of it count linearly.
void robust_weights(const Problem& problem, Workspace& ws) {
  Eigen::VectorXd a = ws.r.cwiseAbs();
  std::nth_element(a.data(), a.data() + a.size() / 2, a.data() + a.size());
  const double s = std::max(1.4826 * a[a.size() / 2], 1e-12);
  for (Eigen::Index i = 0; i < problem.readings(); ++i)
    ws.weight[i] = problem.source_weight[i] * std::min(1.0, 1.345 * s / std::max(std::abs(ws.r[i]), 1e-300));
}

/// Descending singular values of the scaled normal matrix N, their right singular vectors,
/// and which of them the data determine.
Directions determined_directions(const Problem& problem, double noise, const Eigen::MatrixXd& N) {
  const Eigen::Index m = problem.unknowns();
  Directions d;
  const SymmetricEigen eig = symmetric_eigen(N);
  d.sigma = eig.values.cwiseMax(0.0).cwiseSqrt().reverse();
  d.V = eig.vectors.rowwise().reverse();
  const double largest = d.sigma.size() ? d.sigma[0] : 0.0;
  d.identified.assign(static_cast<std::size_t>(m), false);
  std::vector<Eigen::Index> kept;
  for (Eigen::Index k = 0; k < m; ++k)
    if (d.sigma[k] > std::max(kDeterminable * noise, problem.options.rank_tolerance * largest) && d.sigma[k] > 0) {
      d.identified[static_cast<std::size_t>(k)] = true;
      kept.push_back(k);
    }
  d.subspace.resize(m, static_cast<Eigen::Index>(kept.size()));
  for (std::size_t c = 0; c < kept.size(); ++c) d.subspace.col(static_cast<Eigen::Index>(c)) = d.V.col(kept[c]);
  return d;
}

}  // namespace

StepOutcome step(const Problem& problem, double noise, int iteration, Workspace& ws) {
  const Eigen::Index m = problem.unknowns(), n = problem.readings();
  if (problem.options.loss == Loss::huber && iteration > 0) robust_weights(problem, ws);
  // Columns scaled to unit length, so the singular values compare parameters of any unit.
  // What the data determine is decided from the start, and once more after the first step
  // if a shape was blind then (until its amplitudes move): deciding again every iteration
  // lets combinations at the threshold drift in and fit noise.
  const bool decide = iteration == 0 || (iteration == 1 && has_blind_shape(problem, ws));
  if (decide)
    for (Eigen::Index j = 0; j < m; ++j) {
      ws.column_norm[j] = std::sqrt(ws.weight.dot(ws.J.col(j).cwiseAbs2()));
      ws.scale[j] = 1.0 / problem.physical[problem.model_index(j)];
    }
  // A = sqrt(W) J S^-1 is never formed (a copy of the whole design matrix): its normal
  // matrix and gradient come from J and are scaled after.
  const bool unit_weights = (ws.weight.array() == 1.0).all();
  Eigen::MatrixXd N = ws.scale.cwiseInverse().asDiagonal() * normal_matrix(ws.J, unit_weights ? nullptr : &ws.weight) *
                      ws.scale.cwiseInverse().asDiagonal();
  Eigen::VectorXd g = (ws.J.transpose() * ws.weight.cwiseProduct(ws.r)).cwiseQuotient(ws.scale);
  for (const Eigen::Index j : ws.blind) {  // held: no part in the normal equations
    N.row(j).setZero();
    N.col(j).setZero();
    g[j] = 0.0;
    ws.column_norm[j] = 0.0;
  }
  if (decide) ws.directions = determined_directions(problem, noise, N);
  // No direction above the noise floor (a short stroke, few targets, one run): nothing to
  // step along, and nothing to decompose (Eigen's solver of an empty matrix faults).
  const Eigen::MatrixXd& subspace = ws.directions.subspace;
  if (subspace.cols() == 0) return StepOutcome::converged;
  // Levenberg-Marquardt within the identified subspace: where the cost does not fall, the
  // weak directions are damped first (lambda), not the whole step (a period far from its
  // start is not quadratic).
  const SymmetricEigen reduced = symmetric_eigen(subspace.transpose() * N * subspace);
  const Eigen::VectorXd mu = reduced.values.cwiseMax(0.0);
  const Eigen::MatrixXd Q = subspace * reduced.vectors;
  const Eigen::VectorXd Qg = Q.transpose() * g;
  const double largest = mu.size() ? mu.maxCoeff() : 0.0;
  const double before = ws.cost(ws.r);
  // Only directions whose step gains more than the noise would (chi-square by 9, the test
  // the end of the fit applies before keeping a change) are stepped along. The rest is
  // noise: there the least-squares step is long (noise over a small singular value), the
  // model is no longer linear that far out, and the full step fails and is damped back
  // over several passes over the data, only to be reverted at the end. The noise: what
  // the linear model leaves after the full step (from a poor start the residual now is
  // mostly model error, and would hide real effects).
  const Eigen::VectorXd direction_gain =
      (mu.array() > 0).select(Qg.cwiseAbs2().cwiseQuotient(mu.cwiseMax(1e-300)), 0.0);
  const double noise2 = std::max(before - direction_gain.sum(), 0.0) /
                        std::max(1.0, static_cast<double>(n) - static_cast<double>(subspace.cols()));
  Eigen::VectorXd stepped_Qg = Qg;
  // What the step would gain on the local linear model. Below what counts as convergence
  // (see below) no trial is worth its pass over the data: at the optimum every trial
  // fails, and each costs one.
  double predicted_gain = 0.0;
  for (Eigen::Index k = 0; k < mu.size(); ++k) {
    if (direction_gain[k] > kSignificant * kSignificant * noise2)
      predicted_gain += direction_gain[k];
    else
      stepped_Qg[k] = 0.0;
  }
  if (predicted_gain <= before / static_cast<double>(n) + 1e-30) {
    // From a least-squares optimum (a model a plain fit wrote) nothing moves before the
    // robust weights are in: they come at the next iteration.
    if (problem.options.loss == Loss::huber && iteration == 0) return StepOutcome::waiting_for_weights;
    return StepOutcome::converged;
  }
  auto step_for = [&](double damping) {
    const Eigen::VectorXd dp = Q * stepped_Qg.cwiseQuotient((mu.array() + damping).max(1e-300).matrix());
    return Eigen::VectorXd(dp.cwiseQuotient(ws.scale));
  };
  // What the step with a damping gains on the linear model.
  auto linear_gain = [&](double damping) {
    const Eigen::ArrayXd y = stepped_Qg.array() / (mu.array() + damping).max(1e-300);
    return (y * (2.0 * stepped_Qg.array() - mu.array() * y)).sum();
  };
  Eigen::VectorXd trial_p = ws.p, trial_r;
  bool improved = false;
  double damping = 0.0;
  for (int attempt = 0; attempt < 24; ++attempt) {
    damping = ws.lambda * largest;
    Eigen::VectorXd dp = step_for(damping);
    for (const Eigen::Index j : ws.blind) dp[j] = 0.0;  // exactly: not even the rounding of Q
    trial_p = ws.p;
    for (Eigen::Index j = 0; j < m; ++j) trial_p[problem.model_index(j)] += dp[j];
    design_matrix(problem.model, trial_p, problem.data, problem.free, trial_r, nullptr);
    if (ws.cost(trial_r) <= before) {
      improved = true;
      ws.lambda = std::max(ws.lambda * 0.1, 1e-12);
      break;
    }
    ws.lambda = ws.lambda > 0 ? ws.lambda * 10.0 : 1e-8;
  }
  if (!improved) return StepOutcome::converged;
  const double after = ws.cost(trial_r);
  ws.p = trial_p;
  ws.r = std::move(trial_r);
  // Converged when an iteration gains less than one reading's noise variance (chi-square
  // by 1, what a single parameter's one-sigma change is worth): what is left to gain is not
  // information the data hold.
  const double chi1 = before / static_cast<double>(n) + 1e-30;
  // Also converged when the step took (nearly) all the linear model promised and the cost
  // fell by what it predicted, to one noise variance: the model is linear over the step,
  // so a further step would gain less than that (and the design matrix for it is half a
  // fit's time). Not with a robust loss: its weights move each step.
  const double taken = linear_gain(damping);
  const bool linear = problem.options.loss == Loss::least_squares && taken >= predicted_gain - chi1 &&
                      std::abs((before - after) - taken) <= chi1 && !has_blind_shape(problem, ws);
  if (before - after <= chi1 || linear) {
    ws.jacobian_current = false;  // not needed for another step: built only if asked for
    return StepOutcome::converged;
  }
  design_matrix(problem.model, ws.p, problem.data, problem.free, ws.r, &ws.J);
  return StepOutcome::stepped;
}

void revert_unsupported(const Problem& problem, Workspace& ws, FitReport& report) {
  const Eigen::Index m = problem.unknowns(), n = problem.readings();
  const Directions& d = ws.directions;
  if (m == 0 || d.identified.empty()) return;
  // Strong effects pass easily; a nearly invisible parameter (a yaw whose arm is zero)
  // would otherwise take any value the noise suggests.
  const double dof0 = std::max(1.0, static_cast<double>(n) - static_cast<double>(m));
  const double noise = std::sqrt(ws.cost(ws.r) / dof0);
  Eigen::VectorXd change(m);
  for (Eigen::Index j = 0; j < m; ++j)
    change[j] = (ws.p[problem.model_index(j)] - ws.start_p[problem.model_index(j)]) * ws.scale[j];
  const Eigen::VectorXd c = d.V.transpose() * change;
  Eigen::VectorXd kept = Eigen::VectorXd::Zero(m);
  bool reverted = false;
  for (Eigen::Index k = 0; k < m; ++k) {
    if (!d.identified[static_cast<std::size_t>(k)]) continue;
    if (d.sigma[k] * std::abs(c[k]) > kSignificant * noise)
      kept[k] = c[k], ++report.significant;
    else
      reverted = true;
  }
  if (!reverted) return;
  // Linear reasoning: a nonlinear parameter (a period) far from where it started may not
  // come back along a straight line. Keep the fit if reverting costs more than the noise
  // allows for what was reverted.
  Eigen::VectorXd back_p = ws.p, back_r;
  const Eigen::VectorXd back = (d.V * kept).cwiseQuotient(ws.scale);
  for (Eigen::Index j = 0; j < m; ++j) back_p[problem.model_index(j)] = ws.start_p[problem.model_index(j)] + back[j];
  design_matrix(problem.model, back_p, problem.data, problem.free, back_r, nullptr);
  const std::size_t identifiable = d.rank();
  const auto reverted_count = static_cast<double>(identifiable - report.significant);
  if (ws.cost(back_r) - ws.cost(ws.r) <= kSignificant * kSignificant * noise * noise * std::max(1.0, reverted_count)) {
    ws.p = back_p;
    ws.r = back_r;
    ws.jacobian_current = false;
  } else {
    report.significant = identifiable;
  }
}

void restore_held(const Problem& problem, Workspace& ws, FitReport& report) {
  bool unheld = false;
  for (const Eigen::Index j : ws.blind) {  // held, to the bit (a revert's rounding included)
    const Eigen::Index index = problem.model_index(j);
    unheld = unheld || ws.p[index] != ws.start_p[index];
    ws.p[index] = ws.start_p[index];
  }
  if (unheld) {
    ws.r = residuals(problem.model, ws.p, problem.data);
    ws.jacobian_current = false;
  }
  // Every accepted step lowered the cost; the revert of what the noise does not support
  // may raise it a little. A fit never ends worse than it started: then nothing moves.
  // (With the robust loss a move that lowers its own cost may raise the plain one: judged
  // by its own loss, each of its steps already lowered it.)
  auto plain_cost = [&](const Eigen::VectorXd& res) {
    return (problem.source_weight.cwiseSqrt().asDiagonal() * res).squaredNorm();
  };
  if ((problem.options.loss == Loss::least_squares && !(plain_cost(ws.r) <= plain_cost(ws.start_r))) ||
      !ws.p.allFinite()) {
    ws.p = ws.start_p;
    ws.r = ws.start_r;
    ws.jacobian_current = false;
    report.significant = 0;
  }
}

namespace {

/// Each fitted parameter's value and uncertainty, whether it is determined on its own, and
/// the covariance's factor (in physical scales).
void uncertainties(const Problem& problem, const Workspace& ws, FitReport& report) {
  const Eigen::Index m = problem.unknowns();
  const Directions& d = ws.directions;
  const double dof = static_cast<double>(problem.readings()) - static_cast<double>(report.rank);
  const double s2 = dof > 0 ? ws.cost(ws.r) / dof : 0.0;
  for (Eigen::Index j = 0; j < m; ++j) {
    FittedParameter& fp = report.parameters[static_cast<std::size_t>(j)];
    fp.after = ws.p[static_cast<Eigen::Index>(fp.index)];
    // Determined on its own when its unit vector (scaled) has next to nothing in the
    // directions the data cannot see: up to 1% of it there.
    double var = 0.0, unseen = 0.0;
    for (Eigen::Index k = 0; k < m; ++k) {
      if (d.identified[static_cast<std::size_t>(k)])
        var += d.V(j, k) * d.V(j, k) / (d.sigma[k] * d.sigma[k]);
      else
        unseen += d.V(j, k) * d.V(j, k);
    }
    fp.uncertainty = std::sqrt(s2 * var) / ws.scale[j];
    fp.identified = unseen <= 1e-4;
  }
  report.covariance_factor.setZero(m, m);
  for (Eigen::Index k = 0; k < m; ++k) {
    const bool seen = d.identified[static_cast<std::size_t>(k)];
    // In physical scales; a direction the data know to about a scale no worse than one
    // they do not know at all (the residual's rms may exceed the noise floor it was judged on).
    const double sd = seen ? std::min(1.0, std::sqrt(s2) / d.sigma[k]) : 1.0;
    report.covariance_factor.row(k) = (sd * d.V.col(k).cwiseQuotient(ws.scale)).transpose();
  }
}

/// A value far beyond what a machine plausibly has is what the data cannot say (a blind
/// direction, a wrong unit, a diverging fit), never a measurement: refused, named; so is a
/// model predicting beyond its max_correction, and a fit that identified nothing.
void refusals(const Problem& problem, const Workspace& ws, FitReport& report) {
  for (const FittedParameter& fp : report.parameters) {
    const double plausible = problem.physical[static_cast<Eigen::Index>(fp.index)];
    if (std::abs(fp.after - fp.before) > kImplausibleScales * plausible)
      report.refusals.push_back(
          fmt::format("{} moved by {:.4g} (internal units), {:.0f} times its physical scale {:.4g}", fp.label,
                      fp.after - fp.before, std::abs(fp.after - fp.before) / plausible, plausible));
  }
  const MeasurementSet& data = problem.data;
  double largest = 0.0;
  std::uint32_t row = 0;
  for (std::size_t i = 0; i < data.observations.size(); ++i) {
    const double predicted = std::abs(data.observations[i].value - ws.r[static_cast<Eigen::Index>(i)]);
    if (predicted > largest) largest = predicted, row = data.observations[i].row;
  }
  const double max_correction = problem.model.machine().max_correction;
  if (largest > max_correction)
    report.refusals.push_back(
        fmt::format("the fitted model predicts {:.4g} mm at row {}, beyond the model's max_correction of {:.4g} mm",
                    largest, row, max_correction));
  if (std::string nothing = nothing_identifiable(report); !nothing.empty()) report.refusals.push_back(std::move(nothing));
}

/// In words: the parameters the data do not see at all, then the combinations they cannot
/// separate or do not support above the noise, each with what would separate it.
void unidentifiable(const Problem& problem, const Workspace& ws, FitReport& report) {
  const Eigen::Index m = problem.unknowns();
  const Directions& d = ws.directions;
  const model::MachineModel& mm = problem.model.machine();
  if (m == 0) return;
  const double seen_norm = 1e-12 * ws.column_norm.maxCoeff();
  std::string unseen;
  for (Eigen::Index j = 0; j < m; ++j)
    if (ws.column_norm[j] <= seen_norm)
      unseen += (unseen.empty() ? "" : ", ") + report.parameters[static_cast<std::size_t>(j)].label;
  if (!unseen.empty())
    report.unidentifiable.push_back(
        fmt::format("{}: no effect above 3 noise sigmas on these measurements; left as they were", unseen));
  const auto parameter_of = [&](std::size_t j) {
    const FittedParameter& fp = report.parameters[j];
    return TermParameter{fp.term, fp.index - problem.model.parameter_offset(fp.term)};
  };
  for (Eigen::Index k = 0; k < m; ++k) {
    if (d.identified[static_cast<std::size_t>(k)]) continue;
    std::vector<std::pair<double, std::size_t>> members;
    for (Eigen::Index j = 0; j < m; ++j)
      if (std::abs(d.V(j, k)) > 0.1 && ws.column_norm[j] > seen_norm)
        members.emplace_back(-std::abs(d.V(j, k)), static_cast<std::size_t>(j));
    std::sort(members.begin(), members.end());
    if (members.empty()) continue;
    if (members.size() > 6) members.resize(6);
    std::string combination;
    for (const auto& [w, j] : members)
      combination += fmt::format("{}{:+.2f} {}", combination.empty() ? "" : " ", d.V(static_cast<Eigen::Index>(j), k),
                                 report.parameters[j].label);
    // What would separate them: the two heaviest members of different terms.
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
    report.unidentifiable.push_back(fmt::format("{}: the data cannot separate these (relative singular value {:.1e}); "
                                                "this combination is left as it was; to separate them: {}",
                                                combination, d.sigma[0] > 0 ? d.sigma[k] / d.sigma[0] : 0.0, measure));
  }
}

}  // namespace

void conclude(const Problem& problem, Workspace& ws, FitReport& report, Linearization* at_fit) {
  const MeasurementSet& data = problem.data;
  report.all_parameters = ws.p;
  report.rms_after = rms(ws.r);
  if (at_fit) {
    if (!ws.jacobian_current)
      design_matrix(problem.model, ws.p, data, problem.free, ws.r, problem.unknowns() > 0 ? &ws.J : nullptr);
    at_fit->residuals = ws.r;
    at_fit->jacobian = std::move(ws.J);
  }
  report.max_after = ws.r.size() ? ws.r.cwiseAbs().maxCoeff() : 0.0;
  report.outliers = outliers_of(ws.r, data);
  report.source_rms_after = rms_by_source(ws.r, data);
  const Directions& d = ws.directions;
  report.singular_values = d.sigma;
  report.rank = d.rank();
  report.condition_number = report.rank > 0 ? d.sigma[0] / d.sigma[static_cast<Eigen::Index>(report.rank - 1)] : 0.0;
  uncertainties(problem, ws, report);
  refusals(problem, ws, report);
  unidentifiable(problem, ws, report);
}

}  // namespace ccomp::identify::fit_stages
