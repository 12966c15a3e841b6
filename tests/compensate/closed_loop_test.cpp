// Closed loop: compensate a program, run the output through the interpreter and the
// forward model (the machine with its errors), and measure how far the executed tool tip
// strays from the path the original program meant. It must stay within the tolerance
// plus 0.1 um.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <random>

#include "ccomp/compensate/program_job.hpp"
#include "ccomp/model/forward.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

constexpr double kRadPerDeg = 3.14159265358979323846 / 180.0;

/// Chain values of a motion's end (or start), as the job computes them.
model::ChainQ chain_of(const gcode::Axes& controlled, const gcode::Offsets& o) {
  model::ChainQ q = model::ChainQ::Zero();
  for (std::size_t i = 0; i < gcode::kAxisCount; ++i) {
    const double axis = controlled[i] + o.tool[i];
    q[static_cast<Eigen::Index>(i)] = gcode::is_rotary(i) ? axis * kRadPerDeg : axis;
  }
  q[static_cast<Eigen::Index>(model::kToolLengthIndex)] = o.tool[2];
  return q;
}

/// Points along every feed move (rapids are the control's, not cuts), in the table frame:
/// nominal (perfect machine) or actual (the model's errors), as the machine interpolates
/// axis values linearly. Each move is its own polyline.
using Polyline = std::vector<Eigen::Vector3d>;
std::vector<Polyline> path(const RunResult& run, const model::ForwardModel& m, bool actual, int samples) {
  std::vector<Polyline> out;
  model::ForwardData d(m);
  for (const auto& rec : run.motions) {
    if (rec.motion.kind != gcode::MotionKind::feed) continue;
    out.emplace_back();
    const model::ChainQ a = chain_of(rec.motion.start, rec.offsets), b = chain_of(rec.motion.end, rec.offsets);
    for (int k = 0; k <= samples; ++k) {
      model::forward(m, d, a + (b - a) * (static_cast<double>(k) / samples), {});
      out.back().push_back(actual ? d.actual : d.nominal);
    }
  }
  return out;
}

/// A nominal arc (or helix) in the table frame: the nominal map is rigid while the rotary
/// axes hold still, so the machine-frame arc maps to an arc there.
struct ArcRef {
  Eigen::Vector3d centre, e1, e2, n;  ///< in-plane unit vectors, normal
  double r = 0, a0 = 0, sweep = 0, w0 = 0, dw = 0;
  bool ccw = true;
};

std::vector<ArcRef> arcs(const RunResult& run, const model::ForwardModel& m) {
  std::vector<ArcRef> out;
  model::ForwardData d(m);
  for (const auto& rec : run.motions) {
    if (rec.motion.kind != gcode::MotionKind::arc) continue;
    const gcode::Motion& mo = rec.motion;
    const gcode::PlaneAxes pa = gcode::plane_axes(mo.arc.plane);
    auto table = [&](gcode::Axes p) {
      model::forward(m, d, chain_of(p, rec.offsets), {});
      return Eigen::Vector3d(d.nominal);
    };
    gcode::Axes c = mo.start;
    c[pa.first] = mo.arc.center_first;
    c[pa.second] = mo.arc.center_second;
    c[pa.normal] = mo.start[pa.normal];
    ArcRef a;
    a.centre = table(c);
    gcode::Axes c1 = c, c2 = c, cn = c;
    c1[pa.first] += 1, c2[pa.second] += 1, cn[pa.normal] += 1;
    a.e1 = table(c1) - a.centre, a.e2 = table(c2) - a.centre, a.n = table(cn) - a.centre;
    a.r = std::hypot(mo.start[pa.first] - c[pa.first], mo.start[pa.second] - c[pa.second]);
    a.a0 = std::atan2(mo.start[pa.second] - c[pa.second], mo.start[pa.first] - c[pa.first]);
    const double a1 = std::atan2(mo.end[pa.second] - c[pa.second], mo.end[pa.first] - c[pa.first]);
    a.ccw = mo.arc.turns > 0;
    a.sweep = a.ccw ? a1 - a.a0 : a.a0 - a1;
    while (a.sweep <= 1e-12) a.sweep += 2 * M_PI;
    a.w0 = 0.0;
    a.dw = mo.end[pa.normal] - mo.start[pa.normal];
    out.push_back(a);
  }
  return out;
}

