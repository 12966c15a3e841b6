#pragma once
// The nine axis letters of RS-274/NGC and a fixed-size array indexed by them.
#include <array>
#include <cstdint>
#include <optional>

namespace ccomp::gcode {

enum class Axis : std::uint8_t { x, y, z, a, b, c, u, v, w };
inline constexpr std::size_t kAxisCount = 9;
inline constexpr std::array<char, kAxisCount> kAxisLetters = {'X', 'Y', 'Z', 'A', 'B', 'C', 'U', 'V', 'W'};

/// Positions of all nine axes: linear in mm, rotary (A B C) in degrees.
using Axes = std::array<double, kAxisCount>;

[[nodiscard]] constexpr bool is_rotary(std::size_t axis) {
  return axis >= 3 && axis <= 5;
}
/// Each byte's axis index, or -1 (a lookup: every word of every block asks).
inline constexpr std::array<std::int8_t, 256> kAxisOfByte = [] {
  std::array<std::int8_t, 256> of{};
  of.fill(-1);
  for (std::size_t i = 0; i < kAxisCount; ++i)
    of[static_cast<unsigned char>(kAxisLetters[i])] = static_cast<std::int8_t>(i);
  return of;
}();

[[nodiscard]] constexpr std::optional<std::size_t> axis_index(char letter) {
  const std::int8_t i = kAxisOfByte[static_cast<unsigned char>(letter)];
  if (i < 0) return std::nullopt;
  return static_cast<std::size_t>(i);
}

}  // namespace ccomp::gcode
