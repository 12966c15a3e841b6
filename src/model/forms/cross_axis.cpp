// sum_{i,j} c_ij u^i w^j, j >= 1: an error of one axis varying with another's position w.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "ccomp/model/term_forms.hpp"

namespace ccomp::model::forms {
namespace {

void evaluate(const TermShape& s, const Eigen::Ref<const Eigen::VectorXd>& p, const TermInputs& in, bool grad,
              TermValue& r) {
  const double v = in.primary, w = in.secondary;
  Eigen::Index index = 0;
  double ui = 1.0, ui_1 = 0.0;  // v^i and v^(i-1)
  for (int i = 0; i <= s.order_primary; ++i) {
    double wj_1 = 1.0;  // w^(j-1)
    for (int j = 1; j <= s.order; ++j, ++index) {
      const double wj = wj_1 * w;
      r.value += p[index] * ui * wj;
      r.d_primary += p[index] * i * ui_1 * wj;
      r.d_secondary += p[index] * ui * j * wj_1;
      if (grad) r.d_parameters[index] = ui * wj;
      wj_1 = wj;
    }
    ui_1 = ui;
    ui *= v;
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

TermBound bound(const TermShape& s, const Eigen::VectorXd& p, const TermRange& u, const TermRange& w) {
  TermBound b;
  const double U = u.magnitude(), W = w.magnitude();
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
  return b;
}

}  // namespace

TermFormInfo cross_axis() {
  TermFormInfo f;
  f.form = TermForm::cross_axis;
  f.names = {"cross_axis"};
  f.keys = {"other", "coefficients"};
  f.physics =
      "an error of one axis varying smoothly with another's position: a load, an overhang sagging, 2-D Abbe errors";
  f.grows_beyond_data = true;
  f.parameter_count = [](const TermShape& s) {
    return static_cast<std::size_t>(s.order_primary + 1) * static_cast<std::size_t>(s.order);
  };
  f.evaluate = evaluate;
  f.term_label = [](const ErrorTermSpec& t) { return t.iso + " cross-axis"; };
  f.parameter_label = [](const ErrorTermSpec& t, std::size_t k) {
    const auto order = static_cast<std::size_t>(t.shape.order);
    return fmt::format("{}.c{}{}", t.iso, k / order, k % order + 1);
  };
  f.shapes_only = scales_all;
  f.place = [](const TermShape& s, std::size_t k) {
    const auto order = static_cast<std::size_t>(s.order);
    return ParameterPlace{"coefficients", static_cast<int>(k / order), static_cast<int>(k % order)};
  };
  f.unit_name = [](const ErrorTermSpec&, std::size_t, const UnitNames&) { return std::string(); };
  f.physical_scale = [](const ErrorTermSpec& t, std::size_t k, double plausible, const ReachOf& reach) {
    const auto order = static_cast<std::size_t>(std::max(1, t.shape.order));
    const auto i = static_cast<double>(k / order), j = static_cast<double>(k % order + 1);
    return plausible / (std::pow(reach(t.primary, 0.0), i) * std::pow(reach(t.secondary, 0.0), j));
  };
  f.bound = bound;
  f.shortest_feature = no_feature;
  return f;
}

}  // namespace ccomp::model::forms
