#include "ccomp/model/error_term.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "ccomp/model/cubic_spline.hpp"

namespace ccomp::model {
namespace {

using detail::first_harmonic;
using detail::kTwoPi;

/// A table's value: kept out of evaluate() so its dynamic vectors do not weigh on the
/// other forms' calls (the forward model evaluates every term at every point).
[[gnu::noinline]] void evaluate_table(const TermShape& s, const Eigen::Ref<const Eigen::VectorXd>& p, double v,
                                      bool grad, TermValue& r) {
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

}  // namespace

double periodic_value(const double* p, int harmonics, double v, TermValue& cache) {
  PeriodicPhase phase;
  periodic_phase(p[0], v, cache, phase);
  return periodic_sum(p, harmonics, phase);
}

std::size_t parameter_count(const TermShape& s) {
  switch (s.form) {
    case TermForm::constant:
    case TermForm::thermal_linear:
    case TermForm::scale_expansion:
      return 1;
    case TermForm::reversal:
      return static_cast<std::size_t>(std::max(0, s.order_primary)) + 1;
    case TermForm::polynomial:
      return static_cast<std::size_t>(s.order) + 1;
    case TermForm::table:
      return s.knots.size();
    case TermForm::periodic:
      return 1 + 2 * static_cast<std::size_t>(s.order);
    case TermForm::thermal_warmup:
      return 2;
    case TermForm::bump:
      return 3;
    case TermForm::cross_axis:
      return static_cast<std::size_t>(s.order_primary + 1) * static_cast<std::size_t>(s.order);
  }
  return 0;
}

namespace {

void evaluate_polynomial(const TermShape& s, const Eigen::Ref<const Eigen::VectorXd>& p, double v, bool grad,
                         TermValue& r) {
  double power = 1.0, previous = 0.0;  // v^k and v^(k-1)
  for (int k = 0; k <= s.order; ++k) {
    r.value += p[k] * power;
    r.d_primary += k * p[k] * previous;
    if (grad) r.d_parameters[k] = power;
    previous = power;
    power *= v;
  }
}

/// The first harmonic's cosine and sine, turned from the reference phase when it is near;
/// the higher harmonics by the angle-sum recurrence.
void evaluate_periodic(const TermShape& s, const Eigen::Ref<const Eigen::VectorXd>& p, double v, bool grad,
                       TermValue& r) {
  const double period = p[0];
  const double phase1 = kTwoPi * v / period;
  double c1 = 0.0, s1 = 0.0;
  first_harmonic(phase1, r, c1, s1);
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

void evaluate_warmup(const Eigen::Ref<const Eigen::VectorXd>& p, double v, bool grad, TermValue& r) {
  const double amplitude = p[0], tau = p[1];
  const double e = std::exp(-v / tau);
  r.value = amplitude * (1.0 - e);
  r.d_primary = amplitude * e / tau;
  if (grad) {
    r.d_parameters[0] = 1.0 - e;
    r.d_parameters[1] = -amplitude * e * v / (tau * tau);
  }
}

void evaluate_bump(const Eigen::Ref<const Eigen::VectorXd>& p, double v, bool grad, TermValue& r) {
  // A (amplitude), c (where), w (how wide: one standard deviation of the bell).
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

/// Half the reversal on each side: the two approach directions differ by r(w), a
/// polynomial along the axis (a screw worn more at one end plays more there): r_k of w^k,
/// k = 0..order_primary (0: a constant reversal, its only parameter), w the term's
/// secondary variable (`along:` in the model file).
void evaluate_reversal(const TermShape& s, const Eigen::Ref<const Eigen::VectorXd>& p, double v, double w, bool grad,
                       TermValue& r) {
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

void evaluate_cross_axis(const TermShape& s, const Eigen::Ref<const Eigen::VectorXd>& p, double v, double w, bool grad,
                         TermValue& r) {
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

}  // namespace

TermValue evaluate(const TermShape& s, const Eigen::VectorXd& p, const TermInputs& in, bool grad) {
  TermValue r;
  evaluate(s, p, in, grad, r);
  return r;
}

void evaluate(const TermShape& s, const Eigen::Ref<const Eigen::VectorXd>& p, const TermInputs& in, bool grad,
              TermValue& r) {
  r.value = r.d_primary = r.d_secondary = 0.0;
  if (grad) {
    r.d_parameters.resize(static_cast<Eigen::Index>(parameter_count(s)));
    r.d_parameters.setZero();
  }
  const double v = in.primary;
  switch (s.form) {
    case TermForm::constant:
      r.value = p[0];
      if (grad) r.d_parameters[0] = 1.0;
      break;
    case TermForm::polynomial:
      evaluate_polynomial(s, p, v, grad, r);
      break;
    case TermForm::table:
      evaluate_table(s, p, v, grad, r);
      break;
    case TermForm::periodic:
      evaluate_periodic(s, p, v, grad, r);
      break;
    case TermForm::reversal:
      evaluate_reversal(s, p, v, in.secondary, grad, r);
      break;
    case TermForm::thermal_linear:
      r.value = p[0] * (v - s.reference);
      r.d_primary = p[0];
      if (grad) r.d_parameters[0] = v - s.reference;
      break;
    case TermForm::thermal_warmup:
      evaluate_warmup(p, v, grad, r);
      break;
    case TermForm::scale_expansion: {
      const double dT = in.secondary - s.reference;
      r.value = p[0] * v * dT;
      r.d_primary = p[0] * dT;
      r.d_secondary = p[0] * v;
      if (grad) r.d_parameters[0] = v * dT;
      break;
    }
    case TermForm::bump:
      evaluate_bump(p, v, grad, r);
      break;
    case TermForm::cross_axis:
      evaluate_cross_axis(s, p, v, in.secondary, grad, r);
      break;
  }
}

}  // namespace ccomp::model
