#include "ccomp/compensate/program_job.hpp"

#include <fmt/format.h>

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
      : writer_(writer), model_(model), options_(options), input_(input), report_(report) {}

  void block(const gcode::Block& block, const gcode::SourceLine& line) override {
    writer_.advance_to(line.offset);
    ++report_.blocks;
    for (const gcode::Word& w : block.words) {
      if (!gcode::axis_index(w.letter) || model_.axis(w.letter)) continue;
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
  void motion(const gcode::Motion& /*motion*/) override { ++report_.motions; }
  void warning(const std::string& message, std::uint32_t line) override {
    if (options_.warning) options_.warning(message, line);
  }

 private:
  gcode::ProgramWriter& writer_;
  const model::MachineModel& model_;
  const JobOptions& options_;
  const gcode::LineSource& input_;
  JobReport& report_;
  int last_percent_ = -1;
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
