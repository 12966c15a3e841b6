// What the job writes must run on the control. LinuxCNC's own interpreter, rs274, reads
// every program of its suite that it accepts as written, compensated (--flatten) for two
// sample machines, and with --expand-cycles: it must accept the output too. This caught
// chords and split moves under cutter radius compensation, which it refuses.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <utility>

#include "linuxcnc_suite.hpp"
#include "rs274_oracle.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

namespace fs = std::filesystem;

class Rs274AcceptsOutput : public ::testing::TestWithParam<SuiteProgram> {};

TEST_P(Rs274AcceptsOutput, OnTwoSampleMachinesAndWithCyclesExpanded) {
  if (!have_rs274()) GTEST_SKIP() << "rs274 not found at " << rs274() << ": run tools/rs274/fetch.sh build/rs274";
  const fs::path path = fs::path(corpus_dir()) / "linuxcnc" / GetParam().path;
  if (GetParam().path.find("12-M99-endless-main-program") != std::string::npos)
    GTEST_SKIP() << "M99 in a main program: ccomp ends there (out of scope, tests/gcode/linuxcnc_suite_test.cpp)";
  if (GetParam().path.find("endless-loop") != std::string::npos)
    GTEST_SKIP() << "rs274 loops for ever on it (what the suite tests)";
  const std::string dir = temp_dir("rs274_accepts");
  std::string tools = (path.parent_path() / "test.tbl").string();
  if (!fs::exists(tools)) write_file(tools = dir + "/tools.tbl", "T1 P1 Z1 D0.25 ;\n");
  if (const TraceResult original = rs274_trace(path.string(), tools); original.error)
    GTEST_SKIP() << "rs274 refuses the original: " << original.error->what();
  int compensated = 0;
  const std::pair<const char*, const char*> runs[] = {
      {"vmc-xyz", ""}, {"hmc-xyzb-geometric", ""}, {"vmc-xyz", " --expand-cycles"}};
  for (const auto& [machine, options] : runs) {
    const std::string out = dir + "/" + machine + ".ngc";
    const CommandResult job =
        run_command("cd " + shell_quote(path.parent_path().string()) + " && " + shell_quote(ccomp_binary()) + " " +
                    shell_quote(path.filename().string()) + " -m " +
                    shell_quote(source_dir() + "/samples/machines/" + machine + ".yaml") + " --flatten" + options +
                    " -q -o " + shell_quote(out));
    if (job.exit_code != 0) continue;  // refused (an axis the machine lacks, its limits): nothing written
    ++compensated;
    const TraceResult theirs = rs274_trace(out, tools);
    EXPECT_FALSE(theirs.error) << machine << options << ": " << theirs.error->what() << "\n" << read_file(out);
  }
  if (compensated == 0) GTEST_SKIP() << "neither machine compensates it";
}

INSTANTIATE_TEST_SUITE_P(Corpus, Rs274AcceptsOutput, ::testing::ValuesIn(suite_programs()), suite_test_name);

}  // namespace
}  // namespace ccomp::test
