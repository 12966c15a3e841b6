// ccomp plan: the readings that would most narrow the model's uncertainty on given programs
// (identify/plan.hpp), as a measurement file without its deviations.
#include <fmt/format.h>

#include "ccomp/compensate/verify.hpp"
#include "ccomp/error.hpp"
#include "ccomp/identify/plan.hpp"
#include "ccomp/model/conditions.hpp"
#include "ccomp/model/fit_information.hpp"
#include "ccomp/model/model_file.hpp"
#include "ccomp/util/json.hpp"
#include "commands.hpp"
#include "output_file.hpp"

namespace ccomp::cli {

CLI::App* add_plan(CLI::App& app, PlanArgs& args) {
  CLI::App* cmd = app.add_subcommand(
      "plan", "the next measurement for programs: the readings that most narrow the model's uncertainty on them");
  cmd->add_option("measurements", args.identify.measurements, "what was measured so far (measurement files)")
      ->required();
  cmd->add_option("-m,--model", args.identify.model, "the fitted machine model (YAML)")->required();
  cmd->add_option("--program", args.programs, "a program the measurement is for (repeatable)")->required();
  cmd->add_option("--budget", args.budget, "readings at most (300)")->check(CLI::PositiveNumber);
  cmd->add_option("-o,--output", args.identify.output, "the planned readings (CSV without d)")->required();
  cmd->add_option("--tool-length", args.identify.tool_length,
                  "mm: tool or optic length of measurement rows without an L column (100)");
  cmd->add_option("--frame", args.identify.frame, "the measurement files' positions where a file does not say: "
                                                   "program (the default) or machine coordinates")
      ->check(CLI::IsMember({"program", "machine"}));
  cmd->add_option("--sensor", args.sensors, "a temperature reading for the model's thermal terms: NAME=DEGC");
  cmd->add_option("--time", args.time, "s since the machine's warm-up started")->check(seconds_since_warm_up());
  cmd->add_flag("--json", args.identify.json, "the plan as JSON on stdout (docs/json.md)");
  add_program_options(*cmd, args.program);
  return cmd;
}

namespace {

/// Every point predict looks at in the programs (their cuts), with its conditions.
std::vector<identify::ProgramPose> program_poses(const PlanArgs& args, const model::MachineModel& m,
                                                 const model::ForwardModel& forward) {
  std::vector<identify::ProgramPose> poses;
  compensate::CheckOptions o;
  o.interpreter = interpreter_options(args.program, m.dialect, m.work_offsets);
  o.conditions = model::conditions_for(m, model::parse_sensor_readings(args.sensors), args.time);
  o.pose = [&poses](const model::ChainQ& q, const model::Conditions& c, std::uint32_t) {
    poses.push_back({q, c});
  };
  for (const std::string& path : args.programs) {
    gcode::LineSource program = gcode::LineSource::open(path);
    (void)compensate::predict(program, forward, o);
  }
  return poses;
}

std::string plan_json(const PlanArgs& args, const identify::MeasurementPlan& plan) {
  util::JsonWriter j;
  j.begin_object().field("command", "plan").field("output", args.identify.output);
  j.field("readings", plan.readings).field("budget", args.budget).field("candidates", plan.candidates);
  j.field("uncertainty_before_um", plan.before * 1e3).field("uncertainty_after_um", plan.after * 1e3);
  j.key("groups").begin_array();
  for (const identify::PlannedGroup& g : plan.groups) {
    j.begin_object().field("source", g.source).field("kind", g.kind).field("readings", g.readings.size());
    j.field("uncertainty_before_um", g.before * 1e3).field("uncertainty_after_um", g.after * 1e3);
    j.field("why", g.why).end_object();
  }
  j.end_array();
  return j.end_object().text();
}

}  // namespace

int run_plan(const PlanArgs& args) {
  std::vector<RunInput> inputs{{"the machine model", args.identify.model}};
  for (const std::string& f : args.identify.measurements) inputs.push_back({"a measurement file", f});
  for (const std::string& p : args.programs) inputs.push_back({"a program", p});
  check_output(args.identify.output, inputs, "-o");
  const model::MachineModel m = model::load_machine_model(args.identify.model);
  const model::ForwardModel forward(m);
  // The files' frame: their own line, else --work-offset's (one system) or --frame.
  IdentifyArgs reading = args.identify;
  if (args.program.work_offsets.size() == 1) reading.work_offsets = args.program.work_offsets;
  identify::MeasurementSet data;
  identify::ReadOptions o = reading_options(reading);
  o.frame = frame_of(reading);
  for (const std::string& path : args.identify.measurements) identify::read_measurements(path, m, o, data);
  identify::summarize(data, m);
  for (const std::string& notice : data.notices) fmt::print(stderr, "notice: {}\n", notice);
  const std::vector<identify::ProgramPose> poses = program_poses(args, m, forward);
  identify::PlanOptions options;
  options.budget = args.budget;
  if (const std::optional<model::FitInformation> info = model::load_fit_information(m)) options.noise = info->noise;
  const identify::MeasurementPlan plan = identify::plan_measurements(forward, data, poses, options);
  // Written in the frame the data were read in, so the instrument's run uses the same zero.
  const identify::ResolvedFrame frame =
      data.frames.empty() ? identify::resolve_frame(std::nullopt, o.frame, m, args.identify.output) : data.frames.front();
  write_output(args.identify.output, identify::plan_csv(plan, m, frame));
  if (args.identify.json) {
    fmt::print("{}", plan_json(args, plan));
    return 0;
  }
  fmt::print("plan for {} program(s), {} of {} readings in {} group(s) of {} considered: the programs' uncertainty "
             "{:.3f} -> {:.3f} um (rms over their points)\n",
             args.programs.size(), plan.readings, args.budget, plan.groups.size(), plan.candidates, plan.before * 1e3,
             plan.after * 1e3);
  for (const identify::PlannedGroup& g : plan.groups) fmt::print("  {}\n", g.why);
  if (plan.groups.empty())
    fmt::print("  no group of readings within the budget narrows it by more than a hundredth: the data hold what "
               "these programs need\n");
  fmt::print("wrote {}: measure these, append them to the data (their source column names each group), fit again\n",
             args.identify.output);
  return 0;
}

}  // namespace ccomp::cli
