#include "ccomp/compensate/program_job.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "ccomp/error.hpp"
#include "ccomp/gcode/writer.hpp"
#include "ccomp/version.hpp"

namespace ccomp::compensate {
namespace {

constexpr std::string_view kHeaderPrefix = "(ccomp ";

class JobSink : public gcode::CanonSink {
 public:
  JobSink(gcode::ProgramWriter& writer, const model::MachineModel& model, const JobOptions& options,
          const gcode::LineSource& input, JobReport& report)
      : writer_(writer), model_(model), options_(options), input_(input), report_(report) {
    for (const model::AxisSpec& a : model.axes) {
      machine_axes_ |= 1U << (a.letter - 'A');
      has_limits_ = has_limits_ || std::isfinite(a.min) || std::isfinite(a.max);
    }
  }

  void block(const gcode::Block& block, const gcode::SourceLine& line) override {
    writer_.advance_to(line.offset);
    ++report_.blocks;
    for (const gcode::Word& w : block.words) {
      if (w.letter < 'A' || w.letter > 'Z' || ((machine_axes_ >> (w.letter - 'A')) & 1U) || !gcode::axis_index(w.letter))
        continue;
      throw Error(ErrorKind::safety,
                  fmt::format("the program uses axis {}, which machine '{}' does not have", w.letter,
                              model_.name),
                  SourceLocation{input_.name(), block.line, w.span.begin + 1}, std::string(block.text));
    }
    if (options_.progress && input_.size() > 0) {
      const auto percent = static_cast<int>(100.0 * static_cast<double>(line.offset) / static_cast<double>(input_.size()));
      if (percent != last_percent_) {
        last_percent_ = percent;
        options_.progress(percent / 100.0);
      }
    }
  }
  void motion(const gcode::Motion& m) override {
    ++report_.motions;
    if (has_limits_) check_limits(m);
  }
  void warning(const std::string& message, std::uint32_t line) override {
    if (options_.warning) options_.warning(message, line);
  }

 private:
  gcode::ProgramWriter& writer_;
  const model::MachineModel& model_;
  const JobOptions& options_;
  const gcode::LineSource& input_;
  JobReport& report_;
  /// The machine axes (controlled point plus tool offset) must stay within the model's
  /// limits: at every move's end, and for arcs at the extremes they pass through.
  void check_limits(const gcode::Motion& m) const {
    gcode::Axes low = m.end, high = m.end;
    if (m.kind == gcode::MotionKind::arc) arc_extremes(m, low, high);
    for (const model::AxisSpec& a : model_.axes) {
      const auto i = *gcode::axis_index(a.letter);
      const double tool = m.offsets ? m.offsets->tool[i] : 0.0;
      const double lo = low[i] + tool, hi = high[i] + tool;
      if (lo >= a.min - 1e-9 && hi <= a.max + 1e-9) continue;
      const double bad = lo < a.min - 1e-9 ? lo : hi;
      throw Error(ErrorKind::safety,
                  fmt::format("axis {} would go to {:.4f}, outside its limits [{}, {}] of machine '{}'", a.letter, bad,
                              a.min, a.max, model_.name),
                  SourceLocation{input_.name(), m.line, 0});
    }
  }

  /// Widens [low, high] by the points of the arc where its in-plane axes are extreme.
  static void arc_extremes(const gcode::Motion& m, gcode::Axes& low, gcode::Axes& high) {
    const gcode::PlaneAxes pa = gcode::plane_axes(m.arc.plane);
    const double c1 = m.arc.center_first, c2 = m.arc.center_second;
    const double r = std::hypot(m.start[pa.first] - c1, m.start[pa.second] - c2);
    const double a0 = std::atan2(m.start[pa.second] - c2, m.start[pa.first] - c1);
    const double a1 = std::atan2(m.end[pa.second] - c2, m.end[pa.first] - c1);
    constexpr double kTurn = 2.0 * 3.14159265358979323846;
    const bool ccw = m.arc.turns > 0;
    // The swept angle, in the arc's direction, with its whole extra turns.
    double sweep = ccw ? a1 - a0 : a0 - a1;
    while (sweep <= 1e-12) sweep += kTurn;
    sweep += (std::abs(m.arc.turns) - 1) * kTurn;
    for (std::size_t axis : {pa.first, pa.second, pa.normal}) {
      low[axis] = std::min({low[axis], m.start[axis], m.end[axis]});
      high[axis] = std::max({high[axis], m.start[axis], m.end[axis]});
    }
    for (int k = 0; k < 4; ++k) {  // the four quadrant points, where the arc passes them
      const double angle = k * kTurn / 4.0;
      double delta = ccw ? angle - a0 : a0 - angle;
      while (delta < 0) delta += kTurn;
      if (delta > sweep) continue;
      const double p1 = c1 + r * std::cos(angle), p2 = c2 + r * std::sin(angle);
      low[pa.first] = std::min(low[pa.first], p1);
      high[pa.first] = std::max(high[pa.first], p1);
      low[pa.second] = std::min(low[pa.second], p2);
      high[pa.second] = std::max(high[pa.second], p2);
    }
  }

  int last_percent_ = -1;
  bool has_limits_ = false;
  std::uint32_t machine_axes_ = 0;  ///< bit (letter - 'A') for each axis the machine has
};

std::string sanitize(std::string_view s) {
  std::string out;
  for (char c : s) out.push_back(c == '(' || c == ')' || c == '\n' || c == '\r' ? '_' : c);
  return out;
}

}  // namespace

std::string header_line(const model::MachineModel& model) {
  return fmt::format("{}{} compensated for machine '{}' model sha256:{})", kHeaderPrefix, kVersion,
                     sanitize(model.name), model.sha256);
}

bool is_header_line(std::string_view line) {
  const auto first = line.find_first_not_of(" \t");
  return first != std::string_view::npos && line.substr(first).starts_with(kHeaderPrefix) &&
         line.find("compensated for machine") != std::string_view::npos;
}

JobReport run_program_job(gcode::LineSource& input, std::FILE* out, const model::MachineModel& model,
                          const JobOptions& options) {
  JobReport report;
  report.bytes = input.size();
  {
    // Double compensation would apply the correction twice: look at the first lines.
    gcode::LineSource peek = input.another_reader();
    gcode::SourceLine line;
    for (int i = 0; i < 3 && peek.next(line); ++i) {
      if (is_header_line(line.text) && !options.force)
        throw Error(ErrorKind::safety,
                    "the program is already compensated by ccomp (its header is on this line); "
                    "compensating again would apply the correction twice (--force overrides)",
                    SourceLocation{input.name(), line.number, 1}, std::string(line.text));
    }
  }
  gcode::ProgramWriter writer(input.another_reader(), out, header_line(model));
  JobSink sink(writer, model, options, input, report);
  gcode::Interpreter interpreter(options.interpreter);
  interpreter.run(input, sink);
  writer.finish();
  if (options.progress) options.progress(1.0);
  return report;
}

}  // namespace ccomp::compensate
