#include "ccomp/gcode/number.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

namespace ccomp::gcode {

double read_long_decimal(std::string_view digits) {
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (ec == std::errc::result_out_of_range) {
    // Below the smallest double is zero; beyond the largest, infinity (a caller refuses it).
    const std::string_view integer = digits.substr(0, digits.find('.'));
    return integer.find_first_not_of('0') == std::string_view::npos ? 0.0 : std::numeric_limits<double>::infinity();
  }
  return value;
}

namespace {
constexpr std::array<std::uint64_t, 10> kIntegerPower = {1,      10,      100,      1000,      10000,
                                                         100000, 1000000, 10000000, 100000000, 1000000000};

/// magnitude / 10^D and its remainder, 10^D a constant: the compiler multiplies.
template <std::size_t D>
std::pair<std::uint64_t, std::uint64_t> split_at_constant(std::uint64_t magnitude) {
  constexpr std::uint64_t power = kIntegerPower[D];
  return {magnitude / power, magnitude % power};
}

/// magnitude / 10^d and its remainder. The decimals a program's coordinates have are
/// divided by constants: a divisor read from the table is a hardware divide, tens of
/// cycles twice for every number written.
std::pair<std::uint64_t, std::uint64_t> split_at(std::uint64_t magnitude, std::size_t d) {
  switch (d) {
    case 3:
      return split_at_constant<3>(magnitude);
    case 4:
      return split_at_constant<4>(magnitude);
    case 5:
      return split_at_constant<5>(magnitude);
    case 6:
      return split_at_constant<6>(magnitude);
    default:
      return {magnitude / kIntegerPower[d], magnitude % kIntegerPower[d]};
  }
}
}  // namespace

std::size_t format_units(std::int64_t units, int decimals, bool negative, char* out) {
  const auto d = static_cast<std::size_t>(decimals);
  char* at = out;
  if (negative) *at++ = '-';
  // (The magnitude in unsigned arithmetic: -units overflows at the most negative.)
  const std::uint64_t magnitude =
      units < 0 ? 0 - static_cast<std::uint64_t>(units) : static_cast<std::uint64_t>(units);
  auto [integer, fraction] = split_at(magnitude, d);
  at = std::to_chars(at, out + 21, integer).ptr;  // (20 digits at most)
  if (d > 0) {
    *at++ = '.';
    for (std::size_t k = d; k-- > 0;) {
      at[k] = static_cast<char>('0' + fraction % 10);
      fraction /= 10;
    }
    at += d;
  }
  return static_cast<std::size_t>(at - out);
}

std::size_t format_fixed(double v, int decimals, char* out) {
  if (std::int64_t units = 0; fixed_units(v, decimals, units)) return format_units(units, decimals, std::signbit(v), out);
  const auto [end, error] = std::to_chars(out, out + 40, v, std::chars_format::fixed, decimals);
  return error == std::errc{} ? static_cast<std::size_t>(end - out) : 0;
}

}  // namespace ccomp::gcode
