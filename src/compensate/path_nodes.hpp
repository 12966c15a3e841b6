#pragma once
// The inverse's shortcut along a path. Where a solve evaluated the model twice under the
// same conditions (the nodes), the line through the two points extrapolates the actual
// tip to the next prediction, and the error field's bound (model::VariationBound) says
// how far the truth can be: a prediction whose residual is bounded below the caller's
// share of the tolerance is accepted without evaluating the model.
//
// Why it holds. Along the line q(s) = a + s (b - a) the tip f(q(s)) is smooth: the line
// through its values at s = 0 and 1 misses it at s by at most max|f''| |s (s - 1)| / 2,
// the maximum over the hull of 0, 1 and s (the interpolation error of a straight line,
// also beyond its nodes). In that hull's own units max|f''| / 2 is at most 4 times its
// chord bound, which holds the rigid chain's bending too; a table's slope jump on the way
// misses by at most the jump times the travel, which the chord bound counts a quarter
// of. Further out the hull's chord bound grows no faster than the square of its length.
// The prediction lies off the line by w (the path bends, the corrections change): the
// perfect machine's tip is affine in the linear axes while the rotary axis stands, so
// their share of w moves it by the nominal slopes exactly (taken where the rotary axis
// stood, which turns them by at most its travel since); the rotary axis' share turns the
// tip through at most the lever; and the errors change by at most the error field's
// slopes times w. The same for the orientation: with one rotary axis the perfect
// machine's turn from the target is about that axis and linear in it, and the rotary
// residual is that turn plus the error rotation's component along the axis, up to a term
// of third order (the turn times the error angle squared, over 12), which is added.
#include <Eigen/Core>
#include <limits>

#include "ccomp/compensate/inverse.hpp"
#include "ccomp/model/forward.hpp"
#include "ccomp/model/variation_bound.hpp"

namespace ccomp::compensate::detail {

/// Whether the nodes were evaluated under these conditions, target
/// orientation and tool length.
[[nodiscard]] bool nodes_hold(const PathNodes& path, const model::Conditions& conditions,
                              const Eigen::Matrix3d& R_target, double tool_length);

/// An extrapolation's point before the bend carried over and the target: what
/// record_node() asks again of a point evaluated where the bound did not let it through.
struct LinePoint {
  model::ChainQ q = model::ChainQ::Constant(std::numeric_limits<double>::quiet_NaN());
  bool reached = false;  ///< the extrapolation held (extrapolate() returned true)
  double s = 0.0;        ///< q's place along the line
  Eigen::Vector3d tip = Eigen::Vector3d::Zero(),
                  omega = Eigen::Vector3d::Zero();  ///< the actual tip, orientation residual
};

/// Makes the last evaluation at q (`d` holds its actual pose, `omega` its orientation
/// residual against R_target) the newer node, the older one gone where the conditions
/// changed; with two, their line's chord bounds out to where an extrapolation could still
/// stay below `tolerance` (mm), and the nominal slopes there. `kept`: the extrapolation to
/// q already made with these nodes, if it was to q.
void record_node(const model::ForwardModel& model, const model::VariationBound& bound, const InverseProblem& problem,
                 model::ForwardData& d, PathNodes& path, const model::ChainQ& q, const model::Conditions& conditions,
                 const Eigen::Matrix3d& R_target, const Eigen::Vector3d& omega, double tolerance,
                 const LinePoint* kept = nullptr);

/// The residuals at a prediction as the nodes extrapolate them, and how far the truth can be.
struct Extrapolated {
  Eigen::Vector3d position_residual;  ///< actual - target, mm
  Eigen::Vector3d orientation_error;  ///< log of the actual orientation against the target, rad
  double position_bound = 0.0;        ///< mm: |true - extrapolated| position residual
  double angle_bound = 0.0;           ///< rad: the same of the rotary residual
  double lever = 0.0;                 ///< mm: what an angle acts through
};

/// The nodes' extrapolation to q, where two nodes hold (the caller's to check) and the
/// prediction lies within their line's reach; `bent`: with the bend carried from the last
/// line. `at` gets q's place along the line (s), whatever the outcome; `kept`, where given,
/// the point before the bend and target, for record_node() (nodes unchanged meanwhile).
[[nodiscard]] bool extrapolate(const model::VariationBound& bound, const InverseProblem& problem, const PathNodes& path,
                               const model::ChainQ& q, const Eigen::Vector3d& target, Extrapolated& out,
                               bool bent = true, double* at = nullptr, LinePoint* kept = nullptr);

}  // namespace ccomp::compensate::detail
