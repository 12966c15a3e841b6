// ccomp fit, check and simulate: the machine model against measurements (the CSV contract
// of docs/error-model.md, sect. 6).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "ccomp/error.hpp"
#include "ccomp/identify/check.hpp"
#include "ccomp/identify/diagnose.hpp"
#include "ccomp/identify/fit.hpp"
#include "ccomp/identify/fit_caveats.hpp"
#include "ccomp/identify/fit_information.hpp"
#include "ccomp/identify/nine_line.hpp"
#include "ccomp/identify/plan.hpp"
#include "ccomp/identify/positioning.hpp"
#include "ccomp/identify/simulate.hpp"
#include "ccomp/model/fit_information.hpp"
#include "ccomp/model/model_file.hpp"
#include "ccomp/model/parameter_units.hpp"
#include "ccomp/model/term_span.hpp"
#include "ccomp/report/html_report.hpp"
#include "command_line.hpp"
#include "commands.hpp"
#include "identify_json.hpp"
#include "output_file.hpp"
#include "progress.hpp"

namespace ccomp::cli {
namespace {

void add_common(CLI::App& cmd, IdentifyArgs& args) {
  cmd.add_option("-m,--model", args.model, "machine model (YAML)")->required();
  cmd.add_option("--tool-length", args.tool_length, "mm: tool or optic length of rows without an L column (100)")
      ->transform(quantity(model::rules::tool_length(), "--tool-length"));
  add_frame_options(cmd, args);
}

}  // namespace

void add_frame_options(CLI::App& cmd, IdentifyArgs& args) {
  cmd.add_option("--frame", args.frame,
                 "what the files' positions are, where a file does not say (# frame:): program coordinates "
                 "(the default) or machine coordinates")
      ->check(CLI::IsMember({"program", "machine"}));
  cmd.add_option("--work-offset", args.work_offsets,
                 "where the files' program zero lies in machine coordinates: G54=X-250,Y0,Z-300 (over the model's "
                 "work_offsets; docs/identification.md, 'Frames')");
}

std::optional<identify::MeasurementFrame> frame_of(const IdentifyArgs& args) {
  if (args.frame.empty() && args.work_offsets.empty()) return std::nullopt;
  identify::MeasurementFrame f;
  f.kind = args.frame == "machine" ? identify::FrameKind::machine : identify::FrameKind::program;
  if (f.kind == identify::FrameKind::machine && !args.work_offsets.empty())
    throw Error(ErrorKind::usage, "--frame machine has no work offset: --work-offset goes with program coordinates");
  if (args.work_offsets.size() > 1)
    throw Error(ErrorKind::usage, "measurement files are in one coordinate system: give one --work-offset");
  if (!args.work_offsets.empty()) {
    const model::WorkOffsetEntry e = model::parse_work_offset(args.work_offsets[0], "--work-offset " + args.work_offsets[0]);
    f.system = e.system;
    f.origin = e.origin;
  }
  return f;
}

namespace {

identify::MeasurementSet read_all(const IdentifyArgs& args, const model::MachineModel& m) {
  identify::MeasurementSet set;
  identify::ReadOptions o = reading_options(args);
  o.frame = frame_of(args);
  for (const std::string& path : args.measurements) identify::read_measurements(path, m, o, set);
  identify::summarize(set, m);
  for (const std::string& notice : set.notices) fmt::print(stderr, "notice: {}\n", notice);
  return set;
}

void print_summary(const identify::MeasurementSet& set) {
  std::vector<std::size_t> rows(set.sources.size(), 0);
  for (const identify::Observation& o : set.observations) ++rows[o.source];
  fmt::print("read {} observations from {} file(s), {} source(s):", set.observations.size(), set.files.size(),
             set.sources.size());
  for (std::size_t s = 0; s < set.sources.size(); ++s) fmt::print(" {} ({})", set.sources[s], rows[s]);
  fmt::print("\n  ranges:");
  for (const identify::VariableRange& r : set.ranges)
    if (r.max > r.min) fmt::print(" {} [{:g}, {:g}] {};", r.name, r.min, r.max, r.unit);
  fmt::print("\n");
}

std::string read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw Error(ErrorKind::io, fmt::format("cannot read '{}'", path));
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

/// The files a run reads, which no output of it may replace.
std::vector<RunInput> inputs_of(const IdentifyArgs& args) {
  std::vector<RunInput> inputs{{"the machine model", args.model}};
  for (const std::string& m : args.measurements) inputs.push_back({"a measurement file", m});
  return inputs;
}

/// Refuses, before any work, outputs that would replace what the run reads.
void check_outputs(const IdentifyArgs& args) {
  if (!args.output.empty()) check_output(args.output, inputs_of(args), "-o");
  if (!args.report.empty()) check_output(args.report, inputs_of(args), "--report");
  if (!args.output.empty() && !args.report.empty()) check_distinct_outputs({args.output, args.report});
}

/// A parameter in the units a person reads: um, urad, or as is.
std::string readable(const model::ErrorTermSpec& t, std::size_t k, double v) {
  const double unit = t.parameter_unit[k];
  return fmt::format("{:.6g}", v / unit);
}

/// A parameter's unit as the model file writes it, and its uncertainty in that unit.
std::string unit_of(const model::ErrorTermSpec& t, std::size_t k) {
  const std::string unit = model::parameter_unit_name(t, k);
  return unit.empty() ? "(file units)" : unit;
}
/// A parameter the data do not determine, with no uncertainty beyond rounding, has none to give.
std::string uncertainty(const model::ErrorTermSpec& t, std::size_t k, const identify::FittedParameter& p) {
  const double magnitude = std::max(std::abs(p.before), std::abs(p.after));
  if (!p.identified && model::within_rounding(p.uncertainty, magnitude)) return "n/a";
  return model::uncertainty_text(p.uncertainty / t.parameter_unit[k], magnitude / t.parameter_unit[k]);
}

}  // namespace

CLI::App* add_fit(CLI::App& app, IdentifyArgs& args) {
  CLI::App* cmd = app.add_subcommand("fit", "identifies the model's free parameters from measurements");
  cmd->add_option("measurements", args.measurements, "measurement files (the CSV contract, or an instrument's: docs/identification.md)")->required();
  add_common(*cmd, args);
  cmd->add_option("-o,--output", args.output, "the fitted model (YAML)")->required();
  cmd->add_option("--weight", args.weights, "weight of a source's rows: SOURCE=W");
  cmd->add_flag("--robust", args.robust, "Huber loss: outlying rows count linearly, not squared");
  cmd->add_option("--add", args.add, "a term to add before fitting, as check suggests it: '{name: EXX, form: ...}'");
  cmd->add_flag("--json", args.json, "the fit as JSON on stdout (docs/json.md)");
  cmd->add_option("--report", args.report, "also write the check of the fitted model as one self-contained HTML page");
  add_reading_options(*cmd, args, true);
  return cmd;
}

CLI::App* add_check(CLI::App& app, IdentifyArgs& args) {
  CLI::App* cmd = app.add_subcommand("check", "compares the model with measurements: residuals and noise floor");
  cmd->add_option("measurements", args.measurements, "measurement files (the CSV contract, or an instrument's: docs/identification.md)")->required();
  add_common(*cmd, args);
  cmd->add_flag("--json", args.json, "the report as JSON on stdout");
  cmd->add_option("--report", args.report, "also write the check as one self-contained HTML page");
  cmd->add_flag("--robust", args.robust, "refit with the Huber loss: spikes (a laser beam cut) do not pull the base");
  add_reading_options(*cmd, args, true);
  return cmd;
}

CLI::App* add_simulate(CLI::App& app, IdentifyArgs& args) {
  CLI::App* cmd = app.add_subcommand("simulate", "measures a truth model along a plan, with noise: a measurement CSV");
  add_common(*cmd, args);
  cmd->add_option("-o,--output", args.output, "measurement file to write (- for stdout)")->required();
  cmd->add_option("--plan", args.plans,
                  "nine_lines (default), grid, sphere, thermal, or a file ccomp plan wrote (PLAN.csv: its readings); "
                  "repeat for several");
  cmd->add_option("--noise", args.noise_um, "um, standard deviation of each reading (0.2)")
      ->transform(quantity(model::rules::noise(), "--noise"));
  cmd->add_option("--seed", args.seed, "random seed (1)");
  cmd->add_option("--step", args.step,
                  "mm between points along a laser line (25; finer than half a screw's pitch to see it)")
      ->transform(quantity(model::rules::linear_step(), "--step"));
  cmd->add_option("--runs", args.runs, "out-and-back runs of each laser line (1; ISO 230-2 asks for 5)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--rotary-step", args.rotary_step, "deg between the sphere's probings (15)")
      ->transform(quantity(model::rules::rotary_step(), "--rotary-step"));
  cmd->add_flag("--json", args.json, "what was written as JSON on stdout (needs -o FILE; docs/json.md)");
  return cmd;
}

namespace {

/// The fitted model file, with a record of what was fitted from which data.
std::string write_fitted(const std::string& text, const model::MachineModel& m, const model::ForwardModel& forward,
                         const identify::MeasurementSet& data, const identify::FitReport& r,
                         const std::string& output) {
  std::vector<Eigen::VectorXd> per_term;
  for (std::size_t t = 0; t < m.terms.size(); ++t)
    per_term.push_back(
        r.all_parameters.segment(static_cast<Eigen::Index>(forward.parameter_offset(t)), m.terms[t].parameters.size()));
  std::string record = "{data: [";
  for (std::size_t i = 0; i < data.files.size(); ++i) record += (i ? ", " : "") + fmt::format("\"{}\"", data.files[i]);
  record += fmt::format(
      "], observations: {}, free_parameters: {}, identified: {}, significant: {}, rms_before_um: {:.4f}, rms_after_um: "
      "{:.4f}}}",
      data.observations.size(), r.parameters.size(), r.rank, r.significant, r.rms_before * 1e3, r.rms_after * 1e3);
  // With what the fit knew of its values: how far a program may trust them (predict).
  std::string fitted = model::with_fit_information(
      model::rewrite_parameters(text, m, per_term, record, identify::fitted_spans(m, data)),
      identify::fit_information(forward, data, r));
  write_output(output, fitted);
  return fitted;
}

/// Where each fitted term holds: its span, beyond which its value at the end is held.
void print_spans(const model::MachineModel& m, const std::vector<std::optional<model::TermSpan>>& spans) {
  std::string said;
  for (std::size_t t = 0; t < m.terms.size(); ++t)
    if (spans[t]) said += fmt::format(" {} {};", m.terms[t].name, model::span_text(m.terms[t], *spans[t]));
  if (!said.empty())
    fmt::print("  fitted over (each term's value is held at the end of its span beyond it):{}\n", said);
}

/// The page check --report would write for the fitted model: the check against the same data.
void write_fit_report(const IdentifyArgs& args, const std::string& fitted_text, const identify::MeasurementSet& data,
                      const identify::FitOptions& options) {
  const model::MachineModel fitted = model::parse_machine_model(fitted_text, args.output);
  const model::ForwardModel fitted_forward(fitted);
  const identify::CheckReport c = identify::check(fitted_forward, data);
  identify::DiagnoseOptions diagnose_options;
  diagnose_options.noise = c.noise_floor;
  diagnose_options.fit = options;
  diagnose_options.fit.progress = nullptr;
  const identify::Diagnosis d = identify::diagnose(fitted_forward, data, diagnose_options);
  write_output(args.report, report::html_check_report({fitted, data, c, d, "fit", {}}));
}

void write_nine_line(const std::string& text, const model::MachineModel& m, const model::ForwardModel& forward,
                     const identify::MeasurementSet& data, const identify::NineLineReport& r,
                     const std::string& output) {
  std::vector<Eigen::VectorXd> per_term;
  for (std::size_t t = 0; t < m.terms.size(); ++t)
    per_term.push_back(r.fit.all_parameters.segment(static_cast<Eigen::Index>(forward.parameter_offset(t)),
                                                    m.terms[t].parameters.size()));
  write_output(output, model::rewrite_parameters(text, m, per_term,
                                                 fmt::format("{{method: nine-line, observations: {}, rms_after_um: "
                                                             "{:.4f}}}",
                                                             data.observations.size(), r.fit.rms_after * 1e3)));
}

}  // namespace

int run_fit(const IdentifyArgs& args) {
  check_outputs(args);
  // Terms to add go into the model's text, so the fitted file carries them.
  std::string text = read_text(args.model);
  if (!args.add.empty()) {
    // Each term is read on its own first, so a wrong one is shown at its place in its
    // argument, not at a line of the joined text that no file has.
    const model::MachineModel base = model::parse_machine_model(text, args.model);
    for (const std::string& spec : args.add) (void)model::with_terms(base, {spec}, fmt::format("--add '{}'", spec));
    text = model::add_terms(text, args.add, args.model);
  }
  // The free terms over the whole line while they are fitted: the data say where they hold.
  const model::MachineModel m = identify::without_free_spans(model::parse_machine_model(text, args.model));
  const model::ForwardModel forward(m);
  const identify::MeasurementSet data = read_all(args, m);
  if (!args.json) print_summary(data);
  identify::FitOptions options;
  options.loss = args.robust ? identify::Loss::huber : identify::Loss::least_squares;
  for (const std::string& w : args.weights) {
    const auto eq = w.find('=');
    if (eq == std::string::npos) throw Error(ErrorKind::usage, "--weight " + w + ": not SOURCE=W");
    options.source_weights.emplace_back(w.substr(0, eq), std::stod(w.substr(eq + 1)));
  }
  ProgressBar bar("fit", !args.json && stderr_is_terminal());
  options.progress = [&bar](double done) { bar.update(done); };
  const identify::FitReport r = identify::fit(forward, data, options);
  bar.clear();
  for (const std::string& caveat : identify::thin_polynomials(forward, data)) fmt::print(stderr, "warning: {}\n", caveat);
  if (args.json) {
    fmt::print("{}", fit_json(forward, data, r, args.output, r.refusals.empty()));
    if (!r.refusals.empty())
      throw Error(ErrorKind::data, fmt::format("the fit is not written to {}: {}", args.output, r.refusals.front()));
    const std::string fitted_text = write_fitted(text, m, forward, data, r, args.output);
    if (!args.report.empty()) write_fit_report(args, fitted_text, data, options);
    return 0;
  }
  fmt::print(
      "fit: {} free parameters; the data determine {} combinations of them (condition number {:.3g}), {} of "
      "which changed by more than the noise; {} iterations{}\n",
      r.parameters.size(), r.rank, r.condition_number, r.significant, r.iterations,
      r.converged ? "" : " (not converged)");
  fmt::print("  rms {:.3f} um -> {:.3f} um, max left {:.3f} um\n", r.rms_before * 1e3, r.rms_after * 1e3,
             r.max_after * 1e3);
  for (std::size_t s = 0; s < data.sources.size(); ++s)
    fmt::print("    {}: rms {:.3f} -> {:.3f} um\n", data.sources[s], r.source_rms_before[s] * 1e3,
               r.source_rms_after[s] * 1e3);
  for (const identify::FittedParameter& p : r.parameters) {
    const model::ErrorTermSpec& t = m.terms[p.term];
    const std::size_t k = p.index - forward.parameter_offset(p.term);
    fmt::print("  {:<18} {:>12} -> {:>12} {:<9} +- {:<10} {}\n", p.label, readable(t, k, p.before),
               readable(t, k, p.after), unit_of(t, k), uncertainty(t, k, p),
               p.identified ? "" : "(not separable: see below)");
  }
  if (r.singular_values.size() > 0 && r.singular_values[0] > 0) {
    fmt::print("  singular values (relative to the largest, columns in physical scales):");
    for (Eigen::Index k = 0; k < r.singular_values.size(); ++k)
      fmt::print("{}{:.1e}", k == static_cast<Eigen::Index>(r.rank) ? " | dropped:" : " ",
                 r.singular_values[k] / r.singular_values[0]);
    fmt::print("\n");
  }
  for (const std::string& u : r.unidentifiable) fmt::print("  identifiability: {}\n", u);
  if (!r.outliers.empty()) {
    fmt::print("  outliers: {} reading(s) beyond 5 robust sigmas{}:", r.outliers.size(),
               args.robust ? "" : " (--robust keeps them from pulling the fit)");
    for (std::size_t k = 0; k < r.outliers.size() && k < 10; ++k)
      fmt::print(" {}:{} ({:+.3f} um)", data.files[r.outliers[k].file], r.outliers[k].row,
                 r.outliers[k].residual * 1e3);
    fmt::print("{}\n", r.outliers.size() > 10 ? " ..." : "");
  }
  if (!r.refusals.empty()) {
    std::string why;
    for (const std::string& refusal : r.refusals) why += "\n  " + refusal;
    throw Error(ErrorKind::data, fmt::format("the fit is not written to {}: {}", args.output, why));
  }
  const std::string fitted_text = write_fitted(text, m, forward, data, r, args.output);
  print_spans(m, identify::fitted_spans(m, data));
  fmt::print("wrote {}\n", args.output);
  if (!args.report.empty()) {
    write_fit_report(args, fitted_text, data, options);
    fmt::print("wrote {}\n", args.report);
  }
  return 0;
}

int run_check(const IdentifyArgs& args) {
  check_outputs(args);
  const model::MachineModel m = model::load_machine_model(args.model);
  const model::ForwardModel forward(m);
  const identify::MeasurementSet data = read_all(args, m);
  const identify::CheckReport r = identify::check(forward, data);
  identify::DiagnoseOptions options;
  options.noise = r.noise_floor;
  if (args.robust) options.fit.loss = identify::Loss::huber;
  ProgressBar bar("check", !args.json && stderr_is_terminal());
  options.progress = [&bar](double done) { bar.update(done); };
  // The model as it is holds its terms beyond their spans; its refit, as `fit` does, lets
  // the free terms follow these data wherever they reach.
  const model::MachineModel refitted = identify::without_free_spans(m);
  const model::ForwardModel refit_forward(refitted);
  const identify::Diagnosis d = identify::diagnose(refit_forward, data, options);
  bar.clear();
  if (!args.report.empty()) {
    write_output(args.report, report::html_check_report({m, data, r, d, "check", {}}));
    if (!args.json) fmt::print("wrote {}\n", args.report);
  }
  if (args.json) {
    fmt::print("{}", check_json(m, r, d));
    return 0;
  }
  print_summary(data);
  fmt::print("model '{}' against the data: rms {:.3f} um, max {:.3f} um ({}:{}); noise floor {:.3f} um ({})\n", m.name,
             r.rms * 1e3, r.max * 1e3, r.worst_file, r.worst_row, r.noise_floor * 1e3, r.noise_method);
  for (const identify::SourceResidual& s : r.sources)
    fmt::print("  {:<16} {:>6} rows  rms {:8.3f} um  max {:8.3f} um\n", s.source, s.observations, s.rms * 1e3,
               s.max * 1e3);
  if (!d.skipped.empty()) {
    fmt::print("{}\n", d.skipped);
    return 0;
  }
  fmt::print("refitted as it is (its free parameters): rms {:.3f} um\n", d.rms_refit * 1e3);
  if (const std::string nothing = identify::nothing_identifiable(d.refit); !nothing.empty())
    fmt::print("  {}\n", nothing);
  if (d.origin_misfit) {
    const identify::OriginMisfit& o = *d.origin_misfit;
    fmt::print(
        "the readings' program zero looks {:.3f} mm off where they were taken to be ({:+.3f}, {:+.3f}, {:+.3f} mm "
        "along X, Y, Z; rms {:.3f} -> {:.3f} um, BIC {:+.1f}): a wrong work offset? Check each file's '# frame:' "
        "line, --work-offset and the model's work_offsets (docs/identification.md, 'Frames') before adding effects\n",
        o.shift.norm(), o.shift.x(), o.shift.y(), o.shift.z(), o.rms_before * 1e3, o.rms_after * 1e3, o.bic_delta);
  }
  for (const identify::Region& g : d.regions)
    fmt::print("  the residual concentrates at {} in [{:.4g}, {:.4g}]: rms {:.3f} um ({:.1f}x)\n", g.variable, g.from,
               g.to, g.rms * 1e3, g.ratio);
  if (d.suggestions.empty()) {
    if (!d.unexplained.empty())
      fmt::print("missing effects: none of {} candidates is proven; {}\n", d.candidates_tried, d.unexplained);
    else
      fmt::print("missing effects: none of {} candidates is significant against the noise floor\n", d.candidates_tried);
    return 0;
  }
  fmt::print("missing effects, best first ({} candidates tried):\n", d.candidates_tried);
  for (const identify::Suggestion& s : d.suggestions) {
    fmt::print("{}. {}\n   term {} ({}), variable {}, form {}", s.rank, s.effect, s.term, s.error, s.variable, s.form);
    if (const std::string scanned = identify::scanned_value_text(s); !scanned.empty()) fmt::print(", {}", scanned);
    if (!s.aliasing.empty()) fmt::print("\n   {}", s.aliasing);
    fmt::print(
        "\n   rms {:.3f} -> {:.3f} um{}, BIC {:+.1f}; on readings left out (by {}) it predicts {:.0f}% of what it "
        "explains\n   add to the model:\n{}\n   or: ccomp fit ... --add '{}'\n",
        s.rms_before * 1e3, s.rms_after * 1e3, s.refitted ? " (fitted)" : "", s.bic_delta, s.held_out_by,
        100.0 * s.held_out, s.yaml, s.spec);
  }
  for (const identify::Tie& t : d.ties)
    fmt::print("the data cannot tell {} from {} (what they explain correlates {:.2f}): measure next: {}\n",
               d.suggestions[t.first].spec, d.suggestions[t.second].spec, t.correlation, t.measurement);
  return 0;
}

CLI::App* add_nine_line(CLI::App& app, IdentifyArgs& args) {
  CLI::App* cmd =
      app.add_subcommand("nine-line",
                         "a 3-axis machine's geometric errors from nine laser lines (docs/error-model.md [Ref 4]), "
                         "their sensitivity to line placement, and a better placement");
  cmd->add_option("measurements", args.measurements, "the nine lines (CSV; sources x-line1 .. z-line3)")->required();
  add_common(*cmd, args);
  cmd->add_option("-o,--output", args.output, "the fitted model (YAML)");
  cmd->add_flag("--json", args.json, "the figures as JSON on stdout (docs/json.md)");
  add_reading_options(*cmd, args, true);
  return cmd;
}

int run_nine_line(const IdentifyArgs& args) {
  check_outputs(args);
  const std::string text = read_text(args.model);
  const model::MachineModel m = model::parse_machine_model(text, args.model);
  const model::ForwardModel forward(m);
  const identify::MeasurementSet data = read_all(args, m);
  const identify::NineLineReport r = identify::nine_line(forward, data);
  if (args.json) {
    fmt::print("{}", nine_line_json(forward, data, r, args.output));
    if (!args.output.empty()) write_nine_line(text, m, forward, data, r, args.output);
    return 0;
  }
  print_summary(data);
  fmt::print("fit: {} free parameters, {} combinations determined by the lines; rms {:.3f} -> {:.3f} um\n",
             r.fit.parameters.size(), r.fit.rank, r.fit.rms_before * 1e3, r.fit.rms_after * 1e3);
  for (const identify::FittedParameter& p : r.fit.parameters) {
    const model::ErrorTermSpec& t = m.terms[p.term];
    const std::size_t k = p.index - forward.parameter_offset(p.term);
    fmt::print("  {:<14} {:>12} {:<9} +- {:<10} {}\n", p.label, readable(t, k, p.after), unit_of(t, k),
               uncertainty(t, k, p), p.identified ? "" : "(not determined by nine lines alone)");
  }
  if (!r.squareness.empty()) {
    fmt::print("squareness between the lines (straightness against its least-squares line, [Ref 4]):\n");
    for (const identify::LineSquareness& q : r.squareness)
      fmt::print("  {:<5} {:>9.3f} urad  ({} = {:.3f} urad)\n", q.iso, q.value * 1e6, q.seed,
                 q.seed_sign * q.value * 1e6);
  }
  fmt::print("placement sensitivity (change of the fitted value per mm a line sits off, in the file's units):\n");
  for (const identify::PlacementSensitivity& s : r.sensitivity) {
    std::size_t term = 0;
    for (const identify::FittedParameter& p : r.fit.parameters)
      if (p.label == s.parameter) term = p.term;
    const model::ErrorTermSpec& t = m.terms[term];
    std::size_t k = 0;
    for (const identify::FittedParameter& p : r.fit.parameters)
      if (p.label == s.parameter) k = p.index - forward.parameter_offset(p.term);
    fmt::print("  {:<14} {:>12} {} per mm  (most by {})\n", s.parameter, readable(t, k, s.per_mm), unit_of(t, k),
               s.line);
  }
  fmt::print("placement of lines 1 and 3 (fraction of the workspace from its edges) against overall sensitivity:\n");
  for (const auto& [inset, value] : r.placements) fmt::print("  {:4.2f}  {:.4g}\n", inset, value);
  fmt::print("recommended: lines 1 and 3 at {:.2f} of the workspace from its edges ([Ref 4]: spread them across it)\n",
             r.recommended_inset);
  if (!args.output.empty()) {
    write_nine_line(text, m, forward, data, r, args.output);
    fmt::print("wrote {}\n", args.output);
  }
  return 0;
}

int run_simulate(const IdentifyArgs& args) {
  if (args.json && args.output == "-")
    throw Error(ErrorKind::usage, "--json writes on stdout: give the measurements -o FILE");
  check_outputs(args);
  const model::MachineModel m = model::load_machine_model(args.model);
  const model::ForwardModel forward(m);
  identify::SimulateOptions o;
  o.plans.clear();
  // A plan that is a file (`ccomp plan`'s): its rows measured, after the named plans'.
  std::vector<std::string> plan_files;
  for (const std::string& p : args.plans)
    if (p.ends_with(".csv") || p.find('/') != std::string::npos)
      plan_files.push_back(p);
    else
      o.plans.push_back(identify::plan_from_name(p));
  o.noise = args.noise_um * 1e-3;
  o.seed = args.seed;
  o.tool_length = args.tool_length;
  o.step = args.step;
  o.rotary_step = args.rotary_step;
  o.runs = args.runs;
  // The file says its frame, its origin written out: the model's (or the user's) G54.
  const identify::ResolvedFrame frame = identify::resolve_frame(std::nullopt, frame_of(args), m, args.output);
  o.origin = frame.origin;
  identify::MeasurementSet set;
  if (!o.plans.empty() || plan_files.empty()) set = identify::simulate(forward, o);
  if (!plan_files.empty()) {
    identify::MeasurementSet planned;
    identify::ReadOptions reading = reading_options(args);
    reading.frame = frame_of(args);
    for (const std::string& path : plan_files) identify::read_plan(path, m, reading, planned);
    identify::measure_on(forward, planned, o.noise, o.seed + 1);
    for (identify::Observation ob : planned.observations) {
      const auto source = static_cast<std::uint32_t>(
          std::find(set.sources.begin(), set.sources.end(), planned.sources[ob.source]) - set.sources.begin());
      if (source == set.sources.size()) set.sources.push_back(planned.sources[ob.source]);
      ob.source = source;
      ob.temperatures.resize(m.sensors.size(), 20.0);
      set.observations.push_back(std::move(ob));
    }
  }
  write_output(args.output, identify::to_csv(set, m, frame));
  if (args.json)
    fmt::print("{}", simulate_json(m, set, args.output));
  else if (args.output != "-")
    fmt::print(stderr, "simulated {} observations of '{}' into {}\n", set.observations.size(), m.name, args.output);
  return 0;
}

}  // namespace ccomp::cli
