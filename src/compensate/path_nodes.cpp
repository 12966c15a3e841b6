#include "path_nodes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ccomp/kinematics/pose.hpp"

namespace ccomp::compensate::detail {

using model::ChainQ;

namespace {

constexpr auto kTool = static_cast<Eigen::Index>(model::kToolLengthIndex);
/// rad: how far the rotary axis may stand from where the nominal slopes were taken (they
/// turn with it; the bound counts that, and it stays small).
constexpr double kSlopesTurn = 1e-4;
/// The furthest an extrapolation goes, in distances between the nodes.
constexpr double kLongestReach = 64.0;

/// Takes the perfect machine's slopes at q (see PathNodes::NominalSlopes); false
/// where its turn from the target is not about the one rotary axis.
bool take_slopes(const model::ForwardModel& model, const model::VariationBound& bound, const InverseProblem& problem,
                 model::ForwardData& d, PathNodes::NominalSlopes& slopes, const ChainQ& q,
                 const Eigen::Matrix3d& R_target) {
  slopes.valid = false;
  slopes.tool_length = q[kTool];
  slopes.orientation = R_target;
  slopes.tip.setZero();
  slopes.turn.setZero();
  slopes.moving_columns = 0;
  model::forward(model, d, q, {}, false, model::Evaluate::nominal);
  const Eigen::Vector3d tip = d.nominal;
  const Eigen::Vector3d turn = kinematics::so3_log(R_target.transpose() * d.R_nominal);
  slopes.column_norm = 0.0;
  for (const int k : problem.unknowns) {
    if (std::find(problem.rotary_unknowns.begin(), problem.rotary_unknowns.end(), k) != problem.rotary_unknowns.end())
      continue;
    ChainQ moved = q;
    moved[k] += 1.0;  // mm: the tip is affine in it, so the difference is its slope
    model::forward(model, d, moved, {}, false, model::Evaluate::nominal);
    slopes.tip.col(k) = d.nominal - tip;
    slopes.column_norm = std::max(slopes.column_norm, slopes.tip.col(k).norm());
    if (slopes.tip.col(k).squaredNorm() > 0.0) slopes.moving_columns |= 1U << k;
  }
  if (!problem.rotary_unknowns.empty()) {
    const int k = problem.rotary_unknowns.front();
    slopes.rotary_value = q[k];
    ChainQ moved = q;
    moved[k] += kSlopesTurn;
    model::forward(model, d, moved, {}, false, model::Evaluate::nominal);
    slopes.turn = (kinematics::so3_log(R_target.transpose() * d.R_nominal) - turn) / kSlopesTurn;
    const Eigen::Vector3d axis = R_target.transpose() * problem.rotary_directions.front();
    auto about_axis = [&](const Eigen::Vector3d& v) {
      return (v - axis.dot(v) * axis).norm() <= 1e-15 + 1e-9 * v.norm();
    };
    if (!about_axis(turn) || !about_axis(slopes.turn)) return false;
  }
  slopes.error_slopes = bound.error_slopes(q[kTool]);
  slopes.valid = true;
  return true;
}

/// Whether the slopes were taken (or found not to split, `valid` false) for q's tool
/// length, the target orientation and near q's rotary axis value.
bool slopes_taken_for(const InverseProblem& problem, const PathNodes::NominalSlopes& slopes, const ChainQ& q,
                      const Eigen::Matrix3d& R_target) {
  return slopes.tool_length == q[kTool] && slopes.orientation == R_target &&
         (problem.rotary_unknowns.empty() ||
          std::abs(q[problem.rotary_unknowns.front()] - slopes.rotary_value) <= kSlopesTurn);
}

}  // namespace

bool nodes_hold(const PathNodes& path, const model::Conditions& conditions, const Eigen::Matrix3d& R_target,
                double tool_length) {
  return path.count > 0 && path.directions == conditions.directions && path.orientation == R_target &&
         path.nodes[1].q[kTool] == tool_length && path.time == conditions.time &&
         path.temperatures == conditions.temperatures;
}

void record_node(const model::ForwardModel& model, const model::VariationBound& bound, const InverseProblem& problem,
                 model::ForwardData& d, PathNodes& path, const ChainQ& q, const model::Conditions& conditions,
                 const Eigen::Matrix3d& R_target, const Eigen::Vector3d& omega, double tolerance,
                 const LinePoint* kept) {
  if (!nodes_hold(path, conditions, R_target, q[kTool])) {
    path.count = 0;
    path.directions = conditions.directions;
    path.orientation = R_target;
    path.time = conditions.time;
    path.temperatures = conditions.temperatures;
  }
  // What the last line's extrapolation missed this point by, over s (s - 1): its bend,
  // to be carried to the next line (scaled to its length).
  Eigen::Vector3d bend = Eigen::Vector3d::Zero(), turn_bend = Eigen::Vector3d::Zero();
  double bend_s = 0.0;
  if (path.count == 2) {
    LinePoint made;
    const LinePoint* point = kept;
    if (!(point && point->q == q)) {  // (nearly always kept: the prediction, evaluated once)
      Extrapolated x;
      (void)extrapolate(bound, problem, path, q, Eigen::Vector3d::Zero(), x, false, nullptr, &made);
      point = &made;
    }
    bend_s = point->s;
    if (point->reached && std::abs(bend_s * (bend_s - 1.0)) >= 0.5) {
      bend = (d.actual - point->tip) / (bend_s * (bend_s - 1.0));
      turn_bend = (omega - point->omega) / (bend_s * (bend_s - 1.0));
    }
  }
  // (Only a line the nodes made: before two, the nodes are not one, and a fresh workspace's
  // are not even set.)
  const double old_length2 = path.count == 2 ? (path.nodes[1].q - path.nodes[0].q).squaredNorm() : 0.0;
  path.nodes[0] = path.nodes[1];
  path.nodes[1] = {q, d.actual, omega};
  path.count = std::min(path.count + 1, 2);
  if (path.count < 2) return;
  const ChainQ &a = path.nodes[0].q, line = q - a;
  path.line = line;
  path.length2 = line.squaredNorm();
  path.lever = bound.lever(a, q);
  const double scale = old_length2 > 0.0 ? path.length2 / old_length2 : 0.0;
  path.line_bend = bend * scale;
  path.line_turn_bend = turn_bend * scale;
  path.line_chord = bound.chord_deviation(a, q);
  // Out to where 4 (s - 1) s chord, the along-line bound at s, reaches the tolerance, and
  // short of the first table knot the stretched line would step over (the chord bound
  // out there is then at most s^2 times the nodes' own).
  path.line_reach = std::isfinite(path.line_chord) && path.line_chord > 0.0
                        ? std::min({0.5 + std::sqrt(0.25 + tolerance / (4.0 * path.line_chord)), kLongestReach,
                                    std::nextafter(bound.stretch_limit(a, q), 0.0)})
                        : 1.0;
  path.line_reach = std::max(path.line_reach, 1.0);
  if (!slopes_taken_for(problem, path.slopes, q, R_target))
    take_slopes(model, bound, problem, d, path.slopes, q, R_target);
}

bool extrapolate(const model::VariationBound& bound, const InverseProblem& problem, const PathNodes& path,
                 const ChainQ& q, const Eigen::Vector3d& target, Extrapolated& out, bool bent, double* at,
                 LinePoint* kept) {
  const PathNodes::Node &a = path.nodes[0], &b = path.nodes[1];
  if (kept) kept->q = q, kept->reached = false;
  if (!path.slopes.valid || !slopes_taken_for(problem, path.slopes, q, path.orientation) ||
      !std::isfinite(path.line_chord))
    return false;
  const ChainQ& line = path.line;
  const double length2 = path.length2;
  if (!(length2 > 0.0)) return false;
  const double s = line.dot(q - a.q) / length2;
  if (at) *at = s;
  if (kept) kept->s = s;
  if (!(s >= 0.0 && s <= path.line_reach)) return false;
  const ChainQ on_line = a.q + s * line, off = q - on_line;  // off: w
  // Along the line: 4 |s (s - 1)| / hull^2 of the hull's chord bound.
  const double chord = s <= 1.0 ? path.line_chord : s * s * path.line_chord;
  const double hull = std::max(s, 1.0);
  const double along = 4.0 * std::abs(s * (s - 1.0)) / (hull * hull) * chord;
  // Off it: the error field's slopes, the nominal slopes' turn since they were taken, and
  // the rotary axis' own share.
  const PathNodes::NominalSlopes& slopes = path.slopes;
  const double errors = slopes.error_slopes.change(on_line, q);
  double linear = 0.0, turned = 0.0, turning = 0.0;
  for (const int k : problem.unknowns)
    if (slopes.moving_columns >> k & 1U) linear += std::abs(off[k]);
  if (!problem.rotary_unknowns.empty()) {
    const int k = problem.rotary_unknowns.front();
    turning = std::abs(off[k]);
    turned = std::abs(a.q[k] + s * line[k] - slopes.rotary_value);
  }
  out.lever = path.lever;
  // The nodes' tips are computed a lever long: a few units in their last place, weighed.
  const double rounding =
      256.0 * std::numeric_limits<double>::epsilon() * out.lever * (std::abs(1.0 - s) + std::abs(s) + 1.0);
  // (and the nominal slopes' own rounding: differences of tips a lever long, over 1 mm)
  const double slope_rounding = 8.0 * std::numeric_limits<double>::epsilon() * out.lever * linear;
  // The last line's bend, carried over, is a guess: its whole size goes to the bound.
  const double bending = bent ? s * (s - 1.0) : 0.0;
  const Eigen::Vector3d bend = bending * path.line_bend, turn_bend = bending * path.line_turn_bend;
  out.position_bound = along + errors + turned * slopes.column_norm * linear + out.lever * turning + rounding +
                       slope_rounding + bend.norm();
  if (!std::isfinite(out.position_bound)) return false;
  const Eigen::Vector3d tip = a.tip + s * (b.tip - a.tip) + slopes.tip * off;
  const Eigen::Vector3d omega =
      a.omega + s * (b.omega - a.omega) +
      slopes.turn * (problem.rotary_unknowns.empty() ? 0.0 : off[problem.rotary_unknowns.front()]);
  if (kept) kept->reached = true, kept->tip = tip, kept->omega = omega;
  out.position_residual = tip + bend - target;
  out.orientation_error = omega + turn_bend;
  // What the error angles' products leave out of the rotary residual's split: the turn
  // times the error angle squared over 12, doubled for the higher orders, at each of the
  // three points the extrapolation weighs (the turn at most the residual's angle and the
  // error angle's bound together).
  const double angle = bound.largest_error_angle();
  const double turn = std::max({a.omega.norm(), b.omega.norm(), out.orientation_error.norm()}) + angle;
  const double products = (std::abs(1.0 - s) + std::abs(s) + 1.0) * turn * angle * angle / 6.0;
  out.angle_bound = (along + errors + rounding) / out.lever + products + turn_bend.norm();
  return true;
}

}  // namespace ccomp::compensate::detail
