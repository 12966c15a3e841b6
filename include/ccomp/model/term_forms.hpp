#pragma once
// The error-term forms, one descriptor each, in one registry: the names a model file gives
// it, the keys its parameters are written under, its sentence of physics, and what every
// other part asks of a form: its parameter count, its evaluation with derivatives, the
// names and units of its parameters, where each is written, which only shape it, its
// physical scale (identify/), its variation bound (the compensation's error field) and
// its shortest feature (how finely a move is checked).
// Each form is one file, src/model/forms/<form>.cpp; reading a form's keys from a model
// file is the reader's (model/io/read_terms.cpp, one function per form). The parametrised
// Jacobian suite (tests/jacobian_suite_test.cpp) iterates the registry and fails for a
// form it has no case of, so a new form cannot go untested.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "ccomp/model/error_term.hpp"
#include "ccomp/model/machine.hpp"

namespace ccomp::model {

/// Where a parameter is written in its term's node: under `key`, at [index] and [index][sub]
/// when they are not negative. A scalar key with index -1 written into a sequence of one
/// (a model file may give a constant reversal as `[r]`) takes its first element.
struct ParameterPlace {
  std::string_view key;
  int index = -1, sub = -1;
};

/// The values a term's variable takes (an axis within its limits, a condition at its value).
struct TermRange {
  double lo = 0.0, hi = 0.0;
  [[nodiscard]] double magnitude() const {
    const double m = std::max(std::abs(lo), std::abs(hi));
    return std::isnan(m) ? std::numeric_limits<double>::infinity() : m;
  }
};

/// The bounds of one term over the ranges of its variables: value, slopes and curvatures in
/// its primary (p) and secondary (s) variable, the largest slope jump (a linear table's
/// knots, a table's ends) and the shortest knot spacing (0: no knots).
struct TermBound {
  double value = 0.0, slope_p = 0.0, slope_s = 0.0;
  double curvature_pp = 0.0, curvature_ps = 0.0, curvature_ss = 0.0;
  double kink = 0.0;
  double knot_gap = 0.0;
};

/// |c| x^k for |x| <= magnitude, without 0 * inf: a zero coefficient bounds nothing.
[[nodiscard]] inline double power_bound(double c, double magnitude, int k) {
  if (c == 0.0) return 0.0;
  return k == 0 ? std::abs(c) : std::abs(c) * std::pow(magnitude, k);
}

/// How a unit's micro prefix is written: "u" in plain text, "µ" in the report.
enum class MicroSign { ascii, micro };

/// Names of units for one term's parameters (parameter_units.cpp).
struct UnitNames {
  bool angle = false;  ///< the term's value is a rotation
  MicroSign micro = MicroSign::ascii;
  /// The common name of a unit of the term's value `scale` internal units across ("um",
  /// "urad"), or "".
  [[nodiscard]] std::string value(double scale) const;
  /// A variable's unit as model files write it (mm, deg, s, degC) and its scale in internal units.
  [[nodiscard]] std::pair<std::string, double> variable(const Variable& v) const;
  [[nodiscard]] std::string degc() const { return micro == MicroSign::micro ? "°C" : "degC"; }
};

/// The largest magnitude a variable takes in the data (from `reference` for a temperature a
/// thermal form measures from), at least 1 of its unit: what a physical scale divides by.
using ReachOf = std::function<double(const Variable& v, double reference)>;

struct TermFormInfo {
  TermForm form = TermForm::constant;
  std::vector<std::string_view> names;  ///< `form: <name>` in a model file, the first as written
  std::vector<std::string_view> keys;   ///< the keys of its parameters and shape
  std::string_view physics;             ///< what on a machine it describes
  /// Whether a fitted term of this form grows beyond the data it was fitted on (and is held
  /// at the ends of its span there).
  bool grows_beyond_data = false;

  std::size_t (*parameter_count)(const TermShape& shape) = nullptr;
  void (*evaluate)(const TermShape& shape, const Eigen::Ref<const Eigen::VectorXd>& parameters, const TermInputs& in,
                   bool with_parameter_gradient, TermValue& out) = nullptr;
  /// The term as a report's map names it ("EXX periodic", "EA0B location").
  std::string (*term_label)(const ErrorTermSpec& t) = nullptr;
  /// Parameter k as a fit names it ("EXX.a2", "EXX.period").
  std::string (*parameter_label)(const ErrorTermSpec& t, std::size_t k) = nullptr;
  /// Whether parameter k only shapes the error (a period, a time constant, a bump's place
  /// and width) rather than scaling it: zero amplitudes leave it unseen.
  bool (*shapes_only)(std::size_t k) = nullptr;
  /// Where parameter k is written in the term's node.
  ParameterPlace (*place)(const TermShape& shape, std::size_t k) = nullptr;
  /// The unit of parameter k as the file writes it, "" where it has no common name.
  std::string (*unit_name)(const ErrorTermSpec& t, std::size_t k, const UnitNames& units) = nullptr;
  /// The size of parameter k that moves the term by `plausible` (mm or rad: a machine's
  /// plausible error) over its variables' reach.
  double (*physical_scale)(const ErrorTermSpec& t, std::size_t k, double plausible, const ReachOf& reach) = nullptr;
  /// The term's bounds over its primary's range u and its secondary's w.
  TermBound (*bound)(const TermShape& shape, const Eigen::VectorXd& parameters, const TermRange& u,
                     const TermRange& w) = nullptr;
  /// The shortest stretch of its primary variable over which the term changes shape (a
  /// period's share, a knot spacing's, a bump's width's), +inf for a smooth one: what a
  /// move is checked at points spaced by.
  double (*shortest_feature)(const ErrorTermSpec& t) = nullptr;
};

/// A smooth form's shortest feature: none.
[[nodiscard]] inline double no_feature(const ErrorTermSpec&) { return std::numeric_limits<double>::infinity(); }
/// A form whose every parameter scales its error.
[[nodiscard]] inline bool scales_all(std::size_t) { return false; }
/// A form whose parameters are amounts of the term's value: in its unit...
[[nodiscard]] inline std::string value_unit(const ErrorTermSpec& t, std::size_t k, const UnitNames& u) {
  return u.value(t.parameter_unit[k]);
}
/// ... and a machine's plausible error their scale.
[[nodiscard]] inline double plausible_scale(const ErrorTermSpec&, std::size_t, double plausible, const ReachOf&) {
  return plausible;
}

/// Every form, in TermForm's order.
[[nodiscard]] const std::vector<TermFormInfo>& term_forms();

/// The descriptor of a form.
[[nodiscard]] inline const TermFormInfo& term_form(TermForm form) {
  return term_forms()[static_cast<std::size_t>(form)];
}

/// The form a model file names, or null.
[[nodiscard]] const TermFormInfo* term_form(std::string_view name);

namespace forms {
// One per file in src/model/forms/.
[[nodiscard]] TermFormInfo constant();
[[nodiscard]] TermFormInfo polynomial();
[[nodiscard]] TermFormInfo table();
[[nodiscard]] TermFormInfo periodic();
[[nodiscard]] TermFormInfo reversal();
[[nodiscard]] TermFormInfo thermal_linear();
[[nodiscard]] TermFormInfo thermal_warmup();
[[nodiscard]] TermFormInfo scale_expansion();
[[nodiscard]] TermFormInfo cross_axis();
[[nodiscard]] TermFormInfo bump();
}  // namespace forms

}  // namespace ccomp::model
