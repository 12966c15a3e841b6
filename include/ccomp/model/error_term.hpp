#pragma once
// One error term of the machine model: a function of a declared variable (an axis
// position, a temperature, the time, the tool length, an approach direction) with a form
// (constant, polynomial, table, periodic, reversal, thermal, scale expansion, cross-axis)
// and parameters, giving one component (a translation in mm or a rotation in rad) of one
// link's error motion. Every form gives its exact derivatives with respect to its
// variables and to each parameter (the fit uses them); tests/model/error_term_test.cpp
// checks them against finite differences. Units inside are mm, rad, s, degC.
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

namespace ccomp::model {

enum class TermForm : std::uint8_t {
  constant,         ///< c
  polynomial,       ///< sum_k a_k v^k, k = 0..n
  table,            ///< values at knots, linear or cubic (natural spline) between them
  periodic,         ///< sum_k a_k cos(2 pi k v / P) + b_k sin(2 pi k v / P); P is a parameter
  reversal,         ///< r/2 * s, s the approach direction (+1, -1, 0 unknown)
  thermal_linear,   ///< k (T - T0)
  thermal_warmup,   ///< A (1 - exp(-t / tau))
  scale_expansion,  ///< alpha v (T - T0): a scale growing with temperature
  cross_axis,       ///< sum_{i,j} c_ij u^i w^j, j >= 1: varies with another axis' position w
  bump,             ///< A exp(-((v - c) / w)^2 / 2): a local defect of a guideway or a scale at c
};

enum class Interpolation : std::uint8_t { linear, cubic };

/// Where a term was fitted: the range of its primary variable (internal units: mm, rad,
/// degC, s) in the data. Beyond it the term holds its value at the nearer end (as a table
/// holds its end values), and whoever uses the model there says so (term_span.hpp).
struct TermSpan {
  double from = 0.0, to = 0.0;
};

/// The values a term may depend on, for one point of a program or one measurement row.
struct TermInputs {
  double primary = 0.0;    ///< the term's variable (mm, rad, s, degC or a direction sign)
  double secondary = 0.0;  ///< the second variable of scale_expansion (T) and cross_axis (w)
};

/// A term's value and, on request, its derivatives.
struct TermValue {
  double value = 0.0;
  double d_primary = 0.0;
  double d_secondary = 0.0;
  Eigen::VectorXd d_parameters;  ///< one entry per parameter (when asked)
  /// Periodic forms: a phase whose cosine and sine were computed exactly. A value reused
  /// for the next evaluation turns from there by the (small) difference, whose cosine and
  /// sine a short series gives to double precision: neighbouring points cost no sine.
  double phase_reference = std::numeric_limits<double>::quiet_NaN();
  double cos_reference = 1.0, sin_reference = 0.0;
};

struct TermShape {
  TermForm form = TermForm::constant;
  Interpolation interpolation = Interpolation::linear;  ///< table
  std::vector<double> knots;                            ///< table: increasing positions of the values
  int order = 1;            ///< polynomial degree; periodic harmonics; cross_axis degree in w
  int order_primary = 0;    ///< cross_axis degree in u
  double reference = 20.0;  ///< T0 of thermal_linear and scale_expansion (degC)
};

/// Number of parameters a shape takes.
[[nodiscard]] std::size_t parameter_count(const TermShape& shape);

/// Evaluates the form. `parameters` has parameter_count(shape) entries; derivatives with
/// respect to the parameters are filled when `with_parameter_gradient`.
[[nodiscard]] TermValue evaluate(const TermShape& shape, const Eigen::VectorXd& parameters, const TermInputs& in,
                                 bool with_parameter_gradient = false);
/// The same into `out`, reusing its storage (no allocation once sized).
void evaluate(const TermShape& shape, const Eigen::Ref<const Eigen::VectorXd>& parameters, const TermInputs& in,
              bool with_parameter_gradient, TermValue& out);

/// The cosine and sine of a periodic form's first harmonic at `at` for `period`: terms of
/// one variable and period (a worm wheel's or a table's once-per-turn error motions) share
/// them.
struct PeriodicPhase {
  double at = std::numeric_limits<double>::quiet_NaN();
  double period = std::numeric_limits<double>::quiet_NaN();
  double c1 = 1.0, s1 = 0.0;
};

namespace detail {
constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// The first harmonic's cosine and sine at `phase1`, turned from the reference phase in `r`
/// when it is near (no sine), else computed and taken as the new reference.
inline void first_harmonic(double phase1, TermValue& r, double& c1, double& s1) {
  if (const double delta = phase1 - r.phase_reference; std::abs(delta) < 0.05) {
    // Multiplied by the reciprocals, not divided: a division takes several times as long,
    // and the last bit of these small terms is far below the sum's.
    const double d2 = delta * delta;
    const double cd =
        1.0 - d2 * 0.5 *
                  (1.0 - d2 * (1.0 / 12) * (1.0 - d2 * (1.0 / 30) * (1.0 - d2 * (1.0 / 56) * (1.0 - d2 * (1.0 / 90)))));
    const double sd =
        delta * (1.0 - d2 * (1.0 / 6) * (1.0 - d2 * (1.0 / 20) * (1.0 - d2 * (1.0 / 42) * (1.0 - d2 * (1.0 / 72)))));
    c1 = r.cos_reference * cd - r.sin_reference * sd;
    s1 = r.sin_reference * cd + r.cos_reference * sd;
  } else {
    c1 = std::cos(phase1), s1 = std::sin(phase1);
    r.phase_reference = phase1, r.cos_reference = c1, r.sin_reference = s1;
  }
}

}  // namespace detail

/// The phase at v for `period`, turned from `cache`'s reference phase as evaluate() turns it.
/// (Inline, as periodic_sum(): a table's six error motions and its worm wheel take them at
/// every evaluation of the model, and out of line their short dependent chains could not
/// overlap.)
inline void periodic_phase(double period, double v, TermValue& cache, PeriodicPhase& out) {
  detail::first_harmonic(detail::kTwoPi * v / period, cache, out.c1, out.s1);
  out.at = v;
  out.period = period;
}
/// A periodic form's value from its phase. `p`: the period, then a_k, b_k for each of the
/// `harmonics`.
[[nodiscard]] inline double periodic_sum(const double* p, int harmonics, const PeriodicPhase& phase) {
  const double c1 = phase.c1, s1 = phase.s1;
  double value = 0.0, c = 1.0, sn = 0.0;  // cos and sin of k phase1
  for (int k = 1; k <= harmonics; ++k) {
    const double c_next = c * c1 - sn * s1;
    sn = sn * c1 + c * s1;
    c = c_next;
    value += p[2 * k - 1] * c + p[2 * k] * sn;
  }
  return value;
}
/// The two in one, bitwise what evaluate() gives (the same reference phase in `cache`, the
/// same operations): the forward model's loop over the points takes it.
[[nodiscard]] double periodic_value(const double* p, int harmonics, double v, TermValue& cache);

}  // namespace ccomp::model
