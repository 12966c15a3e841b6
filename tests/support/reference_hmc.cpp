#include "reference_hmc.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

namespace ccomp::test {
namespace {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

double value_of(const std::function<double(double)>& f, double v) {
  return f ? f(v) : 0.0;
}

/// Rotation by `angle` (rad) about the unit axis `a` (Rodrigues' formula).
Mat3 rotation(const Vec3& a, double angle) {
  Mat3 cross;
  cross << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return Mat3::Identity() * std::cos(angle) + std::sin(angle) * cross + (1 - std::cos(angle)) * a * a.transpose();
}

/// The table turns about -Y for B+ (the tool about +Y relative to it).
Mat3 nominal_table_turn(double b_rad) {
  return rotation(Vec3(0, -1, 0), b_rad);
}

}  // namespace

Eigen::Vector3d ReferenceHmc::deviation(double x, double y, double z, double b_deg, double L,
                                        const State& state) const {
  const double b = b_deg * std::numbers::pi / 180.0;
  // The tool tip in the machine frame: the head on Y's line, its own error motions, the
  // pitch acting through the tool length (the tip is L below the head's reference point).
  const Vec3 y_line = Vec3(0, 1, EA0Y).normalized();
  const Vec3 tool =
      y * y_line + Vec3(0, value_of(EYY, y), value_of(EZY, y)) + Vec3(0, 0, -L) + Vec3(0, value_of(EAY, y) * L, 0);
  // The table's B centre: carried -x along X's line and -z along Z's; the carriages' error
  // motions are the tool's relative to the table, so the table moves by their opposite.
  const Vec3 x_line = Vec3(1, EC0X, -EB0X).normalized();
  Vec3 x_motion(value_of(EXX, x) + x_scale_expansion * x * (state.bed_T - 20.0), value_of(EYX, x), value_of(EZX, x));
  if (table_load) x_motion += table_load(x, y, z);
  const Vec3 centre = -x * x_line - x_motion - z * Vec3::UnitZ() - Vec3(0, 0, value_of(EZZ, z)) + Vec3(0, 0, -b_centre);
  // The table turns about its real line: through `line_point` (relative to the centre),
  // along `line` (the table's own sense of turning, the opposite of B's direction).
  const Vec3 line_point(-EX0B, 0, -EZ0B);
  const Vec3 line = -Vec3(-EC0B, 1, EA0B).normalized();
  const Mat3 turn = rotation(line, b + value_of(EBB, b_deg) + 0.5 * b_reversal * state.b_approach);
  // Where the tool tip is on the table, and where it should be.
  const Vec3 actual = line_point + turn.transpose() * (tool - centre - line_point);
  const Mat3 nominal_turn = nominal_table_turn(b);
  const Vec3 nominal = nominal_turn.transpose() * Vec3(x, y, z + b_centre - L);
  // Translations of the tool against the work that no line turns: the play each carriage
  // leaves behind by its approach, the spindle's growth.
  Vec3 shift = Vec3::Zero();
  const double position[3] = {x, y, z};
  for (std::size_t i = 0; i < 3; ++i)
    shift[static_cast<Eigen::Index>(i)] = 0.5 * (reversal[i] + value_of(reversal_along[i], position[i])) * state.approach[i];
  shift.z() += spindle_growth * (state.spindle_T - 20.0) + 0.5 * x_rides * state.approach[0];
  return nominal_turn * (actual - nominal) + shift;
}

Eigen::Vector3d ReferenceHmc::nominal_table_point(double x, double y, double z, double b_deg, double L) const {
  return nominal_table_turn(b_deg * std::numbers::pi / 180.0).transpose() * Vec3(x, y, z + b_centre - L);
}

Eigen::Vector3d ReferenceHmc::actual_table_point(double x, double y, double z, double b_deg, double L,
                                                 const State& state) const {
  // deviation() is the actual point less the nominal one, turned into machine directions.
  return nominal_table_point(x, y, z, b_deg, L) +
         nominal_table_turn(b_deg * std::numbers::pi / 180.0).transpose() * deviation(x, y, z, b_deg, L, state);
}

Eigen::Vector3d ReferenceHmc::axes_for_table_point(const Eigen::Vector3d& s, double b_deg, double L) const {
  const Vec3 v = nominal_table_turn(b_deg * std::numbers::pi / 180.0) * s;
  return Vec3(v.x(), v.y(), v.z() - b_centre + L);
}

Eigen::Vector3d ReferenceHmc::axes_of_program(const Eigen::Vector3d& p, double L) const {
  return p + work_origin + Vec3(0, 0, L);
}

Eigen::Vector3d ReferenceHmc::program_of_axes(const Eigen::Vector3d& axes, double L) const {
  return axes - work_origin - Vec3(0, 0, L);
}

std::string ReferenceHmc::work_offset_text() const {
  char text[96];
  std::snprintf(text, sizeof text, "G54=X%.6g,Y%.6g,Z%.6g", work_origin.x(), work_origin.y(), work_origin.z());
  return text;
}

ReferenceHmc geometric_reference() {
  ReferenceHmc m;
  m.EC0X = 22e-6, m.EB0X = -14e-6, m.EA0Y = 17e-6;
  m.EX0B = 0.015, m.EZ0B = -0.006, m.EA0B = 18e-6, m.EC0B = -27e-6;
  m.EXX = [](double x) { return 1.4e-5 * x - 1.2e-8 * x * x; };
  m.EYX = [](double x) { return 1.8e-8 * x * x; };
  m.EZX = [](double x) { return -1.1e-8 * x * x; };
  m.EYY = [](double y) { return 8e-6 * y + 1.2e-8 * y * y; };
  m.EZY = [](double y) { return 9e-9 * y * y; };
  m.EZZ = [](double z) { return 1.3e-5 * z - 7e-9 * z * z; };
  m.EAY = [](double y) { return 3e-6 + 1.5e-8 * y; };
  return m;
}

std::vector<ReferenceReading> measure_reference(const ReferenceHmc& machine, const ReferencePlans& plans) {
  std::mt19937 rng(plans.seed);
  std::normal_distribution<double> noise(0.0, plans.noise);
  std::vector<ReferenceReading> out;
  ReferenceHmc::State state;  // as the plan leaves the machine for the next reading
  double time = 0.0;
  auto read = [&](double x, double y, double z, double b, double L, const Vec3& n, const std::string& source) {
    const double d = n.dot(machine.deviation(x, y, z, b, L, state)) + (plans.noise > 0 ? noise(rng) : 0.0);
    out.push_back({x, y, z, b, L, state, time, n, d, source});
  };
  const double half[3] = {400, 300, 300};  // the workspace: +-400 X, +-300 Y, +-300 Z
  if (plans.nine_lines) {
    // docs/error-model.md Ref 4: three lines per axis, lines 1 and 3 near opposite edges, line 2 between.
    const double offsets[3][2] = {{-0.8, -0.8}, {0.0, 0.8}, {0.8, 0.0}};
    // Irregular targets: each interior target moved by its own draw within a quarter step.
    std::mt19937 target_rng(plans.seed + 1000);
    std::uniform_real_distribution<double> quarter(-0.25 * plans.line_step, 0.25 * plans.line_step);
    for (int axis = 0; axis < 3; ++axis) {
      const int u = (axis + 1) % 3, w = (axis + 2) % 3;
      for (int line = 0; line < 3; ++line) {
        const std::string source = std::string(1, "xyz"[axis]) + "-line" + std::to_string(line + 1);
        const int count = static_cast<int>(std::floor(2 * half[axis] / plans.line_step + 1e-9)) + 1;
        std::vector<double> targets;
        for (int k = 0; k < count; ++k)
          targets.push_back(-half[axis] + plans.line_step * k +
                            (plans.irregular_targets && k > 0 && k + 1 < count ? quarter(target_rng) : 0.0));
        for (int pass = 0; pass < 2; ++pass) {  // out (approaching upward), then back
          state.approach = {};
          state.approach[static_cast<std::size_t>(axis)] = pass == 0 ? 1.0 : -1.0;
          for (int k = 0; k < count; ++k) {
            const double t = targets[static_cast<std::size_t>(pass == 0 ? k : count - 1 - k)];
            double p[3];
            p[axis] = t, p[u] = offsets[line][0] * half[u], p[w] = offsets[line][1] * half[w];
            read(p[0], p[1], p[2], 0, 100, Vec3::Unit(axis), source);
            if (line < 2) read(p[0], p[1], p[2], 0, 100, Vec3::Unit(u), source);
            if (line == 0) read(p[0], p[1], p[2], 0, 100, Vec3::Unit(w), source);
          }
        }
      }
    }
  }
  state.approach = {1.0, 1.0, 1.0};  // the grid and the spheres are approached from below
  if (plans.grid)
    for (double L : plans.grid_tool_lengths)
      for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 5; ++j)
          for (int k = 0; k < 5; ++k) {
            const double x = -half[0] + i * half[0] / 2, y = -half[1] + j * half[1] / 2, z = -half[2] + k * half[2] / 2;
            for (int c = 0; c < 3; ++c) read(x, y, z, 0, L, Vec3::Unit(c), "grid");
          }
  if (plans.sphere) {
    std::vector<double> angles;
    for (double b = 0; b < 360 - 1e-9; b += plans.sphere_step) angles.push_back(b);
    for (int turn = 0; turn < (plans.sphere_both_ways ? 2 : 1); ++turn) {  // up, then down
      state.b_approach = plans.sphere_both_ways ? (turn == 0 ? 1.0 : -1.0) : 0.0;
      for (const Vec3& s : {Vec3(150, 100, 120), Vec3(-100, -50, -150)})
        for (std::size_t k = 0; k < angles.size(); ++k) {
          const double b = angles[turn == 0 ? k : angles.size() - 1 - k];
          const Vec3 q = machine.axes_for_table_point(s, b, 100);
          for (int c = 0; c < 3; ++c) read(q.x(), q.y(), q.z(), b, 100, Vec3::Unit(c), "sphere");
        }
    }
    state.b_approach = 0.0;
  }
  if (plans.thermal)
    for (int k = 0; k <= 24; ++k) {  // every 10 minutes for 4 hours
      time = 600.0 * k;
      state.spindle_T = 20.0 + 12.0 * (1.0 - std::exp(-time / 2400.0));
      state.bed_T = 20.0 + plans.bed_rise * (1.0 - std::exp(-time / 5400.0));
      for (const Vec3& p : {Vec3(-300, 0, -300), Vec3(0, 0, 0), Vec3(300, 0, 300)})
        for (int c = 0; c < 3; ++c) read(p.x(), p.y(), p.z(), 0, 100, Vec3::Unit(c), "thermal");
    }
  return out;
}

}  // namespace ccomp::test
