// alpha v (T - T0): a scale growing with its temperature.
#include <algorithm>
#include <cmath>

#include "ccomp/model/term_forms.hpp"

namespace ccomp::model::forms {
namespace {

void evaluate(const TermShape& s, const Eigen::Ref<const Eigen::VectorXd>& p, const TermInputs& in, bool grad,
              TermValue& r) {
  const double v = in.primary;
  const double dT = in.secondary - s.reference;
  r.value = p[0] * v * dT;
  r.d_primary = p[0] * dT;
  r.d_secondary = p[0] * v;
  if (grad) r.d_parameters[0] = v * dT;
}

TermBound bound(const TermShape& s, const Eigen::VectorXd& p, const TermRange& u, const TermRange& w) {
  TermBound b;
  const double U = u.magnitude();
  const double dT = std::max(std::abs(w.lo - s.reference), std::abs(w.hi - s.reference));
  b.value = power_bound(p[0], U, 1) * dT;
  b.slope_p = std::abs(p[0]) * dT;
  b.slope_s = power_bound(p[0], U, 1);
  b.curvature_ps = std::abs(p[0]);
  return b;
}

}  // namespace

TermFormInfo scale_expansion() {
  TermFormInfo f;
  f.form = TermForm::scale_expansion;
  f.names = {"scale_expansion"};
  f.keys = {"temperature", "coefficient", "reference"};
  f.physics = "a scale growing with its temperature";
  f.grows_beyond_data = true;
  f.parameter_count = [](const TermShape&) -> std::size_t { return 1; };
  f.evaluate = evaluate;
  f.term_label = [](const ErrorTermSpec& t) { return t.iso + " scale expansion"; };
  f.parameter_label = [](const ErrorTermSpec& t, std::size_t) { return t.iso + ".alpha"; };
  f.shapes_only = scales_all;
  f.place = [](const TermShape&, std::size_t) { return ParameterPlace{"coefficient"}; };
  f.unit_name = [](const ErrorTermSpec&, std::size_t, const UnitNames&) { return std::string(); };
  f.physical_scale = [](const ErrorTermSpec& t, std::size_t, double plausible, const ReachOf& reach) {
    return plausible / (reach(t.primary, 0.0) * reach(t.secondary, t.shape.reference));
  };
  f.bound = bound;
  f.shortest_feature = no_feature;
  return f;
}

}  // namespace ccomp::model::forms
