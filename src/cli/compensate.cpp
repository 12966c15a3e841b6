// The main job: ccomp in.nc -m machine.yaml -o out.nc (and its batch and filter forms).
#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include <unistd.h>

#include "ccomp/compensate/program_job.hpp"
#include "ccomp/compensate/verdict.hpp"
#include "ccomp/error.hpp"
#include "ccomp/exit_codes.hpp"
#include "ccomp/model/conditions.hpp"
#include "ccomp/model/model_file.hpp"
#include "ccomp/util/json.hpp"
#include "ccomp/util/parallel.hpp"
#include "commands.hpp"
#include "output_file.hpp"
#include "progress.hpp"
#include "trust.hpp"

namespace ccomp::cli {
namespace fs = std::filesystem;

void add_compensate(CLI::App& app, CompensateArgs& args) {
  app.add_option("inputs", args.inputs, "G-code programs ('-' reads standard input)");
  app.add_option("-m,--model", args.model, "machine model (YAML)");
  app.add_option("-o,--output", args.output, "output program ('-' writes standard output)");
  app.add_option("--out-dir", args.out_dir, "write each output under this folder, same file name");
  app.add_flag("--in-place", args.in_place, "replace each input, keeping a backup");
  app.add_option("--backup-suffix", args.backup_suffix, "suffix of --in-place backups (default .orig)");
  app.add_option("-j,--jobs", args.jobs, "programs compensated at once")->check(CLI::PositiveNumber);
  app.add_option("--threads", args.threads,
                 "threads per program: 2 compensates the moves while the other reads and writes the program "
                 "(the output is the same); default 2 when there are cores for each program's two")
      ->check(CLI::Range(1, 2));
  app.add_flag("--force", args.force, "compensate a program that already carries ccomp's header");
  app.add_flag("--expand-cycles", args.expand_cycles,
               "write canned cycles (G73 G81 G83 G85) as the compensated moves they make; takes L repeats "
               "and G91 cycles");
  app.add_flag("--resolve-cutter-comp", args.resolve_cutter_comp,
               "under G41/G42, write the tool centre's path (the offset taken out), compensated and split like "
               "any path, instead of the programmed path the control offsets");
  app.add_flag("--flatten", args.flatten,
               "compensate the program as it runs: loops and subroutine calls unrolled, expressions replaced by "
               "their values (a line that runs several times needs a correction for each run)");
  app.add_flag("--progress", args.progress, "print FILTER_PROGRESS=N lines on stderr (LinuxCNC filters)");
  app.add_option("--tolerance", args.tolerance, "mm: largest distance of the executed path from the nominal (0.001)")
      ->transform(tolerance_in_mm());
  app.add_flag("--exact", args.exact,
               "solve every point on the model to below 1 nm (slower); by default a point along a path may be "
               "placed where the model's error bound proves it within 8% of the tolerance");
  app.add_option("--decimals", args.decimals,
                 "decimals of the compensated linear coordinates, in the program's units (default: the program's "
                 "own, at least 4 in mm and 5 in inch; up to 2 more on a take-up whose play needs them)")
      ->check(CLI::Range(0, 9));
  app.add_option("--rotary-decimals", args.rotary_decimals,
                 "decimals of the compensated rotary coordinates, in degrees (default: the program's own, at least 5; up to 2 more on a take-up whose play needs them)")
      ->check(CLI::Range(0, 9));
  app.add_option("--sensor", args.sensors, "a temperature reading for the model's thermal terms: NAME=DEGC");
  app.add_option("--time", args.time, "s since the machine's warm-up started, for warm-up terms")
      ->check(seconds_since_warm_up());
  add_hold_option(app, args.holds);
  app.add_flag("-q,--quiet", args.quiet, "no summary line per program");
  app.add_flag("--json", args.json, "the summary of every program as JSON on stdout (docs/json.md)");
  add_program_options(app, args.program);
}

namespace {

struct Target {
  std::string input;
  std::string output;  ///< "-" for stdout
};

/// A program compensated: the job's report and, where the output was judged, the verdict
/// on it (its 'after' is the report's).
struct Compensated {
  compensate::JobReport report;
  std::optional<compensate::Verdict> verdict;
};

/// One line per program for stderr: what the machine's error was and what is left (none
/// with -q, or for the zero model), and whether the output passed.
std::string summary_line(const Target& t, const model::MachineModel& model, const Compensated& c,
                         const CompensateArgs& args) {
  if (args.quiet || model.terms.empty()) return "";
  const compensate::JobReport& r = c.report;
  const bool failed = c.verdict && !c.verdict->passed();
  return fmt::format(
      "{}: {} moves compensated ({} lines added) for '{}' at {} um: error before {:.2f} um, after {:.2f} um; "
      "largest correction {:.1f} um; orientation error left {:.1f} urad{}{}\n",
      t.input == "-" ? "<stdin>" : t.input, r.compensated_moves, r.added_lines, model.name, args.tolerance * 1000.0,
      r.max_error_before * 1000.0, r.max_error_after * 1000.0, r.max_correction * 1000.0,
      r.max_orientation_error * 1e6, r.held_axes.empty() ? "" : " (" + held_axes_text(model, r.held_axes) + ")",
      failed ? fmt::format("\n  {}: written, but NOT PASSED (below); check it before cutting (exit {})",
                           t.output == "-" ? "<stdout>" : t.output, kVerdictExitCode)
             : "");
}

/// Whether the job's output is judged: a model without error terms leaves the program as it
/// is, and verify() needs a chain to follow the tool through.
bool judged(const model::MachineModel& model) {
  return !model.terms.empty() && !(model.workpiece_chain.empty() && model.tool_chain.empty());
}

/// The job's share of a judged program's progress; verify() of its output takes the rest.
constexpr double kJobShare = 0.5;

/// An unnamed file the output goes to first when it goes to standard output: the verdict
/// reads the whole output back, which a pipe cannot give. Removed from the folder as soon
/// as made (read back through /proc/self/fd), so nothing is left behind, even on a kill.
class Spool {
 public:
  Spool() {
    std::error_code ec;
    fs::path folder = fs::temp_directory_path(ec);
    if (ec) folder = "/tmp";
    std::string path = (folder / "ccomp-out-XXXXXX").string();
    const int fd = ::mkstemp(path.data());
    if (fd < 0) throw Error(ErrorKind::io, "cannot create a temporary file for the output (TMPDIR)");
    ::unlink(path.c_str());
    file_ = ::fdopen(fd, "w+b");
    if (!file_) {
      ::close(fd);
      throw Error(ErrorKind::io, "cannot create a temporary file for the output (TMPDIR)");
    }
    path_ = fmt::format("/proc/self/fd/{}", fd);
  }
  Spool(const Spool&) = delete;
  Spool& operator=(const Spool&) = delete;
  ~Spool() { std::fclose(file_); }
  [[nodiscard]] std::FILE* file() const { return file_; }
  [[nodiscard]] const std::string& path() const { return path_; }
  /// Flushed, so that path() reads all of it.
  void flush() const {
    if (std::fflush(file_) != 0 || std::ferror(file_))
      throw Error(ErrorKind::io, "cannot write the output to a temporary file (TMPDIR full?)");
  }
  /// All of it onto `out` (write errors are the caller's to find: finish_standard_output()).
  void copy_to(std::FILE* out) const {
    std::rewind(file_);
    char buffer[1 << 16];
    for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, file_)) > 0;) std::fwrite(buffer, 1, n, out);
  }

 private:
  std::FILE* file_ = nullptr;
  std::string path_;
};

