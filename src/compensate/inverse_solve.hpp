#pragma once
// The inverse's three parts, which solve_inverse() (inverse.cpp) runs in order for a point:
//   path_predictor.cpp    where the solve starts: the last solution moved along the path
//   bounded_shortcut.cpp  the start accepted as it is where the error field's bound holds it
//   newton_solve.cpp      else Newton's method on the exact model from there
// and then the predictor learns from the solution. One point's solve state (SolveStart)
// passes between them; each part keeps its own share of the workspace.
#include <Eigen/Core>
#include <cstdint>

#include "ccomp/compensate/inverse.hpp"
#include "path_nodes.hpp"

namespace ccomp::compensate::detail {

using model::ChainQ;
using Step = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 9, 1>;
using Residual = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1>;  ///< over the equations

/// v over the problem's unknowns.
inline Step over_unknowns(const InverseProblem& problem, const ChainQ& v) {
  Step out(static_cast<Eigen::Index>(problem.unknowns.size()));
  for (Eigen::Index c = 0; c < out.size(); ++c) out[c] = v[problem.unknowns[static_cast<std::size_t>(c)]];
  return out;
}

/// q += sign * step, the step given over the problem's unknowns.
inline void move_unknowns(const InverseProblem& problem, ChainQ& q, const Step& step, double sign) {
  for (std::size_t c = 0; c < problem.unknowns.size(); ++c)
    q[problem.unknowns[c]] += sign * step[static_cast<Eigen::Index>(c)];
}

// The solve's small products (n <= 9 unknowns, m <= 6 equations), written out: Eigen's
// loops for sizes known only at run time cost more than the products themselves, at
// every point of a program.

/// The solve matrix's first three columns (the position equations) times v.
inline Step position_columns_times(const SolveMatrix& S, const Eigen::Vector3d& v) {
  Step out(S.rows());
  for (Eigen::Index c = 0; c < S.rows(); ++c) out[c] = S(c, 0) * v.x() + S(c, 1) * v.y() + S(c, 2) * v.z();
  return out;
}

/// S r, r over the equations.
template <typename Equations>
Step solve_matrix_times(const SolveMatrix& S, const Equations& r) {
  Step out(S.rows());
  for (Eigen::Index c = 0; c < S.rows(); ++c) {
    double sum = 0.0;
    for (Eigen::Index e = 0; e < S.cols(); ++e) sum += S(c, e) * r[e];
    out[c] = sum;
  }
  return out;
}

/// Where a solve starts and what it knows of the last one.
struct SolveStart {
  Eigen::Vector3d target;  ///< where the tool tip would be on a perfect machine
  Eigen::Matrix3d R_target;
  ChainQ q;            ///< the first iterate
  ChainQ program;      ///< the program's axis values (what a damped correction keeps to)
  ChainQ first_order;  ///< the prediction before the last miss is added
  /// The approach changed since the last solution (a play taken up, an axis reversed): each
  /// changed axis' learnt effect on the solution, where every one is known.
  ChainQ approach_step;  ///< set where the approach changed
  int approach_changes = 0;
  std::size_t changed_axis = 0;
  bool approach_known = true;
  bool turned = false;       ///< the target's orientation differs from the last one's
  bool predicted = false;    ///< q is the last solution moved along the path
  bool same_target = false;  ///< solved again where it was, for another approach
  Eigen::Vector3d shift;     ///< the target's move since the last solution
  ChainQ evaluated;          ///< where the model was last evaluated (set once converged)
  Eigen::Vector3d evaluated_omega;  ///< the orientation residual there
  /// The evaluated iterate stands as the solution, its residual known (see iterate()); q
  /// then goes on to what the next prediction starts from.
  bool stands = false;
  bool on_path = false;  ///< a point the nodes' line reaches, that the bound did not let through
  double standing_residual = 0.0;  ///< mm, the rotary residual's share included
};

/// How a solution was reached: by evaluating the model, or accepted on the nodes' bound.
enum class Reached : std::uint8_t { evaluated, on_bound };

// The path predictor (path_predictor.cpp).

/// The first iterate. Without a prediction: the guess, else this point shifted by the last
/// solution's correction (neighbouring points correct alike), else the nominal point. With
/// the same orientation to reach: the last solution moved by the target's shift through the
/// last Jacobian (first order; its rotary equations are unchanged) and by each changed
/// approach's learnt effect, plus the last miss where this step repeats the last one (within
/// 10% and 2.5 degrees). What the solve does not move (the tool length) is this point's.
/// Where the target turned, the solve matrix's position columns turn with it.
[[nodiscard]] SolveStart start_of(const InverseProblem& problem, InverseWorkspace& ws, const ChainQ& q_nominal,
                                  const model::Conditions& conditions, const ChainQ* guess,
                                  const Eigen::Vector3d& target, const Eigen::Matrix3d& R_target);

/// What the next solve predicts from: the solve matrix made exact along the step just taken,
/// a changed approach's effect, the path's last step and miss, the solution itself.
void learn(const InverseProblem& problem, InverseWorkspace& ws, const ChainQ& q_nominal,
           const model::Conditions& conditions, const SolveStart& s, Reached reached);

// The bounded shortcut (bounded_shortcut.cpp).

/// Whether the shortcut applies: it bounds at most one rotary axis' residual.
[[nodiscard]] bool shortcut_applies(const InverseProblem& problem);

/// Accepts the prediction s.q where the nodes bound its residual below the caller's
/// tolerance (see path_nodes.hpp); r gets the extrapolated residuals and the bound,
/// `residual` them over the equations.
[[nodiscard]] bool accept_on_bound(const InverseProblem& problem, const model::Conditions& conditions,
                                   const InverseOptions& options, const InverseWorkspace& ws, const SolveStart& s,
                                   InverseResult& r, Residual& residual, bool& on_path, LinePoint& kept);

// Newton's solve (newton_solve.cpp).

/// Newton's method on the exact model from s.q to the solution (into s.q, s.evaluated and
/// r): with one rotary axis or none, quasi-Newton reusing the solve matrix S while it cuts
/// the residual tenfold a step; with two or more (the tool_direction equations), the exact
/// Jacobian at every iterate, damped near the singular pose. `jacobian_evaluations` counts
/// the Jacobians evaluated.
void newton_solve(const model::ForwardModel& model, const InverseProblem& problem, model::ForwardData& d,
                  const model::Conditions& conditions, const InverseOptions& options, SolveMatrix& S,
                  std::size_t& jacobian_evaluations, SolveStart& s, InverseResult& r);

}  // namespace ccomp::compensate::detail
