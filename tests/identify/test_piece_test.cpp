// Seed 001: a test piece cut at four table angles and measured along its faces' normals
// determines the rotary axis' location and tilt; the shipped data give the shipped truth.
#include <gtest/gtest.h>

#include "ccomp/identify/fit.hpp"
#include "trace_capture.hpp"

namespace ccomp::identify {
namespace {

TEST(TestPiece, FindsTheRotaryAxisLocationAndTilt) {
  const std::string dir = test::source_dir() + "/samples/test-piece/";
  const model::MachineModel start = model::load_machine_model(dir + "hmc-b-axis-test.yaml");
  const model::MachineModel truth = model::load_machine_model(dir + "hmc-b-axis-truth.yaml");
  MeasurementSet data;
  read_measurements(dir + "cmm.csv", start, {}, data);
  ASSERT_EQ(data.observations.size(), 72U);
  const FitReport r = fit(model::ForwardModel(start), data);
  EXPECT_EQ(r.rank, 4U) << "four faces at four angles determine all four";
  EXPECT_LE(r.rms_after, 1.3 * 0.0005);
  for (const FittedParameter& p : r.parameters) {
    const double expected = truth.terms[p.term].parameters[0];
    EXPECT_TRUE(p.identified) << p.label;
    EXPECT_NEAR(p.after, expected, 4 * p.uncertainty) << p.label;
  }
  // The program that cuts it runs through the main job.
  const test::CommandResult c =
      test::run_command(test::shell_quote(test::ccomp_binary()) + " " + test::shell_quote(dir + "test-piece-b.ngc") +
                        " -m " + test::shell_quote(test::source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml") +
                        " --tool-table " + test::shell_quote(test::source_dir() + "/samples/tools.tbl") + " -o -");
  EXPECT_EQ(c.exit_code, 0) << c.err;
  EXPECT_NE(c.out.find("B270"), std::string::npos);
}

}  // namespace
}  // namespace ccomp::identify
