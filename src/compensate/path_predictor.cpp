#include <cmath>

#include "inverse_solve.hpp"

namespace ccomp::compensate::detail {
namespace {

void note_approach_change(const model::Conditions& conditions, const InverseWorkspace& ws, SolveStart& s) {
  if (conditions.directions == ws.memory.last_directions) return;
  s.approach_step.setZero();
  for (std::size_t i = 0; i < conditions.directions.size(); ++i) {
    const double change = conditions.directions[i] - ws.memory.last_directions[i];
    if (change == 0.0) continue;
    ++s.approach_changes, s.changed_axis = i;
    if (ws.memory.approach_gain_known[i])
      s.approach_step += change * ws.memory.approach_gain[i];
    else
      s.approach_known = false;
  }
}

/// Broyden's update: the solve matrix made exact along a step of the solution (s_step) that
/// moved the tip by `shift`, so it follows the Jacobian along the path.
void secant_update(InverseWorkspace& ws, const Step& s_step, const Eigen::Vector3d& shift) {
  const Eigen::Index n = s_step.size();
  const Step predicted = position_columns_times(ws.solve_matrix, shift);
  // A secant far from the matrix is not the Jacobian's drift (a jump of the solution):
  // left out.
  // (Squared lengths summed by hand: GCC 12 takes Eigen's packet loop over a vector of
  // dynamic size and capacity 9 for a read past it, and warns with -Warray-bounds.)
  Step gap(n);
  double gap2 = 0.0, step2 = 0.0;
  for (Eigen::Index c = 0; c < n; ++c) {
    gap[c] = s_step[c] - predicted[c];
    gap2 += gap[c] * gap[c], step2 += s_step[c] * s_step[c];
  }
  if (gap2 < 0.01 * step2) {
    // (gap shift^T) / |shift|^2, rounded as the product over the norm, as Eigen rounded it
    const double shift2 = shift.squaredNorm();
    for (Eigen::Index c = 0; c < n; ++c)
      for (Eigen::Index k = 0; k < 3; ++k) ws.solve_matrix(c, k) += gap[c] * shift[k] / shift2;
  }
}

}  // namespace

SolveStart start_of(const InverseProblem& problem, InverseWorkspace& ws, const ChainQ& q_nominal,
                    const model::Conditions& conditions, const ChainQ* guess, const Eigen::Vector3d& target,
                    const Eigen::Matrix3d& R_target) {
  SolveStart s;
  s.program = q_nominal;
  s.target = target;
  s.R_target = R_target;
  const bool have_solve_matrix = ws.solve_matrix.size() != 0;
  s.turned = R_target != ws.memory.last_target_orientation;  // also true on the first solve (zero)
  note_approach_change(conditions, ws, s);
  const bool continuing = !s.turned && have_solve_matrix && ws.memory.last_solution.allFinite();
  s.predicted = continuing && s.approach_known;
  s.same_target = continuing && target == ws.memory.last_target;
  s.shift = target - ws.memory.last_target;
  if (!s.predicted) {  // (a prediction, below, starts elsewhere: nearly every point of a path)
    s.q = guess                         ? *guess
          : ws.memory.last_nominal.allFinite() ? ChainQ(q_nominal + ws.memory.last_solution - ws.memory.last_nominal)
                                        : q_nominal;
    s.first_order = s.q;
  }
  if (s.turned && have_solve_matrix && ws.memory.last_solution.allFinite() && ws.memory.last_target_orientation.allFinite()) {
    // The table turned: a machine-frame step of the linear axes shows in the table frame
    // turned with it, so the solve matrix's position columns turn by the same rotation.
    ws.solve_matrix.leftCols<3>() = ws.solve_matrix.leftCols<3>() * (ws.memory.last_target_orientation * R_target.transpose());
  }
  if (s.predicted) {
    s.q = q_nominal;
    for (const int k : problem.unknowns) s.q[k] = ws.memory.last_solution[k];
    move_unknowns(problem, s.q, position_columns_times(ws.solve_matrix, s.shift), 1.0);
    if (s.approach_changes > 0) s.q += s.approach_step;
    s.first_order = s.q;
    const double last_length = ws.memory.last_shift.norm(), length = s.shift.norm();
    if (last_length > 0 && std::abs(length / last_length - 1.0) < 0.1 &&
        s.shift.dot(ws.memory.last_shift) > 0.999 * length * last_length)
      s.q += ws.memory.last_miss * (length * length) / (last_length * last_length);
  }
  return s;
}

void learn(const InverseProblem& problem, InverseWorkspace& ws, const ChainQ& q_nominal,
           const model::Conditions& conditions, const SolveStart& s, Reached reached) {
  const ChainQ& q = s.q;
  const bool bounded = reached == Reached::on_bound;
  // A solution accepted on the bound is the extrapolation's, and so is the step from it to
  // the next evaluated one: neither is a secant of the Jacobian, and the latter's miss holds
  // the extrapolation's error, not one to repeat.
  const bool after_bounded = ws.memory.last_bounded && !bounded;
  ws.memory.last_bounded = bounded;
  if (s.predicted && s.shift.norm() > 1e-6 && !bounded && !after_bounded) {
    // Broyden's update along the step just taken: the target shift maps to the solution's.
    const ChainQ step = s.approach_changes > 0 ? ChainQ(q - ws.memory.last_solution - s.approach_step)
                                               : ChainQ(q - ws.memory.last_solution);
    secant_update(ws, over_unknowns(problem, step), s.shift);
  } else if (after_bounded && ws.path.count == 2 && ws.path.nodes[1].q == s.evaluated) {
    // After points accepted on the bound, the step between the last two points evaluated
    // (their actual tips, not their targets) is the secant to follow.
    const PathNodes::Node &older = ws.path.nodes[0], &newer = ws.path.nodes[1];
    if (const Eigen::Vector3d moved = newer.tip - older.tip; moved.norm() > 1e-6)
      secant_update(ws, over_unknowns(problem, newer.q - older.q), moved);
  }
  if (s.same_target && s.approach_changes == 1 && !after_bounded) {
    // The same point for one axis' changed approach: the solution's move per unit of it.
    const double change = conditions.directions[s.changed_axis] - ws.memory.last_directions[s.changed_axis];
    ChainQ& gain = ws.memory.approach_gain[s.changed_axis];
    gain.setZero();
    for (const int k : problem.unknowns) gain[k] = (q[k] - ws.memory.last_solution[k]) / change;
    ws.memory.approach_gain_known[s.changed_axis] = true;
  }
  if (!s.same_target) {
    // A point solved again where it was (for a changed approach) is no step along the
    // path: the path's last step and miss stand for the next prediction.
    ws.memory.last_miss = s.predicted && !after_bounded ? ChainQ(q - s.first_order) : ChainQ(ChainQ::Zero());
    ws.memory.last_shift = s.shift;
  }
  ws.memory.last_solution = q;
  ws.memory.last_nominal = q_nominal;
  ws.memory.last_directions = conditions.directions;
  ws.memory.last_target = s.target;
  ws.memory.last_target_orientation = s.R_target;
}


}  // namespace ccomp::compensate::detail