double distance_to_arc(const Eigen::Vector3d& p, const ArcRef& a) {
  const Eigen::Vector3d v = p - a.centre;
  const double u = v.dot(a.e1), w = v.dot(a.e2), h = v.dot(a.n);
  double phi = std::atan2(w, u) - a.a0;
  if (!a.ccw) phi = -phi;
  while (phi < 0) phi += 2 * M_PI;
  while (phi > 2 * M_PI) phi -= 2 * M_PI;
  if (phi > a.sweep) return 1e300;  // off this arc's span: another piece of the path owns it
  const double radial = std::hypot(u, w) - a.r;
  const double along = h - (a.w0 + a.dw * phi / a.sweep);
  return std::hypot(radial, along);
}

double distance_to_path(const Eigen::Vector3d& p, const std::vector<Polyline>& lines, const std::vector<ArcRef>& arc_refs) {
  double best = 1e300;
  for (const ArcRef& a : arc_refs) best = std::min(best, distance_to_arc(p, a));
  for (const Polyline& line : lines)
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    const Eigen::Vector3d ab = line[i + 1] - line[i];
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0 ? std::clamp((p - line[i]).dot(ab) / len2, 0.0, 1.0) : 0.0;
    best = std::min(best, (line[i] + t * ab - p).norm());
  }
  return best;
}

std::string compensate(const std::string& program, const model::MachineModel& mm, double tolerance,
                       compensate::JobReport* report = nullptr) {
  gcode::LineSource in = gcode::LineSource::from_string(program, "in.ngc");
  char* buffer = nullptr;
  std::size_t size = 0;
  std::FILE* out = open_memstream(&buffer, &size);
  compensate::JobOptions o;
  o.tolerance = tolerance;
  o.interpreter.tools.tools[1] = gcode::ToolEntry{1, 1, {0, 0, 100.0}, 10, ""};
  const compensate::JobReport r = compensate::run_program_job(in, out, mm, o);
  std::fclose(out);
  std::string text(buffer, size);
  std::free(buffer);
  if (report) *report = r;
  return text;
}

/// Random straight moves over the workspace at several table angles, G90 and G91.
std::string random_program(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::string p = "G21 G90 G94 G54\nT1 M6\nG43 H1\nF1200\nG0 X0 Y0 Z-100 B0\n";
  for (int i = 0; i < 40; ++i) {
    char line[160];
    if (i % 10 == 9) {
      std::snprintf(line, sizeof line, "G0 B%.3f\n", 180 * u(rng));
    } else if (i % 5 == 2) {  // an arc (helical half the time) in a random plane, from a known point
      const int plane = 17 + static_cast<int>(3 * (u(rng) + 1) / 2.0001);
      const double a = 150 * u(rng), b = 120 * u(rng), c = -150 + 40 * u(rng);
      const double r = 5 + 40 * (u(rng) + 1), phi = M_PI * (0.2 + 0.7 * (u(rng) + 1));
      const bool cw = u(rng) > 0;
      // In-plane start (p1, p2) = first and second axes; centre at +r along the first axis.
      const double e1 = a + r + r * std::cos(M_PI + (cw ? -phi : phi)), e2 = b + r * std::sin(M_PI + (cw ? -phi : phi));
      const char* names[3][3] = {{"X", "Y", "Z"}, {"Z", "X", "Y"}, {"Y", "Z", "X"}};
      const char* centre[3][2] = {{"I", "J"}, {"K", "I"}, {"J", "K"}};
      const auto pl = static_cast<std::size_t>(plane - 17);
      const double helix = u(rng) > 0 ? 10 * u(rng) : 0.0;
      // The normal axis sits at c (Z in G17), or within the reach of the axes otherwise.
      const double normal = plane == 17 ? c : 50 * u(rng);
      std::snprintf(line, sizeof line, "G%d G1 %s%.4f %s%.4f %s%.4f\nG%d %s%.4f %s%.4f %s%.4f %s%.4f %s0\nG17\n",
                    plane, names[pl][0], plane == 17 ? a : plane == 18 ? c : b, names[pl][1],
                    plane == 17 ? b : plane == 18 ? a : c, names[pl][2], normal, cw ? 2 : 3, names[pl][0],
                    plane == 17 ? e1 : plane == 18 ? c + (e1 - a) : b + (e1 - a), names[pl][1],
                    plane == 17 ? e2 : plane == 18 ? a + (e2 - b) : c + (e2 - b), names[pl][2], normal + helix,
                    centre[pl][0], r, centre[pl][1]);
      (void)e2;
    } else if (i % 7 == 3) {
      std::snprintf(line, sizeof line, "G91 G1 X%.4f Y%.4f\nG90\n", 80 * u(rng), 60 * u(rng));
    } else {
      std::snprintf(line, sizeof line, "G1 X%.4f Y%.4f Z%.4f\n", 300 * u(rng), 250 * u(rng), -150 + 100 * u(rng));
    }
    p += line;
  }
  return p + "M30\n";
}

