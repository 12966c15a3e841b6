#pragma once
// The fit's stages, over one problem (what is asked: fixed while it runs) and one workspace
// (what moves). fit() (fit.cpp) runs them in order:
//   pose -> open -> hold_blind -> step ... -> revert_unsupported -> restore_held -> conclude
// Each stage reads the problem and changes only the workspace and the report.
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "ccomp/identify/fit.hpp"
#include "ccomp/identify/measurements.hpp"
#include "ccomp/model/forward.hpp"

namespace ccomp::identify::fit_stages {

/// A change the data support moves the predictions by more than this many noise sigmas:
/// the test a fit's step directions and its final changes both pass.
inline constexpr double kSignificant = 3.0;
/// A direction the data determine: one physical scale along it moves the predictions by
/// more than one noise sigma (its uncertainty is below one physical scale). Whether the
/// change found along it is kept is the 3-sigma test above, at the end.
inline constexpr double kDeterminable = 1.0;

struct Problem {
  const model::ForwardModel& model;
  const MeasurementSet& data;
  const FitOptions& options;
  std::vector<std::size_t> free;  ///< the model's index of each fitted parameter
  Eigen::VectorXd source_weight;  ///< per reading: its source's weight
  Eigen::VectorXd physical;       ///< per model parameter: its physical scale
  /// Per fitted parameter: a term's shape (a period, a time constant, a bump's place and
  /// width), whose column is zero while its amplitudes are.
  std::vector<bool> shape;

  [[nodiscard]] Eigen::Index readings() const { return source_weight.size(); }
  [[nodiscard]] Eigen::Index unknowns() const { return static_cast<Eigen::Index>(free.size()); }
  [[nodiscard]] Eigen::Index model_index(Eigen::Index j) const {
    return static_cast<Eigen::Index>(free[static_cast<std::size_t>(j)]);
  }
};

/// What the data determine, in scaled coordinates: singular values (descending), their
/// right singular vectors, which of them are determined, and those as columns.
struct Directions {
  Eigen::VectorXd sigma;
  Eigen::MatrixXd V;
  std::vector<bool> identified;
  Eigen::MatrixXd subspace;

  [[nodiscard]] std::size_t rank() const;
};

struct Workspace {
  Eigen::VectorXd p, r;  ///< all the model's parameters, and the residuals there
  Eigen::MatrixXd J;     ///< the design matrix (fitted parameters' columns) at p while jacobian_current
  Eigen::VectorXd start_p, start_r;
  Eigen::VectorXd weight;       ///< per reading: the source's weight times the robust loss'
  Eigen::VectorXd scale;        ///< per fitted parameter: 1 / its physical scale
  Eigen::VectorXd column_norm;  ///< per fitted parameter: its weighted column's length when decided
  std::vector<Eigen::Index> blind;  ///< fitted parameters held exactly: the data do not see them
  Directions directions;
  double lambda = 0.0;  ///< Levenberg-Marquardt damping, relative to the largest singular value squared
  bool jacobian_current = true;

  /// The weighted sum of squares of `residuals` under the current weights.
  [[nodiscard]] double cost(const Eigen::VectorXd& residuals) const;
};

/// The problem, or a data error where there are fewer readings than free parameters.
[[nodiscard]] Problem pose(const model::ForwardModel& model, const MeasurementSet& data, const FitOptions& options);

/// The workspace at the model's parameters, and the report's opening: the parameters, the
/// rms before, the noise floor.
void open(const Problem& problem, Workspace& ws, FitReport& report);

/// The fitted parameters the data do not see on their own (a spindle's yaw when every tool
/// tip sits on its axis): held exactly, no part in any step. Not a shape whose amplitudes
/// are still zero: decided once they move.
void hold_blind(const Problem& problem, double noise, Workspace& ws);

enum class StepOutcome {
  stepped,              ///< the cost fell; iterate again
  waiting_for_weights,  ///< nothing to gain before the robust weights are in
  converged,
};

/// One damped Gauss-Newton step within the identified directions (deciding them first at
/// iteration 0, and once more at 1 where a shape was blind).
[[nodiscard]] StepOutcome step(const Problem& problem, double noise, int iteration, Workspace& ws);

/// Never fit noise: a combination whose change moves the predictions by no more than 3
/// noise sigmas goes back to where it was (unless reverting costs more than the noise allows).
void revert_unsupported(const Problem& problem, Workspace& ws, FitReport& report);

/// The held parameters back to the bit; and a fit never ends worse than it started.
void restore_held(const Problem& problem, Workspace& ws, FitReport& report);

/// The report's figures, uncertainties, refusals and words on what is not identifiable;
/// the linearisation at the result when asked.
void conclude(const Problem& problem, Workspace& ws, FitReport& report, Linearization* at_fit);

}  // namespace ccomp::identify::fit_stages
