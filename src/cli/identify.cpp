// ccomp fit, check and simulate: the machine model against measurements (the CSV contract
// of physics.md sect. 5).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "ccomp/error.hpp"
#include "ccomp/identify/check.hpp"
#include "ccomp/identify/fit.hpp"
#include "ccomp/identify/simulate.hpp"
#include "commands.hpp"

namespace ccomp::cli {
namespace {

void add_common(CLI::App& cmd, IdentifyArgs& args) {
  cmd.add_option("-m,--model", args.model, "machine model (YAML)")->required();
  cmd.add_option("--tool-length", args.tool_length, "mm: tool or optic length of rows without an L column (100)");
}

identify::MeasurementSet read_all(const IdentifyArgs& args, const model::MachineModel& m) {
  identify::MeasurementSet set;
  identify::ReadOptions o;
  o.tool_length = args.tool_length;
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

void write_text(const std::string& path, const std::string& text) {
  if (path == "-") {
    fmt::print("{}", text);
    return;
  }
  const std::string temporary = path + ".ccomp-tmp";
  {
    std::ofstream f(temporary, std::ios::binary);
    if (!f || !(f << text)) throw Error(ErrorKind::io, fmt::format("cannot write '{}'", path));
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) throw Error(ErrorKind::io, fmt::format("cannot write '{}'", path));
}

/// A parameter in the units a person reads: um, urad, or as is.
std::string readable(const model::ErrorTermSpec& t, std::size_t k, double v) {
  const double unit = t.parameter_unit[k];
  return fmt::format("{:.6g}", v / unit);
}

}  // namespace

CLI::App* add_fit(CLI::App& app, IdentifyArgs& args) {
  CLI::App* cmd = app.add_subcommand("fit", "identifies the model's free parameters from measurements");
  cmd->add_option("measurements", args.measurements, "measurement files (CSV)")->required();
  add_common(*cmd, args);
  cmd->add_option("-o,--output", args.output, "the fitted model (YAML)")->required();
  cmd->add_option("--weight", args.weights, "weight of a source's rows: SOURCE=W");
  cmd->add_flag("--robust", args.robust, "Huber loss: outlying rows count linearly, not squared");
  return cmd;
}

CLI::App* add_check(CLI::App& app, IdentifyArgs& args) {
  CLI::App* cmd = app.add_subcommand("check", "compares the model with measurements: residuals and noise floor");
  cmd->add_option("measurements", args.measurements, "measurement files (CSV)")->required();
  add_common(*cmd, args);
  cmd->add_flag("--json", args.json, "the report as JSON on stdout");
  return cmd;
}

CLI::App* add_simulate(CLI::App& app, IdentifyArgs& args) {
  CLI::App* cmd = app.add_subcommand("simulate", "measures a truth model along a plan, with noise: a measurement CSV");
  add_common(*cmd, args);
  cmd->add_option("-o,--output", args.output, "measurement file to write (- for stdout)")->required();
  cmd->add_option("--plan", args.plans, "nine_lines (default), grid, sphere, thermal; repeat for several");
  cmd->add_option("--noise", args.noise_um, "um, standard deviation of each reading (0.2)")->check(CLI::NonNegativeNumber);
  cmd->add_option("--seed", args.seed, "random seed (1)");
  return cmd;
}

int run_fit(const IdentifyArgs& args) {
  const model::MachineModel m = model::load_machine_model(args.model);
  const model::ForwardModel forward(m);
  const identify::MeasurementSet data = read_all(args, m);
  print_summary(data);
  identify::FitOptions options;
  options.loss = args.robust ? identify::Loss::huber : identify::Loss::least_squares;
  for (const std::string& w : args.weights) {
    const auto eq = w.find('=');
    if (eq == std::string::npos) throw Error(ErrorKind::usage, "--weight " + w + ": not SOURCE=W");
    options.source_weights.emplace_back(w.substr(0, eq), std::stod(w.substr(eq + 1)));
  }
  const identify::FitReport r = identify::fit(forward, data, options);
  fmt::print("fit: {} free parameters; the data determine {} combinations of them (condition number {:.3g}), {} of "
             "which changed by more than the noise; {} iterations{}\n",
             r.parameters.size(), r.rank, r.condition_number, r.significant, r.iterations,
             r.converged ? "" : " (not converged)");
  fmt::print("  rms {:.3f} um -> {:.3f} um, max left {:.3f} um\n", r.rms_before * 1e3, r.rms_after * 1e3, r.max_after * 1e3);
  for (std::size_t s = 0; s < data.sources.size(); ++s)
    fmt::print("    {}: rms {:.3f} -> {:.3f} um\n", data.sources[s], r.source_rms_before[s] * 1e3, r.source_rms_after[s] * 1e3);
  for (const identify::FittedParameter& p : r.parameters) {
    const model::ErrorTermSpec& t = m.terms[p.term];
    const std::size_t k = p.index - forward.parameter_offset(p.term);
    fmt::print("  {:<18} {:>12} -> {:>12} +- {:<10} {}\n", p.label, readable(t, k, p.before), readable(t, k, p.after),
               readable(t, k, p.uncertainty), p.identified ? "" : "(not separable: see below)");
  }
  if (r.singular_values.size() > 0) {
    fmt::print("  singular values (relative to the largest, columns scaled):");
    for (Eigen::Index k = 0; k < r.singular_values.size(); ++k)
      fmt::print("{}{:.1e}", k == static_cast<Eigen::Index>(r.rank) ? " | dropped:" : " ", r.singular_values[k] / r.singular_values[0]);
    fmt::print("\n");
  }
  for (const std::string& u : r.unidentifiable) fmt::print("  identifiability: {}\n", u);
  // The fitted file, with a record of what was fitted from which data.
  std::vector<Eigen::VectorXd> per_term;
  for (std::size_t t = 0; t < m.terms.size(); ++t)
    per_term.push_back(r.all_parameters.segment(static_cast<Eigen::Index>(forward.parameter_offset(t)), m.terms[t].parameters.size()));
  std::string record = "{data: [";
  for (std::size_t i = 0; i < data.files.size(); ++i) record += (i ? ", " : "") + fmt::format("\"{}\"", data.files[i]);
  record += fmt::format("], observations: {}, free_parameters: {}, identified: {}, significant: {}, rms_before_um: {:.4f}, rms_after_um: {:.4f}}}",
                        data.observations.size(), r.parameters.size(), r.rank, r.significant, r.rms_before * 1e3, r.rms_after * 1e3);
  write_text(args.output, model::rewrite_parameters(read_text(args.model), m, per_term, record));
  fmt::print("wrote {}\n", args.output);
  return 0;
}

int run_check(const IdentifyArgs& args) {
  const model::MachineModel m = model::load_machine_model(args.model);
  const model::ForwardModel forward(m);
  const identify::MeasurementSet data = read_all(args, m);
  const identify::CheckReport r = identify::check(forward, data);
  if (args.json) {
    std::string sources;
    for (const identify::SourceResidual& s : r.sources)
      sources += fmt::format("{}{{\"source\": \"{}\", \"observations\": {}, \"rms_um\": {:.6f}, \"max_um\": {:.6f}}}",
                             sources.empty() ? "" : ", ", s.source, s.observations, s.rms * 1e3, s.max * 1e3);
    fmt::print("{{\"observations\": {}, \"rms_um\": {:.6f}, \"max_um\": {:.6f}, \"noise_floor_um\": {:.6f}, "
               "\"noise_method\": \"{}\", \"sources\": [{}]}}\n",
               r.observations, r.rms * 1e3, r.max * 1e3, r.noise_floor * 1e3, r.noise_method, sources);
    return 0;
  }
  print_summary(data);
  fmt::print("model '{}' against the data: rms {:.3f} um, max {:.3f} um ({}:{}); noise floor {:.3f} um ({})\n", m.name,
             r.rms * 1e3, r.max * 1e3, r.worst_file, r.worst_row, r.noise_floor * 1e3, r.noise_method);
  for (const identify::SourceResidual& s : r.sources)
    fmt::print("  {:<16} {:>6} rows  rms {:8.3f} um  max {:8.3f} um\n", s.source, s.observations, s.rms * 1e3, s.max * 1e3);
  return 0;
}

int run_simulate(const IdentifyArgs& args) {
  const model::MachineModel m = model::load_machine_model(args.model);
  const model::ForwardModel forward(m);
  identify::SimulateOptions o;
  o.plans.clear();
  for (const std::string& p : args.plans) o.plans.push_back(identify::plan_from_name(p));
  o.noise = args.noise_um * 1e-3;
  o.seed = args.seed;
  o.tool_length = args.tool_length;
  const identify::MeasurementSet set = identify::simulate(forward, o);
  write_text(args.output, identify::to_csv(set, m));
  if (args.output != "-") fmt::print(stderr, "simulated {} observations of '{}' into {}\n", set.observations.size(), m.name, args.output);
  return 0;
}

}  // namespace ccomp::cli
