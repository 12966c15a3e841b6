#include "ccomp/compensate/program_job.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "ccomp/compensate/machine_coordinates.hpp"
#include "ccomp/error.hpp"
#include "ccomp/gcode/flatten.hpp"
#include "ccomp/gcode/writer.hpp"
#include "job_events.hpp"
#include "job_guards.hpp"

// The main job wires its stages; a move passes them in this order (docs/main-job.md):
//   job_events      the interpreter's events read into moves (and refusals)
//   offset_keeping  G92/G10 set from the position, kept the original's
//   move_pipeline   batches, the worker thread, program order kept
//   move_solver     the compensated points (the inverse, splitting, arcs as chords)
//   canned_cycles   a cycle's hole in its block's words, or its moves
//   job_guards      limits, the correction bound, rounding, warnings, the report's figures
//   move_rewriter   points as edits and added lines, in number_style
namespace ccomp::compensate {

void validate(const JobOptions& options) {
  if (!(options.tolerance > 0.0) || !std::isfinite(options.tolerance))
    throw Error(ErrorKind::usage,
                fmt::format("the tolerance must be a positive number of mm, not {}", options.tolerance));
  for (const auto& [name, decimals] :
       {std::pair{"decimals", options.decimals}, {"rotary_decimals", options.rotary_decimals}})
    if (decimals < -1 || decimals > 9)
      throw Error(ErrorKind::usage,
                  fmt::format("{} must be 0 to 9 (or -1: the program's own), not {}", name, decimals));
  if (options.threads != 1 && options.threads != 2)
    throw Error(ErrorKind::usage, fmt::format("threads must be 1 or 2, not {}", options.threads));
  if (options.time && !std::isfinite(*options.time))
    throw Error(ErrorKind::usage, fmt::format("the time must be finite, not {}", *options.time));
  for (const auto& [name, value] : options.sensors)
    if (!std::isfinite(value))
      throw Error(ErrorKind::usage, fmt::format("sensor '{}' must read a finite temperature, not {}", name, value));
}

namespace {

/// The job on the program as it runs: flattened into an unnamed temporary file, which is
/// then compensated line for line; what goes wrong is reported at the original's lines.
JobReport run_flattened_job(gcode::LineSource& input, std::FILE* out, const model::MachineModel& model,
                            const JobOptions& options) {
  std::string path = (std::filesystem::temp_directory_path() / "ccomp-flat-XXXXXX").string();
  const int fd = ::mkstemp(path.data());
  if (fd < 0)
    throw Error(ErrorKind::io, fmt::format("cannot create a temporary file for flattening '{}'", input.name()));
  std::FILE* spool = ::fdopen(fd, "w+b");
  gcode::LineOrigins origins;
  try {
    origins = gcode::flatten(input, spool, options.interpreter);
  } catch (...) {
    std::fclose(spool);
    std::remove(path.c_str());
    throw;
  }
  std::fclose(spool);
  gcode::LineSource flat = gcode::LineSource::open(path);
  std::remove(path.c_str());  // the reader holds it open; nothing is left behind
  JobOptions inner = options;
  inner.flatten = false;
  if (options.warning)
    inner.warning = [&](const std::string& message, std::uint32_t line) {
      options.warning(message, origins.at(line).line);
    };
  try {
    JobReport report = run_program_job(flat, out, model, inner);
    report.bytes = input.size();
    return report;
  } catch (const Error& e) {
    if (e.where().file != flat.name()) throw;
    SourceLocation at = origins.at(e.where().line);
    if (at.file.empty()) at.file = input.name();
    throw Error(e.kind(), e.source_line().empty() ? e.message() : e.message() + " (the line as it runs is shown)", at,
                e.source_line());
  }
}

}  // namespace

JobReport run_program_job(gcode::LineSource& input, std::FILE* out, const model::MachineModel& model,
                          const JobOptions& given) {
  validate(given);
  JobOptions options = given;  // the machine's own work offsets under the caller's
  raise_digits_for_tolerance(options, model);
  options.interpreter = with_model_offsets(given.interpreter, model);
  options.interpreter.origin_matters = !model.terms.empty();  // a machine without error has no lever
  // A TCP program's words are not the joints' positions: its moves are followed through the
  // control's kinematics (tcp_kinematics.hpp). Without an error term nothing is corrected
  // and the program is written back as it is, whichever its coordinates.
  options.interpreter.tcp = gcode::TcpCodes::follow;
  check_work_offsets(options.interpreter, model);
  if (options.flatten) return run_flattened_job(input, out, model, options);
  JobReport report;
  report.bytes = input.size();
  {
    // Double compensation would apply the correction twice: look at the first lines (a
    // transfer or a control may put a `%`, a program number and comments of its own first).
    gcode::LineSource peek = input.another_reader();
    gcode::SourceLine line;
    for (int i = 0; i < kHeaderSearchLines && peek.next(line); ++i) {
      if (is_header_line(line.text) && !options.force)
        throw Error(ErrorKind::safety,
                    "the program is already compensated by ccomp (its header is on this line); "
                    "compensating again would apply the correction twice (--force overrides)",
                    SourceLocation{input.name(), line.number, 1}, std::string(line.text));
    }
  }
  // What the run assumes goes into the header, so that verify and predict assume the same.
  const RunConditions assumed{starting_work_offsets(options.interpreter), options.sensors, options.time};
  gcode::ProgramWriter writer(input.another_reader(), out, header_line(model, options.tolerance, assumed, options.interpreter.dialect.parenthesis_comments));
  JobSink sink(writer, model, options, input, report);
  // The program's G41/G42 stay for the control (the job rewrites the programmed path), or
  // the offset path is written instead.
  gcode::InterpreterOptions interpreting = options.interpreter;
  interpreting.cutter_path =
      options.resolve_cutter_comp ? gcode::CutterPath::tool_centre_by_block : gcode::CutterPath::programmed;
  interpreting.tcp_switch = [&sink](const gcode::Axes& p, const gcode::Offsets& o, bool to_tcp) {
    return sink.tcp_switch(p, o, to_tcp);
  };
  interpreting.tcp_direction = [&sink](const std::array<double, 3>& d, const gcode::Axes& p, const gcode::Offsets& o) {
    return sink.tcp_direction(d, p, o);
  };
  gcode::Interpreter interpreter(interpreting);
  try {
    interpreter.run(input, sink);
    sink.finish();
  } catch (...) {
    sink.abandon();
    throw;
  }
  writer.finish();
  warn_coarse_tolerance(report, options);
  if (options.progress) options.progress(1.0);
  return report;
}

}  // namespace ccomp::compensate
