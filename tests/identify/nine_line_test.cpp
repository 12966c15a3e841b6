// Seed 003's nine-line method: the geometric errors of a 3-axis machine from nine laser
// lines, their sensitivity to where the lines were placed, and the placement study.
#include "ccomp/identify/nine_line.hpp"

#include <gtest/gtest.h>

#include "ccomp/identify/simulate.hpp"
#include "sample_models.hpp"

namespace ccomp::identify {
namespace {

/// The 18 error motions (slope and curvature; their constants are the work offset's) and
/// the 3 squarenesses: seed 003's 21 geometric errors. `scale` 0 gives the blank start.
model::MachineModel vmc(double scale) {
  std::string terms = "terms:\n";
  int k = 0;
  for (const char* axis : {"X", "Y", "Z"})
    for (const char* c : {"X", "Y", "Z", "A", "B", "C"}) {
      const bool angle = std::string("ABC").find(c[0]) != std::string::npos;
      const double a1 = scale * (angle ? 0.02 : 0.01) * (1 + 0.3 * (k % 5)), a2 = scale * 2e-5 * ((k % 3) - 1);
      terms += "  - {name: E" + std::string(c) + axis + ", form: polynomial, unit: " + (angle ? "urad" : "um") +
               ", coefficients: [0, " + std::to_string(a1) + (angle ? "" : ", " + std::to_string(a2)) +
               "], fit: true}\n";
      ++k;
    }
  for (const auto& [name, value] : {std::pair{"EC0X", 20.0}, std::pair{"EB0X", -15.0}, std::pair{"EA0Y", 10.0}})
    terms +=
        "  - {name: " + std::string(name) + ", value: " + std::to_string(scale * value) + ", unit: urad, fit: true}\n";
  return model::parse_machine_model(std::string(test::kVmcChain) +
                                        "axes: {X: {min: -300, max: 300}, Y: {min: -200, max: "
                                        "200}, Z: {min: -250, max: 250}}\n" +
                                        terms,
                                    "vmc.yaml");
}

TEST(NineLine, FitsTheGeometricErrorsAndStudiesThePlacement) {
  SimulateOptions o;
  o.plans = {Plan::nine_lines};
  o.step = 10;
  o.noise = 0.0002;
  const MeasurementSet data = simulate(model::ForwardModel(vmc(1.0)), o);
  ASSERT_EQ(data.sources.size(), 9U);
  const NineLineReport r = nine_line(model::ForwardModel(vmc(0.0)), data);
  EXPECT_GT(r.fit.rms_before, 0.005);
  EXPECT_LE(r.fit.rms_after, 1.3 * 0.0002);
  EXPECT_GT(r.sensitivity.size(), 10U);
  for (const PlacementSensitivity& s : r.sensitivity) {
    EXPECT_TRUE(std::isfinite(s.per_mm)) << s.parameter;
    EXPECT_NE(s.line.find("-line"), std::string::npos) << s.parameter << " names the line that moves it";
  }
  ASSERT_EQ(r.placements.size(), 6U);
  // Seed 003: lines bunched in the middle (0.4 from the edges) make the result far more
  // sensitive to their placement than lines spread across the workspace (0.1).
  auto at = [&](double inset) {
    for (const auto& [where, value] : r.placements)
      if (std::abs(where - inset) < 1e-9) return value;
    return -1.0;
  };
  EXPECT_GT(at(0.4), 1.5 * at(0.1));
  EXPECT_LT(r.recommended_inset, 0.35);
}

}  // namespace
}  // namespace ccomp::identify
