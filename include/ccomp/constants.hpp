#pragma once
// Conversions between units that every layer uses: one home, so each reads the same
// everywhere. Lengths inside ccomp are in mm, angles in rad (degrees only as G-code writes
// them); pi itself is std::numbers::pi.
#include <numbers>

namespace ccomp {

/// mm in an inch, exact by definition (G20 programs).
inline constexpr double kMmPerInch = 25.4;
/// rad in a degree: G-code's rotary words are degrees, the chain's are rad.
inline constexpr double kRadPerDeg = std::numbers::pi / 180.0;

}  // namespace ccomp
