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
#include "ccomp/compensate/verdict.hpp"
#include "commands.hpp"
#include "header_conditions.hpp"
#include "progress.hpp"
#include "trust.hpp"

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

/// What the run assumed (assumed_by(): the header's, the command line's over it): where the
/// programs' zero lies, --work-offset over it, and the readings and time of the thermal
/// terms (the ones the program was compensated with, or the check proves nothing).
compensate::CheckOptions check_options(const CheckArgs& args, const model::MachineModel& m, const Assumed& assumed) {
  compensate::CheckOptions o;
  o.interpreter = interpreter_options(args.program, m.dialect, assumed.work_offsets);
  o.samples = args.samples;
  o.conditions = model::conditions_for(m, assumed.sensors, assumed.time);
  return o;
}

/// The figures as JSON: `what` is "predict" or "verify" (with `verdict`).
std::string path_error_json(const char* what, const CheckArgs& args, const model::MachineModel& m,
                            const compensate::PathError& e, const compensate::Verdict* verdict = nullptr,
                            const compensate::ProgramTrust* trust = nullptr) {
  util::JsonWriter j;
  j.begin_object().field("command", what).field("program", args.input);
  if (!args.compensated.empty()) j.field("compensated", args.compensated);
  j.field("model", m.name).field("model_sha256", m.sha256).field("moves", e.moves).field("points", e.points);
  j.field("max_um", e.max * 1000.0).field("rms_um", e.rms * 1000.0).field("worst_line", e.worst_line);
  j.key("worst_point_mm").begin_array().value(e.worst_point.x()).value(e.worst_point.y()).value(e.worst_point.z());
  j.end_array();
  j.field("orientation_max_urad", e.orientation_max * 1e6).field("orientation_rms_urad", e.orientation_rms * 1e6);
  j.field("orientation_worst_line", e.orientation_worst_line);
  if (verdict) {
    j.field("tolerance_um", verdict->tolerance * 1000.0).field("angular_tolerance_urad", verdict->angular_tolerance * 1e6);
    j.field("uncut_mm", e.uncut_length);
    if (e.uncut_length > 0)
      j.field("uncut_line", e.uncut_line);
    else
      j.key("uncut_line").null();
    j.field("passed", verdict->passed());
  }
  if (trust) trust_fields(j, *trust, 0.0, "");
  return j.end_object().text();
}

void print(const char* what, const std::string& file, const compensate::PathError& e) {
  fmt::print(
      "{}: {} over {} moves ({} points): max {:.2f} um at line {} (table point {:.3f} {:.3f} {:.3f}), rms {:.2f} um; "
      "tool direction off by {:.1f} urad at most, at line {}, rms {:.1f} urad\n",
      file, what, e.moves, e.points, e.max * 1000.0, e.worst_line, e.worst_point.x(), e.worst_point.y(),
      e.worst_point.z(), e.rms * 1000.0, e.orientation_max * 1e6, e.orientation_worst_line, e.orientation_rms * 1e6);
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
  cmd->add_option("--angular-tolerance", args.angular_tolerance_urad,
                  "urad: how far the tool's direction may be off the program's; more exits with 7 (default: the "
                  "tolerance over 10 mm, 100 urad at 1 um)")
      ->check(angle_in_urad());
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
  // A compensated program is predicted as it was made to run: its header's conditions.
  const Assumed assumed = assumed_by(args, m, program);
  ProgressBar bar(program.name(), !args.json && stderr_is_terminal());
  compensate::CheckOptions o = check_options(args, m, assumed);
  o.progress = [&bar](double done) { bar.update(done); };
  o.warning = [&bar, &program](const std::string& message, std::uint32_t line) {
    bar.clear();
    fmt::print(stderr, "{}:{}: warning: {}\n", program.name(), line, message);
  };
  // The trust on the program (how far the model's own values may be off on it) in the same pass.
  compensate::TrustGauge gauge(forward, model::load_fit_information(m));
  o.pose = [&gauge](const model::ChainQ& q, const model::Conditions& c, std::uint32_t line) { gauge.add(q, c, line); };
  const compensate::PathError e = compensate::predict(program, forward, o);
  bar.clear();
  const compensate::ProgramTrust trust = gauge.result();
  if (args.json) {
    fmt::print("{}", path_error_json("predict", args, m, e, nullptr, &trust));
  } else {
    print("machine error", program.name(), e);
    fmt::print("{}: compensated with this model: {}\n", program.name(), compensate::trust_text(trust));
  }
  return 0;
}

int run_verify(const CheckArgs& args) {
  const model::MachineModel m = model_with_chain(args, "verify");
  const model::ForwardModel forward(m);
  gcode::LineSource original = gcode::LineSource::open(args.input);
  gcode::LineSource compensated = gcode::LineSource::open(args.compensated);
  // ccomp's header says which model, tolerance and conditions the output was made for:
  // those are the ones to meet unless told, and another model's output is measured, with a
  // warning.
  const Assumed assumed = assumed_by(args, m, compensated);
  const double tolerance = args.tolerance > 0.0                   ? args.tolerance
                           : std::isfinite(assumed.header_tolerance) ? assumed.header_tolerance
                                                                     : 0.001;
  ProgressBar bar(compensated.name(), !args.json && stderr_is_terminal());
  compensate::CheckOptions o = check_options(args, m, assumed);
  o.progress = [&bar](double done) { bar.update(done); };
  // The main job judges its output with the same function (compensate/verdict.hpp).
  const double angular_tolerance = args.angular_tolerance_urad > 0.0 ? args.angular_tolerance_urad * 1e-6
                                                                      : compensate::default_angular_tolerance(tolerance);
  const compensate::Verdict v = compensate::judge(original, compensated, forward, o, tolerance, angular_tolerance);
  const compensate::PathError& e = v.after;
  bar.clear();
  if (args.json)
    fmt::print("{}", path_error_json("verify", args, m, e, &v));
  else
    print("contour error left", compensated.name(), e);
  if (v.leaves_cuts_out())
    throw Error(ErrorKind::safety,
                fmt::format("{} leaves {:.3f} mm of the original's cuts uncut, the first at this line of the original",
                            compensated.name(), e.uncut_length),
                SourceLocation{original.name(), e.uncut_line, 0});
  if (v.over_tolerance())
    throw Error(ErrorKind::safety, v.failures().front() + " (--tolerance)",
                SourceLocation{compensated.name(), e.worst_line, 0});
  if (v.over_angular_tolerance())
    throw Error(ErrorKind::safety, v.failures().front() + " (--angular-tolerance)",
                SourceLocation{compensated.name(), e.orientation_worst_line, 0});
  return 0;
}

}  // namespace ccomp::cli
