#include "number_style.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
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

}  // namespace

NumberStyle style_of(std::string_view original, bool inch, bool rotary, int decimals) {
  NumberStyle style{rotary ? kDefaultRotaryDecimals : inch ? kDefaultInchDecimals : kDefaultDecimals, true};
  if (const auto dot = original.find('.'); dot != std::string_view::npos) {
    int written = 0;
    for (std::size_t i = dot + 1; i < original.size() && std::isdigit(static_cast<unsigned char>(original[i])); ++i)
      ++written;
    style.decimals = std::max(style.decimals, written);
    const auto first_digit = original.find_first_of("0123456789.");
    style.leading_zero = !(first_digit != std::string_view::npos && original[first_digit] == '.');
  }
  if (decimals >= 0) style.decimals = decimals;
  return style;
}

WrittenValue format_value(double v, const NumberStyle& style) {
  // Rounds the exact binary value as fmt does, without parsing a format string: this runs
  // for every number the job writes.
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
  const std::optional<double> number = fixed_number(v, style);
  written.value = number ? *number : number_of(text);
  return written;
}

std::optional<double> fixed_number(double v, const NumberStyle& style) {
  // The text's digits are units / 10^decimals: the division read_decimal does reading it.
  static constexpr double kPower[] = {1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9};
  std::int64_t units = 0;
  if (!gcode::fixed_units(v, style.decimals, units)) return std::nullopt;
  return static_cast<double>(units) / kPower[style.decimals];
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
