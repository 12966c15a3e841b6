// The ccomp command line: a thin layer over the library. Each subcommand lives in its own
// file under src/cli/; this one wires them up and maps errors to exit codes.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <optional>
#include <system_error>

#include "ccomp/error.hpp"
#include "ccomp/version.hpp"
#include "command_line.hpp"
#include "commands.hpp"
#include "output_file.hpp"

namespace {

constexpr const char* kExitCodes = R"(Exit codes:
  0   success (warnings, if any, are on stderr)
  1   the main job wrote its output, but verify's measure of it is over the tolerance,
      worse than the program as written, or leaves a cut out (said in the summary)
  2   usage: bad command line (a reading or --time the model needs included), or an
      output that would replace an input, a link, a device or another output
  3   program error: the G-code is wrong (file:line:column on stderr)
  4   unsupported: valid G-code that ccomp does not handle (a tool-centre-point
      program: G43.4, M428, M128)
  5   model error: the machine model file is wrong
  6   I/O error: a file could not be read or written (standard output included)
  7   refused: compensating would be unsafe (see the message); verify: the output is
      off the path by more than the tolerance (the tool's direction by more than the
      angular tolerance), or leaves a cut out
  8   data error: a measurement file is wrong (file:row:column on stderr), or the data
      cannot support the fit (too few readings, a value far beyond its scale: not written)
  70  internal error: a bug in ccomp, please report it
  128+N  stopped by signal N (130 Ctrl-C, 143 SIGTERM, 129 SIGHUP, as the shell reports
      it): the temporary output is removed, an earlier output left as it was
With several inputs the exit code is the highest of the files' codes.)";

/// Every option of every command takes one value per occurrence; a repeated option repeats
/// its flag (--sensor a=1 --sensor b=2). CLI11 lets a vector option take every word up to the
/// next option, so a path that a host appends after the configured options (LinuxCNC's
/// [FILTER] entry: `ccomp -m m.yaml -o - --sensor s=20 <path>`) became one more reading and
/// the run had no input program. Positionals (the input programs) still take all.
void one_value_per_occurrence(CLI::App& app) {
  for (CLI::Option* option : app.get_options()) {
    if (option->get_positional()) continue;
    option->allow_extra_args(false);
    // --help would show a repeatable option as `TEXT ...`, several values after one flag.
    if (option->get_expected_max() == CLI::detail::expected_max_vector_size)
      option->option_text(option->get_type_name() + " (repeatable)");
  }
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) one_value_per_occurrence(*sub);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "ccomp: rewrites G-code so a real machine cuts what the program means.\n"
      "  ccomp in.nc -m machine.yaml -o out.nc"};
  app.footer(kExitCodes);
  app.set_version_flag("--version", std::string("ccomp ") + ccomp::kVersion);
  app.require_subcommand(0, 1);
  ccomp::cli::CompensateArgs compensate;
  ccomp::cli::add_compensate(app, compensate);
  ccomp::cli::TraceArgs trace, flatten;
  CLI::App* trace_cmd = ccomp::cli::add_trace(app, trace);
  CLI::App* flatten_cmd = ccomp::cli::add_flatten(app, flatten);
  ccomp::cli::CheckArgs predict, verify;
  CLI::App* predict_cmd = ccomp::cli::add_predict(app, predict);
  CLI::App* verify_cmd = ccomp::cli::add_verify(app, verify);
  ccomp::cli::IdentifyArgs fit, check, simulate, positioning, nine_line, import;
  CLI::App* fit_cmd = ccomp::cli::add_fit(app, fit);
  CLI::App* check_cmd = ccomp::cli::add_check(app, check);
  CLI::App* simulate_cmd = ccomp::cli::add_simulate(app, simulate);
  CLI::App* positioning_cmd = ccomp::cli::add_positioning(app, positioning);
  CLI::App* nine_line_cmd = ccomp::cli::add_nine_line(app, nine_line);
  CLI::App* import_cmd = ccomp::cli::add_import(app, import);
  ccomp::cli::PlanArgs plan;
  CLI::App* plan_cmd = ccomp::cli::add_plan(app, plan);
  ccomp::cli::ExportArgs export_args;
  CLI::App* export_cmd = ccomp::cli::add_export(app, export_args);
  one_value_per_occurrence(app);
  std::signal(SIGPIPE, SIG_IGN);  // a closed pipe is a write error (exit 6), --help's too
  ccomp::cli::remember_command_line(argc, argv);
  try {
    app.parse(argc, argv);
  } catch (const ccomp::Error& e) {  // a quantity refused at its place on the line
    fmt::print(stderr, "{}\n", ccomp::format_error(e));
    return ccomp::exit_code(e.kind());
  } catch (const CLI::ParseError& e) {
    if (const auto mistake = e.get_exit_code() == 0 ? std::nullopt : ccomp::cli::mistyped(app, argc, argv)) {
      fmt::print(stderr, "{}\n", ccomp::format_error(*mistake));
      return ccomp::exit_code(ccomp::ErrorKind::usage);
    }
    const int code = app.exit(e);
    if (code != 0) return ccomp::exit_code(ccomp::ErrorKind::usage);
    // --help and --version to a full disk or a closed pipe: lost text is an I/O error.
    std::cout.flush();
    if (!std::cout || std::fflush(stdout) != 0 || std::ferror(stdout)) {
      fmt::print(stderr, "error: cannot write standard output: {}\n", std::strerror(errno));
      return ccomp::exit_code(ccomp::ErrorKind::io);
    }
    return 0;
  }
  ccomp::cli::remove_temporaries_on_interrupt();
  // What a command printed must have reached its reader: a full disk or a closed pipe on
  // standard output is a write error (exit 6), not a success.
  auto finished = [](int code) {
    ccomp::cli::finish_standard_output();
    return code;
  };
  try {
    if (trace_cmd->parsed()) return finished(ccomp::cli::run_trace(trace));
    if (flatten_cmd->parsed()) return finished(ccomp::cli::run_flatten(flatten));
    if (predict_cmd->parsed()) return finished(ccomp::cli::run_predict(predict));
    if (verify_cmd->parsed()) return finished(ccomp::cli::run_verify(verify));
    if (fit_cmd->parsed()) return finished(ccomp::cli::run_fit(fit));
    if (check_cmd->parsed()) return finished(ccomp::cli::run_check(check));
    if (simulate_cmd->parsed()) return finished(ccomp::cli::run_simulate(simulate));
    if (positioning_cmd->parsed()) return finished(ccomp::cli::run_positioning(positioning));
    if (nine_line_cmd->parsed()) return finished(ccomp::cli::run_nine_line(nine_line));
    if (import_cmd->parsed()) return finished(ccomp::cli::run_import(import));
    if (plan_cmd->parsed()) return finished(ccomp::cli::run_plan(plan));
    if (export_cmd->parsed()) return finished(ccomp::cli::run_export(export_args));
    ccomp::cli::refuse_mistyped_command(app, compensate.inputs);
    return finished(ccomp::cli::run_compensate(compensate));
  } catch (const ccomp::Error& e) {
    fmt::print(stderr, "{}\n", ccomp::format_error(e));
    return ccomp::exit_code(e.kind());
  } catch (const std::system_error& e) {
    // fmt's writes report a full disk or a closed pipe so: an I/O error, not a bug.
    fmt::print(stderr, "error: {}\n", e.what());
    return ccomp::exit_code(ccomp::ErrorKind::io);
  } catch (const std::exception& e) {
    fmt::print(stderr, "internal error: {}\n", e.what());
    return ccomp::exit_code(ccomp::ErrorKind::internal);
  }
}
