// ISO 230-2 positioning figures: a small data set worked by hand, and the split of docs/error-model.md Ref 3
// of a simulated axis into cumulative, periodic and reversal parts.
#include "ccomp/identify/positioning.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "ccomp/error.hpp"
#include "ccomp/identify/simulate.hpp"
#include "ccomp/model/model_file.hpp"
#include "error_of.hpp"
#include "trace_capture.hpp"

namespace ccomp::identify {
namespace {

MeasurementSet read(const std::string& csv) {
  MeasurementSet set;
  parse_measurements(csv, "runs.csv", model::load_machine_model(test::source_dir() + "/samples/machines/zero.yaml"), {},
                     set);
  return set;
}

TEST(Positioning, FiguresOfAWorkedExample) {
  // Two targets, two runs each way; deviations in um: at 0 up 1, 3 and down -1, -1; at
  // 100 up 2, 2 and down 0, 2 (the laser points along -X for the last: its sign flips).
  const MeasurementSet s = read(
      "x,y,z,vx,nx,ny,nz,d\n"
      "0,0,0,1,1,0,0,0.001\n0,0,0,1,1,0,0,0.003\n0,0,0,-1,1,0,0,-0.001\n0,0,0,-1,1,0,0,-0.001\n"
      "100,0,0,1,1,0,0,0.002\n100,0,0,1,1,0,0,0.002\n100,0,0,-1,1,0,0,0\n100,0,0,-1,-1,0,0,-0.002\n"
      "50,0,0,0,1,0,0,0.5\n");  // no approach direction: not part of a run
  const PositioningReport r = analyse_positioning(s, 0);
  ASSERT_EQ(r.targets.size(), 2U);
  EXPECT_EQ(r.runs_up, 2);
  EXPECT_EQ(r.runs_down, 2);
  const double s2 = std::sqrt(2.0) * 1e-3;  // the spread of 1 and 3 um
  EXPECT_NEAR(*r.targets[0].mean_up, 0.002, 1e-15);
  EXPECT_NEAR(*r.targets[0].s_up, s2, 1e-15);
  EXPECT_NEAR(*r.targets[1].mean_down, 0.001, 1e-15);
  EXPECT_NEAR(*r.B, 0.003, 1e-15);
  EXPECT_NEAR(*r.B_mean, 0.002, 1e-15);
  EXPECT_NEAR(*r.E_up, 0.0, 1e-15);
  EXPECT_NEAR(*r.E_down, 0.002, 1e-15);
  EXPECT_NEAR(*r.E, 0.003, 1e-15);
  EXPECT_NEAR(*r.M, 0.001, 1e-15);
  EXPECT_NEAR(*r.R, 2 * s2 + 0.003, 1e-15);
  EXPECT_NEAR(*r.R_up, 4 * s2, 1e-15);
  // A: from the highest mean + 2s (up at 0: 2 um + 2s) to the lowest mean - 2s (down at
  // 100: 1 um - 2s).
  EXPECT_NEAR(*r.A_up, 4 * s2, 1e-15);
  EXPECT_NEAR(*r.A_down, 4 * s2, 1e-15);
  EXPECT_NEAR(*r.A, 0.001 + 4 * s2, 1e-15);
  EXPECT_TRUE(r.not_stated.empty());
}

TEST(Positioning, SeedTwoSplitsCumulativePeriodicAndReversal) {
  const model::MachineModel truth =
      model::load_machine_model(test::source_dir() + "/samples/measurements/hmc-truth.yaml");
  SimulateOptions o;
  o.plans = {Plan::nine_lines};
  o.step = 2.5;
  o.runs = 5;
  o.noise = 0.0002;
  const MeasurementSet data = simulate(model::ForwardModel(truth), o);
  const PositioningReport y = analyse_positioning(data, 1, "y-line2");
  EXPECT_EQ(y.runs_up, 5);
  EXPECT_EQ(y.runs_down, 5);
  EXPECT_NEAR(*y.B_mean, -0.0035, 0.00005) << "the truth's backlash on Y";
  EXPECT_GT(*y.R, 4 * 0.0002) << "repeatability is at least four noise sigmas";
  const PositioningReport x = analyse_positioning(data, 0, "x-line2");
  EXPECT_NEAR(x.period, 10.0, 0.2) << "the truth's lead-screw pitch";
  EXPECT_NEAR(x.periodic_amplitude, std::hypot(0.0016, 0.0009), 0.0002);
  EXPECT_NEAR(*x.B_mean, 0.0, 0.0001);
  EXPECT_LT(x.rms_left, 0.0003);
}

TEST(Positioning, NamesNoPeriodSeenFewerThanFourTimes) {
  // 9 targets over 80 mm, a 40 mm sine: two cycles seen, too few to call it a pitch.
  std::string csv = "x,y,z,vx,nx,ny,nz,d\n";
  for (int run = 0; run < 2; ++run)
    for (int i = 0; i <= 8; ++i)
      for (const char* v : {"1", "-1"}) {
        const double x = 10.0 * i;
        csv += std::to_string(x) + ",0,0," + v + ",1,0,0," + std::to_string(0.002 * std::sin(2 * std::numbers::pi * x / 40)) + "\n";
      }
  const PositioningReport r = analyse_positioning(read(csv), 0);
  ASSERT_EQ(r.targets.size(), 9U);
  EXPECT_EQ(r.period, 0.0) << "named a period of " << r.period << " mm with two cycles seen";
}

}  // namespace
}  // namespace ccomp::identify
