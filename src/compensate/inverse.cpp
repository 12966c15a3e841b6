#include "ccomp/compensate/inverse.hpp"

#include "inverse_solve.hpp"

namespace ccomp::compensate {

using model::ChainQ;

InverseProblem::InverseProblem(const model::ForwardModel& model, AxisSet held_axes) {
  for (const auto* chain : {&model.chain().workpiece, &model.chain().tool}) {
    for (const kinematics::Joint& j : chain->joints) {
      if (j.type != kinematics::JointType::fixed && j.axis == model::kToolLengthIndex)
        tool_axis = j.direction.normalized();  // the tip's frame is this joint's, moved along it
      if (j.type == kinematics::JointType::fixed || j.axis == model::kToolLengthIndex) continue;
      if (held_axes.contains_at(j.axis)) {
        held.push_back(static_cast<int>(j.axis));
        continue;
      }
      unknowns.push_back(static_cast<int>(j.axis));
      if (j.type == kinematics::JointType::rotary) {
        rotary_unknowns.push_back(static_cast<int>(j.axis));
        rotary_directions.push_back(j.direction);
      }
      const auto column = static_cast<Eigen::Index>(unknowns.size() - 1);
      (j.type == kinematics::JointType::rotary ? rotary_columns : linear_columns).push_back(column);
    }
  }
  orientation = rotary_unknowns.empty()       ? OrientationEquations::none
                : rotary_unknowns.size() == 1 ? OrientationEquations::about_rotary
                                              : OrientationEquations::tool_direction;
  // Two directions across the tool: any pair completing its axis to a right-handed frame.
  Eigen::Index least = 0;  // the direction furthest from the axis
  tool_axis.cwiseAbs().minCoeff(&least);
  across_tool[0] = tool_axis.cross(Eigen::Vector3d::Unit(least)).normalized();
  across_tool[1] = tool_axis.cross(across_tool[0]);
}

void InverseWorkspace::forget_problem() {
  solve_matrix.resize(0, 0);
  memory.last_target_orientation.setZero();
  memory.last_miss.setZero();
  memory.last_shift.setZero();
  memory.approach_gain = {};
  memory.approach_gain_known = {};
  memory.last_bounded = false;
  path = PathNodes{};
}

InverseResult solve_inverse(const model::ForwardModel& model, const InverseProblem& problem, model::ForwardData& d,
                            const ChainQ& q_nominal, const model::Conditions& conditions, const InverseOptions& options,
                            const ChainQ* guess, InverseWorkspace* workspace, const NominalPose* nominal) {
  if (!workspace) {  // built only when the caller keeps none: a workspace is 1.5 kB to fill
    InverseWorkspace scratch;
    return solve_inverse(model, problem, d, q_nominal, conditions, options, guess, &scratch, nominal);
  }
  InverseResult r;
  if (!nominal) model::forward(model, d, q_nominal, conditions, false, model::Evaluate::nominal);
  InverseWorkspace& ws = *workspace;
  // Where the solve starts: the path predictor's.
  detail::SolveStart s = detail::start_of(problem, ws, q_nominal, conditions, guess, nominal ? nominal->tip : d.nominal,
                                          nominal ? nominal->orientation : d.R_nominal);
  for (const int k : problem.held) s.q[k] = s.first_order[k] = q_nominal[k];  // (a guess may have turned them)
  const bool bounded = options.bound && options.bounded_tolerance > 0.0;
  detail::LinePoint kept;  // the extrapolation to the prediction, for its node where it is evaluated
  // Accepted there on the error field's bound, or else solved by Newton's method; either
  // way the predictor learns from the solution.
  if (detail::Residual residual;
      bounded && detail::accept_on_bound(problem, conditions, options, ws, s, r, residual, s.on_path, kept)) {
    r.q = s.q;
    r.target = s.target;
    // The point stays where the bound holds; the next prediction starts from it moved by
    // the extrapolated residual, as from an evaluated solution (learn() as after iterate()).
    detail::move_unknowns(problem, s.q, detail::solve_matrix_times(ws.solve_matrix, residual), -1.0);
    detail::learn(problem, ws, q_nominal, conditions, s, detail::Reached::on_bound);
    ++ws.bounded_points;
  } else {
    detail::newton_solve(model, problem, d, conditions, options, ws.solve_matrix, ws.jacobian_evaluations, s, r);
    r.q = s.stands ? s.evaluated : s.q;
    r.target = s.target;
    if (!r.converged) return r;
    if (bounded && detail::shortcut_applies(problem))
      detail::record_node(model, *options.bound, problem, d, ws.path, s.evaluated, conditions, s.R_target,
                          s.evaluated_omega, options.bounded_tolerance, &kept);
    detail::learn(problem, ws, q_nominal, conditions, s, detail::Reached::evaluated);
    r.residual_bound = s.stands ? s.standing_residual : options.position_tolerance;
  }
  ws.last_answer = r.q;
  ws.last_answer_bound = r.residual_bound;
  return r;
}

}  // namespace ccomp::compensate
