#pragma once
// Test support: what the reference machine (reference_hmc.hpp) makes of a program as the
// interpreter runs it. A motion's point is taken back to program coordinates with the
// interpreter's own offsets (whatever the program set), then placed on the reference by its
// own work origin: never through ccomp's model code or its frame conventions.
#include "ccomp/gcode/canon.hpp"
#include "reference_hmc.hpp"

namespace ccomp::test {

/// The reference's axis values of a controlled point: x y z (mm, the gauge line's), b (deg), L (mm).
struct ReferenceAxes {
  double x = 0, y = 0, z = 0, b = 0, L = 0;
};

[[nodiscard]] inline ReferenceAxes reference_axes(const ReferenceHmc& machine, const gcode::Axes& controlled,
                                                  const gcode::Offsets& offsets) {
  const gcode::Axes p = offsets.program_of(controlled);
  const double L = offsets.tool[2];
  const Eigen::Vector3d axes = machine.axes_of_program(Eigen::Vector3d(p[0], p[1], p[2]), L);
  return {axes.x(), axes.y(), axes.z(), p[4], L};
}

}  // namespace ccomp::test
