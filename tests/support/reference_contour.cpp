#include "reference_contour.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

#include "job_runner.hpp"
#include "reference_cut.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {

std::vector<ContourSegment> nominal_contour(const ReferenceHmc& machine, const std::string& program) {
  gcode::InterpreterOptions with_tool;
  with_tool.tools.tools[1] = kTool1;
  std::vector<ContourSegment> path;
  for (const RecordedMotion& r : run_program(program, with_tool).motions) {
    if (r.motion.kind != gcode::MotionKind::feed) continue;
    auto nominal = [&](const gcode::Axes& axes) {
      const ReferenceAxes q = reference_axes(machine, axes, r.offsets);
      return machine.nominal_table_point(q.x, q.y, q.z, q.b, q.L);
    };
    path.push_back({nominal(r.motion.start), nominal(r.motion.end)});
  }
  return path;
}

double contour_error(const ReferenceHmc& machine, const std::vector<ContourSegment>& path, const std::string& program) {
  gcode::InterpreterOptions with_tool;
  with_tool.tools.tools[1] = kTool1;
  const RunResult run = run_program(program, with_tool);
  EXPECT_FALSE(run.error.has_value());
  double worst = 0.0;
  for (const RecordedMotion& m : run.motions) {
    if (m.motion.kind != gcode::MotionKind::feed) continue;
    const ReferenceAxes a = reference_axes(machine, m.motion.start, m.offsets);
    const ReferenceAxes b = reference_axes(machine, m.motion.end, m.offsets);
    const Eigen::Vector3d from(a.x, a.y, a.z), to(b.x, b.y, b.z);
    const int steps = std::max(1, static_cast<int>((to - from).norm()));
    for (int k = 0; k <= steps; ++k) {
      const double f = static_cast<double>(k) / steps;
      const Eigen::Vector3d q = from + (to - from) * f;
      const Eigen::Vector3d cut = machine.actual_table_point(q.x(), q.y(), q.z(), a.b + (b.b - a.b) * f, b.L);
      double nearest = std::numeric_limits<double>::infinity();
      for (const ContourSegment& s : path) {
        const Eigen::Vector3d d = s.b - s.a;
        const double t = std::clamp((cut - s.a).dot(d) / d.squaredNorm(), 0.0, 1.0);
        nearest = std::min(nearest, (cut - (s.a + t * d)).norm());
      }
      worst = std::max(worst, nearest);
    }
  }
  return worst;
}

}  // namespace ccomp::test
