// sum_k a_k v^k, k = 0..n: a smooth error along an axis.
#include <fmt/format.h>

#include "ccomp/model/term_forms.hpp"

namespace ccomp::model::forms {
namespace {

void evaluate(const TermShape& s, const Eigen::Ref<const Eigen::VectorXd>& p, const TermInputs& in, bool grad,
              TermValue& r) {
  const double v = in.primary;
  double power = 1.0, previous = 0.0;  // v^k and v^(k-1)
  for (int k = 0; k <= s.order; ++k) {
    r.value += p[k] * power;
    r.d_primary += k * p[k] * previous;
    if (grad) r.d_parameters[k] = power;
    previous = power;
    power *= v;
  }
}

std::string unit_name(const ErrorTermSpec& t, std::size_t k, const UnitNames& u) {
  const auto [var, var_scale] = u.variable(t.primary);
  const std::string base = u.value(t.parameter_unit[k] * std::pow(var_scale, static_cast<double>(k)));
  if (base.empty()) return "";
  return k == 0 ? base : k == 1 ? base + "/" + var : fmt::format("{}/{}^{}", base, var, k);
}

TermBound bound(const TermShape& s, const Eigen::VectorXd& p, const TermRange& u, const TermRange&) {
  TermBound b;
  const double U = u.magnitude();
  for (int k = 0; k <= s.order; ++k) {
    b.value += power_bound(p[k], U, k);
    if (k >= 1) b.slope_p += k * power_bound(p[k], U, k - 1);
    if (k >= 2) b.curvature_pp += k * (k - 1) * power_bound(p[k], U, k - 2);
  }
  return b;
}

}  // namespace

TermFormInfo polynomial() {
  TermFormInfo f;
  f.form = TermForm::polynomial;
  f.names = {"polynomial"};
  f.keys = {"coefficients"};
  f.physics = "a smooth error along an axis: positioning, straightness, an angular error motion";
  f.grows_beyond_data = true;
  f.parameter_count = [](const TermShape& s) { return static_cast<std::size_t>(s.order) + 1; };
  f.evaluate = evaluate;
  f.term_label = [](const ErrorTermSpec& t) { return t.iso + " polynomial"; };
  f.parameter_label = [](const ErrorTermSpec& t, std::size_t k) { return fmt::format("{}.a{}", t.iso, k); };
  f.shapes_only = scales_all;
  f.place = [](const TermShape&, std::size_t k) { return ParameterPlace{"coefficients", static_cast<int>(k)}; };
  f.unit_name = unit_name;
  f.physical_scale = [](const ErrorTermSpec& t, std::size_t k, double plausible, const ReachOf& reach) {
    return plausible / std::pow(reach(t.primary, 0.0), static_cast<double>(k));
  };
  f.bound = bound;
  f.shortest_feature = no_feature;
  return f;
}

}  // namespace ccomp::model::forms
