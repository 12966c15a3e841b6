#include "ccomp/gcode/trace.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <memory>

#include "ccomp/error.hpp"
#include "ccomp/gcode/flatten.hpp"
#include "ccomp/util/json.hpp"
#include "commands.hpp"
#include "output_file.hpp"

namespace ccomp::cli {

CLI::App* add_trace(CLI::App& app, TraceArgs& args) {
  CLI::App* cmd =
      app.add_subcommand("trace", "print what the interpreter does, in the canonical format of LinuxCNC's rs274 -g");
  cmd->add_option("input", args.input, "G-code program ('-' for standard input)")->required();
  cmd->add_flag("--json", args.json, "JSON Lines: one object per call (docs/json.md)");
  add_program_options(*cmd, args.program);
  return cmd;
}

CLI::App* add_flatten(CLI::App& app, TraceArgs& args) {
  CLI::App* cmd = app.add_subcommand(
      "flatten", "print the program as it runs: loops and subroutine calls unrolled, values in place of expressions");
  cmd->add_option("input", args.input, "G-code program ('-' for standard input)")->required();
  cmd->add_flag("--json", args.json,
                "JSON Lines: one object per line written, with the file and line it came from (docs/json.md)");
  add_program_options(*cmd, args.program);
  return cmd;
}

namespace {

/// The flattened program spooled in `spool`, as JSON Lines with each line's origin.
void print_flattened_json(std::FILE* spool, const gcode::LineOrigins& origins) {
  std::rewind(spool);
  std::string line;
  std::uint32_t number = 0;
  for (int c = std::fgetc(spool);; c = std::fgetc(spool)) {
    if (c != EOF && c != '\n') {
      line.push_back(static_cast<char>(c));
      continue;
    }
    if (c == EOF && line.empty()) break;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const SourceLocation from = origins.at(++number);
    util::JsonWriter j;
    j.begin_object().field("line", number).field("text", line).field("file", from.file).field("source_line", from.line);
    fmt::print("{}", j.end_object().text());
    line.clear();
    if (c == EOF) break;
  }
}

/// The interpreter of trace and flatten: no machine model, so where program zero lies
/// changes nothing they print.
gcode::InterpreterOptions modelless_options(const ProgramArgs& args) {
  gcode::InterpreterOptions o = interpreter_options(args, "");
  o.origin_matters = false;
  return o;
}

}  // namespace

int run_flatten(const TraceArgs& args) {
  gcode::LineSource source = gcode::LineSource::open(args.input);
  buffer_standard_output();
  if (!args.json) {
    (void)gcode::flatten(source, stdout, modelless_options(args.program));
    return 0;
  }
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> spool(std::tmpfile(), &std::fclose);
  if (!spool) throw Error(ErrorKind::io, "cannot make a temporary file for --json");
  print_flattened_json(spool.get(), gcode::flatten(source, spool.get(), modelless_options(args.program)));
  return 0;
}

int run_trace(const TraceArgs& args) {
  gcode::LineSource source = gcode::LineSource::open(args.input);
  gcode::InterpreterOptions options = modelless_options(args.program);
  // A trace prints every run of a loop, as flatten does: the same cap on what it writes.
  if (args.program.max_blocks == 0) options.max_blocks = std::min(options.max_blocks, gcode::kFlattenMaxBlocks);
  gcode::Interpreter interpreter(options);
  buffer_standard_output();
  gcode::TracePrinter printer(stdout);
  printer.set_file_name(source.name());
  printer.set_json(args.json);
  interpreter.run(source, printer);
  std::fflush(stdout);
  return 0;
}

}  // namespace ccomp::cli
