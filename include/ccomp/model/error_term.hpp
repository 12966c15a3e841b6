#pragma once
// One error term of the machine model: a function of a declared variable (an axis
// position, a temperature, the time, the tool length, an approach direction) with a form
// (constant, polynomial, table, periodic, reversal, thermal, scale expansion, cross-axis)
// and parameters, giving one component (a translation in mm or a rotation in rad) of one
// link's error motion. Every form gives its exact derivatives with respect to its
// variables and to each parameter (the fit uses them); tests/model/error_term_test.cpp
// checks them against finite differences. Units inside are mm, rad, s, degC.
#include <Eigen/Core>
#include <cstdint>
#include <limits>
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

/// The phase at v for `period`, turned from `cache`'s reference phase as evaluate() turns it.
void periodic_phase(double period, double v, TermValue& cache, PeriodicPhase& out);
/// A periodic form's value from its phase. `p`: the period, then a_k, b_k for each of the
/// `harmonics`.
[[nodiscard]] double periodic_sum(const double* p, int harmonics, const PeriodicPhase& phase);
/// The two in one, bitwise what evaluate() gives (the same reference phase in `cache`, the
/// same operations): the forward model's loop over the points takes it.
[[nodiscard]] double periodic_value(const double* p, int harmonics, double v, TermValue& cache);

}  // namespace ccomp::model