/// The trust on a program (compensate/trust.hpp), gathered by a pass of predict over it
/// before the job; none, and `why` says so, for standard input (read once, by the job) or
/// a program predict cannot run (the job then says what is wrong with it).
std::optional<compensate::ProgramTrust> gather_trust(const std::string& input, const model::MachineModel& model,
                                                     const std::optional<model::FitInformation>& info,
                                                     const compensate::JobOptions& job, const CompensateArgs& args,
                                                     std::string& why) {
  if (!info) return compensate::ProgramTrust{};
  if (input == "-") {
    why = "not gathered: the program came on standard input, which the job reads once";
    return std::nullopt;
  }
  try {
    compensate::CheckOptions o;
    o.interpreter = job.interpreter;
    o.conditions = model::conditions_for(model, job.sensors, args.time);
    const model::ForwardModel forward(model);
    return trust_on_file(input, forward, info, o);
  } catch (const Error& e) {
    why = "not gathered: " + e.message();
    return std::nullopt;
  }
}

/// The summary's second line: the trust on the program, the job's own residual against the
/// model (its "after") added to the model's uncertainty.
std::string trust_line(const model::MachineModel& model, const compensate::JobReport& r,
                       const std::optional<compensate::ProgramTrust>& trust, const std::string& why,
                       const CompensateArgs& args) {
  if (args.quiet || model.terms.empty()) return "";
  if (!trust) return fmt::format("  trust: {}\n", why);
  if (!trust->known) return fmt::format("  trust: {}\n", compensate::trust_text(*trust));
  compensate::ProgramTrust with_job = *trust;
  with_job.expected_after += r.max_error_after;
  with_job.after_bound += r.max_error_after;
  return fmt::format("  trust: {}\n", compensate::trust_text(with_job));
}

