#include "job_runner.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>

#include "ccomp/model/model_file.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {

model::MachineModel sample_machine(const std::string& name) {
  return model::load_machine_model(source_dir() + "/samples/machines/" + name + ".yaml");
}

/// The main job on `program` in memory, with tool 1 in the table.
std::string compensate(const std::string& program, const model::MachineModel& mm, compensate::JobOptions o,
                       compensate::JobReport* report) {
  gcode::LineSource in = gcode::LineSource::from_string(program, "in.ngc");
  char* buffer = nullptr;
  std::size_t size = 0;
  std::FILE* out = open_memstream(&buffer, &size);
  // Closed and freed when the job throws too: many tests expect a refusal, and LeakSanitizer
  // (tools/sanitize.sh) counts every stream left open.
  struct Release {
    std::FILE*& out;
    char*& buffer;
    ~Release() {
      if (out) std::fclose(out);
      std::free(buffer);
    }
  } release{out, buffer};
  o.interpreter.tools.tools[1] = kTool1;
  const compensate::JobReport r = compensate::run_program_job(in, out, mm, o);
  std::fclose(out);
  out = nullptr;
  std::string text(buffer, size);
  if (report) *report = r;
  // Every output says it was compensated, on its first line or after a leading %.
  const auto first_end = text.find('\n');
  const std::string first = text.substr(0, first_end);
  const std::string second =
      first_end == std::string::npos ? "" : text.substr(first_end + 1, text.find('\n', first_end + 1) - first_end - 1);
  EXPECT_TRUE(compensate::is_header_line(first) || (first.starts_with('%') && compensate::is_header_line(second)))
      << "no ccomp header:\n"
      << text.substr(0, 200);
  return text;
}

std::string compensate(const std::string& program, const model::MachineModel& mm, double tolerance,
                       compensate::JobReport* report) {
  compensate::JobOptions o;
  o.tolerance = tolerance;
  return compensate(program, mm, o, report);
}

std::string random_program(unsigned seed, bool cycles) {
  std::mt19937 rng(seed), cycle_rng(seed + 1000);  // the cycles leave the other moves as they were
  std::uniform_real_distribution<double> u(-1, 1);
  // Its own zero, set by the program as a shop would (G10 L2): machine zero, which puts
  // the B centre at Z-400 on the sample HMCs and the moves within their axes.
  std::string p = "G21 G90 G94 G54\nG10 L2 P1 X0 Y0 Z0 B0\nT1 M6\nG43 H1\nF1200\nG0 X0 Y0 Z-100 B0\n";
  for (int i = 0; i < 40; ++i) {
    char line[240];
    if (cycles && i % 10 == 6) {
      auto v = [&] { return u(cycle_rng); };
      const double r = -120 + 40 * v();
      const int code = std::array{73, 81, 83, 85}[static_cast<std::size_t>(2 * (v() + 1)) % 4];
      if (v() > 0)
        std::snprintf(line, sizeof line, "G0 Z%.4f\nG98 G%d X%.4f Y%.4f Z%.4f R%.4f Q4 F300\nX%.4f Y%.4f\nG80\n",
                      r + 20, code, 150 * v(), 120 * v(), r - 15, r, 150 * v(), 120 * v());
      else
        std::snprintf(line, sizeof line,
                      "G0 X%.4f Y%.4f Z%.4f\nG91 G99 G%d X%.4f Y%.4f Z-15 R-20 Q4 L3 F300\nG90 G80\n", 100 * v(),
                      80 * v(), r + 20, code, 20 * v(), 20 * v());
      p += line;
    }
    if (i % 10 == 9) {
      std::snprintf(line, sizeof line, "G0 B%.3f\n", 180 * u(rng));
    } else if (i % 10 == 4) {  // a 4-axis simultaneous move in inverse time
      std::snprintf(line, sizeof line, "G93 G1 X%.4f Y%.4f Z%.4f B%.3f F%.3f\nG94\n", 200 * u(rng), 150 * u(rng),
                    -150 + 60 * u(rng), 120 * u(rng), 2 + 10 * (u(rng) + 1));
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
      std::snprintf(line, sizeof line, "G%d G1 %s%.4f %s%.4f %s%.4f\nG%d %s%.4f %s%.4f %s%.4f %s%.4f %s0\nG17\n", plane,
                    names[pl][0],
                    plane == 17   ? a
                    : plane == 18 ? c
                                  : b,
                    names[pl][1],
                    plane == 17   ? b
                    : plane == 18 ? a
                                  : c,
                    names[pl][2], normal, cw ? 2 : 3, names[pl][0],
                    plane == 17   ? e1
                    : plane == 18 ? c + (e1 - a)
                                  : b + (e1 - a),
                    names[pl][1],
                    plane == 17   ? e2
                    : plane == 18 ? a + (e2 - b)
                                  : c + (e2 - b),
                    names[pl][2], normal + helix, centre[pl][0], r, centre[pl][1]);
      (void)e2;
      if (i % 20 == 12) {  // every other arc in inverse time: its chords share its time
        std::string arc(line);
        const auto second = arc.find('\n') + 1, end = arc.find('\n', second);
        arc.insert(end, " F4\nG94");
        arc.insert(second, "G93 ");
        p += arc;
        continue;
      }
    } else if (i % 7 == 3) {
      std::snprintf(line, sizeof line, "G91 G1 X%.4f Y%.4f\nG90\n", 80 * u(rng), 60 * u(rng));
    } else {
      std::snprintf(line, sizeof line, "G1 X%.4f Y%.4f Z%.4f\n", 300 * u(rng), 250 * u(rng), -150 + 100 * u(rng));
    }
    p += line;
  }
  return p + "M30\n";
}

}  // namespace ccomp::test
