// k (T - T0): a drift with a sensor's temperature.
#include <fmt/format.h>

#include <algorithm>

#include "ccomp/model/term_forms.hpp"

namespace ccomp::model::forms {
namespace {

void evaluate(const TermShape& s, const Eigen::Ref<const Eigen::VectorXd>& p, const TermInputs& in, bool grad,
              TermValue& r) {
  const double v = in.primary;
  r.value = p[0] * (v - s.reference);
  r.d_primary = p[0];
  if (grad) r.d_parameters[0] = v - s.reference;
}

}  // namespace

TermFormInfo thermal_linear() {
  TermFormInfo f;
  f.form = TermForm::thermal_linear;
  f.names = {"thermal", "thermal_linear"};
  f.keys = {"coefficient", "reference"};
  f.physics = "a drift with a sensor's temperature";
  f.grows_beyond_data = true;
  f.parameter_count = [](const TermShape&) -> std::size_t { return 1; };
  f.evaluate = evaluate;
  f.term_label = [](const ErrorTermSpec& t) { return t.iso + " thermal"; };
  f.parameter_label = [](const ErrorTermSpec& t, std::size_t) { return fmt::format("{}.k_{}", t.iso, t.primary.text); };
  f.shapes_only = scales_all;
  f.place = [](const TermShape&, std::size_t) { return ParameterPlace{"coefficient"}; };
  f.unit_name = [](const ErrorTermSpec& t, std::size_t k, const UnitNames& u) {
    const std::string base = u.value(t.parameter_unit[k]);
    return base.empty() ? std::string() : base + "/" + u.degc();
  };
  f.physical_scale = [](const ErrorTermSpec& t, std::size_t, double plausible, const ReachOf& reach) {
    return plausible / reach(t.primary, t.shape.reference);
  };
  f.bound = [](const TermShape& s, const Eigen::VectorXd& p, const TermRange& u, const TermRange&) {
    TermBound b;
    b.value = power_bound(p[0], std::max(std::abs(u.lo - s.reference), std::abs(u.hi - s.reference)), 1);
    b.slope_p = std::abs(p[0]);
    return b;
  };
  f.shortest_feature = no_feature;
  return f;
}

}  // namespace ccomp::model::forms
