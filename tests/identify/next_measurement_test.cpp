// Which measurement next: a thermal drift that follows the spindle's temperature and one
// that follows the time since the start explain a warm-up run alike; check names the tie
// and the run that would separate them, and says nothing where the data already decide.
#include "ccomp/identify/next_measurement.hpp"

#include <gtest/gtest.h>

#include "ccomp/identify/simulate.hpp"
#include "ccomp/model/model_file.hpp"
#include "sample_models.hpp"
#include "trace_capture.hpp"

namespace ccomp::identify {
namespace {

TEST(NextMeasurement, SaysWhatSeparatesEachKindOfPair) {
  EXPECT_NE(separating_measurement("T_spindle", "t").find("cool-down"), std::string::npos);
  EXPECT_NE(separating_measurement("t", "T_bed").find("T_bed and the time since the start"), std::string::npos);
  EXPECT_NE(separating_measurement("T_bed", "T_spindle").find("heat one source alone"), std::string::npos);
  EXPECT_NE(separating_measurement("x,z", "x").find("readings along x at several z"), std::string::npos);
  EXPECT_NE(separating_measurement("x", "x").find("more of its range"), std::string::npos);
}

TEST(NextMeasurement, SaysWhatSeparatesTwoParametersAFitCouldNot) {
  const model::MachineModel m = model::parse_machine_model(
      test::read_file(test::source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml"), "hmc.yaml");
  const auto term = [&](const std::string& name) {
    for (std::size_t t = 0; t < m.terms.size(); ++t)
      if (m.terms[t].name == name) return t;
    ADD_FAILURE() << "no term " << name;
    return std::size_t{0};
  };
  // Constant offsets of the position: nothing separates them, a work offset takes them.
  const std::string offsets = separating_parameters(m, {term("EXX"), 0}, {term("EXZ"), 0});
  EXPECT_NE(offsets.find("nothing"), std::string::npos) << offsets;
  EXPECT_NE(offsets.find("work offset"), std::string::npos) << offsets;
  // An angle against an offset: another arm (tool length) tells them apart.
  const std::string arm = separating_parameters(m, {term("EC0X"), 0}, {term("EYY"), 0});
  EXPECT_NE(arm.find("tool lengths L"), std::string::npos) << arm;
  EXPECT_NE(arm.find("angle EC0X"), std::string::npos) << arm;
  // A slope along x against a constant: readings at several x.
  const std::string slope = separating_parameters(m, {term("EXX"), 1}, {term("EYY"), 0});
  EXPECT_NE(slope.find("at several x"), std::string::npos) << slope;
  // Two variables: the candidates' wording.
  const std::string two = separating_parameters(m, {term("EXX"), 1}, {term("EYZ"), 1});
  EXPECT_NE(two.find("readings along"), std::string::npos) << two;
}

TEST(NextMeasurement, AWarmUpRunCannotTellTheSpindlesTemperatureFromTheTime) {
  const std::string base = test::read_file(test::source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml");
  std::string truth = base + "sensors: [spindle]\n";
  truth.replace(truth.find("terms:\n"), 7,
                "terms:\n  - {name: EZS, variable: T_spindle, form: thermal, unit: um, coefficient: 2.5}\n");
  SimulateOptions o;
  o.plans = {Plan::thermal, Plan::nine_lines};
  o.seed = 3;
  const MeasurementSet data = simulate(model::ForwardModel(model::parse_machine_model(truth, "truth.yaml")), o);
  const Diagnosis d = diagnose(model::ForwardModel(model::parse_machine_model(base, "base.yaml")), data);
  ASSERT_GE(d.suggestions.size(), 2U);
  ASSERT_FALSE(d.ties.empty()) << d.suggestions[0].spec << " / " << d.suggestions[1].spec;
  const Tie& t = d.ties.front();
  const std::string pair = d.suggestions[t.first].variable + " " + d.suggestions[t.second].variable;
  EXPECT_TRUE(pair == "T_spindle t" || pair == "t T_spindle") << pair;
  EXPECT_GT(t.correlation, 0.9);
  EXPECT_NE(t.measurement.find("cool-down"), std::string::npos) << t.measurement;
}

TEST(NextMeasurement, WhereTheDataDecideThereIsNoTie) {
  // A lead-screw error along X alone: nothing else explains it.
  const std::string base = test::read_file(test::source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml");
  const std::string truth = model::add_terms(
      base, {"{name: EXX, form: periodic, period: 10 mm, unit: um, harmonics: [[1.5, -1.0]]}"}, "truth.yaml");
  SimulateOptions o;
  o.plans = {Plan::nine_lines};
  o.step = 2.5;
  const MeasurementSet data = simulate(model::ForwardModel(model::parse_machine_model(truth, "truth.yaml")), o);
  const Diagnosis d = diagnose(model::ForwardModel(model::parse_machine_model(base, "base.yaml")), data);
  ASSERT_FALSE(d.suggestions.empty());
  EXPECT_TRUE(d.ties.empty()) << d.ties.front().measurement;
}

}  // namespace
}  // namespace ccomp::identify
