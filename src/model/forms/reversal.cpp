// r/2 * s, s the approach direction (+1, -1, 0 unknown); r a polynomial along an axis:
// backlash, lost motion.
#include <fmt/format.h>

#include <algorithm>

#include "ccomp/model/term_forms.hpp"

namespace ccomp::model::forms {
namespace {

/// Half the reversal on each side: the two approach directions differ by r(w), a
/// polynomial along the axis (a screw worn more at one end plays more there): r_k of w^k,
/// k = 0..order_primary (0: a constant reversal, its only parameter), w the term's
/// secondary variable (`along:` in the model file).
void evaluate(const TermShape& s, const Eigen::Ref<const Eigen::VectorXd>& p, const TermInputs& in, bool grad,
              TermValue& r) {
  const double v = in.primary, w = in.secondary;
  double reversal = 0.0, slope = 0.0, power = 1.0, previous = 0.0;  // w^k and w^(k-1)
  for (int k = 0; k <= s.order_primary; ++k) {
    reversal += p[k] * power;
    slope += k * p[k] * previous;
    if (grad) r.d_parameters[k] = 0.5 * v * power;
    previous = power;
    power *= w;
  }
  r.value = 0.5 * reversal * v;
  r.d_primary = 0.5 * reversal;
  r.d_secondary = 0.5 * slope * v;
}

std::string unit_name(const ErrorTermSpec& t, std::size_t k, const UnitNames& u) {  // r_k of w^k along its axis
  const auto [along, along_scale] = u.variable(t.secondary);
  const std::string base = u.value(t.parameter_unit[k] * std::pow(along_scale, static_cast<double>(k)));
  if (base.empty() || k == 0) return base;
  return k == 1 ? base + "/" + along : fmt::format("{}/{}^{}", base, along, k);
}

/// |r(w)| / 2 |s|, r(w) = sum_k r_k w^k along its axis: bounded term by term.
TermBound bound(const TermShape& s, const Eigen::VectorXd& p, const TermRange& u, const TermRange& w) {
  TermBound b;
  const double U = u.magnitude(), W = w.magnitude();
  double reversal = 0.0, slope = 0.0, curvature = 0.0;
  for (int k = 0; k <= s.order_primary; ++k) {
    reversal += power_bound(p[k], W, k);
    if (k >= 1) slope += k * power_bound(p[k], W, k - 1);
    if (k >= 2) curvature += k * (k - 1) * power_bound(p[k], W, k - 2);
  }
  const double S = std::max(1.0, U);
  b.value = b.slope_p = 0.5 * reversal * S;
  b.slope_s = 0.5 * slope * S;
  b.curvature_ps = 0.5 * slope;
  b.curvature_ss = 0.5 * curvature * S;
  return b;
}

}  // namespace

TermFormInfo reversal() {
  TermFormInfo f;
  f.form = TermForm::reversal;
  f.names = {"reversal"};
  f.keys = {"reversal", "along"};
  f.physics =
      "backlash, lost motion: an error switched by the approach, of a linear or a rotary axis, constant or "
      "varying along an axis (a screw worn more where it works most)";
  f.parameter_count = [](const TermShape& s) { return static_cast<std::size_t>(std::max(0, s.order_primary)) + 1; };
  f.evaluate = evaluate;
  f.term_label = [](const ErrorTermSpec& t) { return t.iso + " reversal"; };
  f.parameter_label = [](const ErrorTermSpec& t, std::size_t k) {
    return t.shape.order_primary == 0 ? t.iso + ".reversal" : fmt::format("{}.reversal{}", t.iso, k);
  };
  f.shapes_only = scales_all;
  f.place = [](const TermShape& s, std::size_t k) {
    return s.order_primary == 0 ? ParameterPlace{"reversal"} : ParameterPlace{"reversal", static_cast<int>(k)};
  };
  f.unit_name = unit_name;
  f.physical_scale = [](const ErrorTermSpec& t, std::size_t k, double plausible, const ReachOf& reach) {
    return k == 0 ? plausible : plausible / std::pow(reach(t.secondary, 0.0), static_cast<double>(k));
  };
  f.bound = bound;
  f.shortest_feature = no_feature;
  return f;
}

}  // namespace ccomp::model::forms
