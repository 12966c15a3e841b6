// sum_k a_k cos(2 pi k v / P) + b_k sin(2 pi k v / P): a lead screw's or a scale's pitch, a
// worm wheel's teeth, a table's once-per-turn errors. P is the first parameter.
#include <fmt/format.h>

#include <algorithm>

#include "ccomp/model/term_forms.hpp"

namespace ccomp::model::forms {
namespace {

using detail::kTwoPi;

/// The first harmonic's cosine and sine, turned from the reference phase when it is near;
/// the higher harmonics by the angle-sum recurrence.
void evaluate(const TermShape& s, const Eigen::Ref<const Eigen::VectorXd>& p, const TermInputs& in, bool grad,
              TermValue& r) {
  const double period = p[0];
  const double phase1 = kTwoPi * in.primary / period;
  double c1 = 0.0, s1 = 0.0;
  detail::first_harmonic(phase1, r, c1, s1);
  double c = 1.0, sn = 0.0;  // cos and sin of k phase1
  for (int k = 1; k <= s.order; ++k) {
    const double a = p[2 * k - 1], b = p[2 * k];
    const double phase = k * phase1;
    const double c_next = c * c1 - sn * s1;
    sn = sn * c1 + c * s1;
    c = c_next;
    r.value += a * c + b * sn;
    const double d_phase = -a * sn + b * c;  // d(value)/d(phase)
    r.d_primary += d_phase * kTwoPi * k / period;
    if (grad) {
      r.d_parameters[2 * k - 1] = c;
      r.d_parameters[2 * k] = sn;
      r.d_parameters[0] += d_phase * (-phase / period);
    }
  }
}

TermBound bound(const TermShape& s, const Eigen::VectorXd& p, const TermRange&, const TermRange&) {
  TermBound b;
  for (int k = 1; k <= s.order; ++k) {
    const double amplitude = std::hypot(p[2 * k - 1], p[2 * k]);
    const double omega = kTwoPi * k / std::abs(p[0]);
    b.value += amplitude;
    b.slope_p += omega * amplitude;
    b.curvature_pp += omega * omega * amplitude;
  }
  return b;
}

}  // namespace

TermFormInfo periodic() {
  TermFormInfo f;
  f.form = TermForm::periodic;
  f.names = {"periodic"};
  f.keys = {"period", "harmonics"};
  f.physics = "a lead screw's or a scale's pitch, a worm wheel's teeth, a table's once-per-turn errors";
  f.parameter_count = [](const TermShape& s) { return 1 + 2 * static_cast<std::size_t>(s.order); };
  f.evaluate = evaluate;
  f.term_label = [](const ErrorTermSpec& t) { return t.iso + " periodic"; };
  f.parameter_label = [](const ErrorTermSpec& t, std::size_t k) {
    return k == 0 ? t.iso + ".period" : fmt::format("{}.{}{}", t.iso, k % 2 ? 'a' : 'b', (k + 1) / 2);
  };
  f.shapes_only = [](std::size_t k) { return k == 0; };
  f.place = [](const TermShape&, std::size_t k) {
    return k == 0 ? ParameterPlace{"period"}
                  : ParameterPlace{"harmonics", static_cast<int>((k - 1) / 2), static_cast<int>((k - 1) % 2)};
  };
  f.unit_name = [](const ErrorTermSpec& t, std::size_t k, const UnitNames& u) {
    return k == 0 ? u.variable(t.primary).first : u.value(t.parameter_unit[k]);
  };
  f.physical_scale = [](const ErrorTermSpec& t, std::size_t k, double plausible, const ReachOf&) {
    return k == 0 ? std::abs(t.parameters[0]) : plausible;
  };
  f.bound = bound;
  // The highest harmonic's period / 8.
  f.shortest_feature = [](const ErrorTermSpec& t) { return t.parameters[0] / (8.0 * std::max(1, t.shape.order)); };
  return f;
}

}  // namespace ccomp::model::forms
