#pragma once
// Test support: the seed's horizontal machining centre as a model-file chain, for tests
// that add terms of their own to it.
namespace ccomp::test {

/// X and Z carry the table, B turns it about -Y 400 mm from the spindle nose, Y carries the
/// spindle head, the tool points along -Z; one sensor, "spindle". Append "terms:" lines.
inline constexpr const char* kHmcChain = R"(
name: test-hmc
axes: {X: {}, Y: {}, Z: {}, B: {type: rotary}}
sensors: [spindle]
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

}  // namespace ccomp::test
