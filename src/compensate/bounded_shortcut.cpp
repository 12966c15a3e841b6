#include "inverse_solve.hpp"

namespace ccomp::compensate::detail {

bool shortcut_applies(const InverseProblem& problem) {
  // (With an axis held its bound is not worked out: on the sample HMC with B held, accepted
  // points differed from exact solves by 4.6 um at a reversal.)
  return problem.rotary_unknowns.size() <= 1 && problem.held.empty();
}

bool accept_on_bound(const InverseProblem& problem, const model::Conditions& conditions, const InverseOptions& options,
                     const InverseWorkspace& ws, const SolveStart& s, InverseResult& r, Residual& residual,
                     bool& on_path, LinePoint& kept) {
  if (!s.predicted || ws.path.count < 2 || !shortcut_applies(problem) ||
      !nodes_hold(ws.path, conditions, s.R_target, s.q[static_cast<Eigen::Index>(model::kToolLengthIndex)]))
    return false;
  Extrapolated x;
  if (!extrapolate(*options.bound, problem, ws.path, s.q, s.target, x, true, nullptr, &kept)) return false;
  on_path = true;
  residual.resize(3 + static_cast<Eigen::Index>(problem.rotary_unknowns.size()));
  residual.head<3>() = x.position_residual;
  double tip = x.position_residual.norm() + x.position_bound;
  if (!problem.rotary_unknowns.empty()) {
    residual[3] = (s.R_target.transpose() * problem.rotary_directions[0]).dot(x.orientation_error);
    tip += x.lever * (std::abs(residual[3]) + x.angle_bound);
  }
  if (!(tip <= options.bounded_tolerance)) return false;
  r.converged = true;
  r.evaluated = false;
  r.residual_bound = tip;
  r.position_residual = x.position_residual;
  r.orientation_error = x.orientation_error;
  return true;
}


}  // namespace ccomp::compensate::detail
