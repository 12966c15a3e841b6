// Compensation judged on a machine written apart from ccomp's model code
// (tests/support/reference_hmc): a contour cut at several table angles, compensated with a
// model of the same errors, lands on the programmed path when the reference machine runs it,
// though the machine as it is misses it by several um. Location errors (squareness, the B
// axis' line) are where ccomp's model and the reference most easily disagree.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <optional>

#include "ccomp/compensate/verify.hpp"
#include "ccomp/model/model_file.hpp"
#include "job_runner.hpp"
#include "reference_cut.hpp"
#include "reference_hmc.hpp"
#include "sample_models.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

/// The reference's errors, and the same in a model file.
ReferenceHmc reference() {
  ReferenceHmc m;
  m.EC0X = 30e-6, m.EB0X = -20e-6, m.EA0Y = 15e-6;
  m.EX0B = 0.012, m.EZ0B = -0.008, m.EA0B = 25e-6, m.EC0B = -18e-6;
  m.EXX = [](double x) { return 1.2e-5 * x - 1.5e-8 * x * x; };
  m.EYY = [](double y) { return 9e-6 * y; };
  m.EZX = [](double x) { return 1.2e-8 * x * x; };
  m.EAY = [](double y) { return 4e-6 + 1.8e-8 * y; };
  return m;
}

constexpr const char* kModelTerms = R"(terms:
  - {name: EC0X, value: 30, unit: urad}
  - {name: EB0X, value: -20, unit: urad}
  - {name: EA0Y, value: 15, unit: urad}
  - {name: EX0B, value: 12, unit: um}
  - {name: EZ0B, value: -8, unit: um}
  - {name: EA0B, value: 25, unit: urad}
  - {name: EC0B, value: -18, unit: urad}
  - {name: EXX, form: polynomial, unit: um, coefficients: [0, 0.012, -1.5e-5]}
  - {name: EYY, form: polynomial, unit: um, coefficients: [0, 0.009]}
  - {name: EZX, form: polynomial, unit: um, coefficients: [0, 0, 1.2e-5]}
  - {name: EAY, form: polynomial, unit: urad, coefficients: [4, 0.018]}
)";

/// A closed contour (a slanted rectangle) cut at each table angle.
std::string contour_program() {
  std::string p = "G21 G17 G90 G94 G54\nT1 M6\nG43 H1\n";
  for (const char* b : {"0", "45", "120", "250"})
    p += std::string("G0 B") + b +
         "\nG0 X-150 Y-80 Z-250\nG1 X160 F800\nG1 Y90 Z-150\nG1 X-150\nG1 Y-80 Z-250\nG0 Z-350\n";
  return p + "M30\n";
}

struct Segment {
  Eigen::Vector3d a, b;
};

