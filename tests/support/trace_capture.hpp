#pragma once
// Test support: run the interpreter on a program and capture what `ccomp trace` prints,
// and compare canonical motion calls the way LinuxCNC's suite needs (numbers to 1e-4).
#include <optional>
#include <string>
#include <vector>

#include "ccomp/error.hpp"
#include "ccomp/gcode/interpreter.hpp"

namespace ccomp::test {

struct TraceResult {
  std::vector<std::string> lines;  ///< the trace, one call a line
  std::optional<Error> error;      ///< set when the interpreter refused the program
  std::vector<std::string> warnings;
};

TraceResult trace_file(const std::string& path, const gcode::InterpreterOptions& options = {});
TraceResult trace_text(const std::string& program, const gcode::InterpreterOptions& options = {});

/// A motion as the interpreter reported it, with the offsets in force then.
struct RecordedMotion {
  gcode::Motion motion;
  gcode::Offsets offsets;
};

struct RunResult {
  std::vector<RecordedMotion> motions;
  std::optional<Error> error;
  std::vector<std::string> warnings;
  std::vector<std::string> messages;  ///< (DEBUG,...) and (MSG,...) texts
};

/// Runs a program and records its motions (machine frame, mm and deg).
RunResult run_program(const std::string& program, const gcode::InterpreterOptions& options = {});
/// The value of a G-code expression, through `G0 X[expr]` in G21 (throws on error).
double evaluate(const std::string& expression);

/// The motion calls (STRAIGHT_TRAVERSE, STRAIGHT_FEED, ARC_FEED, STRAIGHT_PROBE) and the
/// MESSAGE calls of (DEBUG,...) and (MSG,...) of a trace or of an `expected` file, as
/// "NAME(args)". Messages show parameter values, so they check expressions and subroutines.
std::vector<std::string> motion_calls(const std::vector<std::string>& lines);

/// What LinuxCNC's suite observes of a trace: motion and MESSAGE calls, and the plain lines
/// that (PRINT,...) writes, as "PRINT text". With `awk`, lines are first transformed as the
/// suite's `awk '{$1=""; print}'` does (first field dropped, blanks collapsed).
std::vector<std::string> observable(const std::vector<std::string>& lines, bool awk);
/// Every call of a trace named `name`, as its argument text.
std::vector<std::string> calls_named(const std::vector<std::string>& lines, const std::string& name);

/// Compares two lists of calls: same names, same numbers within `tolerance`. On mismatch
/// returns a description of the first difference.
std::optional<std::string> compare_calls(const std::vector<std::string>& actual,
                                         const std::vector<std::string>& expected, double tolerance = 1e-4);

std::vector<std::string> read_lines(const std::string& path);
std::string read_file(const std::string& path);
void write_file(const std::string& path, const std::string& text);

/// Runs a shell command; returns its exit code, stdout and stderr.
struct CommandResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};
CommandResult run_command(const std::string& command, const std::string& stdin_text = "");
/// Single-quotes a string for the shell.
std::string shell_quote(const std::string& s);

/// Paths the build gives the tests.
std::string source_dir();
/// Real programs and LinuxCNC's test suite (tests/data/corpus, from ../shared/corpus).
std::string corpus_dir();
std::string ccomp_binary();
/// The ccomp binary, quoted for a shell command.
std::string ccomp();
/// A file under samples/ (path relative to it), quoted for a shell command.
std::string sample(const std::string& path);
/// A fresh empty folder under the build's temp area, private to this test process.
std::string temp_dir(const std::string& name);

}  // namespace ccomp::test
