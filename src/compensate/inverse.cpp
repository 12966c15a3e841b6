#include "ccomp/compensate/inverse.hpp"

#include <Eigen/QR>
#include <array>
#include <limits>

#include "ccomp/kinematics/pose.hpp"

namespace ccomp::compensate {

using model::ChainQ;

InverseProblem::InverseProblem(const model::ForwardModel& model) {
  for (const auto* chain : {&model.chain().workpiece, &model.chain().tool}) {
    for (const kinematics::Joint& j : chain->joints) {
      if (j.type == kinematics::JointType::fixed || j.axis == model::kToolLengthIndex) continue;
      unknowns.push_back(static_cast<int>(j.axis));
      if (j.type == kinematics::JointType::rotary) {
        rotary_unknowns.push_back(static_cast<int>(j.axis));
        rotary_directions.push_back(j.direction);
      }
    }
  }
}

namespace {
using Step = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 9, 1>;

/// q += sign * step, the step given over the problem's unknowns.
void move_unknowns(const InverseProblem& problem, ChainQ& q, const Step& step, double sign) {
  for (std::size_t c = 0; c < problem.unknowns.size(); ++c)
    q[problem.unknowns[c]] += sign * step[static_cast<Eigen::Index>(c)];
}
}  // namespace

InverseResult solve_inverse(const model::ForwardModel& model, const InverseProblem& problem, model::ForwardData& d,
                            const ChainQ& q_nominal, const model::Conditions& conditions, const InverseOptions& options,
                            const ChainQ* guess, InverseWorkspace* workspace, const NominalPose* nominal) {
  InverseResult r;
  // The target: where the tool tip would be on a perfect machine.
  if (!nominal) model::forward(model, d, q_nominal, conditions, false, model::Evaluate::nominal);
  const Eigen::Vector3d target = nominal ? nominal->tip : d.nominal;
  const Eigen::Matrix3d R_target = nominal ? nominal->orientation : d.R_nominal;
  const auto n = static_cast<Eigen::Index>(problem.unknowns.size());
  const auto m = 3 + static_cast<Eigen::Index>(problem.rotary_unknowns.size());
  InverseWorkspace scratch;
  InverseWorkspace& ws = workspace ? *workspace : scratch;
  // Without a prediction: the guess, else this point shifted by the last solution's
  // correction (neighbouring points correct alike), else the nominal point.
  ChainQ q = guess                         ? *guess
             : ws.last_nominal.allFinite() ? ChainQ(q_nominal + ws.last_solution - ws.last_nominal)
                                           : q_nominal;
  const bool have_solve_matrix = ws.solve_matrix.size() != 0;
  ChainQ first_order = q;
  // The same orientation to reach: the last solution moved by the target's shift through the
  // last Jacobian (first order; its rotary equations are unchanged) and by each changed
  // approach's learnt effect, plus the last miss where this step repeats the last one
  // (within 10% and 2.5 degrees). What the solve does not move (the tool length) is this
  // point's.
  const bool turned = R_target != ws.last_target_orientation;  // also true on the first solve (zero)
  // The approach changed since the last solution (a play taken up, an axis reversed): each
  // changed axis' learnt effect on the solution, where every one is known.
  ChainQ approach_step;  // set where the approach changed
  int approach_changes = 0;
  std::size_t changed_axis = 0;
  bool approach_known = true;
  if (conditions.directions != ws.last_directions) {
    approach_step.setZero();
    for (std::size_t i = 0; i < conditions.directions.size(); ++i) {
      const double change = conditions.directions[i] - ws.last_directions[i];
      if (change == 0.0) continue;
      ++approach_changes, changed_axis = i;
      if (ws.approach_gain_known[i])
        approach_step += change * ws.approach_gain[i];
      else
        approach_known = false;
    }
  }
  const bool continuing = !turned && have_solve_matrix && ws.last_solution.allFinite();
  const bool predicted = continuing && approach_known;
  const bool same_target = continuing && target == ws.last_target;  // solved again, for another approach
  const Eigen::Vector3d shift = target - ws.last_target;
  if (turned && have_solve_matrix && ws.last_solution.allFinite() && ws.last_target_orientation.allFinite()) {
    // The table turned: a machine-frame step of the linear axes shows in the table frame
    // turned with it, so the solve matrix's position columns turn by the same rotation.
    ws.solve_matrix.leftCols<3>() = ws.solve_matrix.leftCols<3>() * (ws.last_target_orientation * R_target.transpose());
  }
  if (predicted) {
    q = q_nominal;
    for (const int k : problem.unknowns) q[k] = ws.last_solution[k];
    move_unknowns(problem, q, ws.solve_matrix.leftCols<3>() * shift, 1.0);
    if (approach_changes > 0) q += approach_step;
    first_order = q;
    const double last_length = ws.last_shift.norm(), length = shift.norm();
    if (last_length > 0 && std::abs(length / last_length - 1.0) < 0.1 &&
        shift.dot(ws.last_shift) > 0.999 * length * last_length)
      q += ws.last_miss * (length * length) / (last_length * last_length);
  }
  // At most 3 + 3 equations in at most 9 unknowns: sized on the stack.
  Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1> residual(m);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 9> J(m, n);
  bool fresh = !have_solve_matrix;  // evaluate the Jacobian at this iteration
  double last_norm = std::numeric_limits<double>::infinity();
  Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1> last_residual(m);  // before the step taken
  bool stepped = false;
  // Each rotary axis seen from the tool: in the table frame it is its own direction (a
  // rotation about d leaves d in place, and the table frame follows the rotary link),
  // turned into the tool frame by the target orientation.
  std::array<Eigen::Vector3d, 3> rotary_axes;
  for (std::size_t k = 0; k < problem.rotary_unknowns.size(); ++k)
    rotary_axes[k] = R_target.transpose() * problem.rotary_directions[k];
  for (r.iterations = 0; r.iterations <= options.max_iterations; ++r.iterations) {
    model::forward(model, d, q, conditions, fresh, model::Evaluate::actual, false);
    residual.head<3>() = d.actual - target;
    Eigen::Matrix3d Jr_inv;
    const Eigen::Vector3d omega = kinematics::so3_log(R_target.transpose() * d.R_actual, fresh ? &Jr_inv : nullptr);
    for (std::size_t k = 0; k < problem.rotary_unknowns.size(); ++k)
      residual[3 + static_cast<Eigen::Index>(k)] = rotary_axes[k].dot(omega);
    if (stepped && turned) {
      // Where the table turns, the error field's slopes change from point to point faster
      // than the matrix turned with it follows: Broyden's update from the step just taken
      // (q moved by -S r_last, the residual changed by delta) makes S delta that step, for
      // this solve's next step and the next solve's. (Along a translation the update
      // between solves does better alone: one per solve, from the target's shift.)
      const auto delta = (residual - last_residual).eval();
      if (const double delta2 = delta.squaredNorm(); delta2 > 0)
        ws.solve_matrix -= (ws.solve_matrix * residual) * delta.transpose() / delta2;
    }
    r.position_residual = residual.head<3>();
    r.orientation_error = omega;
    const bool position_ok = r.position_residual.norm() < options.position_tolerance;
    bool angles_ok = true;
    for (Eigen::Index k = 3; k < m; ++k) angles_ok = angles_ok && std::abs(residual[k]) < options.angle_tolerance;
    if (position_ok && angles_ok) {
      r.converged = true;
      // One more step on the residual already known (no evaluation): what is left is the
      // Jacobian's error times it, far below the tolerance, and the next prediction
      // extrapolates from this solution.
      if (ws.solve_matrix.size() != 0) move_unknowns(problem, q, ws.solve_matrix * residual, -1.0);
      break;
    }
    if (r.iterations == options.max_iterations) break;
    // A step with an old Jacobian that did not cut the residual tenfold: evaluate afresh here.
    const double norm = residual.norm();
    if (!fresh && norm > 0.1 * last_norm) {
      last_norm = std::numeric_limits<double>::infinity();
      fresh = true;
      stepped = false;
      continue;
    }
    last_norm = norm;
    if (fresh) {
      // Rotation rows of dE/dq (right tangent of the tool in the table frame).
      const Eigen::Matrix<double, 3, Eigen::Dynamic> J_rot = Jr_inv * d.actual_chain.J_q.bottomRows<3>();
      for (std::size_t k = 0; k < problem.rotary_unknowns.size(); ++k)
        for (Eigen::Index c = 0; c < n; ++c)
          J(3 + static_cast<Eigen::Index>(k), c) =
              rotary_axes[k].dot(J_rot.col(problem.unknowns[static_cast<std::size_t>(c)]));
      for (Eigen::Index c = 0; c < n; ++c)
        J.block<3, 1>(0, c) = d.J_q.col(problem.unknowns[static_cast<std::size_t>(c)]);
      ws.solve_matrix = J.completeOrthogonalDecomposition().pseudoInverse();
      ++ws.jacobian_evaluations;
      fresh = false;
    }
    move_unknowns(problem, q, ws.solve_matrix * residual, -1.0);
    last_residual = residual;
    stepped = true;
  }
  r.q = q;
  r.target = target;
  if (r.converged && predicted && shift.norm() > 1e-6) {
    // Broyden's update: the solve matrix made exact along the step just taken (the target
    // shift maps to the solution's shift), so it follows the Jacobian along the path.
    Step s_step(n);
    for (Eigen::Index c = 0; c < n; ++c) {
      const auto k = problem.unknowns[static_cast<std::size_t>(c)];
      s_step[c] = q[k] - ws.last_solution[k] - (approach_changes > 0 ? approach_step[k] : 0.0);
    }
    const Step gap = s_step - ws.solve_matrix.leftCols<3>() * shift;
    // A secant far from the matrix is not the Jacobian's drift (a jump of the solution):
    // left out.
    // (Squared lengths summed by hand: GCC 12 takes Eigen's packet loop over a vector of
    // dynamic size and capacity 9 for a read past it, and warns with -Warray-bounds.)
    double gap2 = 0.0, step2 = 0.0;
    for (Eigen::Index c = 0; c < n; ++c) gap2 += gap[c] * gap[c], step2 += s_step[c] * s_step[c];
    if (gap2 < 0.01 * step2) ws.solve_matrix.leftCols<3>() += gap * shift.transpose() / shift.squaredNorm();
  }
  if (r.converged && same_target && approach_changes == 1) {
    // The same point for one axis' changed approach: the solution's move per unit of it.
    const double change = conditions.directions[changed_axis] - ws.last_directions[changed_axis];
    ChainQ& gain = ws.approach_gain[changed_axis];
    gain.setZero();
    for (const int k : problem.unknowns) gain[k] = (q[k] - ws.last_solution[k]) / change;
    ws.approach_gain_known[changed_axis] = true;
  }
  if (r.converged && !same_target) {
    // A point solved again where it was (for a changed approach) is no step along the
    // path: the path's last step and miss stand for the next prediction.
    ws.last_miss = predicted ? ChainQ(q - first_order) : ChainQ(ChainQ::Zero());
    ws.last_shift = shift;
  }
  if (r.converged) {
    ws.last_solution = q;
    ws.last_nominal = q_nominal;
    ws.last_directions = conditions.directions;
    ws.last_target = target;
    ws.last_target_orientation = R_target;
  }
  return r;
}

}  // namespace ccomp::compensate
