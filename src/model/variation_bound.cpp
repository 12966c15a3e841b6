#include "ccomp/model/variation_bound.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "ccomp/axis.hpp"
#include "ccomp/model/term_forms.hpp"

namespace ccomp::model {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kTwoPi = 2.0 * std::numbers::pi;

using Range = TermRange;

/// An axis' limits in chain units (mm, rad), widened by the largest correction: a nominal
/// point may lie outside them by that much.
Range axis_range(const MachineModel& machine, std::size_t index) {
  const AxisSpec* axis = machine.axis(kAxisLetters[index]);
  if (!axis) return {-kInf, kInf};
  const bool rotary = axis->type == AxisType::rotary;
  const double scale = rotary ? kTwoPi / 360.0 : 1.0;                                     // limits in deg, chain in rad
  const double margin = rotary ? machine.max_correction * kRotaryBoundPerMm : machine.max_correction;
  return {axis->min * scale - margin, axis->max * scale + margin};
}

Range range_of(const Variable& v, const MachineModel& machine, const Conditions& c) {
  switch (v.kind) {
    case VariableKind::axis:
      return axis_range(machine, v.index);
    case VariableKind::tool_length:
      return {-kInf, kInf};
    case VariableKind::time:
      return {c.time, c.time};
    case VariableKind::temperature:
      if (v.index < c.temperatures.size()) return {c.temperatures[v.index], c.temperatures[v.index]};
      return {20.0, 20.0};
    case VariableKind::direction:
      return {-1.0, 1.0};
    case VariableKind::none:
      break;
  }
  return {};
}

int chain_variable(const Variable& v) {
  if (v.kind == VariableKind::axis) return static_cast<int>(v.index);
  if (v.kind == VariableKind::tool_length) return static_cast<int>(kToolLengthIndex);
  return -1;
}

TermBound term_bound(const ErrorTermSpec& t, const Range& u, const Range& w) {
  return term_form(t.shape.form).bound(t.shape, t.parameters, u, w);
}

/// bound x travel, zero when nothing travels (an unbounded term on a still axis adds nothing).
double along(double bound, double travel) {
  return travel == 0.0 ? 0.0 : bound * travel;
}

}  // namespace

VariationBound::VariationBound(const ForwardModel& model, const Conditions& conditions) {
  const MachineModel& machine = model.machine();
  for (std::size_t i = 0; i < 9; ++i)
    if (const AxisSpec* a = machine.axis(kAxisLetters[i])) rotary_[i] = a->type == AxisType::rotary;
  for (const ErrorTermSpec& t : machine.terms) {
    const TermBound b =
        term_bound(t, range_of(t.primary, machine, conditions), range_of(t.secondary, machine, conditions));
    const bool angular = t.component >= 3;
    (angular ? angular_sum_ : translation_sum_) += b.value;
    // (A direction is no chain variable: it stands along a move, and changes between moves.)
    auto per_direction = [&](const Variable& v, double slope) {
      if (v.kind != VariableKind::direction) return;
      if (v.index >= direction_translation_.size() || !(slope >= 0.0)) {  // (NaN too)
        directions_bounded_ = false;
        return;
      }
      (angular ? direction_angular_ : direction_translation_)[v.index] += slope;
    };
    per_direction(t.primary, b.slope_p);
    per_direction(t.secondary, b.slope_s);
    const int p = chain_variable(t.primary), s = chain_variable(t.secondary);
    if (p >= 0 && s >= 0) {
      two_variables_.push_back({static_cast<std::size_t>(p), static_cast<std::size_t>(s), angular, b.slope_p, b.slope_s,
                                b.curvature_pp, b.curvature_ps, b.curvature_ss});
      continue;
    }
    if (p < 0 && s < 0) continue;  // constant along any move
    AlongVariable& v = along_[static_cast<std::size_t>(p >= 0 ? p : s)];
    const bool on_primary = p >= 0;
    (angular ? v.angular_curvature : v.translation_curvature) += on_primary ? b.curvature_pp : b.curvature_ss;
    (angular ? v.angular_slope : v.translation_slope) += on_primary ? b.slope_p : b.slope_s;
    if (on_primary) (angular ? v.angular_kink : v.translation_kink) += b.kink;
    if (on_primary && b.knot_gap > 0.0) v.knot_gap = std::min(v.knot_gap, b.knot_gap);
  }
  // Any two frames of the chain are no further apart than all offsets and strokes together.
  for (const auto* side : {&model.chain().workpiece, &model.chain().tool})
    for (const kinematics::Joint& j : side->joints) {
      lever_ += j.placement.t.norm();
      if (j.type == kinematics::JointType::linear && j.axis < 9) lever_ += axis_range(machine, j.axis).magnitude();
    }
  bounded_ = std::isfinite(lever_) && angular_sum_ <= 0.01 && translation_sum_ <= 1.0;  // false for NaN too
}

VariationBound::Travel VariationBound::travel(const ChainQ& a, const ChainQ& b) const {
  Travel t;
  for (std::size_t i = 0; i < kChainVariables; ++i) {
    t.by_variable[i] = std::abs(b[static_cast<Eigen::Index>(i)] - a[static_cast<Eigen::Index>(i)]);
    (rotary_[i] ? t.turning : t.linear) += t.by_variable[i];
  }
  t.lever = lever(a, b);
  return t;
}

double VariationBound::stretch_limit(const ChainQ& a, const ChainQ& b) const {
  const Travel m = travel(a, b);
  double limit = kInf;
  for (std::size_t i = 0; i < kChainVariables; ++i)
    if (const double d = m.by_variable[i]; d > 0.0)
      limit = std::min(limit, along_[i].knot_gap / d);  // chord_deviation() needs d < knot_gap
  return limit;
}

