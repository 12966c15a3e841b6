// How the readings' spacing shows in what check says, on data of the reference machine
// (tests/support/reference_hmc, written apart from ccomp's model code): a noise floor from
// any evenly spaced run (spheres probed at even B angles included, and lines at ISO 230-2's
// irregular targets), and a period that evenly spaced readings could alias said to be so,
// where irregular targets name the right one.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "ccomp/identify/check.hpp"
#include "ccomp/identify/diagnose.hpp"
#include "ccomp/identify/simulate.hpp"
#include "ccomp/model/model_file.hpp"
#include "metrology_loop.hpp"
#include "reference_hmc.hpp"
#include "reference_measurements.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

constexpr double kNoise = 0.0002;  // mm

std::string geometric_model() {
  return read_file(source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml");
}

/// The noise floor check reports of the sample model (the reference's terms, its values
/// not fitted) on `plans`' readings of the geometric reference.
identify::NoiseFloor floor_of(const ReferencePlans& plans) {
  const ReferenceHmc machine = geometric_reference();
  const identify::MeasurementSet data = reference_measurements(machine, measure_reference(machine, plans));
  const model::ForwardModel model(model::parse_machine_model(geometric_model(), "m.yaml"));
  const identify::CheckReport report = identify::check(model, data);
  return {report.noise_floor, report.noise_method};
}

TEST(NoiseFloor, SpheresProbedAtEvenAnglesGiveIt) {
  ReferencePlans plans;
  plans.noise = kNoise, plans.seed = 7, plans.nine_lines = false, plans.grid = false, plans.sphere_step = 2.5;
  const identify::NoiseFloor floor = floor_of(plans);
  EXPECT_NEAR(floor.value, kNoise, 0.25 * kNoise) << floor.method;
}

TEST(NoiseFloor, LinesAtIrregularTargetsGiveIt) {
  ReferencePlans plans;
  plans.noise = kNoise, plans.seed = 8, plans.grid = false, plans.sphere = false, plans.line_step = 10;
  plans.irregular_targets = true;
  const identify::NoiseFloor floor = floor_of(plans);
  EXPECT_NEAR(floor.value, kNoise, 0.2 * kNoise) << floor.method;
}

ReferenceHmc with_screw() {
  ReferenceHmc m = geometric_reference();
  const auto polynomial = m.EXX;
  m.EXX = [polynomial](double x) { return polynomial(x) + 0.0015 * std::sin(2 * std::numbers::pi * x / 10.0 + 0.4); };
  return m;
}

/// The first periodic suggestion on X of check's diagnosis of the geometric model.
const identify::Suggestion* periodic_x(const identify::Diagnosis& d) {
  for (const identify::Suggestion& s : d.suggestions)
    if (s.term == "EXX" && s.form == "periodic") return &s;
  return nullptr;
}

// A 10 mm screw read every 25 mm: every reading sits at the same phase but for its sign,
// which a period of 50 mm (two steps) gives as well. Whatever is named is said to be
// possibly aliased, with 10 mm among what it could be, and the run that settles it.
TEST(Aliasing, AScrewReadEveryTwentyFiveMillimetresIsFlagged) {
  const ReferenceHmc machine = with_screw();
  ReferencePlans plans;
  plans.noise = kNoise, plans.seed = 9, plans.line_step = 25.0;
  const identify::MeasurementSet data = reference_measurements(machine, measure_reference(machine, plans));
  const model::ForwardModel model(model::parse_machine_model(geometric_model(), "m.yaml"));
  const identify::Diagnosis d = identify::diagnose(model, data);
  const identify::Suggestion* s = periodic_x(d);
  ASSERT_NE(s, nullptr) << (d.suggestions.empty() ? d.unexplained : d.suggestions.front().spec);
  EXPECT_NE(s->aliasing.find("possibly aliased"), std::string::npos) << s->aliasing;
  EXPECT_NE(s->aliasing.find("a laser line along X"), std::string::npos) << s->aliasing;
  EXPECT_TRUE(std::any_of(s->aliases.begin(), s->aliases.end(), [](double p) { return std::abs(p - 10.0) < 0.3; }))
      << s->aliasing;
}

// The same screw read at ISO 230-2's irregular targets about every 25 mm: the loop names
// the 10 mm period itself, with nothing said of aliasing, and ends at the noise.
TEST(Aliasing, IrregularTargetsNameTheRightPeriod) {
  const ReferenceHmc machine = with_screw();
  ReferencePlans plans;
  plans.noise = kNoise, plans.seed = 10, plans.line_step = 25.0, plans.irregular_targets = true;
  const identify::MeasurementSet data = reference_measurements(machine, measure_reference(machine, plans));
  const model::ForwardModel model(model::parse_machine_model(geometric_model(), "m.yaml"));
  const identify::Diagnosis d = identify::diagnose(model, data);
  const identify::Suggestion* s = periodic_x(d);
  ASSERT_NE(s, nullptr) << (d.suggestions.empty() ? d.unexplained : d.suggestions.front().spec);
  EXPECT_NEAR(s->period, 10.0, 0.1) << s->spec;
  EXPECT_TRUE(s->aliasing.empty()) << s->aliasing;
  const LoopResult loop = follow_the_loop(geometric_model(), data, 2);
  ASSERT_EQ(loop.added.size(), 1U) << ::testing::PrintToString(loop.added);
  const std::string& spec = loop.added.front();
  ASSERT_NE(spec.find("name: EXX, form: periodic, period: "), std::string::npos) << spec;
  EXPECT_NEAR(std::stod(spec.substr(spec.find("period: ") + 8)), 10.0, 0.1) << spec;
  EXPECT_LE(loop.last.rms_after, 1.3 * kNoise);
}

// simulate's laser lines: ISO 230-2's targets, P_i = (i - 1) p + r_i, irregular within a
// quarter of p, the travel's ends kept, and on no lattice of their spacing.
TEST(Aliasing, SimulatedLinesUseIrregularTargets) {
  const std::vector<double> t = identify::iso230_targets(-500.0, 500.0, 25.0);
  ASSERT_EQ(t.size(), 41U);
  EXPECT_EQ(t.front(), -500.0);
  EXPECT_EQ(t.back(), 500.0);
  int off_lattice = 0;
  for (std::size_t i = 1; i < t.size(); ++i) {
    EXPECT_GT(t[i], t[i - 1]);
    const double nominal = -500.0 + 25.0 * static_cast<double>(i);
    EXPECT_LE(std::abs(t[i] - nominal), 6.25 + 1e-9);
    if (std::abs(t[i] - nominal) > 1.0) ++off_lattice;
  }
  EXPECT_GE(off_lattice, 30);
}

}  // namespace
}  // namespace ccomp::test
