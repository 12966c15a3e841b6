// fit, check and positioning on measurements that support nothing above their noise (a short
// stroke, one run each way, few targets, one direction, one row) end with their documented
// codes: "nothing identifiable above the noise floor" is a result, never a signal
// (issue 45: the reduced solve decomposed an empty matrix and the process died of SIGSEGV).
#include <gtest/gtest.h>

#include <filesystem>

#include "short_runs.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

struct ShortDataCase {
  ShortRuns runs;
  const char* fit_says;    ///< on stderr, exit 8, no model written
  const char* check_says;  ///< on stdout, exit 0
  int positioning_exit;
};

std::ostream& operator<<(std::ostream& os, const ShortDataCase& c) {
  return os << c.runs.name;
}

class ShortData : public ::testing::TestWithParam<ShortDataCase> {};

constexpr const char* kNothing = "nothing identifiable above the noise floor";

TEST_P(ShortData, EndsWithItsDocumentedCode) {
  const ShortDataCase& c = GetParam();
  const std::string dir = temp_dir(std::string("short_data_") + c.runs.name);
  write_file(dir + "/m.yaml", one_axis_model());
  write_file(dir + "/runs.csv", short_runs_csv(c.runs));
  const std::string args = shell_quote(dir + "/runs.csv") + " -m " + shell_quote(dir + "/m.yaml");
  const std::string fitted = dir + "/fitted.yaml";
  const std::string ccomp = shell_quote(ccomp_binary());

  CommandResult r = run_command(ccomp + " fit " + args + " -o " + shell_quote(fitted));
  EXPECT_EQ(r.exit_code, 8) << r.out << r.err;
  EXPECT_NE(r.err.find(c.fit_says), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(fitted)) << "a refused fit writes nothing";
  EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;

  r = run_command(ccomp + " fit " + args + " -o " + shell_quote(fitted) + " --json");
  EXPECT_EQ(r.exit_code, 8) << r.err;
  EXPECT_FALSE(std::filesystem::exists(fitted));

  r = run_command(ccomp + " check " + args);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find(c.check_says), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;

  r = run_command(ccomp + " check " + args + " --json --report " + shell_quote(dir + "/check.html"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  if (c.check_says == std::string(kNothing)) {
    EXPECT_NE(r.out.find("\"nothing_identifiable\": \"nothing identifiable"), std::string::npos) << r.out;
  }
  EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;

  r = run_command(ccomp + " positioning " + args + " --axis x");
  EXPECT_EQ(r.exit_code, c.positioning_exit) << r.out << r.err;
}

INSTANTIATE_TEST_SUITE_P(
    Issue45, ShortData,
    ::testing::Values(
        // 3 mm of a 2000 mm axis, one run each way, 20 um of noise: the 14-row file.
        ShortDataCase{{"short_stroke", {0, 0.5, 1, 1.5, 2, 2.5, 3}, true, 1, 0.035}, kNothing, kNothing, 0},
        ShortDataCase{{"single_run", {0, 20, 40, 60, 80, 100, 120, 140, 160, 180, 200}, true, 1, 0.09},
                      kNothing,
                      kNothing,
                      0},
        ShortDataCase{{"few_targets", {0, 100, 200}, true, 5, 0.1}, kNothing, kNothing, 0},
        // positioning: the unidirectional figures, the bidirectional ones not stated
        ShortDataCase{{"one_direction", {0, 20, 40, 60, 80, 100}, false, 3, 0.09}, kNothing, kNothing, 0},
        ShortDataCase{{"one_row", {10}, false, 1, 0.001},
                      "1 readings cannot determine 2 free parameters",
                      "1 readings cannot determine the model's 2 free parameters",
                      8}),
    [](const ::testing::TestParamInfo<ShortDataCase>& p) { return std::string(p.param.runs.name); });

}  // namespace
}  // namespace ccomp::test
