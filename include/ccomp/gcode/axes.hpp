#pragma once
// The program's view of the nine axes (ccomp/axis.hpp): their positions, and which words are
// angles. In RS-274 the letter decides: A B C are degrees, the others lengths in the
// program's unit.
#include <array>
#include <cstdint>
#include <optional>

#include "ccomp/axis.hpp"

namespace ccomp::gcode {

using ccomp::kAxisCount;
using ccomp::kAxisLetters;

/// Positions of all nine axes: linear in mm, rotary (A B C) in degrees; indexed by Axis or
/// by place.
using Axes = AxisArray<double>;

/// Whether the program gives axis i (X..W order) in degrees.
[[nodiscard]] constexpr bool is_rotary(std::size_t axis) {
  return angular_at(axis);
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
