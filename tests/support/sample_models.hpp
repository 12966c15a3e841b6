#pragma once
// Test support: model-file chains (the seed's horizontal machining centre, a 3-axis
// vertical one) for tests that add settings and terms of their own to them.
namespace ccomp::test {

/// X and Z carry the table, B turns it about -Y 400 mm from the spindle nose, Y carries the
/// spindle head, the tool points along -Z; sensors "bed" and "spindle". Append "terms:" lines.
inline constexpr const char* kHmcChain = R"(
name: test-hmc
axes: {X: {}, Y: {}, Z: {}, B: {type: rotary}}
sensors: [bed, spindle]
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

}  // namespace ccomp::test
