// The promise users buy, end to end on a machine written apart from ccomp's model code
// (tests/support/reference_hmc): measure it (nine laser lines, a grid at two tool lengths,
// two spheres probed as B turns), follow the loop from the geometric sample model as a script
// would (check's first suggestion added, refit, again until nothing is missing), compensate
// a program cut across the workspace at several table angles with the model it ends with,
// and judge the compensated program on the reference machine itself.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numbers>

#include "ccomp/compensate/verify.hpp"
#include "ccomp/identify/diagnose.hpp"
#include "ccomp/identify/fit.hpp"
#include "ccomp/model/chain_values.hpp"
#include "ccomp/model/model_file.hpp"
#include "job_runner.hpp"
#include "metrology_loop.hpp"
#include "reference_hmc.hpp"
#include "reference_measurements.hpp"
#include "trace_capture.hpp"

namespace ccomp::identify {
namespace {

constexpr double kNoise = 0.0002;  // mm

/// The reference: a machine of the sample HMC's kind with a 10 mm lead-screw error on X
/// that the geometric model lacks.
test::ReferenceHmc reference() {
  test::ReferenceHmc m = test::geometric_reference();
  const auto polynomial = m.EXX;
  m.EXX = [polynomial](double x) {
    return polynomial(x) + 0.0018 * std::cos(2 * std::numbers::pi * x / 10.0) -
           0.0009 * std::sin(2 * std::numbers::pi * x / 10.0);
  };
  return m;
}

/// A slanted rectangle cut at each table angle, across the workspace.
std::string contour_program() {
  std::string p = "G21 G17 G90 G94 G54\nT1 M6\nG43 H1\n";
  for (const char* b : {"0", "30", "135", "220", "300"})
    p += std::string("G0 B") + b +
         "\nG0 X-300 Y-200 Z-280\nG1 X310 F800\nG1 Y180 Z-120\nG1 X-300\nG1 Y-200 Z-280\nG0 Z-380\n";
  return p + "M30\n";
}

struct Segment {
  Eigen::Vector3d a, b;
};

/// The largest distance from the programmed path of what the reference machine cuts
/// running `program`, sampled every millimetre or so along each feed move.
double contour_error(const test::ReferenceHmc& machine, const std::vector<Segment>& path, const std::string& program) {
  gcode::InterpreterOptions with_tool;
  with_tool.tools.tools[1] = test::kTool1;
  const test::RunResult run = test::run_program(program, with_tool);
  EXPECT_FALSE(run.error.has_value());
  double worst = 0.0;
  for (const test::RecordedMotion& m : run.motions) {
    if (m.motion.kind != gcode::MotionKind::feed) continue;
    const model::ChainQ a = model::chain_of(m.motion.start, m.offsets);
    const model::ChainQ b = model::chain_of(m.motion.end, m.offsets);
    const int steps = std::max(1, static_cast<int>((b - a).head<3>().norm()));
    for (int k = 0; k <= steps; ++k) {
      const model::ChainQ q = a + (b - a) * (static_cast<double>(k) / steps);
      const Eigen::Vector3d cut =
          machine.actual_table_point(q[0], q[1], q[2], q[4] * 180.0 / std::numbers::pi, q[model::kToolLengthIndex]);
      double nearest = std::numeric_limits<double>::infinity();
      for (const Segment& s : path) {
        const Eigen::Vector3d d = s.b - s.a;
        const double t = std::clamp((cut - s.a).dot(d) / d.squaredNorm(), 0.0, 1.0);
        nearest = std::min(nearest, (cut - (s.a + t * d)).norm());
      }
      worst = std::max(worst, nearest);
    }
  }
  return worst;
}

TEST(ReferenceLoop, FollowingTheSuggestionsThenCompensatingLeavesUnderFivePercentOfTheError) {
  const test::ReferenceHmc machine = reference();
  test::ReferencePlans plans;
  plans.noise = kNoise, plans.seed = 11, plans.line_step = 2.5;  // four readings per screw pitch, as the samples
  const MeasurementSet data = test::reference_measurements(test::measure_reference(machine, plans));
  // The loop, as a script follows check --json: add the first suggestion, refit, again.
  const test::LoopResult loop =
      test::follow_the_loop(test::read_file(test::source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml"), data);
  ASSERT_TRUE(loop.refusals.empty()) << loop.refusals.front();
  const std::vector<std::string>& added = loop.added;
  const model::MachineModel m = model::parse_machine_model(loop.text, "fitted.yaml");
  ASSERT_FALSE(added.empty()) << "the lead screw is missing from the geometric model";
  EXPECT_NE(added.front().find("name: EXX, form: periodic, period: "), std::string::npos) << added.front();
  const double period = std::stod(added.front().substr(added.front().find("period: ") + 8));
  EXPECT_NEAR(period, 10.0, 0.01) << added.front();
  EXPECT_TRUE(loop.ended) << "the loop ends: nothing is missing";
  EXPECT_LE(loop.last.rms_after, 1.3 * kNoise);
  // Compensate with the model the loop ended with; judge on the reference machine.
  const std::string program = contour_program();
  gcode::InterpreterOptions with_tool;
  with_tool.tools.tools[1] = test::kTool1;
  std::vector<Segment> path;
  for (const test::RecordedMotion& r : test::run_program(program, with_tool).motions) {
    if (r.motion.kind != gcode::MotionKind::feed) continue;
    auto nominal = [&](const gcode::Axes& axes) {
      const model::ChainQ q = model::chain_of(axes, r.offsets);
      return machine.nominal_table_point(q[0], q[1], q[2], q[4] * 180.0 / std::numbers::pi, q[model::kToolLengthIndex]);
    };
    path.push_back({nominal(r.motion.start), nominal(r.motion.end)});
  }
  const double before = contour_error(machine, path, program);
  const double after = contour_error(machine, path, test::compensate(program, m, 0.001));
  EXPECT_GT(before, 0.015) << "the machine as it is misses the contour by tens of um";
  EXPECT_LE(after, 0.05 * before) << "before " << before * 1e3 << " um, after " << after * 1e3 << " um";
  std::cout << "[ reference ] loop added " << added.size() << " term(s); contour error before " << before * 1e3
            << " um, after " << after * 1e3 << " um\n";
}

}  // namespace
}  // namespace ccomp::identify
