#include "ccomp/compensate/inverse.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/QR>
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>

#include "ccomp/kinematics/pose.hpp"
#include "path_nodes.hpp"

namespace ccomp::compensate {

using model::ChainQ;

InverseProblem::InverseProblem(const model::ForwardModel& model, unsigned held_axes) {
  for (const auto* chain : {&model.chain().workpiece, &model.chain().tool}) {
    for (const kinematics::Joint& j : chain->joints) {
      if (j.type != kinematics::JointType::fixed && j.axis == model::kToolLengthIndex)
        tool_axis = j.direction.normalized();  // the tip's frame is this joint's, moved along it
      if (j.type == kinematics::JointType::fixed || j.axis == model::kToolLengthIndex) continue;
      if ((held_axes >> j.axis & 1U) != 0) {
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

namespace {
using Step = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 9, 1>;

using SolveMatrix = decltype(InverseWorkspace::solve_matrix);
using Residual = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1>;  ///< over the equations

/// v over the problem's unknowns.
Step over_unknowns(const InverseProblem& problem, const ChainQ& v) {
  Step out(static_cast<Eigen::Index>(problem.unknowns.size()));
  for (Eigen::Index c = 0; c < out.size(); ++c) out[c] = v[problem.unknowns[static_cast<std::size_t>(c)]];
  return out;
}

/// q += sign * step, the step given over the problem's unknowns.
void move_unknowns(const InverseProblem& problem, ChainQ& q, const Step& step, double sign) {
  for (std::size_t c = 0; c < problem.unknowns.size(); ++c)
    q[problem.unknowns[c]] += sign * step[static_cast<Eigen::Index>(c)];
}

// The solve's small products (n <= 9 unknowns, m <= 6 equations), written out: Eigen's
// loops for sizes known only at run time cost more than the products themselves, at
// every point of a program.

/// The solve matrix's first three columns (the position equations) times v.
Step position_columns_times(const SolveMatrix& S, const Eigen::Vector3d& v) {
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
}  // namespace

namespace {

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

void note_approach_change(const model::Conditions& conditions, const InverseWorkspace& ws, SolveStart& s) {
  if (conditions.directions == ws.last_directions) return;
  s.approach_step.setZero();
  for (std::size_t i = 0; i < conditions.directions.size(); ++i) {
    const double change = conditions.directions[i] - ws.last_directions[i];
    if (change == 0.0) continue;
    ++s.approach_changes, s.changed_axis = i;
    if (ws.approach_gain_known[i])
      s.approach_step += change * ws.approach_gain[i];
    else
      s.approach_known = false;
  }
}

/// The first iterate. Without a prediction: the guess, else this point shifted by the last
/// solution's correction (neighbouring points correct alike), else the nominal point. With
/// the same orientation to reach: the last solution moved by the target's shift through the
/// last Jacobian (first order; its rotary equations are unchanged) and by each changed
/// approach's learnt effect, plus the last miss where this step repeats the last one (within
/// 10% and 2.5 degrees). What the solve does not move (the tool length) is this point's.
SolveStart start_of(const InverseProblem& problem, InverseWorkspace& ws, const ChainQ& q_nominal,
                    const model::Conditions& conditions, const ChainQ* guess, const Eigen::Vector3d& target,
                    const Eigen::Matrix3d& R_target) {
  SolveStart s;
  s.program = q_nominal;
  s.target = target;
  s.R_target = R_target;
  const bool have_solve_matrix = ws.solve_matrix.size() != 0;
  s.turned = R_target != ws.last_target_orientation;  // also true on the first solve (zero)
  note_approach_change(conditions, ws, s);
  const bool continuing = !s.turned && have_solve_matrix && ws.last_solution.allFinite();
  s.predicted = continuing && s.approach_known;
  s.same_target = continuing && target == ws.last_target;
  s.shift = target - ws.last_target;
  if (!s.predicted) {  // (a prediction, below, starts elsewhere: nearly every point of a path)
    s.q = guess                         ? *guess
          : ws.last_nominal.allFinite() ? ChainQ(q_nominal + ws.last_solution - ws.last_nominal)
                                        : q_nominal;
    s.first_order = s.q;
  }
  if (s.turned && have_solve_matrix && ws.last_solution.allFinite() && ws.last_target_orientation.allFinite()) {
    // The table turned: a machine-frame step of the linear axes shows in the table frame
    // turned with it, so the solve matrix's position columns turn by the same rotation.
    ws.solve_matrix.leftCols<3>() = ws.solve_matrix.leftCols<3>() * (ws.last_target_orientation * R_target.transpose());
  }
  if (s.predicted) {
    s.q = q_nominal;
    for (const int k : problem.unknowns) s.q[k] = ws.last_solution[k];
    move_unknowns(problem, s.q, position_columns_times(ws.solve_matrix, s.shift), 1.0);
    if (s.approach_changes > 0) s.q += s.approach_step;
    s.first_order = s.q;
    const double last_length = ws.last_shift.norm(), length = s.shift.norm();
    if (last_length > 0 && std::abs(length / last_length - 1.0) < 0.1 &&
        s.shift.dot(ws.last_shift) > 0.999 * length * last_length)
      s.q += ws.last_miss * (length * length) / (last_length * last_length);
  }
  return s;
}

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
             const model::Conditions& conditions, const InverseOptions& options, InverseWorkspace& ws, SolveStart& s,
             InverseResult& r) {
  ChainQ& q = s.q;
  const auto n = static_cast<Eigen::Index>(problem.unknowns.size());
  const auto m = 3 + static_cast<Eigen::Index>(problem.rotary_unknowns.size());
  // At most 3 + 3 equations in at most 9 unknowns: sized on the stack.
  Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1> residual(m);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 9> J(m, n);
  bool fresh = ws.solve_matrix.size() == 0;  // evaluate the Jacobian at this iteration
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
        ws.solve_matrix -= (ws.solve_matrix * residual) * delta.transpose() / delta2;
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
      if (ws.solve_matrix.size() != 0) move_unknowns(problem, q, solve_matrix_times(ws.solve_matrix, residual), -1.0);
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
    move_unknowns(problem, q, solve_matrix_times(ws.solve_matrix, residual), -1.0);
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
                            const model::Conditions& conditions, const InverseOptions& options, InverseWorkspace& ws,
                            SolveStart& s, InverseResult& r) {
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
    const Step step = damped_step(problem, J, residual, q, s.program, ws.solve_matrix);
    ++ws.jacobian_evaluations;
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

/// How a solution was reached: by evaluating the model, or accepted on the nodes' bound.
enum class Reached : std::uint8_t { evaluated, on_bound };

/// The path shortcut (path_nodes.hpp) bounds at most one rotary axis' residual.
bool shortcut_applies(const InverseProblem& problem) {
  // (With an axis held its bound is not worked out: on the sample HMC with B held, accepted
  // points differed from exact solves by 4.6 um at a reversal.)
  return problem.rotary_unknowns.size() <= 1 && problem.held.empty();
}

/// What the next solve predicts from: the solve matrix made exact along the step just taken,
/// a changed approach's effect, the path's last step and miss, the solution itself.
void learn(const InverseProblem& problem, InverseWorkspace& ws, const ChainQ& q_nominal,
           const model::Conditions& conditions, const SolveStart& s, Reached reached) {
  const ChainQ& q = s.q;
  const bool bounded = reached == Reached::on_bound;
  // A solution accepted on the bound is the extrapolation's, and so is the step from it to
  // the next evaluated one: neither is a secant of the Jacobian, and the latter's miss holds
  // the extrapolation's error, not one to repeat.
  const bool after_bounded = ws.last_bounded && !bounded;
  ws.last_bounded = bounded;
  if (s.predicted && s.shift.norm() > 1e-6 && !bounded && !after_bounded) {
    // Broyden's update along the step just taken: the target shift maps to the solution's.
    const ChainQ step = s.approach_changes > 0 ? ChainQ(q - ws.last_solution - s.approach_step)
                                               : ChainQ(q - ws.last_solution);
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
    const double change = conditions.directions[s.changed_axis] - ws.last_directions[s.changed_axis];
    ChainQ& gain = ws.approach_gain[s.changed_axis];
    gain.setZero();
    for (const int k : problem.unknowns) gain[k] = (q[k] - ws.last_solution[k]) / change;
    ws.approach_gain_known[s.changed_axis] = true;
  }
  if (!s.same_target) {
    // A point solved again where it was (for a changed approach) is no step along the
    // path: the path's last step and miss stand for the next prediction.
    ws.last_miss = s.predicted && !after_bounded ? ChainQ(q - s.first_order) : ChainQ(ChainQ::Zero());
    ws.last_shift = s.shift;
  }
  ws.last_solution = q;
  ws.last_nominal = q_nominal;
  ws.last_directions = conditions.directions;
  ws.last_target = s.target;
  ws.last_target_orientation = s.R_target;
}

/// Accepts the prediction s.q where the nodes bound its residual below the caller's
/// tolerance (see path_nodes.hpp); r gets the extrapolated residuals and the bound,
/// `residual` them over the equations.
bool accept_on_bound(const InverseProblem& problem, const model::Conditions& conditions, const InverseOptions& options,
                     const InverseWorkspace& ws, const SolveStart& s, InverseResult& r, Residual& residual,
                     bool& on_path, detail::LinePoint& kept) {
  if (!s.predicted || ws.path.count < 2 || !shortcut_applies(problem) ||
      !detail::nodes_hold(ws.path, conditions, s.R_target, s.q[static_cast<Eigen::Index>(model::kToolLengthIndex)]))
    return false;
  detail::Extrapolated x;
  if (!detail::extrapolate(*options.bound, problem, ws.path, s.q, s.target, x, true, nullptr, &kept)) return false;
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

}  // namespace

void InverseWorkspace::forget_problem() {
  solve_matrix.resize(0, 0);
  last_target_orientation.setZero();
  last_miss.setZero();
  last_shift.setZero();
  approach_gain = {};
  approach_gain_known = {};
  path = PathNodes{};
  last_bounded = false;
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
  SolveStart s = start_of(problem, ws, q_nominal, conditions, guess, nominal ? nominal->tip : d.nominal,
                          nominal ? nominal->orientation : d.R_nominal);
  for (const int k : problem.held) s.q[k] = s.first_order[k] = q_nominal[k];  // (a guess may have turned them)
  const bool bounded = options.bound && options.bounded_tolerance > 0.0;
  detail::LinePoint kept;  // the extrapolation to the prediction, for its node where it is evaluated
  if (Residual residual;
      bounded && accept_on_bound(problem, conditions, options, ws, s, r, residual, s.on_path, kept)) {
    r.q = s.q;
    r.target = s.target;
    // The point stays where the bound holds; the next prediction starts from it moved by
    // the extrapolated residual, as from an evaluated solution (learn() as after iterate()).
    move_unknowns(problem, s.q, solve_matrix_times(ws.solve_matrix, residual), -1.0);
    learn(problem, ws, q_nominal, conditions, s, Reached::on_bound);
    ++ws.bounded_points;
  } else {
    if (problem.orientation == OrientationEquations::tool_direction)
      iterate_tool_direction(model, problem, d, conditions, options, ws, s, r);
    else
      iterate(model, problem, d, conditions, options, ws, s, r);
    r.q = s.stands ? s.evaluated : s.q;
    r.target = s.target;
    if (!r.converged) return r;
    if (bounded && shortcut_applies(problem))
      detail::record_node(model, *options.bound, problem, d, ws.path, s.evaluated, conditions, s.R_target,
                          s.evaluated_omega, options.bounded_tolerance, &kept);
    learn(problem, ws, q_nominal, conditions, s, Reached::evaluated);
    r.residual_bound = s.stands ? s.standing_residual : options.position_tolerance;
  }
  ws.last_answer = r.q;
  ws.last_answer_bound = r.residual_bound;
  return r;
}

}  // namespace ccomp::compensate
