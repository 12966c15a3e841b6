// c: a location error, a squareness, a constant offset.
#include <fmt/format.h>

#include "ccomp/model/term_forms.hpp"

namespace ccomp::model::forms {
namespace {

void evaluate(const TermShape&, const Eigen::Ref<const Eigen::VectorXd>& p, const TermInputs&, bool grad,
              TermValue& r) {
  r.value = p[0];
  if (grad) r.d_parameters[0] = 1.0;
}

}  // namespace

TermFormInfo constant() {
  TermFormInfo f;
  f.form = TermForm::constant;
  f.names = {"constant"};
  f.keys = {"value"};
  f.physics = "a constant offset or angle: a location error, a squareness";
  f.parameter_count = [](const TermShape&) -> std::size_t { return 1; };
  f.evaluate = evaluate;
  f.term_label = [](const ErrorTermSpec& t) {
    return t.iso + (t.placement == ErrorPlacement::location ? " location" : " constant");
  };
  f.parameter_label = [](const ErrorTermSpec& t, std::size_t) { return t.iso; };
  f.shapes_only = scales_all;
  f.place = [](const TermShape&, std::size_t) { return ParameterPlace{"value"}; };
  f.unit_name = value_unit;
  f.physical_scale = plausible_scale;
  f.bound = [](const TermShape&, const Eigen::VectorXd& p, const TermRange&, const TermRange&) {
    TermBound b;
    b.value = std::abs(p[0]);
    return b;
  };
  f.shortest_feature = no_feature;
  return f;
}

}  // namespace ccomp::model::forms
