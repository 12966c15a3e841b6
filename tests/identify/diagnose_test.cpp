// Discovery on data with a hidden effect: the truth is the geometric HMC plus one effect;
// the base model (the geometric HMC, its terms free) lacks it. check must rank the effect
// first with the right term, variable and form (and period within 2%); fitting with the
// suggested term must bring the residual to the noise; on data with no hidden effect
// nothing is suggested.
#include "ccomp/identify/diagnose.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "ccomp/identify/check.hpp"
#include "ccomp/identify/fit.hpp"
#include "ccomp/identify/simulate.hpp"
#include "ccomp/model/model_file.hpp"
#include "trace_capture.hpp"

namespace ccomp::identify {
namespace {

// What check prints of a suggestion's scanned value names it and its unit: a place is not a
// period, a table's period is in degrees, a warm-up's time constant in seconds.
TEST(ScannedValueText, NamesTheValueAndItsUnit) {
  Suggestion s;
  s.form = "periodic", s.variable = "x", s.period = 9.99973, s.period_uncertainty = 0.0002;
  EXPECT_EQ(scanned_value_text(s), "period 9.99973 +- 0.0002 mm");
  s.variable = "b", s.period = 7.5, s.period_uncertainty = 0.01;
  EXPECT_EQ(scanned_value_text(s), "period 7.5 +- 0.01 deg");
  s.form = "harmonic", s.period = 120.0, s.period_uncertainty = 0.0;
  EXPECT_EQ(scanned_value_text(s), "period 120 deg") << "a harmonic's period is fixed";
  s.form = "exponential", s.variable = "t", s.period = 2400.0, s.period_uncertainty = 52.0;
  EXPECT_EQ(scanned_value_text(s), "time constant 2400 +- 52 s");
  s.form = "bump", s.variable = "y", s.period = -50.0, s.period_uncertainty = 0.41;
  EXPECT_EQ(scanned_value_text(s), "at -50 +- 0.41 mm") << "a local defect's place, wherever it is";
  s.form = "reversal", s.variable = "vx", s.period = 0.0;
  EXPECT_EQ(scanned_value_text(s), "");
}

constexpr double kNoise = 0.0002;  // 0.2 um

struct Hidden {
  const char* name;
  const char* truth_term;  // added to the truth
  std::vector<Plan> plans;
  double step = 25.0, rotary_step = 15.0;
  const char* term;  // what check must name
  const char* variable;
  const char* form;
  double period = 0.0;               // periodic forms (mm, deg), warm-up (s)
  std::vector<const char*> fixed{};  // base terms held at the truth (so they cannot stand in)
  const char* removed = nullptr;     // a term of the truth the base lacks
  bool fix_all = false;              // hold every base term at the truth: on this machine free ones could stand in
};

std::ostream& operator<<(std::ostream& os, const Hidden& h) {
  return os << h.name;
}

/// The geometric HMC with the three sensors of the full one, so thermal effects can be read.
std::string truth_base() {
  return test::read_file(test::source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml") +
         "sensors: [bed, column, spindle]\n";
}

/// The base model's text: the truth's base without the term the case removes.
std::string base_text(const Hidden& h) {
  std::string text = truth_base();
  if (h.removed) {
    const auto at = text.find(std::string("{name: ") + h.removed + ",");
    const auto begin = text.rfind('\n', at) + 1, end = text.find('\n', at) + 1;
    text.erase(begin, end - begin);
  }
  return text;
}

/// The base terms held at the truth; a term the check suggests stays free.
model::MachineModel with_fixed(model::MachineModel m, const Hidden& h, std::size_t base_terms) {
  for (std::size_t i = 0; i < m.terms.size() && i < base_terms; ++i) {
    if (h.fix_all) m.terms[i].free = false;
    for (const char* fixed : h.fixed)
      if (m.terms[i].iso == fixed) m.terms[i].free = false;
  }
  return m;
}

model::MachineModel base_model(const Hidden& h) {
  const model::MachineModel m = model::parse_machine_model(base_text(h), "base.yaml");
  return with_fixed(m, h, m.terms.size());
}

MeasurementSet measure(const Hidden& h, unsigned seed) {
  const std::string truth_text = h.truth_term ? model::add_terms(truth_base(), {h.truth_term}, "truth") : truth_base();
  const model::ForwardModel truth(model::parse_machine_model(truth_text, "truth.yaml"));
  SimulateOptions o;
  o.plans = h.plans;
  o.noise = kNoise;
  o.seed = seed;
  o.step = h.step;
  o.rotary_step = h.rotary_step;
  o.warm_temperatures = {26.0, 24.0, 32.0};
  return simulate(truth, o);
}

class HiddenEffect : public ::testing::TestWithParam<Hidden> {};

TEST_P(HiddenEffect, IsRankedFirstAndFittingItReachesTheNoise) {
  const Hidden& h = GetParam();
  const MeasurementSet data = measure(h, 11);
  const model::MachineModel base = base_model(h);
  const Diagnosis d = diagnose(model::ForwardModel(base), data);
  ASSERT_FALSE(d.suggestions.empty()) << h.name << ": nothing suggested; refit rms " << d.rms_refit * 1e3 << " um";
  const Suggestion& top = d.suggestions.front();
  EXPECT_EQ(top.term, h.term) << top.effect;
  EXPECT_EQ(top.variable, h.variable) << top.effect;
  EXPECT_EQ(top.form, h.form) << top.effect;
  // A period within 2%; a warm-up's time constant within three of its standard deviations
  // (four hours of readings pin 20 minutes to about 5%).
  if (h.period > 0) {
    const double allowed = top.form == "exponential" ? 3 * top.period_uncertainty : 0.02 * h.period;
    EXPECT_NEAR(top.period, h.period, allowed) << top.effect;
  }
  // What is left with the effect added, per reading: the rms the suggestion reports (to
  // the rounding of the base's projector, whose weakest kept directions sit just above the
  // noise: a few parts in a million).
  ASSERT_EQ(top.residual.size(), static_cast<Eigen::Index>(data.observations.size()));
  EXPECT_NEAR(std::sqrt(top.residual.squaredNorm() / static_cast<double>(top.residual.size())), top.rms_after,
              1e-5 * top.rms_after);
  // Add what check suggests, fit, and the residual is the noise.
  const std::string with = model::add_terms(base_text(h), {top.spec}, "with.yaml");
  const FitReport r =
      fit(model::ForwardModel(with_fixed(model::parse_machine_model(with, "with.yaml"), h, base.terms.size())), data);
  EXPECT_LE(r.rms_after, 1.3 * kNoise) << h.name << ": " << top.spec;
  // What is scored is what is suggested: the spec, fitted, gives the rms it was scored with
  // (within 5%: the spec's values are rounded to four digits, the fit starts from them).
  EXPECT_NEAR(r.rms_after, top.rms_after, 0.05 * top.rms_after) << h.name << ": " << top.spec;
  // And it predicts readings it was not fitted to nearly as well as those it was.
  EXPECT_GT(top.held_out, 0.8) << h.name << ": held out by " << top.held_out_by;
}

INSTANTIATE_TEST_SUITE_P(
    Candidates, HiddenEffect,
    ::testing::Values(Hidden{"screw",
                             "{name: EXX, form: periodic, period: 10 mm, unit: um, harmonics: [[1.5, -1.0]]}",
                             {Plan::nine_lines},
                             2.0,
                             15.0,
                             "EXX",
                             "x",
                             "periodic",
                             10.0},
                      Hidden{"reversal",
                             "{name: EYY, variable: vy, form: reversal, unit: um, reversal: -4}",
                             {Plan::nine_lines},
                             25.0,
                             15.0,
                             "EYY",
                             "vy",
                             "reversal"},
                      Hidden{"higher_order",
                             "{name: EYX, form: polynomial, unit: um, coefficients: [0, 0, 0, 2.0e-8]}",
                             {Plan::nine_lines},
                             25.0,
                             15.0,
                             "EYX",
                             "x",
                             "polynomial"},
                      // The X carriage's constant yaw would stand in for its squareness: the base holds it.
                      Hidden{"squareness",
                             nullptr,
                             {Plan::nine_lines, Plan::grid},
                             25.0,
                             15.0,
                             "EC0X",
                             "x",
                             "polynomial",
                             0.0,
                             {},
                             "EC0X",
                             true},
                      // Carriage and table angles would stand in for a spindle tilt: the base holds them.
                      Hidden{"spindle_tilt",
                             "{name: EA0S, value: 25, unit: urad}",
                             {Plan::grid},
                             25.0,
                             15.0,
                             "EA0S",
                             "L",
                             "linear",
                             0.0,
                             {},
                             nullptr,
                             true},
                      Hidden{"table_harmonic",
                             "{name: EXB, form: periodic, period: 180 deg, unit: um, harmonics: [[3, -2]]}",
                             {Plan::sphere},
                             25.0,
                             15.0,
                             "EXB",
                             "b",
                             "harmonic",
                             180.0},
                      Hidden{"worm_wheel",
                             "{name: EBB, form: periodic, period: 4 deg, unit: urad, harmonics: [[6, 4]]}",
                             {Plan::sphere},
                             25.0,
                             0.5,
                             "EBB",
                             "b",
                             "periodic",
                             4.0},
                      Hidden{"thermal_drift",
                             "{name: EZS, variable: T_spindle, form: thermal, unit: um, coefficient: 1.5}",
                             {Plan::thermal},
                             25.0,
                             15.0,
                             "EZS",
                             "T_spindle",
                             "linear"},
                      // (Quicker than any sensor warms: 40 minutes would be the bed sensor's own curve.)
                      Hidden{"warm_up",
                             "{name: EYS, variable: t, form: warmup, unit: um, amplitude: 6, time_constant: 1200 s}",
                             {Plan::thermal},
                             25.0,
                             15.0,
                             "EYS",
                             "t",
                             "exponential",
                             1200.0},
                      Hidden{"scale_expansion",
                             "{name: EXX, form: scale_expansion, temperature: T_bed, coefficient: 1.15e-5 /degC}",
                             {Plan::thermal, Plan::nine_lines},
                             25.0,
                             15.0,
                             "EXX",
                             "x,T_bed",
                             "interaction"},
                      // (A yaw of Z growing with x is the X yaw's slope on this layout; a pitch is not, but
                      // X's positioning growing with z plus its straightness would stand in: the base holds.)
                      Hidden{"cross_axis",
                             "{name: EBZ, form: cross_axis, other: x, unit: urad, coefficients: [[0.03]]}",
                             {Plan::grid},
                             25.0,
                             15.0,
                             "EBZ",
                             "z,x",
                             "interaction",
                             0.0,
                             {},
                             nullptr,
                             true}),
    [](const ::testing::TestParamInfo<Hidden>& param) { return std::string(param.param.name); });

TEST(HiddenEffect, NoHiddenEffectNoSuggestion) {
  for (unsigned seed : {21U, 22U, 23U}) {
    const Hidden none{"none", nullptr, {Plan::nine_lines, Plan::grid, Plan::sphere}, 25.0, 15.0, "", "", ""};
    const Diagnosis d = diagnose(model::ForwardModel(base_model(none)), measure(none, seed));
    EXPECT_TRUE(d.suggestions.empty()) << "seed " << seed << ": suggested " << d.suggestions.front().spec << " (BIC "
                                       << d.suggestions.front().bic_delta << ")";
    EXPECT_GT(d.candidates_tried, 50U);
  }
}

}  // namespace
}  // namespace ccomp::identify

namespace ccomp::identify {
namespace {

/// A 3-axis machine whose model has only X's positioning, free.
const model::MachineModel& two_line_machine() {
  static const model::MachineModel m = model::parse_machine_model(
      "name: two\naxes:\n  X: {min: -400, max: 400}\n  Y: {min: -250, max: 250}\n  Z: {min: -400, max: 400}\n"
      "chain:\n  workpiece: [{link: Y, axis: Y, direction: [0, -1, 0]}, {link: X, axis: X, direction: [-1, 0, 0]}]\n"
      "  tool: [{link: Z, axis: Z, offset: [0, 0, 600], direction: [0, 0, 1]}, {link: tool, tool_length: [0, 0, -1]}]\n"
      "terms:\n  - {name: EXX, form: polynomial, unit: um, coefficients: [0, 0], fit: true}\n",
      "two.yaml");
  return m;
}

/// X's positioning along X, and Y's along Y, read at one y and one x: the model fits X's
/// line exactly; Y's readings carry what it lacks, `y_error(y, approach)` (mm).
MeasurementSet two_lines(double (*y_error)(double, double)) {
  std::mt19937 random(11);
  std::normal_distribution<double> noise(0.0, 1e-4);
  std::string csv = "x,y,z,vx,vy,nx,ny,nz,d,source\n";
  for (const double way : {1.0, -1.0}) {
    for (int k = -80; k <= 80; ++k)
      csv += fmt::format("{},0,0,{},0,1,0,0,{:.8e},x-pos\n", 5.0 * k * way, way, 1e-5 * 5.0 * k * way + noise(random));
    for (int k = -50; k <= 50; ++k) {
      const double y = 5.0 * k * way;
      csv += fmt::format("0,{},0,0,{},0,1,0,{:.8e},y-pos\n", y, way, y_error(y, way) + noise(random));
    }
  }
  const model::MachineModel& m = two_line_machine();
  MeasurementSet data;
  parse_measurements(csv, "two.csv", m, {}, data);
  return data;
}

// Only Y's line varies along y, and all of it carries Y's reversal the model lacks: every bin
// along y stands above the rest alike, which says which readings, not where. A bump at one
// place along Y's line is where, and is said.
TEST(Diagnose, WhereTheResidualConcentratesIsAPlaceNotAReadingsSet) {
  const model::MachineModel& m = two_line_machine();
  auto along_y = [](const Diagnosis& d) {
    return std::count_if(d.regions.begin(), d.regions.end(), [](const Region& r) { return r.variable == "y"; });
  };
  const Diagnosis reversal =
      diagnose(model::ForwardModel(m), two_lines([](double, double way) { return 0.002 * way; }));
  EXPECT_EQ(along_y(reversal), 0);
  const Diagnosis bump = diagnose(model::ForwardModel(m), two_lines([](double y, double) {
                                    return std::abs(y - 150.0) < 25.0 ? 0.004 : 0.0;
                                  }));
  EXPECT_GE(along_y(bump), 1);
}

}  // namespace
}  // namespace ccomp::identify
