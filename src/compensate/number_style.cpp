#include "number_style.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cstdint>

#include "ccomp/gcode/number.hpp"

namespace ccomp::compensate {
namespace {

/// The number a value as written means (".5", "-.25", "12.0000").
double number_of(std::string_view text) {
  double value = 0.0;
  std::size_t end = 0;
  if (gcode::read_decimal(text, end, value) && end == text.size()) return value;
  std::from_chars(text.data(), text.data() + text.size(), value);
  return value;
}

/// format_value where fixed_units cannot decide: to_chars (or fmt) writes it.
WrittenValue format_value_slowly(double v, const NumberStyle& style) {
  std::array<char, 40> buffer{};
  const std::size_t length = gcode::format_fixed(v, style.decimals, buffer.data());
  WrittenValue written{length > 0 ? std::string(buffer.data(), length) : fmt::format("{:.{}f}", v, style.decimals),
                       0.0};
  std::string& text = written.text;
  if (text.starts_with('-') && text.find_first_not_of("0.", 1) == std::string::npos) text.erase(0, 1);  // no "-0.0000"
  if (!style.leading_zero) {
    if (text.starts_with("0."))
      text.erase(0, 1);
    else if (text.starts_with("-0."))
      text.erase(1, 1);
  }
  written.value = number_of(text);  // (here the units were not cheap to decide: the text says)
  return written;
}

}  // namespace

NumberStyle style_of(std::string_view original, bool inch, bool rotary, int decimals) {
  // One pass: whether a digit or the point comes first, and how many digits follow the
  // first point.
  auto digit = [](char c) { return c >= '0' && c <= '9'; };
  std::size_t i = 0;
  while (i < original.size() && !digit(original[i]) && original[i] != '.') ++i;
  const bool point_first = i < original.size() && original[i] == '.';
  while (i < original.size() && original[i] != '.') ++i;
  int written = 0;
  if (i < original.size())
    for (++i; i < original.size() && digit(original[i]); ++i) ++written;
  return style_written(written, point_first, inch, rotary, decimals);
}

double format_value(double v, const NumberStyle& style, std::string& out) {
  // Rounds the exact binary value as fmt does, without parsing a format string: this runs
  // for every number the job writes. Where the rounding is cheap to decide, from the units
  // of the last digit: their digits are the text (gcode::write_units, then one copy),
  // their quotient its value.
  if (std::int64_t units = 0; gcode::fixed_units(v, style.decimals, units)) {
    std::array<char, 32> buffer;
    char* const end = buffer.data() + buffer.size();
    // (no "-0.0000": a zero has no units below it)
    const char* const at = gcode::write_units(units, style.decimals, units < 0, style.leading_zero, end);
    out.assign(at, static_cast<std::size_t>(end - at));
    return gcode::units_value(units, style.decimals);
  }
  WrittenValue written = format_value_slowly(v, style);
  out = std::move(written.text);
  return written.value;
}

WrittenValue format_value(double v, const NumberStyle& style) {
  WrittenValue written;
  written.value = format_value(v, style, written.text);
  return written;
}

std::optional<double> fixed_number(double v, const NumberStyle& style) {
  std::int64_t units = 0;
  if (!gcode::fixed_units(v, style.decimals, units)) return std::nullopt;
  return gcode::units_value(units, style.decimals);
}

double written_number(double v, const NumberStyle& style) {
  if (const std::optional<double> number = fixed_number(v, style)) return *number;
  return format_value(v, style).value;
}

WrittenValue format_value(double v, std::string_view original, bool inch, bool rotary, int decimals) {
  return format_value(v, style_of(original, inch, rotary, decimals));
}

bool written_alike(double a, double b, const NumberStyle& style) {
  std::int64_t units_a = 0, units_b = 0;
  if (gcode::fixed_units(a, style.decimals, units_a) && gcode::fixed_units(b, style.decimals, units_b))
    return units_a == units_b;  // "-0.0000" is written "0.0000"
  return format_value(a, style).text == format_value(b, style).text;
}

}  // namespace ccomp::compensate
