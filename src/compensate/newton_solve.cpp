#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/QR>
#include <algorithm>
#include <array>
#include <limits>

#include "ccomp/kinematics/pose.hpp"
#include "inverse_solve.hpp"

namespace ccomp::compensate::detail {
namespace {

/// The share of the bounded tolerance an evaluated iterate may stand with (a tenth).
constexpr double kStandingShare = 0.1;

/// mm: what a residual over the equations moves the tip by, the rotary residuals' share
/// through `lever`.
template <typename Equations>
double tip_displacement(const Equations& residual, double lever) {
  double tip = residual.template head<3>().norm();
  for (Eigen::Index k = 3; k < residual.size(); ++k) tip += lever * std::abs(residual[k]);
  return tip;
}

/// Newton's iteration from s.q, the solve matrix reused while it cuts the residual tenfold a
/// step; r gets the outcome, s.q the solution.
void iterate(const model::ForwardModel& model, const InverseProblem& problem, model::ForwardData& d,
             const model::Conditions& conditions, const InverseOptions& options, SolveMatrix& S, std::size_t& jacobian_evaluations, SolveStart& s,
             InverseResult& r) {
  ChainQ& q = s.q;
  const auto n = static_cast<Eigen::Index>(problem.unknowns.size());
  const auto m = 3 + static_cast<Eigen::Index>(problem.rotary_unknowns.size());
  // At most 3 + 3 equations in at most 9 unknowns: sized on the stack.
  Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1> residual(m);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 9> J(m, n);
  bool fresh = S.size() == 0;  // evaluate the Jacobian at this iteration
  double last_norm = std::numeric_limits<double>::infinity();
  Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1> last_residual(m);  // before the step taken
  bool stepped = false;
  // Each rotary axis seen from the tool: in the table frame it is its own direction (a
  // rotation about d leaves d in place, and the table frame follows the rotary link),
  // turned into the tool frame by the target orientation.
  std::array<Eigen::Vector3d, 3> rotary_axes;
  for (std::size_t k = 0; k < problem.rotary_unknowns.size(); ++k)
    rotary_axes[k] = s.R_target.transpose() * problem.rotary_directions[k];
  for (r.iterations = 0; r.iterations <= options.max_iterations; ++r.iterations) {
    model::forward(model, d, q, conditions, fresh, model::Evaluate::actual, false);
    residual.head<3>() = d.actual - s.target;
    Eigen::Matrix3d Jr_inv;
    const Eigen::Vector3d omega = kinematics::so3_log(s.R_target.transpose() * d.R_actual, fresh ? &Jr_inv : nullptr);
    for (std::size_t k = 0; k < problem.rotary_unknowns.size(); ++k)
      residual[3 + static_cast<Eigen::Index>(k)] = rotary_axes[k].dot(omega);
    if (stepped && s.turned) {
      // Where the table turns, the error field's slopes change from point to point faster
      // than the matrix turned with it follows: Broyden's update from the step just taken
      // (q moved by -S r_last, the residual changed by delta) makes S delta that step, for
      // this solve's next step and the next solve's. (Along a translation the update
      // between solves does better alone: one per solve, from the target's shift.)
      const auto delta = (residual - last_residual).eval();
      if (const double delta2 = delta.squaredNorm(); delta2 > 0)
        S -= (S * residual) * delta.transpose() / delta2;
    }
    r.position_residual = residual.head<3>();
    r.orientation_error = omega;
    const bool position_ok = r.position_residual.norm() < options.position_tolerance;
    bool angles_ok = true;
    for (Eigen::Index k = 3; k < m; ++k) angles_ok = angles_ok && std::abs(residual[k]) < options.angle_tolerance;
    // On a path where residuals may be bounded (InverseOptions::bound), an iterate whose
    // exact residual is within a tenth of that tolerance stands as it is: a step would cost
    // another evaluation for less than what the points accepted on the bound are allowed.
    // (Not at a point off any path, a plunge or a rapid's end: there a few nanometres can
    // decide whether an axis that barely moves has reversed, and with it its take-up.)
    // (s.on_path: the solve has a bound, InverseOptions::bound.)
    const double standing = s.on_path && !(position_ok && angles_ok)
                                ? tip_displacement(residual, options.bound->lever(q, q))
                                : std::numeric_limits<double>::infinity();
    const bool stands = standing <= kStandingShare * options.bounded_tolerance;
    if ((position_ok && angles_ok) || stands) {
      r.converged = true;
      s.evaluated = q;
      s.evaluated_omega = omega;
      s.stands = stands;
      s.standing_residual = standing;
      // One more step on the residual already known (no evaluation): what is left is the
      // Jacobian's error times it, far below the tolerance, and the next prediction
      // extrapolates from this solution.
      if (S.size() != 0) move_unknowns(problem, q, solve_matrix_times(S, residual), -1.0);
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
      S = J.completeOrthogonalDecomposition().pseudoInverse();
      ++jacobian_evaluations;
      fresh = false;
    }
    move_unknowns(problem, q, solve_matrix_times(S, residual), -1.0);
    last_residual = residual;
    stepped = true;
  }
}

using Jacobian = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 9>;

/// lambda^2 of the damped step (kSingularZone) for the rotary axes' normal matrix M^T M,
/// whose least eigenvalue is their weakest turn of the tool squared.
template <typename Normal>
double singular_damping2(const Normal& MtM) {
  const Eigen::SelfAdjointEigenSolver<Normal> eigen(MtM, Eigen::EigenvaluesOnly);
  const double sigma2 = std::max(0.0, eigen.eigenvalues()[0]);
  const double zone2 = kSingularZone * kSingularZone;
  return sigma2 >= zone2 ? 0.0 : kSingularDamping * kSingularDamping * (1.0 - sigma2 / zone2);
}

/// damped_step() for NL linear and NR rotary unknowns (Eigen::Dynamic: any count, at most 9):
/// fixed sizes where the machine has three linear axes and two rotary ones, so the small
/// products are written out, and the linear axes' 3 x 3 block is inverted directly (the
/// model refuses X, Y, Z along parallel lines or in a plane).
template <int NL, int NR>
Step damped_step_sized(const InverseProblem& problem, const Jacobian& J, const Residual& residual, const ChainQ& q,
                       const ChainQ& program, SolveMatrix& S) {
  constexpr int ML = NL == Eigen::Dynamic ? 9 : NL, MR = NR == Eigen::Dynamic ? 9 : NR;
  using Linear = Eigen::Matrix<double, 3, NL, 0, 3, ML>;
  using Rotary = Eigen::Matrix<double, 3, NR, 0, 3, MR>;
  using LinearTurn = Eigen::Matrix<double, 2, NL, 0, 2, ML>;
  using RotaryTurn = Eigen::Matrix<double, 2, NR, 0, 2, MR>;
  using LinearInverse = Eigen::Matrix<double, NL, 3, 0, ML, 3>;
  using Normal = Eigen::Matrix<double, NR, NR, 0, MR, MR>;
  using RotaryRows = Eigen::Matrix<double, NR, 5, 0, MR, 5>;
  using LinearRows = Eigen::Matrix<double, NL, 5, 0, ML, 5>;
  using RotaryVector = Eigen::Matrix<double, NR, 1, 0, MR, 1>;
  using LinearVector = Eigen::Matrix<double, NL, 1, 0, ML, 1>;
  const auto& linear = problem.linear_columns;
  const auto& rotary = problem.rotary_columns;
  const auto nl = static_cast<Eigen::Index>(linear.size()), nr = static_cast<Eigen::Index>(rotary.size());
  Linear Pl(3, nl);
  LinearTurn Ol(2, nl);
  Rotary Pr(3, nr);
  RotaryTurn Or(2, nr);
  for (Eigen::Index c = 0; c < nl; ++c) Pl.col(c) = J.col(linear[c]).head<3>(), Ol.col(c) = J.col(linear[c]).tail<2>();
  for (Eigen::Index c = 0; c < nr; ++c) Pr.col(c) = J.col(rotary[c]).head<3>(), Or.col(c) = J.col(rotary[c]).tail<2>();
  LinearInverse Pl_inv;
  if constexpr (NL == 3)
    Pl_inv = Pl.inverse();
  else
    Pl_inv = Pl.completeOrthogonalDecomposition().pseudoInverse();
  // The linear axes take whatever the rotary axes move the tip by: the direction rows as
  // the rotary axes alone see them (M) and the direction residual left by that (reduce).
  const Eigen::Matrix<double, 2, 3> turn_per_tip = Ol * Pl_inv;
  const RotaryTurn M = Or - turn_per_tip * Pr;
  Eigen::Matrix<double, 2, 5> reduce;
  reduce << -turn_per_tip, Eigen::Matrix2d::Identity();
  const Normal MtM = M.transpose() * M;
  const double damping2 = singular_damping2(MtM);
  const Eigen::LDLT<Normal> normal(MtM + damping2 * Normal::Identity(nr, nr));
  const RotaryRows Sr = normal.solve(M.transpose() * reduce);
  LinearRows Sl(nl, 5);
  Sl << Pl_inv, Eigen::Matrix<double, NL, 2, 0, ML, 2>::Zero(nl, 2);
  Sl -= Pl_inv * Pr * Sr;
  RotaryVector from_program(nr);
  for (Eigen::Index c = 0; c < nr; ++c) {
    const int k = problem.unknowns[static_cast<std::size_t>(rotary[c])];
    from_program[c] = q[k] - program[k];
  }
  const RotaryVector keep_r = normal.solve(damping2 * from_program);
  const LinearVector keep_l = -Pl_inv * (Pr * keep_r);
  S.resize(J.cols(), 5);
  Step step(J.cols());
  for (Eigen::Index c = 0; c < nl; ++c) S.row(linear[c]) = Sl.row(c), step[linear[c]] = keep_l[c];
  for (Eigen::Index c = 0; c < nr; ++c) S.row(rotary[c]) = Sr.row(c), step[rotary[c]] = keep_r[c];
  return step + solve_matrix_times(S, residual);
}

/// The tool_direction solve's step from the exact Jacobian J (the position rows, then the
/// tool's turn across its axis) at q: the linear axes land the tip exactly, the rotary axes
/// answer the tool's direction in the least-squares sense, near the singular pose damped
/// toward the program's rotary values (kSingularZone). S gets the step per unit of
/// residual, which the next point's prediction reads; the step to subtract from q is returned.
Step damped_step(const InverseProblem& problem, const Jacobian& J, const Residual& residual, const ChainQ& q,
                 const ChainQ& program, SolveMatrix& S) {
  if (problem.linear_columns.size() == 3 && problem.rotary_columns.size() == 2)
    return damped_step_sized<3, 2>(problem, J, residual, q, program, S);
  return damped_step_sized<Eigen::Dynamic, Eigen::Dynamic>(problem, J, residual, q, program, S);
}

/// Newton's iteration for the tool_direction equations (two rotary axes or more): the exact
/// Jacobian at every iterate (the rotary lines turn with the pose), converged where the tip
/// is within the position tolerance and the rotary step below the angle tolerance; r gets
/// the outcome, s.q the solution.
void iterate_tool_direction(const model::ForwardModel& model, const InverseProblem& problem, model::ForwardData& d,
                            const model::Conditions& conditions, const InverseOptions& options, SolveMatrix& S,
                            std::size_t& jacobian_evaluations, SolveStart& s, InverseResult& r) {
  ChainQ& q = s.q;
  const auto n = static_cast<Eigen::Index>(problem.unknowns.size());
  Residual residual(5);
  Jacobian J(5, n);
  for (r.iterations = 0; r.iterations <= options.max_iterations; ++r.iterations) {
    model::forward(model, d, q, conditions, true, model::Evaluate::actual, false);
    Eigen::Matrix3d Jr_inv;
    const Eigen::Vector3d omega = kinematics::so3_log(s.R_target.transpose() * d.R_actual, &Jr_inv);
    residual.head<3>() = d.actual - s.target;
    residual[3] = problem.across_tool[0].dot(omega);
    residual[4] = problem.across_tool[1].dot(omega);
    r.position_residual = residual.head<3>();
    r.orientation_error = omega - problem.tool_axis.dot(omega) * problem.tool_axis;
    if (!residual.allFinite()) break;
    const Eigen::Matrix<double, 3, Eigen::Dynamic> J_rot = Jr_inv * d.actual_chain.J_q.bottomRows<3>();
    for (Eigen::Index c = 0; c < n; ++c) {
      const int k = problem.unknowns[static_cast<std::size_t>(c)];
      J.block<3, 1>(0, c) = d.J_q.col(k);
      J(3, c) = problem.across_tool[0].dot(J_rot.col(k));
      J(4, c) = problem.across_tool[1].dot(J_rot.col(k));
    }
    const Step step = damped_step(problem, J, residual, q, s.program, S);
    ++jacobian_evaluations;
    double rotary_step = 0.0;
    for (const Eigen::Index c : problem.rotary_columns) rotary_step = std::max(rotary_step, std::abs(step[c]));
    const bool converged =
        r.position_residual.norm() < options.position_tolerance && rotary_step < options.angle_tolerance;
    if (converged) {
      r.converged = true;
      s.evaluated = q;
      s.evaluated_omega = omega;
    }
    // (Converged too: the step on the residual already known costs no evaluation.)
    move_unknowns(problem, q, step, -1.0);
    if (converged || r.iterations == options.max_iterations) break;
  }
}

}  // namespace

void newton_solve(const model::ForwardModel& model, const InverseProblem& problem, model::ForwardData& d,
                  const model::Conditions& conditions, const InverseOptions& options, SolveMatrix& S,
                  std::size_t& jacobian_evaluations, SolveStart& s, InverseResult& r) {
  if (problem.orientation == OrientationEquations::tool_direction)
    iterate_tool_direction(model, problem, d, conditions, options, S, jacobian_evaluations, s, r);
  else
    iterate(model, problem, d, conditions, options, S, jacobian_evaluations, s, r);
}

}  // namespace ccomp::compensate::detail
