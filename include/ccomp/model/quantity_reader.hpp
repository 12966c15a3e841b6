#pragma once
// One reader for the lengths and angles a user types (command-line options, the model's
// work offsets): a number with its unit ("1um", "0.001 mm", "0.0001in", "5urad", "0.01deg",
// "30arcsec") or a bare number in the place's own unit. A bare number where it cannot be
// meant in that unit (--tolerance 1: 1 mm, where a micrometre is what tolerances are made
// of) is refused with the reading it suggests ("did you mean 1um?"); written with its unit,
// the same value is taken as meant.
#include <limits>
#include <string>
#include <string_view>

#include "ccomp/model/units.hpp"

namespace ccomp::model {

/// What a place takes. Every bound is in `unit`.
struct QuantityRule {
  Dimension dimension = kLength;
  std::string_view unit = "mm";  ///< the result's unit, and a bare number's
  /// Every value, with a unit or without: min < value (or <= with min_inclusive) <= max.
  double min = -std::numeric_limits<double>::infinity();
  bool min_inclusive = true;
  double max = std::numeric_limits<double>::infinity();
  /// A bare number is taken where bare_min <= |value| <= bare_max (0 passes always);
  /// outside, it reads as another unit and is refused with that reading.
  double bare_min = 0.0;
  double bare_max = std::numeric_limits<double>::infinity();
  std::string_view meaning = "value";  ///< "compensation tolerance", said when a bare number is refused
};

/// The value of `text` in rule.unit. Throws ccomp::Error (usage) starting with `what`
/// (the option or key, and the text) when it is not a number, its unit measures something
/// else, it is not finite, it is out of range, or it is bare and out of its plausible range.
[[nodiscard]] double read_quantity(std::string_view text, const QuantityRule& rule, const std::string& what);

/// The rules of the command line's quantities (docs/input-limits.md lists them).
namespace rules {
/// --tolerance: mm, positive; a bare number up to 0.1 mm (100 um).
[[nodiscard]] QuantityRule tolerance();
/// A position along a linear axis (--at, --from, --to, a work offset): mm, within 1e7.
[[nodiscard]] QuantityRule position();
/// A position of a rotary axis: degrees, within 1e7.
[[nodiscard]] QuantityRule angle();
/// A tool or optic length (--tool-length): mm, 0 to 10 m.
[[nodiscard]] QuantityRule tool_length();
/// A step along a linear axis (export's and simulate's --step): mm, positive; a bare number from 0.01 mm.
[[nodiscard]] QuantityRule linear_step();
/// A step of a rotary axis (--rotary-step): degrees, positive; a bare number from 0.01 deg.
[[nodiscard]] QuantityRule rotary_step();
/// simulate's --noise: um, 0 or more; a bare number up to 100 um.
[[nodiscard]] QuantityRule noise();
}  // namespace rules

}  // namespace ccomp::model
