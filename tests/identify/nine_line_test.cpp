// The nine-line method (docs/error-model.md Ref 4): the geometric errors of a 3-axis machine from nine laser
// lines, their sensitivity to where the lines were placed, and the placement study.
#include "ccomp/identify/nine_line.hpp"

#include <gtest/gtest.h>

#include "ccomp/identify/simulate.hpp"
#include "ccomp/model/model_file.hpp"
#include "sample_models.hpp"

namespace ccomp::identify {
namespace {

/// The 18 error motions (slope and curvature; their constants are the work offset's) and
/// the 3 squarenesses: Ref 4's 21 geometric errors. `scale` 0 gives the blank start.
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
  return model::parse_machine_model(
      test::with_axes(test::kVmcChain,
                      "axes: {X: {min: -300, max: 300}, Y: {min: -200, max: 200}, Z: {min: -250, "
                      "max: 250}}\n") +
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
  // Ref 4: lines bunched in the middle (0.4 from the edges) make the result far more
  // sensitive to their placement than lines spread across the workspace (0.1).
  auto at = [&](double inset) {
    for (const auto& [where, value] : r.placements)
      if (std::abs(where - inset) < 1e-9) return value;
    return -1.0;
  };
  EXPECT_GT(at(0.4), 1.5 * at(0.1));
  EXPECT_LT(r.recommended_inset, 0.35);
}

TEST(NineLine, DeterminesTheSquarenessBetweenTheLines) {
  // A machine out of square, its straightness lines sloped too (the slope of a straightness
  // is the line's direction): Ref 4 reports the angles between the lines, X along
  // (1, EC0X + EYX', -EB0X + EZX'), Y along (EXY', 1, EA0Y + EZY'), Z along (EXZ', EYZ', 1),
  // a prime the slope. The start knows nothing; the truth's carriages do not turn.
  std::string text =
      test::with_axes(test::kVmcChain,
                      "axes: {X: {min: -300, max: 300}, Y: {min: -200, max: 200}, Z: {min: -250, max: 250}}\n") +
      "terms:\n";
  const char* slopes[] = {"EYX", "EZX", "EXY", "EZY", "EXZ", "EYZ"};
  const double slope_urad[] = {6, -4, 3, 5, -2, 7};
  for (int i = 0; i < 6; ++i)
    text += std::string("  - {name: ") + slopes[i] + ", form: polynomial, unit: um, coefficients: [0, " +
            std::to_string(slope_urad[i] * 1e-3) + ", 2e-5]}\n";
  text +=
      "  - {name: EC0X, value: 20, unit: urad}\n  - {name: EB0X, value: -15, unit: urad}\n"
      "  - {name: EA0Y, value: 10, unit: urad}\n";
  SimulateOptions o;
  o.plans = {Plan::nine_lines};
  o.step = 10;
  o.noise = 0.0002;
  const MeasurementSet data = simulate(model::ForwardModel(model::parse_machine_model(text, "truth.yaml")), o);
  const NineLineReport r = nine_line(model::ForwardModel(vmc(0.0)), data);
  EXPECT_LE(r.fit.rms_after, 1.3 * 0.0002);
  // A straightness' curvature (2e-5 um/mm^2) slopes its least-squares line where the
  // measured travel is not centred on the axis' zero: Z's chain travel is centred on c.
  double low = 1e9, high = -1e9;
  for (const Observation& ob : data.observations) low = std::min(low, ob.q[2]), high = std::max(high, ob.q[2]);
  const double curved = 2 * 2e-5 * 0.5 * (low + high) * 1e3;  // urad
  const double expected[3] = {(20 + 6 + 3) * 1e-6, (-15 - (-4) - (-2 + curved)) * 1e-6, (10 + 5 + (7 + curved)) * 1e-6};
  ASSERT_EQ(r.squareness.size(), 3U);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_NEAR(r.squareness[i].value, expected[i], 1e-6) << r.squareness[i].iso;
  EXPECT_EQ(r.squareness[0].iso, "EC0X");
  EXPECT_EQ(r.squareness[0].seed, "S_xy");
  EXPECT_EQ(r.squareness[0].seed_sign, -1.0);
}

}  // namespace
}  // namespace ccomp::identify
