// Progress as its readers see it: LinuxCNC reads FILTER_PROGRESS lines (whole percents,
// growing, each once); a person at a terminal sees a bar redrawn in place (run here under
// a pseudo-terminal by script(1)); a pipe gets neither.
#include <gtest/gtest.h>

#include <map>
#include <regex>
#include <sstream>

#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

std::string model() {
  return shell_quote(source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml");
}

/// A program of `n` feed moves, and a loop that runs back over its lines.
std::string long_program(const std::string& dir, int n, bool loop) {
  std::ostringstream p;
  p << "G21 G90 G17\nG0 X0 Y0 Z5\nG1 Z0 F500\n";
  if (loop) p << "#1=0\no100 while [#1 lt 3]\n";
  for (int i = 0; i < n; ++i) p << "G1 X" << (i % 100) << " Y" << (i % 37) << "\n";
  if (loop) p << "#1=[#1+1]\no100 endwhile\n";
  p << "M2\n";
  const std::string path = dir + (loop ? "/loop.ngc" : "/long.ngc");
  write_file(path, p.str());
  return path;
}

/// The FILTER_PROGRESS values in `err`, per prefix ("" when unnamed).
std::map<std::string, std::vector<int>> filter_progress(const std::string& err) {
  std::map<std::string, std::vector<int>> out;
  const std::regex line("^(.*?)FILTER_PROGRESS=(\\d+)$");
  std::istringstream in(err);
  std::smatch m;
  for (std::string l; std::getline(in, l);)
    if (std::regex_match(l, m, line)) out[m[1]].push_back(std::stoi(m[2]));
  return out;
}

TEST(Progress, FilterProgressGivesEveryPercentOnceInOrder) {
  const std::string dir = temp_dir("progress_filter");
  const CommandResult r = run_command(ccomp() + " " + shell_quote(long_program(dir, 20000, false)) + " -m " + model() +
                                      " -o " + shell_quote(dir + "/out.ngc") + " --progress");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto seen = filter_progress(r.err);
  ASSERT_EQ(seen.size(), 1U);
  const std::vector<int>& p = seen.at("");
  ASSERT_EQ(p.size(), 101U);
  for (int k = 0; k <= 100; ++k) EXPECT_EQ(p[static_cast<std::size_t>(k)], k);
}

TEST(Progress, FilterProgressNeverGoesBackInALoop) {
  const std::string dir = temp_dir("progress_loop");
  const CommandResult r = run_command(ccomp() + " " + shell_quote(long_program(dir, 3000, true)) + " -m " + model() +
                                      " -o - --flatten --progress");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto seen = filter_progress(r.err);
  const std::vector<int>& p = seen.at("");
  ASSERT_GE(p.size(), 50U);
  for (std::size_t k = 1; k < p.size(); ++k) EXPECT_GT(p[k], p[k - 1]) << "at " << k;
  EXPECT_EQ(p.back(), 100);
}

TEST(Progress, SeveralProgramsAtOnceNameTheirLines) {
  const std::string dir = temp_dir("progress_jobs");
  const std::string a = long_program(dir, 5000, false), b = long_program(dir, 3000, true);
  const CommandResult r = run_command(ccomp() + " " + shell_quote(a) + " " + shell_quote(b) + " -m " + model() +
                                      " --out-dir " + shell_quote(dir + "/out") + " -j 2 --flatten --progress");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto seen = filter_progress(r.err);
  ASSERT_EQ(seen.size(), 2U) << r.err;
  for (const auto& [prefix, p] : seen) {
    EXPECT_TRUE(prefix == a + ": " || prefix == b + ": ") << prefix;
    for (std::size_t k = 1; k < p.size(); ++k) EXPECT_GT(p[k], p[k - 1]);
    EXPECT_EQ(p.back(), 100);
  }
}

/// `command` run with its stderr on a pseudo-terminal (script(1)); what the terminal got.
std::string on_terminal(const std::string& command) {
  const CommandResult r = run_command("script -qec " + shell_quote(command + " 2>&1 >/dev/null") + " /dev/null");
  return r.out;
}

TEST(Progress, ATerminalGetsABarThatIsClearedAtTheEnd) {
  const std::string dir = temp_dir("progress_bar");
  const std::string program = long_program(dir, 20000, false);
  const std::string bar =
      on_terminal(ccomp() + " " + shell_quote(program) + " -m " + model() + " -o " + shell_quote(dir + "/out.ngc"));
  EXPECT_NE(bar.find("\r\033[K"), std::string::npos) << bar;
  EXPECT_NE(bar.find("] 100%"), std::string::npos) << bar;
  // The bar's line is cleared before the summary line is written.
  const std::size_t summary = bar.find("moves compensated");
  ASSERT_NE(summary, std::string::npos) << bar;
  EXPECT_EQ(bar.rfind("\r\033[K", summary), bar.rfind('\r', summary)) << bar;
  const std::string small = temp_dir("progress_bar_verify");
  const std::string short_program = long_program(small, 1000, false);
  ASSERT_EQ(run_command(ccomp() + " " + shell_quote(short_program) + " -m " + model() + " -o " +
                        shell_quote(small + "/out.ngc") + " -q")
                .exit_code,
            0);
  const std::string verify = on_terminal(ccomp() + " verify " + shell_quote(short_program) + " " +
                                         shell_quote(small + "/out.ngc") + " -m " + model());
  EXPECT_NE(verify.find("] 100%"), std::string::npos) << verify;
}

TEST(Progress, APipeGetsNoBar) {
  const std::string dir = temp_dir("progress_pipe");
  const std::string program = long_program(dir, 20000, false);
  const CommandResult r =
      run_command(ccomp() + " " + shell_quote(program) + " -m " + model() + " -o " + shell_quote(dir + "/out.ngc"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find('\r'), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("FILTER_PROGRESS"), std::string::npos);
  EXPECT_NE(r.err.find("moves compensated"), std::string::npos);  // the summary line stays
}

}  // namespace
}  // namespace ccomp::test

namespace ccomp::test {
namespace {

TEST(Progress, AJsonRunDrawsNoBarEvenAtATerminal) {
  const std::string dir = temp_dir("progress_json");
  const std::string program = long_program(dir, 5000, false);
  const std::string terminal = on_terminal(ccomp() + " " + shell_quote(program) + " -m " + model() + " -o " +
                                           shell_quote(dir + "/out.ngc") + " --json");
  EXPECT_EQ(terminal.find('\r'), std::string::npos) << terminal;
  EXPECT_EQ(terminal.find('%'), std::string::npos) << terminal;
}

}  // namespace
}  // namespace ccomp::test