/// Keeps a copy of `input` as `<input><suffix>`, else numbered `.1`, `.2`... (a backup already
/// there is the user's: a second --in-place run with --force must not replace the original
/// with the compensated text). Written whole and synced before it gets its name, so a backup
/// is never partial, even after an interrupt or a power cut.
void keep_backup(const std::string& input, const std::string& suffix) {
  // The backup keeps the input's mode (a program others may not read stays so).
  std::error_code ec;
  const auto mode = fs::status(input, ec).permissions();
  OutputFile backup(input + suffix, ec ? std::optional<unsigned>{} : static_cast<unsigned>(mode) & 07777u);
  {
    std::ifstream in(input, std::ios::binary);
    if (!in) throw Error(ErrorKind::io, fmt::format("cannot read '{}' to back it up", input));
    char buffer[1 << 16];
    while (in.read(buffer, sizeof buffer) || in.gcount() > 0)
      std::fwrite(buffer, 1, static_cast<std::size_t>(in.gcount()), backup.file());
  }
  backup.finish();
  for (int k = 0; k < 1000; ++k)
    if (backup.link_as(k == 0 ? input + suffix : fmt::format("{}{}.{}", input, suffix, k))) return;
  throw Error(ErrorKind::io, fmt::format("'{}' has 999 numbered backups: clear some first", input));
}

/// `write()`'s result; the writer's "cannot write the output" (a full disk, `ulimit -f`)
/// names `output` instead: in a batch, which of the files.
template <typename Write>
auto name_the_output(const std::string& output, Write write) {
  constexpr std::string_view kUnnamed = "cannot write the output";
  try {
    return write();
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::io || !e.message().starts_with(kUnnamed)) throw;
    throw Error(ErrorKind::io, fmt::format("cannot write '{}'{}", output, e.message().substr(kUnnamed.size())),
                e.where(), e.source_line());
  }
}

/// The output at `written` judged as `ccomp verify` judges it (compensate/verdict.hpp): its
/// 'after' becomes the report's, so the summary and verify of the output agree.
std::optional<compensate::Verdict> judge_written(gcode::LineSource& input, const std::string& written,
                                                 const model::MachineModel& model,
                                                 const compensate::JobOptions& options, compensate::JobReport& r) {
  if (!judged(model)) return std::nullopt;
  gcode::LineSource original = input.another_reader();
  gcode::LineSource output = gcode::LineSource::open(written);
  std::function<void(double)> progress;
  if (options.progress) progress = [&options](double f) { options.progress(kJobShare + (1.0 - kJobShare) * f); };
  compensate::Verdict v = compensate::judge_job_output(original, output, model, options, r, progress);
  r.max_error_after = v.after.max;
  return v;
}

