#pragma once
// Decimal numbers as G-code writes them, read and written exactly: the exact binary value
// correctly rounded either way, as std::from_chars and std::to_chars give it, at a
// fraction of their cost for the short fixed-point numbers a program carries (every
// coordinate of a program goes through these).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>

namespace ccomp::gcode {

/// What std::from_chars reads of `digits` (more digits than read_decimal's fast path takes);
/// infinity beyond the largest double, zero below the smallest.
double read_long_decimal(std::string_view digits);

/// 10^k, exact in a double for k <= 22: what the decimal readers divide by and the
/// writers scale by.
inline constexpr double kPowersOfTen[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                            1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

/// How a number was written: what a writer keeps of it.
struct DecimalForm {
  std::size_t fraction_digits = 0;  ///< after the point (0 without one)
  bool point_first = false;         ///< ".5": a point before any digit
};

/// Reads `[+-] digits [. digits] | [+-] . digits` at `i` in `t` into `value`, advancing `i`
/// past it; false when no digit is there (`i` may have passed a sign or a lone point; an `i`
/// past the end comes back as the end). `form`, where given, gets how it was written.
/// Inline: the parser reads every number of a program with it.
inline bool read_decimal(std::string_view t, std::size_t& i, double& value, DecimalForm* form = nullptr) {
  // (Pointers, not indices into t: the loops then keep the end in a register.)
  const char* const begin = t.data();
  const char* const end = begin + t.size();
  const char* at = begin + std::min(i, t.size());
  auto digit = [&] { return at < end && static_cast<unsigned>(*at - '0') < 10U; };
  bool negative = false;
  if (at < end && (*at == '+' || *at == '-')) negative = *at++ == '-';
  const char* const digits_start = at;
  std::uint64_t mantissa = 0;
  while (digit()) mantissa = mantissa * 10 + static_cast<std::uint64_t>(*at++ - '0');
  const auto integer_digits = static_cast<std::size_t>(at - digits_start);
  std::size_t fraction = 0;
  if (at < end && *at == '.') {
    const char* const first = ++at;
    while (digit()) mantissa = mantissa * 10 + static_cast<std::uint64_t>(*at++ - '0');
    fraction = static_cast<std::size_t>(at - first);
  }
  i = static_cast<std::size_t>(at - begin);
  if (integer_digits + fraction == 0) return false;
  if (form) *form = {fraction, integer_digits == 0};
  // Exact while the digits fit 15 decimal places (2^53 > 10^15): one correctly rounded
  // division of two exact numbers. (Leading zeros make the count pessimistic, never wrong.)
  if (integer_digits + fraction <= 15) {
    value = static_cast<double>(mantissa) / kPowersOfTen[fraction];
  } else {
    value = read_long_decimal(std::string_view(digits_start, static_cast<std::size_t>(at - digits_start)));
  }
  if (negative) value = -value;
  return true;
}

/// v * 10^decimals rounded to the nearest integer exactly as std::to_chars(fixed, decimals)
/// rounds v, when that is cheap to decide: false next to a halfway point, beyond 1e15, or
/// for more than 9 decimals (format_fixed then asks to_chars). Two values with the same
/// units are written alike (but for the sign of a zero); the text means units / 10^decimals.
/// Inline: every number the job writes, or compares as written, comes here.
inline bool fixed_units(double v, int decimals, std::int64_t& units) {
  if (decimals < 0 || decimals > 9 || !std::isfinite(v)) return false;
  const double scaled = v * kPowersOfTen[decimals];  // 10^d is exact: within half an ulp of v 10^d
  if (!(std::abs(scaled) < 1e15)) return false;
  const double nearest = std::nearbyint(scaled);
  // Exact (the two are within one of each other). Further from halfway than the product's
  // error, the product rounds as the exact value does; nearer, to_chars decides.
  const double off = std::abs(scaled - nearest);
  if (!(0.5 - off > 1e-15 * std::abs(scaled) + 1e-300)) return false;
  units = static_cast<std::int64_t>(nearest);
  return true;
}

/// "00" to "99", each number's two digits.
inline constexpr std::array<char, 200> kDigitPairs = [] {
  std::array<char, 200> pairs{};
  for (std::size_t n = 0; n < 100; ++n) {
    pairs[2 * n] = static_cast<char>('0' + n / 10);
    pairs[2 * n + 1] = static_cast<char>('0' + n % 10);
  }
  return pairs;
}();

/// Writes units / 10^decimals (0 <= decimals <= 9, |units| below 1e15), a minus sign
/// first when `negative`, right to left ending just before `end` (room for 32 characters
/// before it), and returns where the text starts. Without `leading_zero` a zero integer
/// part is left out where a point follows (".5", "-.25"). Inline, two digits a step (one
/// division by a constant for two): every coordinate the job writes comes here.
inline char* write_units(std::int64_t units, int decimals, bool negative, bool leading_zero, char* end) {
  // (The magnitude in unsigned arithmetic: -units overflows at the most negative.)
  std::uint64_t magnitude = units < 0 ? 0 - static_cast<std::uint64_t>(units) : static_cast<std::uint64_t>(units);
  char* at = end;
  auto two_digits = [&] {
    at -= 2;
    std::memcpy(at, &kDigitPairs[2 * (magnitude % 100)], 2);
    magnitude /= 100;
  };
  int fraction = decimals;
  for (; fraction >= 2; fraction -= 2) two_digits();
  if (fraction == 1) *--at = static_cast<char>('0' + magnitude % 10), magnitude /= 10;
  if (decimals > 0) *--at = '.';
  if (magnitude != 0 || leading_zero || decimals == 0) {
    while (magnitude >= 10) two_digits();
    // The last digit, or the single 0 of a zero integer part (nothing or the point after it).
    if (magnitude != 0 || at == end || *at == '.') *--at = static_cast<char>('0' + magnitude);
  }
  if (negative) *--at = '-';
  return at;
}

/// Writes units / 10^decimals (0 <= decimals <= 9), a minus sign first when `negative`,
/// into `out` (room for 32 characters) and returns the length.
std::size_t format_units(std::int64_t units, int decimals, bool negative, char* out);

/// The number units / 10^decimals (0 <= decimals <= 9) is: the division read_decimal does
/// reading the text format_units writes.
inline double units_value(std::int64_t units, int decimals) {
  return static_cast<double>(units) / kPowersOfTen[decimals];
}

/// Writes v with `decimals` digits after the point into `out` (room for 40 characters) and
/// returns the length: exactly what std::to_chars(fixed, decimals) writes; 0 when the text
/// would not fit.
std::size_t format_fixed(double v, int decimals, char* out);

}  // namespace ccomp::gcode
