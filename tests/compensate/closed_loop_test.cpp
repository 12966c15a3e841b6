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

double distance_to_path(const Eigen::Vector3d& p, const std::vector<Polyline>& lines) {
  double best = 1e300;
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
      double worst = 0.0, worst_before = 0.0;
      for (const Polyline& move : path(compensated_run, m, true, 8))
        for (const Eigen::Vector3d& p : move) worst = std::max(worst, distance_to_path(p, meant));
      for (const Polyline& move : path(nominal_run, m, true, 8))
        for (const Eigen::Vector3d& p : move) worst_before = std::max(worst_before, distance_to_path(p, meant));
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