/// Writes through an OutputFile (a temporary beside the output, renamed into place only on
/// success), so a failed or interrupted run leaves the previous output as it was. The output
/// is judged before it gets its name.
Compensated compensate_one(const Target& t, const model::MachineModel& model, const compensate::JobOptions& options,
                           const CompensateArgs& args) {
  gcode::LineSource input = gcode::LineSource::open(t.input);
  compensate::JobOptions job = options;
  if (judged(model) && options.progress) job.progress = [&options](double f) { options.progress(kJobShare * f); };
  Compensated c;
  if (t.output == "-") {
    buffer_standard_output();
    if (!judged(model)) {
      c.report = compensate::run_program_job(input, stdout, model, job);
      return c;
    }
    const Spool spool;
    c.report = compensate::run_program_job(input, spool.file(), model, job);
    spool.flush();
    c.verdict = judge_written(input, spool.path(), model, options, c.report);
    spool.copy_to(stdout);
    return c;
  }
  OutputFile out(t.output);
  c.report = name_the_output(t.output, [&] {
    compensate::JobReport r = compensate::run_program_job(input, out.file(), model, job);
    if (std::fflush(out.file()) != 0) throw Error(ErrorKind::io, "cannot write the output");
    return r;
  });
  c.verdict = judge_written(input, out.temporary(), model, options, c.report);
  if (args.in_place) keep_backup(t.input, args.backup_suffix);
  // Keep the input's permissions on the output (post processors may mark files executable).
  std::error_code ec;
  if (t.input != "-") {
    const fs::file_status input_status = fs::status(t.input, ec);
    if (!ec) fs::permissions(out.temporary(), input_status.permissions(), ec);
  }
  out.commit();
  return c;
}

/// What became of one program, for --json.
struct Outcome {
  bool done = false;
  Compensated result;
  std::optional<compensate::ProgramTrust> trust;  ///< none: not gathered (standard input, or it failed)
  std::string no_trust;                            ///< why not
  int exit_code = 0;
  std::string error;
  /// Every warning printed for it: the file it names, the line, the message.
  struct Warning {
    std::string file;
    std::uint32_t line = 0;
    std::string message;
  };
  std::vector<Warning> warnings;
};

std::string outcomes_json(const std::vector<Target>& targets, const std::vector<Outcome>& outcomes,
                          const model::MachineModel& model, const CompensateArgs& args, int exit_code) {
  util::JsonWriter j;
  j.begin_object().field("command", "compensate").field("model", model.name).field("model_sha256", model.sha256);
  j.field("tolerance_um", args.tolerance * 1000.0).field("exit_code", exit_code).key("programs").begin_array();
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const Outcome& o = outcomes[i];
    const compensate::JobReport& r = o.result.report;
    j.begin_object().field("input", targets[i].input).field("output", targets[i].output);
    j.field("exit_code", o.exit_code);
    if (o.error.empty())
      j.key("error").null();
    else
      j.field("error", o.error);
    if (o.done) {
      j.field("moves_compensated", r.compensated_moves).field("lines_added", r.added_lines);
      j.field("error_before_um", r.max_error_before * 1000.0).field("error_after_um", r.max_error_after * 1000.0);
      j.field("largest_correction_um", r.max_correction * 1000.0);
      j.field("orientation_error_urad", r.max_orientation_error * 1e6);
      if (o.result.verdict)
        j.field("passed", o.result.verdict->passed());
      else
        j.key("passed").null();
      trust_fields(j, o.trust, r.max_error_after, o.no_trust);
      j.key("held_axes").begin_array();
      for (const Axis a : r.held_axes) j.value(std::string(1, letter(a)));
      j.end_array();
    }
    j.key("warnings").begin_array();
    for (const Outcome::Warning& w : o.warnings)
      j.begin_object().field("file", w.file).field("line", w.line).field("message", w.message).end_object();
    j.end_array();
    j.end_object();
  }
  j.end_array().end_object();
  return j.text();
}

/// Whether `input` is itself an --in-place backup: `<name><suffix>` or `<name><suffix>.N`.
bool is_backup(const std::string& input, const std::string& suffix) {
  if (suffix.empty()) return false;
  if (input.ends_with(suffix)) return true;
  const auto dot = input.rfind('.');
  if (dot == std::string::npos || dot + 1 == input.size()) return false;
  const std::string number = input.substr(dot + 1);
  return std::all_of(number.begin(), number.end(), [](char c) { return c >= '0' && c <= '9'; }) &&
         input.substr(0, dot).ends_with(suffix);
}

}  // namespace

