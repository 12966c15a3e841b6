#include "ccomp/gcode/number.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>

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

std::size_t format_units(std::int64_t units, int decimals, bool negative, char* out) {
  std::array<char, 32> buffer;
  char* const end = buffer.data() + buffer.size();
  const char* const start = write_units(units, decimals, negative, true, end);
  std::copy(start, static_cast<const char*>(end), out);
  return static_cast<std::size_t>(end - start);
}

std::size_t format_fixed(double v, int decimals, char* out) {
  if (std::int64_t units = 0; fixed_units(v, decimals, units)) return format_units(units, decimals, std::signbit(v), out);
  const auto [end, error] = std::to_chars(out, out + 40, v, std::chars_format::fixed, decimals);
  return error == std::errc{} ? static_cast<std::size_t>(end - out) : 0;
}

}  // namespace ccomp::gcode
