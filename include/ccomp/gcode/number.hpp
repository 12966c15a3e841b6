#pragma once
// Decimal numbers as G-code writes them, read and written exactly: the exact binary value
// correctly rounded either way, as std::from_chars and std::to_chars give it, at a
// fraction of their cost for the short fixed-point numbers a program carries (every
// coordinate of a program goes through these).
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace ccomp::gcode {

/// What std::from_chars reads of `digits` (more digits than read_decimal's fast path takes);
/// infinity beyond the largest double, zero below the smallest.
double read_long_decimal(std::string_view digits);

/// Reads `[+-] digits [. digits] | [+-] . digits` at `i` in `t` into `value`, advancing `i`
/// past it; false when no digit is there (`i` may have passed a sign). Inline: the parser
/// reads every number of a program with it.
inline bool read_decimal(std::string_view t, std::size_t& i, double& value) {
  const std::size_t n = t.size();
  auto digit = [&](std::size_t at) { return at < n && static_cast<unsigned>(t[at] - '0') < 10U; };
  bool negative = false;
  if (i < n && (t[i] == '+' || t[i] == '-')) negative = t[i++] == '-';
  const std::size_t digits_start = i;
  std::uint64_t mantissa = 0;
  while (digit(i)) mantissa = mantissa * 10 + static_cast<std::uint64_t>(t[i++] - '0');
  const std::size_t integer_digits = i - digits_start;
  std::size_t fraction = 0;
  if (i < n && t[i] == '.') {
    const std::size_t first = ++i;
    while (digit(i)) mantissa = mantissa * 10 + static_cast<std::uint64_t>(t[i++] - '0');
    fraction = i - first;
  }
  if (integer_digits + fraction == 0) return false;
  constexpr double kPow10[16] = {1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15};
  // Exact while the digits fit 15 decimal places (2^53 > 10^15): one correctly rounded
  // division of two exact numbers. (Leading zeros make the count pessimistic, never wrong.)
  if (integer_digits + fraction <= 15) {
    value = static_cast<double>(mantissa) / kPow10[fraction];
  } else {
    value = read_long_decimal(t.substr(digits_start, i - digits_start));
  }
  if (negative) value = -value;
  return true;
}

/// v * 10^decimals rounded to the nearest integer exactly as std::to_chars(fixed, decimals)
/// rounds v, when that is cheap to decide: false next to a halfway point, beyond 1e15, or
/// for more than 9 decimals (format_fixed then asks to_chars). Two values with the same
/// units are written alike (but for the sign of a zero); the text means units / 10^decimals.
bool fixed_units(double v, int decimals, std::int64_t& units);

/// Writes units / 10^decimals (0 <= decimals <= 9), a minus sign first when `negative`,
/// into `out` (room for 32 characters) and returns the length.
std::size_t format_units(std::int64_t units, int decimals, bool negative, char* out);

/// The number units / 10^decimals (0 <= decimals <= 9) is: the division read_decimal does
/// reading the text format_units writes.
double units_value(std::int64_t units, int decimals);

/// Writes v with `decimals` digits after the point into `out` (room for 40 characters) and
/// returns the length: exactly what std::to_chars(fixed, decimals) writes; 0 when the text
/// would not fit.
std::size_t format_fixed(double v, int decimals, char* out);

}  // namespace ccomp::gcode
