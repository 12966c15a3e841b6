#include "ccomp/compensate/inverse.hpp"

#include <Eigen/QR>

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


InverseResult solve_inverse(const model::ForwardModel& model, const InverseProblem& problem, model::ForwardData& d,
                            const ChainQ& q_nominal, const model::Conditions& conditions,
                            const InverseOptions& options, const ChainQ* guess) {
  InverseResult r;
  // The target: where the tool tip would be on a perfect machine.
  model::forward(model, d, q_nominal, conditions, false, model::Evaluate::nominal);
  const Eigen::Vector3d target = d.nominal;
  const Eigen::Matrix3d R_target = d.R_nominal;
  const auto n = static_cast<Eigen::Index>(problem.unknowns.size());
  const auto m = 3 + static_cast<Eigen::Index>(problem.rotary_unknowns.size());
  ChainQ q = guess ? *guess : q_nominal;
  // At most 3 + 3 equations in at most 9 unknowns: sized on the stack.
  Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1> residual(m);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 9> J(m, n);
  for (r.iterations = 0; r.iterations <= options.max_iterations; ++r.iterations) {
    model::forward(model, d, q, conditions, true, model::Evaluate::actual, false);
    residual.head<3>() = d.actual - target;
    Eigen::Matrix3d Jr_inv;
    const Eigen::Vector3d omega = kinematics::so3_log(R_target.transpose() * d.R_actual, &Jr_inv);
    // Rotation rows of dE/dq (right tangent of the tool in the table frame).
    const Eigen::Matrix<double, 3, Eigen::Dynamic> J_rot = Jr_inv * d.actual_chain.J_q.bottomRows<3>();
    for (std::size_t k = 0; k < problem.rotary_unknowns.size(); ++k) {
      // The rotary axis seen from the tool: in the table frame it is its own direction (a
      // rotation about d leaves d in place, and the table frame follows the rotary link),
      // turned into the tool frame by the target orientation.
      const Eigen::Vector3d axis = R_target.transpose() * problem.rotary_directions[k];
      residual[3 + static_cast<Eigen::Index>(k)] = axis.dot(omega);
      for (Eigen::Index c = 0; c < n; ++c)
        J(3 + static_cast<Eigen::Index>(k), c) = axis.dot(J_rot.col(problem.unknowns[static_cast<std::size_t>(c)]));
    }
    for (Eigen::Index c = 0; c < n; ++c) J.block<3, 1>(0, c) = d.J_q.col(problem.unknowns[static_cast<std::size_t>(c)]);
    r.position_residual = residual.head<3>();
    r.orientation_error = omega;
    const bool position_ok = r.position_residual.norm() < options.position_tolerance;
    const bool angles_ok = residual.tail(m - 3).size() == 0 || residual.tail(m - 3).cwiseAbs().maxCoeff() < options.angle_tolerance;
    if (position_ok && angles_ok) {
      r.converged = true;
      break;
    }
    if (r.iterations == options.max_iterations) break;
    const Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 9, 1> step = J.completeOrthogonalDecomposition().solve(-residual);
    for (Eigen::Index c = 0; c < n; ++c) q[problem.unknowns[static_cast<std::size_t>(c)]] += step[c];
  }
  r.q = q;
  return r;
}

}  // namespace ccomp::compensate
