// The five-axis sample as a user runs it: samples/programs/five-axis-xyzac.ngc (a joint-
// coordinate program tilting the tool out of A 0 as the C table turns) on the sample XYZAC
// trunnion with both rotary lines' location errors. The job compensates it (it refused the
// program before two rotary axes were solved for the tool's direction: a 13.7 mm correction
// at its first line), `verify` finds the output within the tolerance, LinuxCNC's interpreter
// runs it, and the model without error rewrites it byte for byte but the header.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <string>

#include "rs274_oracle.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

/// The number after `"key": ` in a --json answer, or NaN.
double json_number(const std::string& json, const std::string& key) {
  std::smatch m;
  if (!std::regex_search(json, m, std::regex("\"" + key + "\": ([-+0-9.eE]+)"))) return std::nan("");
  return std::stod(m[1]);
}

class FiveAxisSample : public ::testing::Test {
 protected:
  std::string dir = temp_dir("five_axis_sample");
  std::string program = source_dir() + "/samples/programs/five-axis-xyzac.ngc";
  std::string tools = source_dir() + "/samples/tools.tbl";

  CommandResult compensate(const std::string& machine, const std::string& out) const {
    return run_command(shell_quote(ccomp_binary()) + " " + shell_quote(program) + " -m " +
                       shell_quote(source_dir() + "/samples/machines/" + machine + ".yaml") + " --tool-table " +
                       shell_quote(tools) + " --json -o " + shell_quote(out));
  }
};

TEST_F(FiveAxisSample, CompensatesOnTheTrunnionAndVerifyFindsItWithinTheTolerance) {
  const std::string out = dir + "/out.ngc";
  const CommandResult job = compensate("vmc-xyzac-trunnion", out);
  ASSERT_EQ(job.exit_code, 0) << job.err;
  EXPECT_GT(json_number(job.out, "error_before_um"), 10.0) << job.out;
  EXPECT_LT(json_number(job.out, "error_after_um"), 1.0) << job.out;
  // What the tool's direction keeps at A 0 (C's tilt across C's line), reported.
  EXPECT_GT(json_number(job.out, "orientation_error_urad"), 0.5) << job.out;
  EXPECT_LT(json_number(job.out, "orientation_error_urad"), 10.0) << job.out;
  const CommandResult verify =
      run_command(shell_quote(ccomp_binary()) + " verify " + shell_quote(program) + " " + shell_quote(out) + " -m " +
                  shell_quote(source_dir() + "/samples/machines/vmc-xyzac-trunnion.yaml") + " --tool-table " +
                  shell_quote(tools) + " --json");
  ASSERT_EQ(verify.exit_code, 0) << verify.out << verify.err;
  EXPECT_LT(json_number(verify.out, "max_um"), 1.0) << verify.out;
  EXPECT_EQ(json_number(verify.out, "uncut_mm"), 0.0) << verify.out;
}

TEST_F(FiveAxisSample, LinuxCncRunsTheOutput) {
  CCOMP_REQUIRE_RS274();
  const std::string out = dir + "/out.ngc";
  ASSERT_EQ(compensate("vmc-xyzac-trunnion", out).exit_code, 0);
  // rs274 alone reads its tool table in inches: tool 1 of samples/tools.tbl, 100 mm.
  write_file(dir + "/tools.tbl", "T1 P1 Z3.937008 D0.393701 ;\n");
  const TraceResult theirs = rs274_trace(out, dir + "/tools.tbl");
  EXPECT_FALSE(theirs.error) << theirs.error->what();
}

TEST_F(FiveAxisSample, TheModelWithoutErrorRewritesItByteForByte) {
  const std::string out = dir + "/zero.ngc";
  ASSERT_EQ(compensate("zero", out).exit_code, 0);
  std::string written = read_file(out);
  const std::size_t header = written.find("(ccomp ");
  ASSERT_NE(header, std::string::npos);
  written.erase(header, written.find('\n', header) + 1 - header);
  EXPECT_EQ(written, read_file(program));
}

}  // namespace
}  // namespace ccomp::test
