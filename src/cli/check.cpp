// ccomp predict (the machine's error on a program as it is) and ccomp verify (what is
// left on a compensated program), against the machine model.
#include <fmt/format.h>

#include <cmath>
#include <optional>

#include "ccomp/compensate/program_job.hpp"
#include "ccomp/compensate/verify.hpp"
#include "ccomp/error.hpp"
#include "ccomp/model/conditions.hpp"
#include "ccomp/model/model_file.hpp"
#include "ccomp/util/json.hpp"
#include "commands.hpp"
#include "progress.hpp"

namespace ccomp::cli {

namespace {

void add_model_options(CLI::App& cmd, CheckArgs& args) {
  cmd.add_option("-m,--model", args.model, "machine model (YAML)")->required();
  cmd.add_option("--sensor", args.sensors, "a temperature reading for the model's thermal terms: NAME=DEGC");
  cmd.add_option("--time", args.time, "s since the machine's warm-up started")
      ->check(seconds_since_warm_up());
  cmd.add_option("--samples", args.samples, "points checked inside each move (8)")->check(CLI::PositiveNumber);
  cmd.add_flag("--json", args.json, "the figures as JSON on stdout (docs/json.md)");
  add_program_options(cmd, args.program);
}

/// `work_offsets`: where the programs' zero lies, unless --work-offset says otherwise (the
/// model's, or those a compensated program's header records).
compensate::CheckOptions check_options(const CheckArgs& args, const model::MachineModel& m,
                                       const model::WorkOffsets& work_offsets) {
  compensate::CheckOptions o;
  o.interpreter = interpreter_options(args.program, m.dialect, work_offsets);
  o.samples = args.samples;
  // As the main job: a thermal term needs its reading (the same one the program was
  // compensated with, or the check proves nothing).
  o.conditions = model::conditions_for(m, model::parse_sensor_readings(args.sensors), args.time);
  return o;
}

/// The figures as JSON: `what` is "predict" or "verify".
std::string path_error_json(const char* what, const CheckArgs& args, const model::MachineModel& m,
                            const compensate::PathError& e, double tolerance) {
  util::JsonWriter j;
  j.begin_object().field("command", what).field("program", args.input);
  if (!args.compensated.empty()) j.field("compensated", args.compensated);
  j.field("model", m.name).field("model_sha256", m.sha256).field("moves", e.moves).field("points", e.points);
  j.field("max_um", e.max * 1000.0).field("rms_um", e.rms * 1000.0).field("worst_line", e.worst_line);
  j.key("worst_point_mm").begin_array().value(e.worst_point.x()).value(e.worst_point.y()).value(e.worst_point.z());
  j.end_array();
  if (tolerance > 0) {
    j.field("tolerance_um", tolerance * 1000.0).field("uncut_mm", e.uncut_length);
    if (e.uncut_length > 0)
      j.field("uncut_line", e.uncut_line);
    else
      j.key("uncut_line").null();
    j.field("passed", e.uncut_length <= 0.0 && e.max <= tolerance);
  }
  return j.end_object().text();
}

void print(const char* what, const std::string& file, const compensate::PathError& e) {
  fmt::print(
      "{}: {} over {} moves ({} points): max {:.2f} um at line {} (table point {:.3f} {:.3f} {:.3f}), rms {:.2f} um\n",
      file, what, e.moves, e.points, e.max * 1000.0, e.worst_line, e.worst_point.x(), e.worst_point.y(),
      e.worst_point.z(), e.rms * 1000.0);
}

}  // namespace

CLI::App* add_predict(CLI::App& app, CheckArgs& args) {
  CLI::App* cmd = app.add_subcommand("predict", "the error the machine would make on a program as it is");
  cmd->add_option("input", args.input, "G-code program")->required();
  add_model_options(*cmd, args);
  return cmd;
}

CLI::App* add_verify(CLI::App& app, CheckArgs& args) {
  CLI::App* cmd = app.add_subcommand(
      "verify", "runs a compensated program through the model: how far the tool strays from the original's path");
  cmd->add_option("original", args.input, "the program as written")->required();
  cmd->add_option("compensated", args.compensated, "ccomp's output for it")->required();
  cmd->add_option("--tolerance", args.tolerance,
                  "mm: the contour error allowed; more, or a cut of the original left out, exits with 7 (default: "
                  "the tolerance in the output's ccomp header, else 0.001)")
      ->transform(tolerance_in_mm());
  add_model_options(*cmd, args);
  return cmd;
}

namespace {

/// predict and verify follow the tool through the machine's chain: a model without one (the
/// zero model) would put every point at the origin and measure nothing.
model::MachineModel model_with_chain(const CheckArgs& args, const char* command) {
  model::MachineModel m = model::load_machine_model(args.model);
  if (m.workpiece_chain.empty() && m.tool_chain.empty())
    throw Error(ErrorKind::model,
                fmt::format("machine '{}' has no kinematic chain ('chain:'): {} follows the tool's path through it, "
                            "and without one would measure nothing; give the model its machine's chain",
                            m.name, command),
                SourceLocation{args.model, 0, 0});
  return m;
}

}  // namespace

int run_predict(const CheckArgs& args) {
  const model::MachineModel m = model_with_chain(args, "predict");
  const model::ForwardModel forward(m);
  gcode::LineSource program = gcode::LineSource::open(args.input);
  ProgressBar bar(program.name(), !args.json && stderr_is_terminal());
  compensate::CheckOptions o = check_options(args, m, m.work_offsets);
  o.progress = [&bar](double done) { bar.update(done); };
  o.warning = [&bar, &program](const std::string& message, std::uint32_t line) {
    bar.clear();
    fmt::print(stderr, "{}:{}: warning: {}\n", program.name(), line, message);
  };
  const compensate::PathError e = compensate::predict(program, forward, o);
  bar.clear();
  if (args.json)
    fmt::print("{}", path_error_json("predict", args, m, e, 0.0));
  else
    print("machine error", program.name(), e);
  return 0;
}

int run_verify(const CheckArgs& args) {
  const model::MachineModel m = model_with_chain(args, "verify");
  const model::ForwardModel forward(m);
  gcode::LineSource original = gcode::LineSource::open(args.input);
  gcode::LineSource compensated = gcode::LineSource::open(args.compensated);
  // ccomp's header says which model and tolerance the output was made for: the tolerance
  // is the one to meet unless told, and another model's output is measured, with a warning.
  double tolerance = args.tolerance > 0.0 ? args.tolerance : 0.001;
  model::WorkOffsets work_offsets = m.work_offsets;  // the header's, where it has them
  if (args.compensated != "-") {
    gcode::LineSource head = compensated.another_reader();
    gcode::SourceLine line;
    for (int k = 0; k < 2 && head.next(line); ++k) {
      const std::optional<compensate::HeaderFacts> facts = compensate::read_header(line.text);
      if (!facts) continue;
      if (args.tolerance <= 0.0 && std::isfinite(facts->tolerance)) tolerance = facts->tolerance;
      if (facts->work_offsets) {
        work_offsets.override_with(*facts->work_offsets);
        // Told another origin than the output was made for: measured there, and said.
        const model::WorkOffsets told = work_offsets_of(args.program.work_offsets);
        for (std::size_t s = 1; s <= model::kCoordinateSystems; ++s)
          if (told.of(s) && facts->work_offsets->of(s) && *told.of(s) != *facts->work_offsets->of(s))
            fmt::print(stderr,
                       "{}:{}: warning: compensated with {}, measured with --work-offset's {}: this measures the "
                       "program run there\n",
                       compensated.name(), line.number, model::describe_work_offset(s, *facts->work_offsets->of(s)),
                       model::describe_work_offset(s, *told.of(s)));
      }
      if (!facts->model_sha256.empty() && facts->model_sha256 != m.sha256)
        fmt::print(stderr,
                   "{}:{}: warning: compensated with another model (sha256:{}), not {} (sha256:{}): this measures "
                   "what {} makes of it\n",
                   compensated.name(), line.number, facts->model_sha256.substr(0, 12), args.model,
                   m.sha256.substr(0, 12), args.model);
      break;
    }
  }
  ProgressBar bar(compensated.name(), !args.json && stderr_is_terminal());
  compensate::CheckOptions o = check_options(args, m, work_offsets);
  o.progress = [&bar](double done) { bar.update(done); };
  const compensate::PathError e = compensate::verify(original, compensated, forward, o);
  bar.clear();
  if (args.json)
    fmt::print("{}", path_error_json("verify", args, m, e, tolerance));
  else
    print("contour error left", compensated.name(), e);
  if (e.uncut_length > 0.0)
    throw Error(ErrorKind::safety,
                fmt::format("{} leaves {:.3f} mm of the original's cuts uncut, the first at this line of the original",
                            compensated.name(), e.uncut_length),
                SourceLocation{original.name(), e.uncut_line, 0});
  if (e.max > tolerance) {
    // As many digits as show the difference ("1.0004 um is more than 1.00 um", not 1.00).
    int digits = 2;
    while (digits < 6 && fmt::format("{:.{}f}", e.max * 1000.0, digits) == fmt::format("{:.{}f}", tolerance * 1000.0, digits))
      ++digits;
    throw Error(ErrorKind::safety,
                fmt::format("the contour error left, {:.{}f} um, is more than the tolerance of {:.2f} um (--tolerance)",
                            e.max * 1000.0, digits, tolerance * 1000.0),
                SourceLocation{compensated.name(), e.worst_line, 0});
  }
  return 0;
}

}  // namespace ccomp::cli
