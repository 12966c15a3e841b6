// LinuxCNC's own interpreter test suite (tests/data/corpus/linuxcnc, from LinuxCNC commit
// 5c41560e, tests/interp and tests/ccomp) is ccomp's reference for reading G-code: every
// test a milling dialect covers must give the same motion calls (STRAIGHT_TRAVERSE,
// STRAIGHT_FEED, ARC_FEED, STRAIGHT_PROBE, to 1e-4), and every program LinuxCNC rejects
// must be rejected. What is out of scope is listed with its reason in the cases' table
// (tests/support/linuxcnc_suite.cpp).
#include "linuxcnc_suite.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "ccomp/gcode/dialect.hpp"
#include "ccomp/gcode/tool_table.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

namespace fs = std::filesystem;

class LinuxcncSuite : public ::testing::TestWithParam<SuiteCase> {};

gcode::InterpreterOptions options_for(const SuiteCase& c, const fs::path& folder) {
  gcode::InterpreterOptions o;
  o.machine_units = gcode::Units::inch;  // rs274 run alone, as the suite ran it
  if (*c.tool_table) o.tools = gcode::read_tool_table_file((folder / c.tool_table).string());
  if (*c.sub_path) o.subroutine_path.push_back((folder / c.sub_path).string());
  if (*c.param) {
    const std::string p = c.param;
    const auto eq = p.rfind('=');
    o.parameters.emplace_back(p.substr(0, eq), std::stod(p.substr(eq + 1)));
  }
  return o;
}

TEST_P(LinuxcncSuite, MatchesLinuxcnc) {
  const SuiteCase& c = GetParam();
  if (c.expect == Expect::out_of_scope) GTEST_SKIP() << "out of scope: " << c.reason;
  const fs::path program = fs::path(corpus_dir()) / "linuxcnc" / c.program;
  ASSERT_TRUE(fs::exists(program)) << program;
  const fs::path folder = program.parent_path();
  const TraceResult result = trace_file(program.string(), options_for(c, folder));
  if (c.expect == Expect::rejected) {
    EXPECT_TRUE(result.error.has_value()) << c.program << " must be rejected";
    if (result.error) {
      EXPECT_GT(result.error->where().line, 0U) << "the error must name a line: " << result.error->what();
    }
    return;
  }
  ASSERT_FALSE(result.error.has_value()) << format_error(*result.error);
  if (c.expect == Expect::accepted) return;
  const fs::path expected_path = folder / (*c.expected ? c.expected : "expected");
  std::vector<std::string> expected_lines = read_lines(expected_path.string());
  std::vector<std::string> actual_lines = result.lines;
  const auto expected = observable(expected_lines, false);
  auto actual = observable(actual_lines, c.awk);
  if (c.expect == Expect::same_messages)
    std::erase_if(actual, [](const std::string& call) { return !call.starts_with("MESSAGE("); });
  if (c.expect == Expect::same_motions || c.expect == Expect::same_messages) {
    EXPECT_FALSE(expected.empty()) << "nothing to compare in " << expected_path;
  }
  if (auto diff = compare_calls(actual, expected)) ADD_FAILURE() << c.program << ": " << *diff;
}

INSTANTIATE_TEST_SUITE_P(Corpus, LinuxcncSuite, ::testing::ValuesIn(suite_cases()),
                         [](const auto& test) { return std::string(test.param.name); });

// interp/bad: every program must be rejected with a positioned message.
TEST(LinuxcncBad, EveryBadProgramIsRejectedWithAPosition) {
  const fs::path dir = fs::path(corpus_dir()) / "linuxcnc/interp/bad";
  int checked = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() != ".ngc") continue;
    const TraceResult r = trace_file(entry.path().string());
    ++checked;
    EXPECT_TRUE(r.error.has_value()) << entry.path().filename() << " was accepted";
    if (r.error) {
      EXPECT_GT(r.error->where().line, 0U) << entry.path().filename() << ": " << r.error->what();
      EXPECT_FALSE(r.error->where().file.empty()) << entry.path().filename();
    }
  }
  EXPECT_GE(checked, 16);
}

// interp/good: accepted, with the motions LinuxCNC gives.
TEST(LinuxcncGood, EveryGoodProgramMatches) {
  const fs::path dir = fs::path(corpus_dir()) / "linuxcnc/interp/good";
  int checked = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() != ".ngc") continue;
    const TraceResult r = trace_file(entry.path().string());
    ++checked;
    ASSERT_FALSE(r.error.has_value()) << format_error(*r.error);
    const auto expected = motion_calls(read_lines(entry.path().string() + ".expected"));
    if (auto diff = compare_calls(motion_calls(r.lines), expected))
      ADD_FAILURE() << entry.path().filename() << ": " << *diff;
  }
  EXPECT_GE(checked, 4);
}

}  // namespace
}  // namespace ccomp::test