int run_compensate(const CompensateArgs& args) {
  if (args.inputs.empty())
    throw Error(ErrorKind::usage, "no input program: ccomp in.nc -m machine.yaml -o out.nc (see --help)");
  if (args.model.empty()) throw Error(ErrorKind::usage, "no machine model: give one with -m machine.yaml");
  if (args.json && args.output == "-")
    throw Error(ErrorKind::usage,
                "--json writes the report on stdout: give the program -o FILE, --out-dir or --in-place");
  const int modes = !args.output.empty() + !args.out_dir.empty() + args.in_place;
  if (modes != 1)
    throw Error(ErrorKind::usage, "say where the output goes: exactly one of -o FILE, -o -, --out-dir DIR, --in-place");
  if (!args.output.empty() && args.inputs.size() > 1)
    throw Error(ErrorKind::usage, "-o takes one input; use --out-dir or --in-place for several");
  if (args.in_place && std::count(args.inputs.begin(), args.inputs.end(), "-"))
    throw Error(ErrorKind::usage, "--in-place cannot replace standard input");

  const model::MachineModel model = with_holds(model::load_machine_model(args.model), args.holds);
  const std::optional<model::FitInformation> fit_information = model::load_fit_information(model);
  compensate::JobOptions options;
  options.interpreter = interpreter_options(args.program, model.dialect, model.work_offsets);
  options.force = args.force;
  options.expand_cycles = args.expand_cycles;
  options.resolve_cutter_comp = args.resolve_cutter_comp;
  options.flatten = args.flatten;
  options.tolerance = args.tolerance;
  options.exact = args.exact;
  options.decimals = args.decimals;
  options.rotary_decimals = args.rotary_decimals;
  options.time = args.time;
  options.sensors = model::parse_sensor_readings(args.sensors);

  // Nothing of the user's is overwritten: no output is an input, the model or the tool
  // table, or a link, device or FIFO; no two outputs are one file.
  std::vector<Target> targets;
  std::vector<std::string> outputs;
  for (const std::string& in : args.inputs) {
    Target t{in, args.output};
    std::vector<RunInput> kept{{"the machine model", args.model}, {"the tool table", args.program.tool_table}};
    for (const std::string& other : args.inputs)
      if (!(args.in_place && other == in)) kept.push_back({"the program", other});
    if (args.in_place) {
      t.output = in;
      if (is_backup(in, args.backup_suffix))
        throw Error(ErrorKind::usage,
                    fmt::format("'{}' is an --in-place backup (it ends in '{}'): compensate a copy under another name",
                                in, args.backup_suffix));
    }
    if (!args.out_dir.empty()) {
      if (in == "-") throw Error(ErrorKind::usage, "--out-dir needs file inputs, not '-'");
      std::error_code ec;
      fs::create_directories(args.out_dir, ec);
      if (ec) throw Error(ErrorKind::io, fmt::format("cannot create the folder '{}': {}", args.out_dir, ec.message()));
      t.output = (fs::path(args.out_dir) / fs::path(in).filename()).string();
    }
    // A subroutine file the run may read through --sub-path (LinuxCNC treats every .ngc
    // there as callable): the output's name in each such folder, refused if it is that file.
    if (!args.in_place && t.output != "-" && fs::path(t.output).extension() == ".ngc")
      for (const std::string& folder : args.program.sub_path)
        kept.push_back({"a subroutine file on --sub-path", (fs::path(folder) / fs::path(t.output).filename()).string()});
    check_output(t.output, kept, args.in_place ? "--in-place" : args.out_dir.empty() ? "-o" : "--out-dir");
    outputs.push_back(t.output);
    targets.push_back(t);
  }
  check_distinct_outputs(outputs);

  std::mutex report, warned;
  std::vector<Outcome> outcomes(targets.size());
  std::atomic<int> worst{0};
  std::atomic<std::size_t> next{0};
  // Progress: LinuxCNC's FILTER_PROGRESS lines when asked, else a bar at a terminal.
  std::vector<std::uint64_t> sizes;
  for (const Target& t : targets) {
    std::error_code ec;
    sizes.push_back(t.input == "-" ? 0 : static_cast<std::uint64_t>(fs::file_size(t.input, ec)));
  }
  SharedProgress whole(sizes);
  ProgressBar bar(targets.size() == 1 ? targets[0].input : fmt::format("{} programs", targets.size()),
                  !args.progress && !args.quiet && !args.json && stderr_is_terminal());
  std::vector<std::unique_ptr<FilterProgress>> filter;
  for (const Target& t : targets)
    filter.push_back(std::make_unique<FilterProgress>(targets.size() > 1 ? t.input + ": " : std::string()));
  auto worker = [&]() {
    for (std::size_t i = next++; i < targets.size(); i = next++) {
      compensate::JobOptions mine = options;
      const std::string name = targets[i].input == "-" ? "<stdin>" : targets[i].input;
      auto warn = [&bar, &warned, &outcomes, i](const std::string& file, std::uint32_t line,
                                                 const std::string& message) {
        // (line 0: the whole program, as a tolerance coarser than its error)
        bar.print_above(line == 0 ? fmt::format("{}: warning: {}\n", file, message)
                                  : fmt::format("{}:{}: warning: {}\n", file, line, message));
        std::lock_guard lock(warned);
        outcomes[i].warnings.push_back({file, line, message});
      };
      mine.warning = [&warn, name](const std::string& message, std::uint32_t line) { warn(name, line, message); };
      if (args.progress)
        mine.progress = [&filter, i](double fraction) { filter[i]->update(fraction); };
      else
        mine.progress = [&bar, &whole, i](double fraction) { bar.update(whole.update(i, fraction)); };
      try {
        // Before the job: --in-place replaces the program.
        std::string no_trust;
        const std::optional<compensate::ProgramTrust> trust =
            gather_trust(targets[i].input, model, fit_information, options, args, no_trust);
        const Compensated c = compensate_one(targets[i], model, mine, args);
        int code = 0;
        {
          std::lock_guard lock(report);
          outcomes[i].done = true, outcomes[i].result = c;
          outcomes[i].trust = trust, outcomes[i].no_trust = no_trust;
          if (!args.json)
            bar.print_above(summary_line(targets[i], model, c, args) + trust_line(model, c.report, trust, no_trust, args));
        }
        // Written, but short of what was asked: said at the output's worst line, and exit 1.
        if (c.verdict && !c.verdict->passed()) {
          code = kVerdictExitCode;
          const std::string output = targets[i].output == "-" ? "<stdout>" : targets[i].output;
          for (const std::string& failure : c.verdict->failures())
            warn(output, c.verdict->after.worst_line,
                 failure + fmt::format("; the output is written: check it before cutting (exit {})", code));
        }
        std::lock_guard lock(report);
        outcomes[i].exit_code = code;
        int seen = worst.load();
        while (code > seen && !worst.compare_exchange_weak(seen, code)) {
        }
      } catch (const std::exception& caught) {
        // Anything but a ccomp::Error is a bug in ccomp; it must not end the other programs.
        const auto* known = dynamic_cast<const Error*>(&caught);
        const Error e = known ? *known : Error(ErrorKind::internal, caught.what());
        std::lock_guard lock(report);
        bar.print_above(format_error(e) + "\n");
        int code = exit_code(e.kind());
        outcomes[i].exit_code = code, outcomes[i].error = format_error(e);
        int seen = worst.load();
        while (code > seen && !worst.compare_exchange_weak(seen, code)) {
        }
      }
    }
  };
  const int threads = std::clamp(args.jobs, 1, static_cast<int>(targets.size()));
  options.threads = args.threads > 0 ? args.threads : util::hardware_threads() >= 2 * threads ? 2 : 1;
  compensate::validate(options);
  // A sensor mistake is refused here, once and before any program is read, as predict and
  // verify refuse it; the job builds the same conditions again for itself.
  (void)model::conditions_for(model, options.sensors, args.time);
  std::vector<std::thread> pool;
  // A thread the system will not give (a low `ulimit -u`) means fewer workers, not an abort:
  // the programs are shared out among those there are (this one at least).
  for (int i = 1; i < threads; ++i) {
    try {
      pool.emplace_back(worker);
    } catch (const std::system_error&) {
      break;
    }
  }
  worker();
  for (auto& t : pool) t.join();
  bar.clear();
  if (args.json) fmt::print("{}", outcomes_json(targets, outcomes, model, args, worst.load()));
  return worst.load();
}

}  // namespace ccomp::cli
