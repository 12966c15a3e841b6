#pragma once
// Test support: model-file chains (the seed's horizontal machining centre, a 3-axis
// vertical one) for tests that add settings and terms of their own to them.
#include <string>

namespace ccomp::test {

/// X and Z carry the table, B turns it about -Y 400 mm from the spindle nose, Y carries the
/// spindle head, the tool points along -Z; sensors "bed" and "spindle"; program zero (G54) on
/// the B centre. Append "terms:" lines.
inline constexpr const char* kHmcChain = R"(
name: test-hmc
axes: {X: {}, Y: {}, Z: {}, B: {type: rotary}}
sensors: [bed, spindle]
work_offsets: {G54: {Z: -400 mm}}
chain:
  workpiece:
    - {link: X, axis: X, direction: [-1, 0, 0]}
    - {link: Z, axis: Z, direction: [0, 0, -1]}
    - {link: B, axis: B, direction: [0, -1, 0], offset: [0, 0, -400 mm]}
  tool:
    - {link: Y, axis: Y, direction: [0, 1, 0]}
    - {link: S}
    - {link: tool, tool_length: [0, 0, -1]}
)";

/// A 3-axis vertical machining centre: X and Y carry the table, Z the spindle, the tool
/// points along -Z; one sensor, "spindle". Append "terms:" lines (and other settings).
inline constexpr const char* kVmcChain = R"(
name: test-vmc
axes: {X: {}, Y: {}, Z: {}}
sensors: [spindle]
chain:
  workpiece:
    - {link: X, axis: X, direction: [-1, 0, 0]}
    - {link: Y, axis: Y, direction: [0, -1, 0]}
  tool:
    - {link: Z, axis: Z, direction: [0, 0, 1]}
    - {link: tool, tool_length: [0, 0, -1]}
)";

/// A chain with its `axes:` line replaced by `axes` (limits of the test's own).
inline std::string with_axes(std::string chain, const std::string& axes) {
  const std::string line = "axes: {X: {}, Y: {}, Z: {}}\n";
  const auto at = chain.find(line);
  if (at != std::string::npos) chain.replace(at, line.size(), axes);
  return chain;
}

/// `chain` with its X, Y and Z limited to +-`mm` and a B axis to +-`deg` (the chains above
/// leave their axes unlimited).
inline std::string with_limits(std::string chain, double mm, double deg = 360.0) {
  auto replace = [&chain](const std::string& from, const std::string& to) {
    if (const auto at = chain.find(from); at != std::string::npos) chain.replace(at, from.size(), to);
  };
  const std::string limit = "{min: " + std::to_string(-mm) + ", max: " + std::to_string(mm) + "}";
  replace("X: {}, Y: {}, Z: {}", "X: " + limit + ", Y: " + limit + ", Z: " + limit);
  replace("B: {type: rotary}",
          "B: {type: rotary, min: " + std::to_string(-deg) + ", max: " + std::to_string(deg) + "}");
  return chain;
}

}  // namespace ccomp::test