double VariationBound::lever(const ChainQ& a, const ChainQ& b) const {
  const auto tool = static_cast<Eigen::Index>(kToolLengthIndex);
  return lever_ + std::max(std::abs(a[tool]), std::abs(b[tool]));
}

double VariationBound::second_order(double lever) const {
  return 1.0 + 4.0 * (angular_sum_ + translation_sum_ / std::max(lever, 1.0));
}

double VariationBound::chord_deviation(const ChainQ& a, const ChainQ& b) const {
  if (!bounded_) return kInf;
  const Travel m = travel(a, b);
  const double lever = m.lever, linear = m.linear, turning = m.turning;
  // The rigid chain bends the path where an axis turns: d2/dt2 of R(t) r(t).
  const double rigid = lever * turning * turning + 2.0 * turning * linear;
  // A translation delta turned by R(t): delta'' + 2 R' delta' + R'' delta; a rotation eps
  // acting through the lever r(t): eps'' r + 2 eps' r' + eps r''.
  const double translation_slope_weight = 2.0 * turning, angular_slope_weight = 2.0 * (linear + lever * turning);
  double curvature = translation_sum_ * turning * turning + angular_sum_ * rigid, kinks = 0.0;
  for (std::size_t i = 0; i < kChainVariables; ++i) {
    const double d = m.by_variable[i];
    if (d == 0.0) continue;
    const AlongVariable& v = along_[i];
    if (d >= v.knot_gap) return kInf;  // more than one knot on the way
    curvature +=
        (v.translation_curvature + lever * v.angular_curvature) * d * d +
        (along(v.translation_slope, translation_slope_weight) + along(v.angular_slope, angular_slope_weight)) * d;
    kinks += (v.translation_kink + lever * v.angular_kink) * d;
  }
  for (const TwoVariables& t : two_variables_) {
    const double du = m.by_variable[t.u], dw = m.by_variable[t.w];
    if (du == 0.0 && dw == 0.0) continue;
    const double second = along(along(t.curvature_uu, du), du) + 2.0 * along(along(t.curvature_uw, du), dw) +
                          along(along(t.curvature_ww, dw), dw);
    const double first = along(t.slope_u, du) + along(t.slope_w, dw);
    curvature += t.angular ? lever * second + angular_slope_weight * first : second + translation_slope_weight * first;
  }
  // and what rounding leaves in a computed tip: a few units in the last place of its lever
  const double rounding = 64.0 * std::numeric_limits<double>::epsilon() * lever;
  return second_order(lever) * (curvature / 8.0 + kinks / 4.0) + rigid / 8.0 + rounding;
}

double VariationBound::error_change(const ChainQ& a, const ChainQ& b) const {
  if (!bounded_) return kInf;
  const Travel m = travel(a, b);
  // d/dt of R(t) delta and of R(t) (eps x r): delta' + R' delta, and eps' r + eps r' + R' eps r.
  double slope = translation_sum_ * m.turning + angular_sum_ * (m.linear + 2.0 * m.lever * m.turning);
  for (std::size_t i = 0; i < kChainVariables; ++i) {
    const double d = m.by_variable[i];
    if (d == 0.0) continue;
    slope += (along_[i].translation_slope + m.lever * along_[i].angular_slope) * d;
  }
  for (const TwoVariables& t : two_variables_) {
    const double first = along(t.slope_u, m.by_variable[t.u]) + along(t.slope_w, m.by_variable[t.w]);
    slope += t.angular ? m.lever * first : first;
  }
  // Rounding: of both errors, each the difference of two computed tips.
  const double rounding = 256.0 * std::numeric_limits<double>::epsilon() * m.lever;
  return second_order(m.lever) * slope + rounding;
}

double VariationBound::direction_change(const AxisArray<double>& a, const AxisArray<double>& b,
                                        double tool_length) const {
  if (!bounded_ || !directions_bounded_) return kInf;
  // At one point the chain stands: only the terms reading a direction change, each by at
  // most its slope in it times the change; a translation moves the tip by as much, a
  // rotation through the lever; their products with the rest, by second_order().
  const double lever = lever_ + std::abs(tool_length);
  double change = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (const double d = std::abs(b[i] - a[i]); d != 0.0)
      change += (direction_translation_[i] + lever * direction_angular_[i]) * d;
  return second_order(lever) * change;
}

VariationBound::ErrorSlopes VariationBound::error_slopes(double tool_length) const {
  ErrorSlopes slopes;
  slopes.tool_length = tool_length;
  slopes.per_variable.fill(kInf);
  slopes.rounding = kInf;
  if (!bounded_) return slopes;
  // error_change() is linear in each variable's travel: its terms, variable by variable.
  const double lever = lever_ + std::abs(tool_length), factor = second_order(lever);
  for (std::size_t i = 0; i < kChainVariables; ++i) {
    double slope = rotary_[i] ? translation_sum_ + 2.0 * angular_sum_ * lever : angular_sum_;
    slope += along_[i].translation_slope + lever * along_[i].angular_slope;
    for (const TwoVariables& t : two_variables_) {
      const double first = (t.u == i ? t.slope_u : 0.0) + (t.w == i ? t.slope_w : 0.0);
      slope += t.angular ? lever * first : first;
    }
    slopes.per_variable[i] = factor * slope;
  }
  // error_change()'s rounding, and as much again for summing in another order
  slopes.rounding = 512.0 * std::numeric_limits<double>::epsilon() * lever;
  return slopes;
}

}  // namespace ccomp::model