double distance(const Eigen::Vector3d& p, const Segment& s) {
  const Eigen::Vector3d d = s.b - s.a;
  const double t = std::clamp((p - s.a).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (p - (s.a + t * d)).norm();
}

/// A motion's end as the reference's axes: x y z (mm), b (deg), L (mm).
using Chain = ReferenceAxes;
Chain chain(const RecordedMotion& m) {
  return reference_axes(reference(), m.motion.end, m.offsets);
}

/// A program compensated at 1 um (told the reference's program zero, as --work-offset
/// tells it), and both run through the interpreter with tool 1.
struct Runs {
  std::string output;
  RunResult original, compensated;
};
Runs compensate_and_run(const std::string& program, const model::MachineModel& mm) {
  Runs r;
  compensate::JobOptions o;
  o.tolerance = 0.001;
  const Eigen::Vector3d origin = reference().work_origin;
  o.interpreter.work_offsets[0] = gcode::Axes{origin.x(), origin.y(), origin.z()};
  r.output = compensate(program, mm, o);
  gcode::InterpreterOptions with_tool;
  with_tool.tools.tools[1] = kTool1;
  r.original = run_program(program, with_tool);
  r.compensated = run_program(r.output, with_tool);
  return r;
}

/// Its chain values where it starts.
Chain chain_at_start(const RecordedMotion& m) {
  RecordedMotion start = m;
  start.motion.end = m.motion.start;
  return chain(start);
}

/// The path the program's feed moves mean, on the table.
std::vector<Segment> nominal_path(const ReferenceHmc& machine, const std::vector<RecordedMotion>& motions) {
  std::vector<Segment> path;
  for (const RecordedMotion& m : motions) {
    if (m.motion.kind != gcode::MotionKind::feed) continue;
    const Chain a = chain_at_start(m), b = chain(m);
    path.push_back(
        {machine.nominal_table_point(a.x, a.y, a.z, a.b, a.L), machine.nominal_table_point(b.x, b.y, b.z, b.b, b.L)});
  }
  return path;
}

double distance_to(const Eigen::Vector3d& p, const std::vector<Segment>& path) {
  double nearest = std::numeric_limits<double>::infinity();
  for (const Segment& s : path) nearest = std::min(nearest, distance(p, s));
  return nearest;
}

TEST(ReferenceMachine, ACompensatedContourLandsOnThePathAtEveryTableAngle) {
  const ReferenceHmc machine = reference();
  const model::MachineModel mm = model::parse_machine_model(std::string(kHmcChain) + kModelTerms, "m.yaml");
  const std::string program = contour_program();
  const Runs runs = compensate_and_run(program, mm);
  const RunResult &original = runs.original, &compensated = runs.compensated;
  ASSERT_FALSE(original.error.has_value()) << original.error->message();
  ASSERT_FALSE(compensated.error.has_value()) << runs.output;
  // The path the program means, on the table, and what the machine as it is cuts.
  const std::vector<Segment> path = nominal_path(machine, original.motions);
  double before = 0.0;
  for (const RecordedMotion& m : original.motions) {
    if (m.motion.kind != gcode::MotionKind::feed) continue;
    const Chain b = chain(m);
    before = std::max(before, machine.deviation(b.x, b.y, b.z, b.b, b.L).norm());
  }
  ASSERT_EQ(path.size(), 16U);
  EXPECT_GT(before, 0.008) << "the machine as it is misses the contour by several um";
  // Every point the compensated program feeds through, as the reference runs it.
  double after = 0.0;
  int points = 0;
  for (const RecordedMotion& m : compensated.motions) {
    if (m.motion.kind != gcode::MotionKind::feed) continue;
    const Chain c = chain(m);
    after = std::max(after, distance_to(machine.actual_table_point(c.x, c.y, c.z, c.b, c.L), path));
    ++points;
  }
  EXPECT_GE(points, 16);
  // The tolerance, and the written digits (4 decimals: up to 0.09 um).
  EXPECT_LE(after, 0.001 + 1e-4) << after * 1e3 << " um off the path; before " << before * 1e3 << " um";
}

// X's carriage riding 6 um higher after travelling up than down, given to ccomp as a
// polynomial in X's approach: each cut along X, run by the reference with the approach its
// own travel gives, ends on the path, though the machine as it is misses it by 3 um and
// more. (The turns themselves are the closed-loop tests': this machine has no lost motion,
// so the switch shows there for an instant.)
TEST(ReferenceMachine, ACutIsCompensatedForTheWayItsAxisTravels) {
  ReferenceHmc machine = reference();
  machine.x_rides = 0.006;
  const model::MachineModel mm = model::parse_machine_model(
      std::string(kHmcChain) + kModelTerms +
          "  - {name: EZX, variable: vx, form: polynomial, unit: um, coefficients: [0, 3]}\n",
      "m.yaml");
  std::string program = "G21 G17 G90 G94 G54\nT1 M6\nG43 H1\n";
  for (const char* b : {"0", "120"}) {
    program += std::string("G0 B") + b + "\nG0 X-160 Y0 Z-250\nG0 X-150\n";
    for (int row = 1; row <= 4; ++row)
      program += fmt::format("G1 X{} F800\nG1 Y{}\n", row % 2 ? 150 : -150, 10 * row);
    program += "G0 Z-350\n";
  }
  program += "M30\n";
  const Runs runs = compensate_and_run(program, mm);
  const RunResult &original = runs.original, &compensated = runs.compensated;
  ASSERT_FALSE(original.error.has_value()) << original.error->message();
  ASSERT_FALSE(compensated.error.has_value()) << runs.output;
  // Where the reference puts the tool at the end of a cut along X, approaching as it travels.
  auto cut_end = [&machine](const RecordedMotion& m, Eigen::Vector3d& nominal) {
    const Chain a = chain_at_start(m), c = chain(m);
    ReferenceHmc::State state;
    state.approach[0] = c.x > a.x ? 1.0 : -1.0;
    nominal = machine.nominal_table_point(c.x, c.y, c.z, c.b, c.L);
    const Eigen::Vector3d seen = machine.actual_table_point(c.x, c.y, c.z, c.b, c.L, state);
    return std::abs(c.x - a.x) > 1.0 ? std::optional(seen) : std::nullopt;
  };
  const std::vector<Segment> path = nominal_path(machine, original.motions);
  double before = 0.0;
  for (const RecordedMotion& m : original.motions) {
    Eigen::Vector3d nominal;
    const auto seen = m.motion.kind == gcode::MotionKind::feed ? cut_end(m, nominal) : std::nullopt;
    if (seen) before = std::max(before, (*seen - nominal).norm());
  }
  EXPECT_GT(before, 0.003) << "the machine as it is misses the path by the ride and more";
  double after = 0.0;
  int cuts = 0;
  for (const RecordedMotion& m : compensated.motions) {
    Eigen::Vector3d nominal;
    const auto seen = m.motion.kind == gcode::MotionKind::feed ? cut_end(m, nominal) : std::nullopt;
    if (!seen) continue;
    after = std::max(after, distance_to(*seen, path));
    ++cuts;
  }
  EXPECT_EQ(cuts, 8);
  EXPECT_LE(after, 0.001 + 1e-4) << after * 1e3 << " um off the path; before " << before * 1e3 << " um";
}

/// Y's carriage behind its command by a dead band of `play` mm: it stays where it was until
/// the command is half the play past it, then is dragged along (the reference's own
/// backlash, apart from ccomp's play).
struct DeadBand {
  double play = 0.0;
  std::optional<double> carriage;
  double follow(double command) {
    if (!carriage) carriage = command;
    carriage = std::clamp(*carriage, command - 0.5 * play, command + 0.5 * play);
    return *carriage;
  }
};

// Y's straightness bows 9 um along X's travel (a sagging guide) and Y has 5 um of
// backlash: along each cut in X, Y's correction goes up to the bow's top and back down.
// Y must take up its play where its correction turns round, inside the move; the reference
// runs the output with its own dead band, every point of every cut, and the tool stays on
// the path, though the machine as it is misses it by the bow and the play.
TEST(ReferenceMachine, ACorrectionThatTurnsRoundInsideAMoveTakesUpThePlayThere) {
  ReferenceHmc machine = reference();
  machine.EYX = [](double x) { return 1e-7 * x * x; };
  const model::MachineModel mm = model::parse_machine_model(
      std::string(kHmcChain) + kModelTerms +
          "  - {name: EYX, form: polynomial, unit: um, coefficients: [0, 0, 1.0e-4]}\n"
          "  - {name: EYY, variable: vy, form: reversal, unit: um, reversal: -5}\n",
      "m.yaml");
  std::string program = "G21 G17 G90 G94 G54\nT1 M6\nG43 H1\nG0 X-300 Y-20 Z-250\nG1 Y-10 F800\n";
  for (int row = 0; row < 4; ++row) program += fmt::format("G1 X{}\nG1 Y{}\n", row % 2 ? -300 : 300, 10 * row);
  program += "M30\n";
  const Runs runs = compensate_and_run(program, mm);
  ASSERT_FALSE(runs.original.error.has_value()) << runs.original.error->message();
  ASSERT_FALSE(runs.compensated.error.has_value()) << runs.output;
  const std::vector<Segment> path = nominal_path(machine, runs.original.motions);
  // The largest distance from the path of the cuts' points, the reference running each
  // motion in 200 steps through its dead band.
  auto worst = [&](const std::vector<RecordedMotion>& motions) {
    DeadBand y{0.005, std::nullopt};
    double off = 0.0;
    for (const RecordedMotion& m : motions) {
      const Chain a = chain_at_start(m), c = chain(m);
      for (int k = 0; k <= 200; ++k) {
        const double t = k / 200.0;
        const double x = a.x + t * (c.x - a.x), z = a.z + t * (c.z - a.z), b = a.b + t * (c.b - a.b);
        const double carriage = y.follow(a.y + t * (c.y - a.y));
        if (m.motion.kind == gcode::MotionKind::feed && k > 0)
          off = std::max(off, distance_to(machine.actual_table_point(x, carriage, z, b, c.L), path));
      }
    }
    return off;
  };
  const double before = worst(runs.original.motions), after = worst(runs.compensated.motions);
  EXPECT_GT(before, 0.008) << "the machine as it is misses the path by the bow and the play";
  EXPECT_LE(after, 0.001 + 1e-4) << after * 1e3 << " um off the path; before " << before * 1e3 << " um\n"
                                 << runs.output;
}

}  // namespace
}  // namespace ccomp::test
