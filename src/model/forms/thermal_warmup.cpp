// A (1 - exp(-t / tau)): a warm-up drift, first order in time.
#include <algorithm>
#include <cmath>

#include "ccomp/model/term_forms.hpp"

namespace ccomp::model::forms {
namespace {

void evaluate(const TermShape&, const Eigen::Ref<const Eigen::VectorXd>& p, const TermInputs& in, bool grad,
              TermValue& r) {
  const double v = in.primary;
  const double amplitude = p[0], tau = p[1];
  const double e = std::exp(-v / tau);
  r.value = amplitude * (1.0 - e);
  r.d_primary = amplitude * e / tau;
  if (grad) {
    r.d_parameters[0] = 1.0 - e;
    r.d_parameters[1] = -amplitude * e * v / (tau * tau);
  }
}

TermBound bound(const TermShape&, const Eigen::VectorXd& p, const TermRange& u, const TermRange&) {
  TermBound b;
  const double amplitude = std::abs(p[0]), tau = std::abs(p[1]);
  const double growth = std::exp(std::max(-u.lo, -u.hi) / tau);  // exp(-v / tau) at its largest
  b.value = amplitude * std::max(1.0, growth);
  b.slope_p = amplitude / tau * growth;
  b.curvature_pp = b.slope_p / tau;
  return b;
}

}  // namespace

TermFormInfo thermal_warmup() {
  TermFormInfo f;
  f.form = TermForm::thermal_warmup;
  f.names = {"warmup"};
  f.keys = {"amplitude", "time_constant"};
  f.physics = "a warm-up drift, first order in time";
  f.parameter_count = [](const TermShape&) -> std::size_t { return 2; };
  f.evaluate = evaluate;
  f.term_label = [](const ErrorTermSpec& t) { return t.iso + " warm-up"; };
  f.parameter_label = [](const ErrorTermSpec& t, std::size_t k) {
    return k == 0 ? t.iso + ".amplitude" : t.iso + ".time_constant";
  };
  f.shapes_only = [](std::size_t k) { return k == 1; };
  f.place = [](const TermShape&, std::size_t k) {
    return k == 0 ? ParameterPlace{"amplitude"} : ParameterPlace{"time_constant"};
  };
  f.unit_name = [](const ErrorTermSpec& t, std::size_t k, const UnitNames& u) {
    return k == 1 ? std::string("s") : u.value(t.parameter_unit[k]);
  };
  f.physical_scale = [](const ErrorTermSpec& t, std::size_t k, double plausible, const ReachOf&) {
    return k == 0 ? plausible : std::abs(t.parameters[1]);
  };
  f.bound = bound;
  f.shortest_feature = no_feature;
  return f;
}

}  // namespace ccomp::model::forms
