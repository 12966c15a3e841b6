// How far a fitted model may be trusted on a program, and the measurement that narrows it
// (issue 47, points 4 and 5), end to end on the reference machine written apart from
// ccomp's model code (tests/support/reference_hmc): a thin campaign (laser lines and a grid
// at B0, two spheres probed every 90 deg of B), a fit, the bound predict gives for a
// program cut at B 120, 180 and 240 and the extrapolation it names; the plan for that program,
// measured on the reference, appended, fitted again: the bound falls, and what the
// reference cuts running the program compensated with that model is within it.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numbers>
#include <random>
#include <string_view>

#include "ccomp/compensate/trust.hpp"
#include "ccomp/compensate/verify.hpp"
#include "ccomp/identify/fit.hpp"
#include "ccomp/identify/fit_information.hpp"
#include "ccomp/identify/plan.hpp"
#include "ccomp/identify/simulate.hpp"
#include "ccomp/model/model_file.hpp"
#include "job_runner.hpp"
#include "metrology_loop.hpp"
#include "reference_contour.hpp"
#include "reference_hmc.hpp"
#include "reference_measurements.hpp"
#include "trace_capture.hpp"

namespace ccomp::identify {
namespace {

constexpr double kNoise = 0.0002;  // mm

/// The sample's geometric model, its G54 the reference's program zero.
std::string sample_model(const test::ReferenceHmc& machine) {
  std::string text = test::read_file(test::source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml");
  const std::string g54 = "G54: {X: 0 mm, Y: 0 mm, Z: -400 mm}";
  const auto at = text.find(g54);
  EXPECT_NE(at, std::string::npos) << "the sample's work offset, to replace";
  const Eigen::Vector3d& o = machine.work_origin;
  if (at != std::string::npos) text.replace(at, g54.size(), fmt::format("G54: {{X: {}, Y: {}, Z: {}}}", o.x(), o.y(), o.z()));
  return text;
}

/// The model fitted to `data` as `ccomp fit` writes it, with its fit information.
std::string fitted(const std::string& text, const MeasurementSet& data) {
  const model::MachineModel m = without_free_spans(model::parse_machine_model(text, "model.yaml"));
  const model::ForwardModel forward(m);
  const FitReport r = fit(forward, data);
  EXPECT_TRUE(r.refusals.empty()) << r.refusals.front();
  std::vector<Eigen::VectorXd> per_term;
  for (std::size_t t = 0; t < m.terms.size(); ++t)
    per_term.push_back(
        r.all_parameters.segment(static_cast<Eigen::Index>(forward.parameter_offset(t)), m.terms[t].parameters.size()));
  return model::with_fit_information(model::rewrite_parameters(text, m, per_term, "{}", fitted_spans(m, data)),
                                     fit_information(forward, data, r));
}

/// A slanted rectangle cut at each of `angles` (deg), in the reference's program coordinates.
std::string program_at(const test::ReferenceHmc& machine, const std::vector<int>& angles) {
  const Eigen::Vector3d o = -machine.work_origin;  // machine zero in program coordinates
  std::string p = "G21 G17 G90 G94 G54\nT1 M6\nG43 H1\n";
  for (const int b : angles)
    p += fmt::format("G0 B{}\nG0 X{} Y{} Z{}\nG1 X{} F800\nG1 Y{} Z{}\nG1 X{}\nG1 Y{} Z{}\nG0 Z{}\n", b, o.x() - 250,
                     o.y() - 200, o.z() - 250, o.x() + 250, o.y() + 180, o.z() - 120, o.x() - 250, o.y() - 200,
                     o.z() - 250, o.z() - 400);
  return p + "M30\n";
}

/// The program's poses as predict sees them, through `gauge` and into `poses`.
void program_poses(const std::string& program, const model::ForwardModel& model, compensate::TrustGauge* gauge,
                   std::vector<ProgramPose>* poses) {
  compensate::CheckOptions o;
  o.interpreter.tools.tools[1] = test::kTool1;
  o.interpreter.tools.tools[2] = gcode::ToolEntry{2, 2, {0, 0, 160.0}, 10, ""};
  o.pose = [&](const model::ChainQ& q, const model::Conditions& c, std::uint32_t line) {
    if (gauge) gauge->add(q, c, line);
    if (poses) poses->push_back({q, c});
  };
  gcode::LineSource source = gcode::LineSource::from_string(program, "program.ngc");
  (void)compensate::predict(source, model, o);
}

compensate::ProgramTrust trust_of(const std::string& text, const std::string& program) {
  const model::MachineModel m = model::parse_machine_model(text, "fitted.yaml");
  const model::ForwardModel forward(m);
  compensate::TrustGauge gauge(forward, model::parse_fit_information(text, "fitted.yaml", m));
  program_poses(program, forward, &gauge, nullptr);
  return gauge.result();
}

/// The planned readings as the reference measures them (noise included).
std::vector<test::ReferenceReading> measured(const test::ReferenceHmc& machine, const MeasurementPlan& plan,
                                             unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, kNoise);
  std::vector<test::ReferenceReading> out;
  for (const PlannedGroup& g : plan.groups)
    for (const Observation& o : g.readings) {
      test::ReferenceReading r;
      r.x = o.q[0], r.y = o.q[1], r.z = o.q[2], r.b_deg = o.q[4] * 180.0 / std::numbers::pi;
      r.L = o.q[static_cast<Eigen::Index>(model::kToolLengthIndex)];
      for (std::size_t i = 0; i < 3; ++i) r.state.approach[i] = o.directions[i];
      r.direction = o.direction;
      r.value = o.direction.dot(machine.deviation(r.x, r.y, r.z, r.b_deg, r.L, r.state)) + noise(rng);
      r.source = g.source;
      out.push_back(r);
    }
  return out;
}

TEST(TrustAndPlan, AThinCampaignsBoundIsNamedAsExtrapolationAndThePlanNarrowsItAndHolds) {
  const test::ReferenceHmc machine = test::geometric_reference();
  test::ReferencePlans thin;
  thin.noise = kNoise, thin.seed = 5, thin.sphere_step = 90;  // two spheres, every 90 deg
  const std::vector<test::ReferenceReading> campaign = test::measure_reference(machine, thin);
  const std::string base = sample_model(machine);
  const std::string first = fitted(base, test::reference_measurements(machine, campaign));
  const std::string program = program_at(machine, {120, 180, 240});
  const compensate::ProgramTrust before = trust_of(first, program);
  ASSERT_TRUE(before.known);
  std::string named;
  for (const std::string& e : before.extrapolation) named += e + "\n";
  // Between the spheres' angles (90 180 270) nothing else was read: the program's B 120-240.
  EXPECT_NE(named.find("B 120-270: only sphere (6 readings) measured there"), std::string::npos) << named;
  // The plan for it, measured on the reference, appended, fitted again.
  const model::MachineModel m1 = model::parse_machine_model(first, "fitted.yaml");
  const model::ForwardModel f1(m1);
  std::vector<ProgramPose> poses;
  program_poses(program, f1, nullptr, &poses);
  PlanOptions options;
  options.budget = 400;
  const MeasurementPlan plan = plan_measurements(f1, test::reference_measurements(machine, campaign), poses, options);
  ASSERT_FALSE(plan.groups.empty());
  EXPECT_LE(plan.readings, options.budget);
  EXPECT_LT(plan.after, 0.7 * plan.before);
  for (const PlannedGroup& g : plan.groups) EXPECT_NE(g.why.find(" -> "), std::string::npos) << g.why;
  std::vector<test::ReferenceReading> all = campaign;
  for (const test::ReferenceReading& r : measured(machine, plan, 17)) all.push_back(r);
  const std::string second = fitted(base, test::reference_measurements(machine, all));
  const compensate::ProgramTrust after = trust_of(second, program);
  EXPECT_LT(after.after_bound, 0.7 * before.after_bound);
  // Judged on the reference: the compensated program's true error within the bound (and
  // what the job itself leaves against the model, at its tolerance).
  constexpr double kTolerance = 0.0002;
  const std::vector<test::ContourSegment> path = test::nominal_contour(machine, program);
  compensate::JobReport job;
  const double cut = test::contour_error(
      machine, path, test::compensate(program, model::parse_machine_model(second, "fitted.yaml"), kTolerance, &job));
  EXPECT_LE(cut, after.after_bound + job.max_error_after) << "the bound holds";
  const double thin_cut = test::contour_error(
      machine, path, test::compensate(program, model::parse_machine_model(first, "fitted.yaml"), kTolerance));
  std::cout << fmt::format(
      "[ trust ] thin campaign: bound {:.3f} um, true {:.3f} um; plan {} readings in {} groups ({:.3f} -> {:.3f} um); "
      "after: bound {:.3f} um, true {:.3f} um\n",
      before.after_bound * 1e3, thin_cut * 1e3, plan.readings, plan.groups.size(), plan.before * 1e3,
      plan.after * 1e3, after.after_bound * 1e3, cut * 1e3);
  for (const PlannedGroup& g : plan.groups) std::cout << "  " << g.why << "\n";
  std::cout << named;
}

// The whole loop the issue asks for, end to end on a reference with an effect the sample
// model lacks (a 10 mm lead-screw error on X): a thin campaign, check's suggestions followed
// until nothing is missing, then the plan for three programs cut at B 0 to 270 measured and
// appended, refitted; each program compensated keeps at most 5% of its error judged on the
// reference, and the bound predict gave for it holds.
TEST(TrustAndPlan, AThinCampaignTheLoopThenThePlanForThreeProgramsLeaveEachUnderFivePercent) {
  test::ReferenceHmc machine = test::geometric_reference();
  const auto polynomial = machine.EXX;
  machine.EXX = [polynomial](double x) {
    return polynomial(x) + 0.0018 * std::cos(2 * std::numbers::pi * x / 10.0) -
           0.0009 * std::sin(2 * std::numbers::pi * x / 10.0);
  };
  test::ReferencePlans thin;
  thin.noise = kNoise, thin.seed = 23, thin.sphere_step = 90, thin.line_step = 2.5, thin.irregular_targets = true;
  const std::vector<test::ReferenceReading> campaign = test::measure_reference(machine, thin);
  const MeasurementSet first_data = test::reference_measurements(machine, campaign);
  const test::LoopResult loop = test::follow_the_loop(sample_model(machine), first_data);
  ASSERT_TRUE(loop.refusals.empty()) << loop.refusals.front();
  ASSERT_FALSE(loop.added.empty()) << "the lead screw is missing from the sample's model";
  EXPECT_NE(loop.added.front().find("name: EXX, form: periodic"), std::string::npos) << loop.added.front();
  const std::string looped = fitted(loop.text, first_data);
  const std::vector<std::string> programs = {program_at(machine, {0, 60}), program_at(machine, {135, 170}),
                                             program_at(machine, {220, 270})};
  const model::MachineModel m1 = model::parse_machine_model(looped, "looped.yaml");
  const model::ForwardModel f1(m1);
  std::vector<ProgramPose> poses;
  for (const std::string& program : programs) program_poses(program, f1, nullptr, &poses);
  PlanOptions options;
  options.budget = 500;
  const MeasurementPlan plan = plan_measurements(f1, first_data, poses, options);
  ASSERT_FALSE(plan.groups.empty());
  EXPECT_LE(plan.readings, options.budget);
  std::vector<test::ReferenceReading> all = campaign;
  for (const test::ReferenceReading& r : measured(machine, plan, 29)) all.push_back(r);
  const std::string second = fitted(loop.text, test::reference_measurements(machine, all));
  constexpr double kTolerance = 0.0002;
  double worst_thin = 0.0;  // what the loop's model alone leaves, of the error before
  for (std::size_t i = 0; i < programs.size(); ++i) {
    const compensate::ProgramTrust trust = trust_of(second, programs[i]);
    ASSERT_TRUE(trust.known);
    const std::vector<test::ContourSegment> path = test::nominal_contour(machine, programs[i]);
    const double before = test::contour_error(machine, path, programs[i]);
    compensate::JobReport job;
    const double after = test::contour_error(
        machine, path,
        test::compensate(programs[i], model::parse_machine_model(second, "fitted.yaml"), kTolerance, &job));
    const double thin_after = test::contour_error(
        machine, path, test::compensate(programs[i], model::parse_machine_model(looped, "looped.yaml"), kTolerance));
    worst_thin = std::max(worst_thin, thin_after / before);
    EXPECT_LE(after, 0.05 * before) << "program " << i << ": before " << before * 1e3 << " um, after "
                                    << after * 1e3 << " um";
    EXPECT_LE(after, trust.after_bound + job.max_error_after) << "program " << i << ": the bound holds";
    std::cout << fmt::format("[ loop+plan ] program {}: before {:.3f} um, after {:.3f} um ({:.1f}%; the loop's model alone {:.1f}%), "
                             "bound {:.3f} um\n",
                             i, before * 1e3, after * 1e3, 100 * after / before, 100 * thin_after / before,
                             trust.after_bound * 1e3);
  }
  EXPECT_GT(worst_thin, 0.05) << "the thin campaign alone leaves more than 5% on one program: the plan is what helps";
  std::cout << fmt::format("[ loop+plan ] loop added {} term(s); plan {} readings in {} groups ({:.3f} -> {:.3f} um)\n",
                           loop.added.size(), plan.readings, plan.groups.size(), plan.before * 1e3, plan.after * 1e3);
}

/// Every reading of `group` has the nominal tool tip on one point of the table, within the
/// axes' limits; the angles of the rotary axes `rotary` it is probed at, in degrees.
std::vector<double> probed_on_one_point(const model::ForwardModel& model, const PlannedGroup& group,
                                        const std::vector<Eigen::Index>& rotary) {
  model::ForwardData fd(model);
  model::forward(model, fd, group.readings.front().q, {}, false, model::Evaluate::nominal);
  const Eigen::Vector3d centre = fd.nominal;
  std::vector<double> angles;
  for (const Observation& o : group.readings) {
    model::forward(model, fd, o.q, {}, false, model::Evaluate::nominal);
    EXPECT_LT((fd.nominal - centre).norm(), 1e-6) << group.source << ": one point of the table";
    for (const Eigen::Index r : rotary) angles.push_back(o.q[r] / (std::numbers::pi / 180));
    for (const model::AxisSpec& axis : model.machine().axes) {  // where the machine reaches
      const auto j = static_cast<Eigen::Index>(std::string_view("XYZABCUVW").find(axis.letter));
      const double v = axis.type == model::AxisType::rotary ? o.q[j] * 180 / std::numbers::pi : o.q[j];
      EXPECT_GE(v, axis.min - 1e-9) << axis.letter;
      EXPECT_LE(v, axis.max + 1e-9) << axis.letter;
    }
  }
  return angles;
}

// A program that turns the table through many angles is best served by a sphere probed as
// the table turns (ISO 10791-6): 3 readings an angle against a grid's 81 or a line's 22 at
// one. The plan offers it, on the table where the program cuts, over the program's turn.
TEST(TrustAndPlan, AProgramTurningThroughManyAnglesIsPlannedASphereProbedAsTheTableTurns) {
  const test::ReferenceHmc machine = test::geometric_reference();
  test::ReferencePlans thin;
  thin.noise = kNoise, thin.seed = 5, thin.sphere = false;  // lines and grids at B0 only
  const MeasurementSet data = test::reference_measurements(machine, test::measure_reference(machine, thin));
  const std::string first = fitted(sample_model(machine), data);
  const model::MachineModel m = model::parse_machine_model(first, "fitted.yaml");
  const model::ForwardModel f(m);
  std::vector<ProgramPose> poses;
  // Cut with two tools (100 and 160 mm): the sphere is placed for, and probed with, one probe.
  std::string program = program_at(machine, {0, 30, 60, 90, 120, 150, 180, 210, 240});
  program.replace(program.find("G0 B150"), 0, "T2 M6\nG43 H2\n");
  program_poses(program, f, nullptr, &poses);
  PlanOptions options;
  options.budget = 90;
  const MeasurementPlan plan = plan_measurements(f, data, poses, options);
  ASSERT_FALSE(plan.groups.empty());
  const PlannedGroup& sphere = plan.groups.front();
  EXPECT_EQ(sphere.kind, "probed sphere") << sphere.why;
  EXPECT_NE(sphere.why.find("fixed on the table"), std::string::npos) << sphere.why;
  const std::vector<double> angles = probed_on_one_point(f, sphere, {4});
  ASSERT_FALSE(angles.empty());
  // Over the program's turn (0-240), every 20 degrees, where the axes reach the sphere (with
  // the 160 mm probe, 8 of the 13 angles).
  const auto [least, most] = std::minmax_element(angles.begin(), angles.end());
  EXPECT_GE(*least, 0.0);
  EXPECT_LE(*most, 240.0);
  EXPECT_GE(*most - *least, 120.0);
  EXPECT_GE(angles.size(), 18U) << "six angles or more, three readings each";
  EXPECT_LT(plan.after, 0.5 * plan.before);
}

// Two rotary axes: the sphere is probed at combinations of both over the programs' ranges,
// each pose within the axes' limits (taken once the grids at the programs' settings are in).
TEST(TrustAndPlan, OnATrunnionTheSphereIsProbedOverBothRotaryAxesWithinTheirLimits) {
  const model::MachineModel m = model::parse_machine_model(
      test::read_file(test::source_dir() + "/samples/machines/vmc-xyzac-trunnion.yaml"), "vmc.yaml");
  const model::ForwardModel f(m);
  SimulateOptions lines;
  lines.plans = {Plan::nine_lines};
  const MeasurementSet data = simulate(f, lines);
  std::vector<ProgramPose> poses;
  for (const double a : {-30.0, 0.0, 30.0, 60.0})
    for (const double c : {0.0, 90.0, 180.0, 270.0}) {
      ProgramPose pose;
      pose.q = model::ChainQ::Zero();
      pose.q << 20, -10, -150, a * std::numbers::pi / 180, 0, c * std::numbers::pi / 180, 0, 0, 0, 100;
      for (const double x : {-40.0, 40.0}) {
        pose.q[0] = x;
        poses.push_back(pose);
      }
    }
  PlanOptions options;
  options.budget = 400;
  const MeasurementPlan plan = plan_measurements(f, data, poses, options);
  ASSERT_FALSE(plan.groups.empty());
  const auto sphere = std::find_if(plan.groups.begin(), plan.groups.end(),
                                   [](const PlannedGroup& g) { return g.kind == "probed sphere"; });
  ASSERT_NE(sphere, plan.groups.end()) << plan.groups.front().why;
  const std::vector<double> angles = probed_on_one_point(f, *sphere, {3, 5});
  std::vector<double> a, c;
  for (std::size_t k = 0; k < angles.size(); k += 2) a.push_back(angles[k]), c.push_back(angles[k + 1]);
  // Both axes over the whole of the programs' range: A -30..60, C 0..270.
  EXPECT_NEAR(*std::min_element(a.begin(), a.end()), -30.0, 1e-9);
  EXPECT_NEAR(*std::max_element(a.begin(), a.end()), 60.0, 1e-9);
  EXPECT_NEAR(*std::min_element(c.begin(), c.end()), 0.0, 1e-9);
  EXPECT_NEAR(*std::max_element(c.begin(), c.end()), 270.0, 1e-9);
  EXPECT_LE(angles.size() / 2, 3U * 25U) << "25 poses at most, three readings each";
}

// The fit's information survives the model file: written by fit, read with the model, the
// same numbers; a file whose terms were edited since is refused by name; a model without
// it gives no bound rather than one invented.
TEST(TrustAndPlan, TheFitInformationIsReadBackAndAModelWithoutItHasNoBound) {
  const test::ReferenceHmc machine = test::geometric_reference();
  test::ReferencePlans plans;
  plans.noise = kNoise, plans.seed = 3, plans.sphere_step = 30;
  const MeasurementSet data = test::reference_measurements(machine, test::measure_reference(machine, plans));
  const std::string base = sample_model(machine);
  const model::MachineModel m = without_free_spans(model::parse_machine_model(base, "model.yaml"));
  const model::ForwardModel forward(m);
  const FitReport r = fit(forward, data);
  const model::FitInformation info = fit_information(forward, data, r);
  const std::string text = model::with_fit_information(base, info);
  const model::MachineModel read = model::parse_machine_model(text, "fitted.yaml");
  const std::optional<model::FitInformation> read_back = model::parse_fit_information(text, "fitted.yaml", read);
  ASSERT_TRUE(read_back.has_value());
  const model::FitInformation& back = *read_back;
  ASSERT_EQ(back.parameters.size(), info.parameters.size());
  EXPECT_EQ(back.parameters.back().label, info.parameters.back().label);
  EXPECT_LT((back.covariance_factor - info.covariance_factor).cwiseAbs().maxCoeff(),
            1e-9 * info.covariance_factor.cwiseAbs().maxCoeff());
  EXPECT_NEAR(back.noise, info.noise, 1e-12);
  ASSERT_EQ(back.coverage.size(), info.coverage.size());
  EXPECT_EQ(back.coverage[3].bins[6].total(), info.coverage[3].bins[6].total());  // B 180-210: the spheres
  EXPECT_GT(info.coverage[3].bins[6].total(), 0u);
  // A term taken out after the fit: its parameters no longer name what they did.
  std::string edited = text;
  const auto at = edited.find("name: EC0B");
  ASSERT_NE(at, std::string::npos);
  edited.erase(edited.rfind('\n', at) + 1, edited.find('\n', at) - edited.rfind('\n', at));
  try {
    (void)model::parse_machine_model(edited, "edited.yaml");
    ADD_FAILURE() << "a fit information naming a term the file no longer has is refused";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::model);
    EXPECT_NE(e.message().find("edited after its fit"), std::string::npos) << e.message();
  }
  // New values (another fit, nine-line) drop the section: it described the old ones.
  const std::string again = model::rewrite_parameters(text, read, {}, "{}");
  EXPECT_FALSE(model::parse_fit_information(again, "again.yaml", model::parse_machine_model(again, "again.yaml")));
  const compensate::ProgramTrust none = trust_of(base, program_at(machine, {0}));
  EXPECT_FALSE(none.known);
  EXPECT_EQ(compensate::trust_text(none), "no fit information: bound unknown");
}

}  // namespace
}  // namespace ccomp::identify
