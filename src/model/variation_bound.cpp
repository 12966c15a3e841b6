#include "ccomp/model/variation_bound.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "ccomp/model/cubic_spline.hpp"

namespace ccomp::model {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// The bounds of one term over the ranges of its variables: value, slopes and curvatures
/// in its primary (p) and secondary (s) variable, the largest slope jump (a linear table's
/// knots, a table's ends) and the shortest knot spacing (0: no knots).
struct TermBound {
  double value = 0.0, slope_p = 0.0, slope_s = 0.0;
  double curvature_pp = 0.0, curvature_ps = 0.0, curvature_ss = 0.0;
  double kink = 0.0;
  double knot_gap = 0.0;
};

/// The values a variable takes: an axis within its limits, a condition at its value.
struct Range {
  double lo = 0.0, hi = 0.0;
  [[nodiscard]] double magnitude() const {
    const double m = std::max(std::abs(lo), std::abs(hi));
    return std::isnan(m) ? kInf : m;
  }
};

/// An axis' limits in chain units (mm, rad), widened by the largest correction: a nominal
/// point may lie outside them by that much.
Range axis_range(const MachineModel& machine, std::size_t index) {
  const AxisSpec* axis = machine.axis("XYZABCUVW"[index]);
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

/// |c| x^k for |x| <= magnitude, without 0 * inf: a zero coefficient bounds nothing.
double power_bound(double c, double magnitude, int k) {
  if (c == 0.0) return 0.0;
  return k == 0 ? std::abs(c) : std::abs(c) * std::pow(magnitude, k);
}

void table_bound(const TermShape& s, const Eigen::VectorXd& p, TermBound& b) {
  const std::vector<double>& x = s.knots;
  const std::size_t n = x.size();
  b.value = p.cwiseAbs().maxCoeff();
  if (n < 2) return;
  b.knot_gap = kInf;
  std::vector<double> slope(n - 1);
  for (std::size_t k = 0; k + 1 < n; ++k) {
    const double h = x[k + 1] - x[k];
    slope[k] = (p[static_cast<Eigen::Index>(k + 1)] - p[static_cast<Eigen::Index>(k)]) / h;
    b.knot_gap = std::min(b.knot_gap, h);
  }
  if (s.interpolation == Interpolation::linear) {
    // Held constant outside: the ends are kinks too.
    for (std::size_t k = 0; k + 1 < n; ++k) b.slope_p = std::max(b.slope_p, std::abs(slope[k]));
    b.kink = std::max(std::abs(slope.front()), std::abs(slope.back()));
    for (std::size_t k = 1; k + 1 < n; ++k) b.kink = std::max(b.kink, std::abs(slope[k] - slope[k - 1]));
    return;
  }
  std::vector<double> m;
  spline_moments(x, p.data(), m);
  double largest = 0.0, widest = 0.0;
  for (std::size_t k = 0; k + 1 < n; ++k) {
    const double h = x[k + 1] - x[k];
    // s' = slope - (3a^2 - 1) h M_k / 6 + (3b^2 - 1) h M_k+1 / 6, |3a^2 - 1| <= 2
    b.slope_p = std::max(b.slope_p, std::abs(slope[k]) + h * (std::abs(m[k]) + std::abs(m[k + 1])) / 3.0);
    largest = std::max({largest, std::abs(m[k]), std::abs(m[k + 1])});
    widest = std::max(widest, h);
  }
  b.curvature_pp = largest;
  b.value += widest * widest / 8.0 * largest;  // a spline leaves its chords by at most h^2 max|s''| / 8
  b.kink = b.slope_p;                          // held constant outside: the ends' slopes
}

void polynomial_bound(const TermShape& s, const Eigen::VectorXd& p, double U, TermBound& b) {
  for (int k = 0; k <= s.order; ++k) {
    b.value += power_bound(p[k], U, k);
    if (k >= 1) b.slope_p += k * power_bound(p[k], U, k - 1);
    if (k >= 2) b.curvature_pp += k * (k - 1) * power_bound(p[k], U, k - 2);
  }
}

void periodic_bound(const TermShape& s, const Eigen::VectorXd& p, TermBound& b) {
  for (int k = 1; k <= s.order; ++k) {
    const double amplitude = std::hypot(p[2 * k - 1], p[2 * k]);
    const double omega = kTwoPi * k / std::abs(p[0]);
    b.value += amplitude;
    b.slope_p += omega * amplitude;
    b.curvature_pp += omega * omega * amplitude;
  }
}

/// |c| d^du/du d^dw/dw (u^i w^j) bounded, for |u| <= U and |w| <= W.
double monomial_derivative_bound(double c, int i, int j, int du, int dw, double U, double W) {
  if (du > i || dw > j) return 0.0;
  double falling = 1.0;
  for (int k = 0; k < du; ++k) falling *= i - k;
  for (int k = 0; k < dw; ++k) falling *= j - k;
  const double pu = power_bound(1.0, U, i - du), pw = power_bound(1.0, W, j - dw);
  return c == 0.0 ? 0.0 : std::abs(c) * falling * pu * pw;
}

void cross_axis_bound(const TermShape& s, const Eigen::VectorXd& p, double U, double W, TermBound& b) {
  Eigen::Index index = 0;
  for (int i = 0; i <= s.order_primary; ++i)
    for (int j = 1; j <= s.order; ++j, ++index) {
      auto term = [&](int du, int dw) { return monomial_derivative_bound(p[index], i, j, du, dw, U, W); };
      b.value += term(0, 0);
      b.slope_p += term(1, 0);
      b.slope_s += term(0, 1);
      b.curvature_pp += term(2, 0);
      b.curvature_ps += term(1, 1);
      b.curvature_ss += term(0, 2);
    }
}

TermBound term_bound(const ErrorTermSpec& t, const Range& u, const Range& w) {
  TermBound b;
  const Eigen::VectorXd& p = t.parameters;
  const double U = u.magnitude(), W = w.magnitude();
  switch (t.shape.form) {
    case TermForm::constant:
      b.value = std::abs(p[0]);
      break;
    case TermForm::polynomial:
      polynomial_bound(t.shape, p, U, b);
      break;
    case TermForm::table:
      table_bound(t.shape, p, b);
      break;
    case TermForm::periodic:
      periodic_bound(t.shape, p, b);
      break;
    case TermForm::reversal: {
      // |r(w)| / 2 |s|, r(w) = sum_k r_k w^k along its axis: bounded term by term.
      double reversal = 0.0, slope = 0.0, curvature = 0.0;
      for (int k = 0; k <= t.shape.order_primary; ++k) {
        reversal += power_bound(p[k], W, k);
        if (k >= 1) slope += k * power_bound(p[k], W, k - 1);
        if (k >= 2) curvature += k * (k - 1) * power_bound(p[k], W, k - 2);
      }
      const double S = std::max(1.0, U);
      b.value = b.slope_p = 0.5 * reversal * S;
      b.slope_s = 0.5 * slope * S;
      b.curvature_ps = 0.5 * slope;
      b.curvature_ss = 0.5 * curvature * S;
      break;
    }
    case TermForm::thermal_linear:
      b.value = power_bound(p[0], std::max(std::abs(u.lo - t.shape.reference), std::abs(u.hi - t.shape.reference)), 1);
      b.slope_p = std::abs(p[0]);
      break;
    case TermForm::thermal_warmup: {
      const double amplitude = std::abs(p[0]), tau = std::abs(p[1]);
      const double growth = std::exp(std::max(-u.lo, -u.hi) / tau);  // exp(-v / tau) at its largest
      b.value = amplitude * std::max(1.0, growth);
      b.slope_p = amplitude / tau * growth;
      b.curvature_pp = b.slope_p / tau;
      break;
    }
    case TermForm::bump: {
      // |A g| <= |A|; |d/dv| <= |A| / w max|u g| = |A| / w e^-1/2; |d2/dv2| <= |A| / w^2.
      const double amplitude = std::abs(p[0]), width = std::abs(p[2]);
      b.value = amplitude;
      b.slope_p = amplitude / width * std::exp(-0.5);
      b.curvature_pp = amplitude / (width * width);
      break;
    }
    case TermForm::scale_expansion: {
      const double dT = std::max(std::abs(w.lo - t.shape.reference), std::abs(w.hi - t.shape.reference));
      b.value = power_bound(p[0], U, 1) * dT;
      b.slope_p = std::abs(p[0]) * dT;
      b.slope_s = power_bound(p[0], U, 1);
      b.curvature_ps = std::abs(p[0]);
      break;
    }
    case TermForm::cross_axis:
      cross_axis_bound(t.shape, p, U, W, b);
      break;
  }
  return b;
}

/// bound x travel, zero when nothing travels (an unbounded term on a still axis adds nothing).
double along(double bound, double travel) {
  return travel == 0.0 ? 0.0 : bound * travel;
}

}  // namespace

VariationBound::VariationBound(const ForwardModel& model, const Conditions& conditions) {
  const MachineModel& machine = model.machine();
  for (std::size_t i = 0; i < 9; ++i)
    if (const AxisSpec* a = machine.axis("XYZABCUVW"[i])) rotary_[i] = a->type == AxisType::rotary;
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

double VariationBound::direction_change(const std::array<double, 9>& a, const std::array<double, 9>& b,
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
