#include "ccomp/gcode/trace.hpp"

#include <algorithm>
#include <cstdio>

#include "ccomp/gcode/flatten.hpp"
#include "commands.hpp"

namespace ccomp::cli {

CLI::App* add_trace(CLI::App& app, TraceArgs& args) {
  CLI::App* cmd =
      app.add_subcommand("trace", "print what the interpreter does, in the canonical format of LinuxCNC's rs274 -g");
  cmd->add_option("input", args.input, "G-code program ('-' for standard input)")->required();
  add_program_options(*cmd, args.program);
  return cmd;
}

CLI::App* add_flatten(CLI::App& app, TraceArgs& args) {
  CLI::App* cmd = app.add_subcommand(
      "flatten", "print the program as it runs: loops and subroutine calls unrolled, values in place of expressions");
  cmd->add_option("input", args.input, "G-code program ('-' for standard input)")->required();
  add_program_options(*cmd, args.program);
  return cmd;
}

int run_flatten(const TraceArgs& args) {
  gcode::LineSource source = gcode::LineSource::open(args.input);
  std::setvbuf(stdout, nullptr, _IOFBF, 1 << 16);
  (void)gcode::flatten(source, stdout, interpreter_options(args.program, ""));
  return 0;
}

int run_trace(const TraceArgs& args) {
  gcode::LineSource source = gcode::LineSource::open(args.input);
  gcode::InterpreterOptions options = interpreter_options(args.program, "");
  // A trace prints every run of a loop, as flatten does: the same cap on what it writes.
  if (args.program.max_blocks == 0) options.max_blocks = std::min(options.max_blocks, gcode::kFlattenMaxBlocks);
  gcode::Interpreter interpreter(options);
  std::setvbuf(stdout, nullptr, _IOFBF, 1 << 16);
  gcode::TracePrinter printer(stdout);
  printer.set_file_name(source.name());
  interpreter.run(source, printer);
  std::fflush(stdout);
  return 0;
}

}  // namespace ccomp::cli