TEST(ClosedLoop, ExecutedPathStaysWithinTheTolerance) {
  const model::MachineModel mm = model::load_machine_model(source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml");
  const model::ForwardModel m(mm);
  for (double tolerance : {0.001, 0.0002}) {
    for (unsigned seed = 1; seed <= 3; ++seed) {
      const std::string original = random_program(seed);
      compensate::JobReport report;
      const std::string output = compensate(original, mm, tolerance, &report);
      gcode::InterpreterOptions with_tool;
      with_tool.tools.tools[1] = gcode::ToolEntry{1, 1, {0, 0, 100.0}, 10, ""};
      const RunResult nominal_run = run_program(original, with_tool), compensated_run = run_program(output, with_tool);
      ASSERT_FALSE(compensated_run.error) << format_error(*compensated_run.error) << "\n" << output;
      const std::vector<Polyline> meant = path(nominal_run, m, false, 64);
      const std::vector<ArcRef> meant_arcs = arcs(nominal_run, m);
      double worst = 0.0, worst_before = 0.0;
      for (const Polyline& move : path(compensated_run, m, true, 8))
        for (const Eigen::Vector3d& p : move) worst = std::max(worst, distance_to_path(p, meant, meant_arcs));
      for (const Polyline& move : path(nominal_run, m, true, 8))
        for (const Eigen::Vector3d& p : move) worst_before = std::max(worst_before, distance_to_path(p, meant, {}));
      EXPECT_LE(worst, tolerance + 1e-4) << "seed " << seed << " tolerance " << tolerance;
      EXPECT_GT(worst_before, 0.010) << "the sample machine's error is tens of um";
      EXPECT_GT(report.compensated_moves, 30U);
      if (tolerance < 0.001) EXPECT_GT(report.added_lines, 0U) << "a tight tolerance must split some moves";
    }
  }
}

TEST(ClosedLoop, ZeroErrorModelLeavesTheProgramAsItWas) {
  const model::MachineModel mm = model::load_machine_model(source_dir() + "/samples/machines/zero.yaml");
  const std::string program = random_program(9);
  std::string out = compensate(program, mm, 0.001);
  out.erase(0, out.find('\n') + 1);
  EXPECT_EQ(out, program);
}

TEST(ClosedLoop, Refusals) {
  const model::MachineModel mm = model::load_machine_model(source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml");
  auto refusal = [&](const std::string& program) {
    try {
      (void)compensate(program, mm, 0.001);
    } catch (const Error& e) {
      return e.message();
    }
    return std::string("accepted");
  };
  EXPECT_NE(refusal("G21 F100 G0 X0 Y0 Z-100\n#1=0\no1 while [#1 LT 2]\nG1 X[#1*10]\n#1=[#1+1]\no1 endwhile\nM30\n")
                .find("runs more than once"),
            std::string::npos);
  model::MachineModel big = mm;
  big.terms.push_back(big.terms.front());
  big.terms.back().shape = model::TermShape{};
  big.terms.back().parameters = Eigen::VectorXd::Constant(1, 0.8);  // 0.8 mm: beyond the 0.5 mm bound
  try {
    gcode::LineSource in = gcode::LineSource::from_string("G21 G0 X10\nM30\n", "in.ngc");
    std::FILE* sink = std::tmpfile();
    (void)compensate::run_program_job(in, sink, big, {});
    std::fclose(sink);
    ADD_FAILURE() << "accepted a 0.8 mm correction";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::safety);
    EXPECT_NE(e.message().find("beyond the model's bound"), std::string::npos) << e.message();
  }
}

}  // namespace
}  // namespace ccomp::test
