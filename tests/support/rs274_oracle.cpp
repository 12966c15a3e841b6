#include "rs274_oracle.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "ccomp/error.hpp"

namespace ccomp::test {

namespace fs = std::filesystem;

std::string rs274() {
  if (const char* env = std::getenv("CCOMP_RS274")) return env;
  return CCOMP_RS274_DEFAULT;
}

bool have_rs274() {
  return fs::exists(rs274());
}

TraceResult rs274_trace(const std::string& program, const std::string& tool_table) {
  // rs274 reads and writes rs274ngc.var in its working folder, so it gets one of its own;
  // and two rs274 at once crash or lose tools (bus error, "tool 2 not found": LinuxCNC's
  // tool data is shared machine-wide), so every run on this machine (parallel test
  // processes, another checkout's tests, tools/rs274-diff.sh) takes turns on one lock. A
  // program that loops for ever (the suite has some) is stopped after 60 s, as an error.
  const std::string cwd = temp_dir("rs274_cwd");
  const std::string lock = (fs::temp_directory_path() / "ccomp-rs274.lock").string();
  const CommandResult r =
      run_command("cd " + shell_quote(cwd) + " && flock " + shell_quote(lock) + " timeout 60 " + shell_quote(rs274()) +
                  " -t " + shell_quote(tool_table) + " -g " + shell_quote(program));
  // timeout's exit code: a program that loops for ever is the caller's to skip, not an error
  // of the program's to report.
  EXPECT_NE(r.exit_code, 124) << "rs274 ran out of time on " << program;
  TraceResult t;
  std::istringstream in(r.out);
  for (std::string line; std::getline(in, line);) t.lines.push_back(line);
  if (r.exit_code != 0)
    t.error = Error(ErrorKind::program, "rs274 exited " + std::to_string(r.exit_code) + ": " +
                                            r.out.substr(r.out.rfind('\n', r.out.size() - 2) + 1) + r.err);
  return t;
}

}  // namespace ccomp::test
