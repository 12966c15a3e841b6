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
[[nodiscard]] constexpr std::optional<std::size_t> axis_index(char letter) {
  for (std::size_t i = 0; i < kAxisCount; ++i)
    if (kAxisLetters[i] == letter) return i;
  return std::nullopt;
}

}  // namespace ccomp::gcode
