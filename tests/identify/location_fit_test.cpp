// A machine with known squareness and B-axis location, built apart from ccomp's model code
// (tests/support/reference_hmc), measured with nine laser lines, a grid at two tool lengths
// and a sphere on the table probed as B turns: ccomp's fit gives those values back within
// 2 urad and 1 um, and leaves only the noise.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "ccomp/identify/fit.hpp"
#include "ccomp/identify/measurements.hpp"
#include "ccomp/model/model_file.hpp"
#include "fitted_location.hpp"
#include "reference_hmc.hpp"
#include "reference_measurements.hpp"
#include "sample_models.hpp"

namespace ccomp::identify {
namespace {

constexpr double kNoise = 0.0002;  // mm

/// The geometric model to fit: error motions as quadratics, the location errors, all free
/// and starting at zero.
model::MachineModel geometric_start() {
  std::string text = std::string(test::kHmcChain) + "terms:\n";
  for (const char* motion : {"EXX", "EYX", "EZX", "EYY", "EXY", "EZY", "EZZ", "EXZ", "EYZ"})
    text += std::string("  - {name: ") + motion + ", form: polynomial, unit: um, coefficients: [0, 0, 0], fit: true}\n";
  text += "  - {name: EAY, form: polynomial, unit: urad, coefficients: [0, 0], fit: true}\n";
  for (const char* location : {"EC0X", "EB0X", "EA0Y", "EA0B", "EC0B"})
    text += std::string("  - {name: ") + location + ", value: 0, unit: urad, fit: true}\n";
  for (const char* location : {"EX0B", "EZ0B"})
    text += std::string("  - {name: ") + location + ", value: 0, unit: um, fit: true}\n";
  return model::parse_machine_model(text, "start.yaml");
}

TEST(LocationFit, SquarenessAndTheBAxisLocationOfAReferenceMachineAreFittedBack) {
  test::ReferenceHmc truth;
  truth.EC0X = 30e-6, truth.EB0X = -20e-6, truth.EA0Y = 15e-6;
  truth.EX0B = 0.012, truth.EZ0B = -0.008, truth.EA0B = 25e-6, truth.EC0B = -18e-6;
  truth.EXX = [](double x) { return 1.2e-5 * x - 1.5e-8 * x * x; };
  truth.EYX = [](double x) { return 2.0e-8 * x * x; };
  truth.EZX = [](double x) { return 1.2e-8 * x * x; };
  truth.EYY = [](double y) { return 9e-6 * y + 1e-8 * y * y; };
  truth.EZY = [](double y) { return 1.1e-8 * y * y; };
  truth.EZZ = [](double z) { return 1.5e-5 * z - 1e-8 * z * z; };
  truth.EAY = [](double y) { return 4e-6 + 1.8e-8 * y; };
  const model::ForwardModel start(geometric_start());
  const MeasurementSet data = test::reference_measurements(truth, test::measure_reference(truth, {kNoise, 7}));
  const FitReport r = fit(start, data);
  EXPECT_TRUE(r.converged);
  EXPECT_GT(r.rms_before, 0.005) << "the start misses several um";
  EXPECT_LE(r.rms_after, 1.3 * kNoise) << "the reference is what the model can say, up to the noise";
  struct Expected {
    const char* iso;
    double value, within;
  };
  for (const Expected& e :
       {Expected{"EC0X", truth.EC0X, 2e-6}, Expected{"EB0X", truth.EB0X, 2e-6}, Expected{"EA0Y", truth.EA0Y, 2e-6},
        Expected{"EA0B", truth.EA0B, 2e-6}, Expected{"EC0B", truth.EC0B, 2e-6}, Expected{"EX0B", truth.EX0B, 0.001},
        Expected{"EZ0B", truth.EZ0B, 0.001}})
    EXPECT_NEAR(test::fitted_location(start, r, e.iso), e.value, e.within) << e.iso;
}

TEST(LocationFit, TheReferenceAndTheModelAgreeTermByTerm) {
  // Each location term alone, the reference against ccomp's forward model at points all
  // over the workspace and the turn: the two implementations say the same.
  struct Case {
    const char* term;
    void (*set)(test::ReferenceHmc&);
  };
  const Case cases[] = {
      {"{name: EC0X, value: 40, unit: urad}", [](test::ReferenceHmc& m) { m.EC0X = 40e-6; }},
      {"{name: EB0X, value: 40, unit: urad}", [](test::ReferenceHmc& m) { m.EB0X = 40e-6; }},
      {"{name: EA0Y, value: 40, unit: urad}", [](test::ReferenceHmc& m) { m.EA0Y = 40e-6; }},
      {"{name: EX0B, value: 15, unit: um}", [](test::ReferenceHmc& m) { m.EX0B = 0.015; }},
      {"{name: EZ0B, value: 15, unit: um}", [](test::ReferenceHmc& m) { m.EZ0B = 0.015; }},
      {"{name: EA0B, value: 40, unit: urad}", [](test::ReferenceHmc& m) { m.EA0B = 40e-6; }},
      {"{name: EC0B, value: 40, unit: urad}", [](test::ReferenceHmc& m) { m.EC0B = 40e-6; }},
  };
  for (const Case& c : cases) {
    test::ReferenceHmc reference;
    c.set(reference);
    const model::ForwardModel m(
        model::parse_machine_model(std::string(test::kHmcChain) + "terms:\n  - " + c.term + "\n", "m.yaml"));
    model::ForwardData d(m);
    for (const Eigen::Vector4d& p : {Eigen::Vector4d(300, -200, 150, 0), Eigen::Vector4d(-250, 180, -300, 75),
                                     Eigen::Vector4d(120, 90, 40, 200), Eigen::Vector4d(-30, -260, 280, 310)}) {
      model::ChainQ q = model::ChainQ::Zero();
      q << p[0], p[1], p[2], 0, p[3] * std::numbers::pi / 180.0, 0, 0, 0, 0, 100;
      model::forward(m, d, q, MeasurementSet::conditions(Observation{}));
      const Eigen::Vector3d ours = reference.deviation(p[0], p[1], p[2], p[3], 100);
      // First order alike; the two turn lines by different but equally exact means.
      EXPECT_LT((model::deviation(d) - ours).norm(), 2e-6)
          << c.term << " at " << p.transpose() << ": ccomp " << model::deviation(d).transpose() << ", reference "
          << ours.transpose();
    }
  }
}

}  // namespace
}  // namespace ccomp::identify
