// Both rotary lines' location errors (ISO 230-7) of the five-axis reference machines
// (tests/support/reference_five_axis: a trunnion table XYZAC and a head-head XYZBC, written
// apart from ccomp's model code), identified from two spheres on the part probed at every
// combination of the rotary angles simulate's sphere plan gives: the readings are the
// reference's, written as a measurement file in its own program coordinates (the frame line
// carries its work offset) and read by ccomp's reader; the fitted model gives each line's
// location back within 2 urad and 1 um.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "ccomp/identify/fit.hpp"
#include "ccomp/identify/measurements.hpp"
#include "ccomp/identify/simulate.hpp"
#include "ccomp/model/model_file.hpp"
#include "fitted_location.hpp"
#include "reference_five_axis.hpp"
#include "reference_measurements.hpp"

namespace ccomp::identify {
namespace {

using test::ReferenceHeads;
using test::ReferenceTrunnion;

constexpr double kNoise = 0.0002;  // mm
constexpr double kProbeLength = 100.0;

/// The trunnion in ccomp's terms, in machine coordinates: the base frame is the reference's
/// table base, the gauge point at the spindle nose; no work offset (the file gives it).
std::string machine_model(const ReferenceTrunnion& r) {
  return R"(
name: reference-trunnion
axes: {X: {}, Y: {}, Z: {}, A: {type: rotary, min: -120, max: 120}, C: {type: rotary}}
max_correction: 1 mm
chain:
  workpiece:
    - {link: Y, axis: Y, direction: [0, -1, 0]}
    - {link: X, axis: X, direction: [-1, 0, 0]}
    - {link: A, axis: A, direction: [-1, 0, 0], offset: )" +
         test::yaml_mm(r.a_centre) + R"(}
    - {link: C, axis: C, direction: [0, 0, -1], offset: )" +
         test::yaml_mm(r.c_from_a) + R"(}
  tool:
    - {link: Z, axis: Z, direction: [0, 0, 1], offset: )" +
         test::yaml_mm(r.spindle_nose) + R"(}
    - {link: tool, tool_length: [0, 0, -1]}
terms:
)";
}

/// The head-head machine likewise: the table moved by X, the head's Y and Z, C at its centre,
/// B's fork from it, the spindle nose from B's centre.
std::string machine_model(const ReferenceHeads& r) {
  return R"(
name: reference-heads
axes: {X: {}, Y: {}, Z: {}, B: {type: rotary, min: -90, max: 90}, C: {type: rotary}}
max_correction: 1 mm
chain:
  workpiece:
    - {link: X, axis: X, direction: [-1, 0, 0]}
  tool:
    - {link: Y, axis: Y, direction: [0, 1, 0]}
    - {link: Z, axis: Z, direction: [0, 0, 1], offset: )" +
         test::yaml_mm(r.c_centre) + R"(}
    - {link: C, axis: C, direction: [0, 0, 1]}
    - {link: B, axis: B, direction: [0, 1, 0], offset: )" +
         test::yaml_mm(r.b_from_c) + R"(}
    - {link: tool, tool_length: [0, 0, -1], offset: )" +
         test::yaml_mm(r.nose_from_b) + R"(}
terms:
)";
}

/// A location error of the reference (mm or rad) and its term's name.
template <typename Reference>
struct Location {
  const char* iso;
  double Reference::*member;
  double value;  ///< um or urad
  bool length;
};

