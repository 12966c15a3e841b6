#pragma once
// What the refitted base model can absorb of a candidate's columns: diagnose() scores every
// candidate against it, the scanned ones through scanners.hpp.
#include <Eigen/Core>
#include <vector>

#include "candidates.hpp"
#include "ccomp/identify/diagnose.hpp"
#include "ccomp/identify/fit.hpp"
#include "ccomp/identify/measurements.hpp"
#include "ccomp/model/forward.hpp"

namespace ccomp::identify::detail {

/// The refitted model's residual and what its free parameters can absorb.
struct Projector {
  Eigen::VectorXd r;  // residual, orthogonal to the base columns
  Eigen::MatrixXd A;  // the base's columns (the refit's design matrix), scaled to unit length: n x m
  Eigen::MatrixXd W;  // m x k: A W is an orthonormal basis of the combinations the data identify

  /// A^T C over some rows (C has a row per one of them): the base's rows gathered a block at
  /// a time, never a copy of A on each probe's rows (rows x m per probe was much of check's
  /// memory on a large file).
  [[nodiscard]] Eigen::MatrixXd At_on_rows(const std::vector<Eigen::Index>& rows, const Eigen::MatrixXd& C) const;

  /// The sum of squares of column c (A^T c given) that the base cannot absorb.
  [[nodiscard]] double left_over(const Eigen::Ref<const Eigen::VectorXd>& c,
                                 const Eigen::Ref<const Eigen::VectorXd>& Atc) const;

  /// The fall in the sum of squares when columns C join the base fit, and their
  /// coefficients. C is given on some rows (a probe's), `r_rows` is the residual there
  /// and `AtC` is A^T C over the same rows (m x C.cols()). U = A W is never formed: what
  /// the base absorbs of C is W^T (A^T C), and A^T C is one product for many candidates.
  double gain(const Eigen::Ref<const Eigen::MatrixXd>& C, const Eigen::Ref<const Eigen::VectorXd>& r_rows,
              const Eigen::Ref<const Eigen::MatrixXd>& AtC, Eigen::VectorXd* coefficients) const;

  /// The same from the sums over the rows: C^T C, C^T r and A^T C (fixed_sums.hpp).
  double gain_of_sums(const Eigen::MatrixXd& CtC, const Eigen::VectorXd& b,
                      const Eigen::Ref<const Eigen::MatrixXd>& AtC, Eigen::VectorXd* coefficients) const;
};

/// The base model refitted to the data (into `out.refit`, `out.rms_refit`) and what its free
/// parameters can absorb, with the probes' columns: one pass over the data, with a model
/// that has the probes as terms (zero: its predictions are the refit's), gives the base's
/// columns and the probes' alike.
[[nodiscard]] Projector refitted_base(const model::ForwardModel& model, const MeasurementSet& data,
                                      std::vector<Probe>& probes, const FitOptions& fit_options, Diagnosis& out);

/// Each probe's rows (where its column is not zero), and the base's residual on them.
void probe_rows(const Projector& base, Eigen::Index n, std::vector<Probe>& probes);

}  // namespace ccomp::identify::detail
