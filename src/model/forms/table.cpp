// Values at knots, linear or cubic (a natural spline) between them: an error read at targets.
#include <fmt/format.h>

#include <algorithm>
#include <limits>

#include "ccomp/model/cubic_spline.hpp"
#include "ccomp/model/term_forms.hpp"

namespace ccomp::model::forms {
namespace {

void evaluate(const TermShape& s, const Eigen::Ref<const Eigen::VectorXd>& p, const TermInputs& in, bool grad,
              TermValue& r) {
  const double v = in.primary;
  const auto n = static_cast<Eigen::Index>(s.knots.size());
  if (s.interpolation == Interpolation::cubic) {
    std::vector<double> moments;
    spline_moments(s.knots, p.data(), moments);
    r.value = spline_value(s.knots, p.data(), moments.data(), v, &r.d_primary);
    if (grad) spline_weights(s.knots, v, r.d_parameters);
    return;
  }
  // Linear: two knots, no vectors (a fit evaluates every table at every reading).
  if (grad) r.d_parameters.setZero(n);
  const double vc = std::clamp(v, s.knots.front(), s.knots.back());
  if (n == 1) {
    r.value = p[0], r.d_primary = 0.0;
    if (grad) r.d_parameters[0] = 1.0;
    return;
  }
  auto k = static_cast<Eigen::Index>(std::upper_bound(s.knots.begin(), s.knots.end(), vc) - s.knots.begin()) - 1;
  k = std::clamp<Eigen::Index>(k, 0, n - 2);
  const double h = s.knots[static_cast<std::size_t>(k + 1)] - s.knots[static_cast<std::size_t>(k)];
  const double b = (vc - s.knots[static_cast<std::size_t>(k)]) / h;
  r.value = (1.0 - b) * p[k] + b * p[k + 1];
  r.d_primary = v == vc ? (p[k + 1] - p[k]) / h : 0.0;  // held constant outside the table
  if (grad) r.d_parameters[k] = 1.0 - b, r.d_parameters[k + 1] = b;
}

TermBound bound(const TermShape& s, const Eigen::VectorXd& p, const TermRange&, const TermRange&) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  TermBound b;
  const std::vector<double>& x = s.knots;
  const std::size_t n = x.size();
  b.value = p.cwiseAbs().maxCoeff();
  if (n < 2) return b;
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
    return b;
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
  return b;
}

/// A quarter of the closest knots' spacing.
double shortest_feature(const ErrorTermSpec& t) {
  double feature = std::numeric_limits<double>::infinity();
  for (std::size_t k = 1; k < t.shape.knots.size(); ++k)
    feature = std::min(feature, (t.shape.knots[k] - t.shape.knots[k - 1]) / 4.0);
  return feature;
}

}  // namespace

TermFormInfo table() {
  TermFormInfo f;
  f.form = TermForm::table;
  f.names = {"table"};
  f.keys = {"at", "values", "interpolation"};
  f.physics = "an error read at targets (a laser run), through its values";
  f.parameter_count = [](const TermShape& s) { return s.knots.size(); };
  f.evaluate = evaluate;
  f.term_label = [](const ErrorTermSpec& t) { return t.iso + " table"; };
  f.parameter_label = [](const ErrorTermSpec& t, std::size_t k) { return fmt::format("{}.value[{}]", t.iso, k); };
  f.shapes_only = scales_all;
  f.place = [](const TermShape&, std::size_t k) { return ParameterPlace{"values", static_cast<int>(k)}; };
  f.unit_name = value_unit;
  f.physical_scale = plausible_scale;
  f.bound = bound;
  f.shortest_feature = shortest_feature;
  return f;
}

}  // namespace ccomp::model::forms