template <typename Reference>
void fits_back(const std::vector<Location<Reference>>& locations, const std::string& rotary) {
  Reference truth;
  std::string terms;
  for (const Location<Reference>& l : locations) {
    truth.*l.member = l.value * (l.length ? 1e-3 : 1e-6);
    terms += std::string("  - {name: ") + l.iso + ", value: 0, unit: " + (l.length ? "um" : "urad") + ", fit: true}\n";
  }
  const model::MachineModel start_model = model::parse_machine_model(machine_model(truth) + terms, "start.yaml");
  const model::ForwardModel start(start_model);
  // The campaign simulate's sphere plan runs, placed from the reference's program zero.
  SimulateOptions campaign;
  campaign.tool_length = kProbeLength;
  const Eigen::Vector3d g54 = truth.work_offset();
  campaign.origin = model::WorkOrigin{g54.x(), g54.y(), g54.z()};
  const std::vector<model::ChainQ> poses = sphere_poses(start, campaign);
  ASSERT_GE(poses.size(), 100U) << "both axes turned, both spheres";
  MeasurementSet data;
  ReadOptions read;
  read.tool_length = kProbeLength;
  parse_measurements(test::five_axis_csv(truth, poses, rotary, kNoise, 11), "spheres.csv", start_model, read, data);
  const FitReport r = fit(start, data);
  EXPECT_TRUE(r.converged);
  EXPECT_GT(r.rms_before, 0.003) << "the start misses several um";
  EXPECT_LE(r.rms_after, 1.2 * kNoise) << "the reference is what the model can say, up to the noise";
  for (const Location<Reference>& l : locations)
    EXPECT_NEAR(test::fitted_location(start, r, l.iso), l.value * (l.length ? 1e-3 : 1e-6), l.length ? 0.001 : 2e-6)
        << l.iso;
}

TEST(FiveAxisSpherePlan, ProbesTwoSpheresFixedOnTheTableAtEveryAAndCAngleWithinTheLimits) {
  const ReferenceTrunnion machine;
  const model::ForwardModel m(
      model::parse_machine_model(machine_model(machine) + "  - {name: EY0A, value: 0, unit: um}\n", "trunnion.yaml"));
  SimulateOptions options;
  options.plans = {Plan::sphere};
  const Eigen::Vector3d g54 = machine.work_offset();
  options.origin = model::WorkOrigin{g54.x(), g54.y(), g54.z()};
  const std::vector<model::ChainQ> poses = sphere_poses(m, options);
  ASSERT_EQ(poses.size(), 2U * 9U * 24U) << "A -120..120 every 30 deg by a turn of C every 15, two spheres";
  model::ForwardData d(m);
  std::vector<Eigen::Vector3d> spheres;  // where the nominal tip is on the table
  for (const model::ChainQ& q : poses) {
    EXPECT_LE(std::abs(q[3]), 120.0 * std::numbers::pi / 180.0 + 1e-12) << "A within its limits";
    model::forward(m, d, q, model::Conditions{}, false, model::Evaluate::nominal);
    if (std::none_of(spheres.begin(), spheres.end(),
                     [&](const Eigen::Vector3d& s) { return (s - d.nominal).norm() < 1e-6; }))
      spheres.push_back(d.nominal);
  }
  EXPECT_EQ(spheres.size(), 2U) << "each sphere stays where it is on the table as A and C turn";
  EXPECT_EQ(simulate(m, options).observations.size(), 3U * poses.size()) << "X, Y and Z at each pose";
}

TEST(FiveAxisLocationFit, BothLinesOfTheTrunnionTableAreFittedBackFromSpheresProbedAtAAndC) {
  using R = ReferenceTrunnion;
  fits_back<R>({{"EY0A", &R::EY0A, 12, true},
                {"EZ0A", &R::EZ0A, -8, true},
                {"EB0A", &R::EB0A, 15, false},
                {"EC0A", &R::EC0A, -10, false},
                {"EX0C", &R::EX0C, -9, true},
                {"EY0C", &R::EY0C, 7, true},
                {"EA0C", &R::EA0C, 12, false},
                {"EB0C", &R::EB0C, -9, false}},
               "AC");
}

TEST(FiveAxisLocationFit, BothLinesOfTheHeadHeadMachineAreFittedBackFromSpheresProbedAtBAndC) {
  using R = ReferenceHeads;
  fits_back<R>({{"EX0C", &R::EX0C, 10, true},
                {"EY0C", &R::EY0C, -6, true},
                {"EA0C", &R::EA0C, -11, false},
                {"EB0C", &R::EB0C, 8, false},
                {"EX0B", &R::EX0B, -7, true},
                {"EZ0B", &R::EZ0B, 11, true},
                {"EA0B", &R::EA0B, 13, false},
                {"EC0B", &R::EC0B, -12, false}},
               "BC");
}

}  // namespace
}  // namespace ccomp::identify
