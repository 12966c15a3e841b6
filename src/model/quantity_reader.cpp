#include "ccomp/model/quantity_reader.hpp"

#include <fmt/format.h>

#include <array>
#include <charconv>
#include <cmath>

#include "ccomp/error.hpp"

namespace ccomp::model {
namespace {

/// mm, deg, um, whatever the place's unit: no machine travels or turns so far.
constexpr double kBeyondAnyMachine = 1e7;

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

/// The units a bare number may have been meant in, the likeliest slip first.
std::array<std::string_view, 4> other_readings(const Dimension& d) {
  if (d == kAngle) return {"urad", "arcsec", "mrad", "deg"};
  return {"um", "nm", "mm", "in"};
}

double scale_of(std::string_view unit) {
  const auto u = parse_unit(unit);
  return u ? u->scale : std::nan("");
}

std::string range_text(const QuantityRule& rule, double low, double high) {
  if (low > 0 && std::isfinite(high)) return fmt::format("{:g} to {:g} {}", low, high, rule.unit);
  if (std::isfinite(high)) return fmt::format("up to {:g} {}", high, rule.unit);
  return fmt::format("from {:g} {}", low, rule.unit);
}

/// A bare number outside where it is plausible: refused, with the reading that fits.
[[noreturn]] void refuse_bare(std::string_view number_text, double value, const QuantityRule& rule,
                              const std::string& what) {
  std::string suggestion;
  const double own = scale_of(rule.unit);
  // The slip is a number in a smaller unit (micrometres where mm is due): a number too
  // small for its place has no such reading.
  for (const std::string_view unit : other_readings(rule.dimension)) {
    if (!(scale_of(unit) < own) || std::abs(value) < rule.bare_min) continue;
    const double v = value * scale_of(unit) / own;
    if (std::abs(v) >= rule.bare_min && std::abs(v) <= rule.bare_max && v <= rule.max && v >= rule.min) {
      suggestion = fmt::format("; did you mean {}{}?", number_text, unit);
      break;
    }
  }
  throw Error(ErrorKind::usage,
              fmt::format("{}: a number without a unit is {} here, and {} {} is not a plausible {} ({}){} "
                          "(write the unit to mean it: {}{})",
                          what, rule.unit, number_text, rule.unit, rule.meaning,
                          range_text(rule, rule.bare_min, rule.bare_max), suggestion, number_text, rule.unit));
}

}  // namespace

double read_quantity(std::string_view text, const QuantityRule& rule, const std::string& what) {
  text = trim(text);
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  if (begin != end && *begin == '+') ++begin;  // from_chars takes '-' only
  double number = 0.0;
  const auto [stop, ec] = std::from_chars(begin, end, number);
  if (ec == std::errc::result_out_of_range)
    throw Error(ErrorKind::usage, fmt::format("{}: '{}' is beyond any machine", what, text));
  if (ec != std::errc() || stop == begin)
    throw Error(ErrorKind::usage, fmt::format("{}: '{}' is not a number (with a unit, as 1um, 0.01deg)", what, text));
  const std::string_view number_text(text.data(), static_cast<std::size_t>(stop - text.data()));
  const std::string_view unit_text = trim(std::string_view(stop, static_cast<std::size_t>(end - stop)));
  if (!std::isfinite(number)) throw Error(ErrorKind::usage, fmt::format("{}: '{}' is not a finite number", what, text));
  double value = number;
  if (!unit_text.empty()) {
    const auto unit = parse_unit(unit_text);
    if (!unit)
      throw Error(ErrorKind::usage, fmt::format("{}: unknown unit '{}' (lengths: nm, um, mm, in; angles: urad, arcsec, "
                                                "deg, rad)", what, unit_text));
    if (!(unit->dimension == rule.dimension))
      throw Error(ErrorKind::usage, fmt::format("{}: '{}' measures {}, but {} belongs here", what, unit_text,
                                                unit->dimension.describe(), rule.dimension.describe()));
    value = number * unit->scale / scale_of(rule.unit);
  }
  if (std::abs(value) > kBeyondAnyMachine)
    throw Error(ErrorKind::usage, fmt::format("{}: '{}' is beyond any machine", what, text));
  const bool above_min = rule.min_inclusive ? value >= rule.min : value > rule.min;
  if (!above_min || !(value <= rule.max)) {
    const char* low = rule.min_inclusive ? "at least" : "more than";
    throw Error(ErrorKind::usage,
                std::isfinite(rule.min) && std::isfinite(rule.max)
                    ? fmt::format("{}: {:g} {} is outside {:g} to {:g} {}", what, value, rule.unit, rule.min, rule.max,
                                  rule.unit)
                : std::isfinite(rule.min) ? fmt::format("{}: the value must be {} {:g} {}", what, low, rule.min, rule.unit)
                                          : fmt::format("{}: {:g} {} is beyond any machine", what, value, rule.unit));
  }
  if (unit_text.empty() && value != 0.0 && (std::abs(value) < rule.bare_min || std::abs(value) > rule.bare_max))
    refuse_bare(number_text, value, rule, what);
  return value;
}

namespace rules {

QuantityRule tolerance() {
  QuantityRule r;
  r.min = 0.0, r.min_inclusive = false;
  r.bare_max = 0.1;
  r.meaning = "compensation tolerance";
  return r;
}

QuantityRule position() {
  QuantityRule r;
  r.meaning = "position";
  return r;
}

QuantityRule angle() {
  QuantityRule r = position();
  r.dimension = kAngle, r.unit = "deg";
  r.meaning = "angle";
  return r;
}

QuantityRule tool_length() {
  QuantityRule r;
  r.min = 0.0, r.max = 10000.0;
  r.meaning = "tool length";
  return r;
}

QuantityRule linear_step() {
  QuantityRule r;
  r.min = 0.0, r.min_inclusive = false;
  r.bare_min = 0.01;
  r.meaning = "step";
  return r;
}

QuantityRule rotary_step() {
  QuantityRule r = linear_step();
  r.dimension = kAngle, r.unit = "deg";
  r.max = 360.0;
  return r;
}

QuantityRule noise() {
  QuantityRule r;
  r.unit = "um";
  r.min = 0.0;
  r.bare_max = 100.0;
  r.meaning = "reading noise";
  return r;
}

}  // namespace rules
}  // namespace ccomp::model
