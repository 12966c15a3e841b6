// docs/error-model.md Ref 2: a test piece cut at four table angles and measured on a CMM along its faces'
// normals, against its own faces cut at B0 (not against the B axis), determines the rotary
// axis' location and tilt; the shipped data give the shipped truth.
#include <gtest/gtest.h>

#include "ccomp/identify/fit.hpp"
#include "ccomp/model/model_file.hpp"
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
  // The noise floor comes from the faces' rows (0.43 um against the data's 0.5 um). A
  // direction is determined where one physical scale along it moves the readings by more
  // than that noise; the change found along it is kept where it is beyond three sigmas.
  // The four angles separate the axis' tilts (EA0B, EC0B) from the datum's tilt well
  // enough for that: the test piece finds all four of the axis' location errors.
  EXPECT_EQ(r.rank, 9U) << "faces at four angles determine the B axis' four errors and the part's datum";
  EXPECT_LE(r.rms_after, 1.3 * 0.0005);
  int located = 0;
  for (const FittedParameter& p : r.parameters) {
    EXPECT_TRUE(p.identified) << p.label;
    const model::ErrorTermSpec& t = start.terms[p.term];
    if (t.link != "B") continue;  // the datum: where the part sits, which the truth does not say
    ASSERT_EQ(t.placement, model::ErrorPlacement::location) << p.label;
    for (const model::ErrorTermSpec& u : truth.terms)
      if (u.iso == t.iso && u.placement == t.placement) {
        EXPECT_NEAR(p.after, u.parameters[0], 4 * p.uncertainty) << p.label;
        EXPECT_GT(std::abs(u.parameters[0]), 6 * p.uncertainty) << p.label << ": the machine has it, clearly";
        ++located;
      }
  }
  EXPECT_EQ(located, 4);
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
