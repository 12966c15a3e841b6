#include "projector.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "ccomp/identify/physical_scale.hpp"
#include "symmetric_eigen.hpp"

namespace ccomp::identify::detail {

Eigen::MatrixXd Projector::At_on_rows(const std::vector<Eigen::Index>& rows, const Eigen::MatrixXd& C) const {
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

double Projector::left_over(const Eigen::Ref<const Eigen::VectorXd>& c,
                            const Eigen::Ref<const Eigen::VectorXd>& Atc) const {
  const Eigen::VectorXd Utc = W.transpose() * Atc;
  return c.squaredNorm() - Utc.squaredNorm();
}

double Projector::gain(const Eigen::Ref<const Eigen::MatrixXd>& C, const Eigen::Ref<const Eigen::VectorXd>& r_rows,
                       const Eigen::Ref<const Eigen::MatrixXd>& AtC, Eigen::VectorXd* coefficients) const {
  return gain_of_sums(C.transpose() * C, C.transpose() * r_rows, AtC, coefficients);
}

double Projector::gain_of_sums(const Eigen::MatrixXd& CtC, const Eigen::VectorXd& b,
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
  const SymmetricEigen eig = symmetric_eigen(Ns);
  // Columns that are nearly one another once the base is out: the candidate is not one effect.
  if (eig.values.minCoeff() < 1e-6) return 0.0;
  const Eigen::VectorXd xs =
      eig.vectors * (eig.vectors.transpose() * bs).cwiseQuotient(eig.values);
  if (coefficients) *coefficients = xs.cwiseQuotient(d);
  return bs.dot(xs);
}

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
    const SymmetricEigen eig = symmetric_eigen(normal_matrix(base.A));
    const double largest = std::sqrt(std::max(eig.values.maxCoeff(), 0.0));
    const double seen = std::max(3.0 * out.refit.noise, 1e-9 * largest);
    std::vector<Eigen::Index> kept;
    for (Eigen::Index k = 0; k < eig.values.size(); ++k)
      if (std::sqrt(std::max(eig.values[k], 0.0)) > seen) kept.push_back(k);
    base.W.resize(base.A.cols(), static_cast<Eigen::Index>(kept.size()));
    for (std::size_t c = 0; c < kept.size(); ++c)
      base.W.col(static_cast<Eigen::Index>(c)) =
          eig.vectors.col(kept[c]) / std::sqrt(eig.values[kept[c]]);
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

}  // namespace ccomp::identify::detail
