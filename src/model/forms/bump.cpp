// A exp(-((v - c) / w)^2 / 2): a local defect of a guideway or a scale at c.
#include <cmath>

#include "ccomp/model/term_forms.hpp"

namespace ccomp::model::forms {
namespace {

// A (amplitude), c (where), w (how wide: one standard deviation of the bell).
void evaluate(const TermShape&, const Eigen::Ref<const Eigen::VectorXd>& p, const TermInputs& in, bool grad,
              TermValue& r) {
  const double v = in.primary;
  const double amplitude = p[0], centre = p[1], width = p[2];
  const double u = (v - centre) / width, g = std::exp(-0.5 * u * u);
  r.value = amplitude * g;
  r.d_primary = -amplitude * g * u / width;
  if (grad) {
    r.d_parameters[0] = g;
    r.d_parameters[1] = amplitude * g * u / width;
    r.d_parameters[2] = amplitude * g * u * u / width;
  }
}

/// |A g| <= |A|; |d/dv| <= |A| / w max|u g| = |A| / w e^-1/2; |d2/dv2| <= |A| / w^2.
TermBound bound(const TermShape&, const Eigen::VectorXd& p, const TermRange&, const TermRange&) {
  TermBound b;
  const double amplitude = std::abs(p[0]), width = std::abs(p[2]);
  b.value = amplitude;
  b.slope_p = amplitude / width * std::exp(-0.5);
  b.curvature_pp = amplitude / (width * width);
  return b;
}

}  // namespace

TermFormInfo bump() {
  TermFormInfo f;
  f.form = TermForm::bump;
  f.names = {"bump"};
  f.keys = {"at", "width", "amplitude"};
  f.physics = "a local defect: a guideway's bump, a scale joint";
  f.parameter_count = [](const TermShape&) -> std::size_t { return 3; };
  f.evaluate = evaluate;
  f.term_label = [](const ErrorTermSpec& t) { return t.iso + " bump"; };
  f.parameter_label = [](const ErrorTermSpec& t, std::size_t k) {
    return t.iso + (k == 0 ? ".amplitude" : k == 1 ? ".at" : ".width");
  };
  f.shapes_only = [](std::size_t k) { return k >= 1; };
  f.place = [](const TermShape&, std::size_t k) {
    return k == 0 ? ParameterPlace{"amplitude"} : k == 1 ? ParameterPlace{"at"} : ParameterPlace{"width"};
  };
  f.unit_name = [](const ErrorTermSpec& t, std::size_t k, const UnitNames& u) {
    return k == 0 ? u.value(t.parameter_unit[k]) : u.variable(t.primary).first;
  };
  // Its size; where it sits, on the axis' reach; its width.
  f.physical_scale = [](const ErrorTermSpec& t, std::size_t k, double plausible, const ReachOf& reach) {
    return k == 0 ? plausible : k == 1 ? reach(t.primary, 0.0) : std::abs(t.parameters[2]);
  };
  f.bound = bound;
  f.shortest_feature = [](const ErrorTermSpec& t) { return std::abs(t.parameters[2]) / 4.0; };  // a quarter of its width
  return f;
}

}  // namespace ccomp::model::forms
