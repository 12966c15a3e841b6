// Identification on simulated data: the fit recovers a model to the noise, does not fit
// noise (nor step into it), says what the data cannot see, fits a period when allowed,
// hands over its design matrix, resists outliers with the robust loss, and writes its
// result back into the model file.
#include "ccomp/identify/fit.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <fstream>
#include <random>
#include <sstream>

#include "ccomp/error.hpp"
#include "ccomp/identify/check.hpp"
#include "ccomp/identify/simulate.hpp"
#include "ccomp/model/model_file.hpp"
#include "error_of.hpp"
#include "sample_models.hpp"
#include "trace_capture.hpp"

namespace ccomp::identify {
namespace {

constexpr double kNoise = 0.0002;  // 0.2 um

model::MachineModel geometric() {
  return model::load_machine_model(test::source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml");
}

/// The model with every free term's amplitudes at zero: nothing known yet (a period or a
/// time constant stays: it is the mechanism's).
model::MachineModel blank(model::MachineModel m) {
  for (model::ErrorTermSpec& t : m.terms) {
    if (!t.free) continue;
    for (Eigen::Index k = 0; k < t.parameters.size(); ++k) {
      const bool scale = (t.shape.form == model::TermForm::periodic && k == 0) ||
                         (t.shape.form == model::TermForm::thermal_warmup && k == 1);
      if (!scale) t.parameters[k] = 0.0;
    }
  }
  return m;
}

MeasurementSet measure(const model::MachineModel& truth, std::vector<Plan> plans, unsigned seed, double step = 25.0) {
  const model::ForwardModel f(truth);
  SimulateOptions o;
  o.plans = std::move(plans);
  o.noise = kNoise;
  o.seed = seed;
  o.step = step;
  return simulate(f, o);
}

double truth_value(const model::ForwardModel& truth, const FittedParameter& p) {
  return truth.machine().terms[p.term].parameters[static_cast<Eigen::Index>(p.index - truth.parameter_offset(p.term))];
}

TEST(Fit, RecoversTheGeometricModelToTheNoise) {
  const model::MachineModel truth = geometric();
  const model::ForwardModel t(truth);
  const MeasurementSet data = measure(truth, {Plan::nine_lines, Plan::grid, Plan::sphere}, 3);
  const model::MachineModel start = blank(truth);
  const model::ForwardModel s(start);
  const FitReport r = fit(s, data);
  EXPECT_TRUE(r.converged);
  EXPECT_GT(r.rms_before, 0.010) << "the blank model misses tens of um";
  EXPECT_LE(r.rms_after, 1.3 * kNoise);
  EXPECT_GT(r.significant, 30U);
  // Every parameter the data determine on its own lands within 5 of its standard
  // deviations of the truth.
  int checked = 0;
  for (const FittedParameter& p : r.parameters) {
    if (!p.identified) continue;
    ++checked;
    EXPECT_LE(std::abs(p.after - truth_value(t, p)), 5 * p.uncertainty + 1e-12)
        << p.label << ": " << p.after << " vs " << truth_value(t, p) << " +- " << p.uncertainty;
  }
  EXPECT_GT(checked, 20);
  const CheckReport c = check(model::ForwardModel(truth), data);
  EXPECT_NEAR(c.noise_floor, kNoise, 0.25 * kNoise) << c.noise_method;
}

TEST(Fit, DoesNotFitNoise) {
  const model::MachineModel truth = geometric();
  const model::ForwardModel t(truth);
  for (unsigned seed : {1U, 2U}) {
    const FitReport r = fit(t, measure(truth, {Plan::nine_lines, Plan::grid}, seed));
    EXPECT_EQ(r.significant, 0U) << "the truth is already right: nothing moves";
    for (const FittedParameter& p : r.parameters) EXPECT_EQ(p.after, p.before) << p.label;
  }
}

TEST(Fit, SaysWhatTheDataCannotSeeAndLeavesItAlone) {
  // Laser lines at B = 0 cannot see the table's sine harmonics (sin 0 = 0), nor tell a
  // table's cosine term from the carriages' constant offsets.
  const model::MachineModel truth = geometric();
  const model::ForwardModel s(blank(truth));
  const FitReport r = fit(s, measure(truth, {Plan::nine_lines}, 4));
  bool unseen = false;
  for (const std::string& u : r.unidentifiable)
    unseen = unseen || (u.find("EBB.b1") != std::string::npos && u.find("no effect") != std::string::npos);
  EXPECT_TRUE(unseen) << "EBB.b1 should be named as invisible";
  // Each combination the lines cannot separate says what would: here readings with B turned.
  std::size_t combinations = 0;
  for (const std::string& u : r.unidentifiable) {
    if (u.find("cannot separate") == std::string::npos) continue;
    ++combinations;
    EXPECT_NE(u.find("; to separate them: "), std::string::npos) << u;
  }
  EXPECT_GE(combinations, 1U);
  bool turn_b = false;
  for (const std::string& u : r.unidentifiable) turn_b = turn_b || u.find("at several b") != std::string::npos;
  EXPECT_TRUE(turn_b) << "the table's cosine term against constant offsets: readings at several B";
  for (const FittedParameter& p : r.parameters) {
    if (p.label == "EBB.b1") {
      EXPECT_EQ(p.after, 0.0);
    }
  }
  EXPECT_LT(r.rank, r.parameters.size());
  EXPECT_LE(r.rms_after, 1.3 * kNoise) << "what the lines do see is fitted";
}

TEST(Fit, FitsAPeriodWhenTheFileAllows) {
  auto model = [](const char* period, const char* harmonics, bool fit_period) {
    return model::parse_machine_model(
        std::string(test::kHmcChain) + "terms:\n  - {name: EXX, form: periodic, period: " + period +
            ", unit: um, harmonics: " + harmonics + ", fit: true" + (fit_period ? ", fit_period: true" : "") + "}\n",
        "screw.yaml");
  };
  // Laser points 2 mm apart: a 10 mm screw is seen, not aliased.
  const MeasurementSet data = measure(model("10 mm", "[[2, 1]]", false), {Plan::nine_lines}, 5, 2.0);
  const FitReport fixed = fit(model::ForwardModel(model("10.05 mm", "[[0, 0]]", false)), data);
  const FitReport free = fit(model::ForwardModel(model("10.05 mm", "[[0, 0]]", true)), data);
  ASSERT_EQ(free.parameters.front().label, "EXX.period");
  EXPECT_NEAR(free.parameters.front().after, 10.0, 0.001);
  EXPECT_LE(free.rms_after, 1.3 * kNoise);
  // On the X lines (the others see only noise) a period 0.5% off cannot follow 40 turns.
  EXPECT_GT(fixed.source_rms_after[0], 1.5 * free.source_rms_after[0]) << data.sources[0];
}

TEST(Fit, FromTheTruthTakesNoStepIntoTheNoise) {
  // Started where the data were made, the least-squares step is mostly noise over small
  // singular values: far out along them the model is not linear, and such a step made
  // things worse and was damped back over several passes. Only the significant part is
  // taken; the fit ends in one or two steps, no worse than it started. Every error
  // motion of X, Y, Z as a laser table, read at random points, directions, table angles
  // and tool lengths, makes the weak directions.
  std::string text = std::string(test::kHmcChain) + "terms:\n";
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1, 1);
  for (const char* axis : {"X", "Y", "Z"})
    for (const char* component : {"X", "Y", "Z", "A", "B", "C"}) {
      std::string at, values;
      for (int k = 0; k < 15; ++k) {
        at += fmt::format("{}{:.3f}", k ? ", " : "", -500 + 1000.0 * k / 14);
        values += fmt::format("{}{:.2f}", k ? ", " : "", 5 * u(rng));
      }
      text += fmt::format("  - {{name: E{}{}, form: table, at: [{}], values: [{}], unit: {}, fit: true}}\n", component,
                          axis, at, values, std::string("XYZ").find(component[0]) != std::string::npos ? "um" : "urad");
    }
  const model::MachineModel truth = model::parse_machine_model(text, "tables.yaml");
  const model::ForwardModel t(truth);
  model::ForwardData d(t);
  MeasurementSet data;
  data.files = {"random"};
  data.sources = {"random"};
  std::normal_distribution<double> noise(0, kNoise);
  for (int i = 0; i < 20000; ++i) {
    Observation o;
    o.q << 480 * u(rng), 430 * u(rng), 480 * u(rng), 0, 3.1 * u(rng), 0, 0, 0, 0, 100 + 100 * u(rng);
    o.q[2] += o.q[9];
    o.direction = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    o.value = predict(t, d, o) + noise(rng);
    o.row = static_cast<std::uint32_t>(i + 2);
    data.observations.push_back(o);
  }
  const FitReport r = fit(t, data);
  EXPECT_TRUE(r.converged);
  EXPECT_LE(r.iterations, 2);
  EXPECT_LE(r.rms_after, r.rms_before);
  EXPECT_LE(r.rms_after, 1.3 * kNoise);
}

TEST(Fit, HandsOverItsDesignMatrixAtTheFittedParameters) {
  const model::MachineModel truth = geometric();
  const MeasurementSet data = measure(truth, {Plan::nine_lines, Plan::sphere}, 9);
  const model::ForwardModel s(blank(truth));
  Linearization at_fit;
  const FitReport r = fit(s, data, {}, &at_fit);
  Eigen::VectorXd residual;
  Eigen::MatrixXd J;
  design_matrix(s, r.all_parameters, data, free_parameters(s), residual, &J);
  ASSERT_EQ(at_fit.jacobian.rows(), J.rows());
  ASSERT_EQ(at_fit.jacobian.cols(), J.cols());
  EXPECT_LE((at_fit.residuals - residual).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LE((at_fit.jacobian - J).cwiseAbs().maxCoeff(), 1e-9 * J.cwiseAbs().maxCoeff());
}

TEST(Fit, BlockedProductsEqualThePlainOnes) {
  // Fewer rows than blocks, and a count the blocks do not divide.
  for (const Eigen::Index rows : {Eigen::Index{5}, Eigen::Index{1001}}) {
    const Eigen::MatrixXd A = Eigen::MatrixXd::Random(rows, 7), B = Eigen::MatrixXd::Random(rows, 3);
    const Eigen::VectorXd w = Eigen::VectorXd::Random(rows).cwiseAbs();
    EXPECT_LE((normal_matrix(A) - A.transpose() * A).norm(), 1e-12 * static_cast<double>(rows));
    EXPECT_LE((normal_matrix(A, &w) - A.transpose() * w.asDiagonal() * A).norm(), 1e-12 * static_cast<double>(rows));
    EXPECT_LE((transpose_product(A, B) - A.transpose() * B).norm(), 1e-12 * static_cast<double>(rows));
  }
}

TEST(Fit, RobustLossIgnoresOutliers) {
  const model::MachineModel truth = geometric();
  MeasurementSet data = measure(truth, {Plan::nine_lines}, 6);
  for (std::size_t i = 0; i < data.observations.size(); i += 97) data.observations[i].value += 0.05;  // bumped optics
  const model::ForwardModel s(blank(truth));
  FitOptions robust;
  robust.loss = Loss::huber;
  const Eigen::VectorXd plain = residuals(s, fit(s, data).all_parameters, data);
  const Eigen::VectorXd huber = residuals(s, fit(s, data, robust).all_parameters, data);
  auto inlier_rms = [&](const Eigen::VectorXd& r) {
    double sum = 0;
    int n = 0;
    for (Eigen::Index i = 0; i < r.size(); ++i)
      if (i % 97 != 0) sum += r[i] * r[i], ++n;
    return std::sqrt(sum / n);
  };
  EXPECT_LE(inlier_rms(huber), 1.5 * kNoise);
  EXPECT_GT(inlier_rms(plain), 2 * inlier_rms(huber));
  // Rerun with --robust from what the plain fit wrote (as its outliers message advises):
  // the robust fit moves it, though the plain cost rises by leaving the spikes.
  model::MachineModel plain_fitted = blank(truth);
  const FitReport first = fit(s, data);
  for (std::size_t t = 0; t < plain_fitted.terms.size(); ++t)
    plain_fitted.terms[t].parameters = first.all_parameters.segment(static_cast<Eigen::Index>(s.parameter_offset(t)),
                                                                    plain_fitted.terms[t].parameters.size());
  const model::ForwardModel from_plain(plain_fitted);
  EXPECT_LE(inlier_rms(residuals(from_plain, fit(from_plain, data, robust).all_parameters, data)), 1.5 * kNoise);
}

TEST(Fit, WritesTheResultBackInTheFileUnits) {
  const std::string path = test::source_dir() + "/samples/machines/hmc-xyzb.yaml";
  const std::string text = test::read_file(path);
  const model::MachineModel m = model::load_machine_model(path);
  std::vector<Eigen::VectorXd> changed;
  for (const model::ErrorTermSpec& t : m.terms) changed.push_back(t.parameters * 1.25);
  const std::string out = model::rewrite_parameters(text, m, changed, "{data: [a.csv], rms_after_um: 0.2}");
  EXPECT_NE(out.find("reversal: -5 um"), std::string::npos) << "-4 um, with its unit";
  EXPECT_NE(out.find("rms_after_um: 0.2"), std::string::npos);
  const model::MachineModel again = model::parse_machine_model(out, "again.yaml");
  ASSERT_EQ(again.terms.size(), m.terms.size());
  for (std::size_t i = 0; i < m.terms.size(); ++i)
    EXPECT_LT((again.terms[i].parameters - changed[i]).norm(), 1e-9 * (1.0 + changed[i].norm())) << m.terms[i].name;
}

TEST(Fit, FewerReadingsThanFreeParametersIsAClearErrorNotACrash) {
  // 1 to 7 readings made Eigen divide by zero (SIGFPE) in the blocked normal matrix.
  const model::MachineModel truth = geometric();
  const MeasurementSet all = measure(truth, {Plan::nine_lines}, 3);
  for (std::size_t rows : {1U, 5U, 7U, 40U}) {
    MeasurementSet few = all;
    few.observations.resize(rows);
    const Error e = test::error_of([&] { (void)fit(model::ForwardModel(truth), few); }, rows, " readings were fitted");
    EXPECT_EQ(e.kind(), ErrorKind::data);
    EXPECT_NE(e.message().find(fmt::format("{} readings cannot determine", rows)), std::string::npos) << e.message();
  }
  // With few free parameters, a handful of readings is fitted.
  std::string text = std::string(test::kHmcChain) + "terms:\n  - {name: EXX, value: 0, unit: um, fit: true}\n";
  MeasurementSet three = all;
  three.observations.resize(3);
  const FitReport r = fit(model::ForwardModel(model::parse_machine_model(text, "one.yaml")), three);
  EXPECT_TRUE(std::isfinite(r.rms_after));
}

TEST(Fit, AParameterTheDataCannotSeeKeepsItsValueExactly) {
  // The spindle head's yaw (ECY) turns the tool about its own axis: with every tool tip on
  // that axis, no reading sees it. Scaled to unit length its column (zero up to rounding)
  // looked determined, and a fit wrote ECY = -99137 urad.
  model::MachineModel start = blank(geometric());
  for (model::ErrorTermSpec& t : start.terms)
    if (t.iso == "ECY") t.parameters << 3e-6, 2e-8;
  const model::ForwardModel s(start);
  const FitReport r = fit(s, measure(geometric(), {Plan::nine_lines, Plan::grid, Plan::sphere}, 6));
  int held = 0;
  for (const FittedParameter& p : r.parameters)
    if (p.label.starts_with("ECY.")) {
      EXPECT_EQ(p.after, p.before) << p.label << " moved";
      ++held;
    }
  EXPECT_EQ(held, 2);
  EXPECT_TRUE(r.refusals.empty());
  bool said = false;
  for (const std::string& u : r.unidentifiable) said = said || u.find("ECY.a0, ECY.a1") != std::string::npos;
  EXPECT_TRUE(said) << "the report says so in words";
}

TEST(Fit, NeverEndsWorseThanItStartedAndRefusesValuesBeyondTheirScale) {
  const model::MachineModel truth = geometric();
  const MeasurementSet data = measure(truth, {Plan::nine_lines, Plan::grid}, 8);
  // A model the data already explain comes back unchanged.
  const FitReport same = fit(model::ForwardModel(truth), data);
  EXPECT_LE(same.rms_after, same.rms_before);
  EXPECT_EQ(same.all_parameters, model_parameters(model::ForwardModel(truth)));
  // Data 300 um off their model everywhere: EXX.a0 is asked to move by 30 physical scales
  // (kept), and readings 30 mm off would move it by 3000 (refused, named).
  for (const auto& [offset, refused] : {std::pair{0.3, false}, std::pair{30.0, true}}) {
    MeasurementSet shifted = data;
    for (Observation& o : shifted.observations)
      if (o.direction.x() > 0.99) o.value += offset;
    model::MachineModel m = truth;
    m.max_correction = 1000.0;  // the bound on corrections is not what this checks
    const FitReport r = fit(model::ForwardModel(m), shifted);
    bool named = false;
    for (const std::string& why : r.refusals) named = named || why.find("EXX.a0") != std::string::npos;
    EXPECT_EQ(named, refused) << offset << " mm";
  }
  // A model whose corrections the data push beyond max_correction is refused.
  MeasurementSet far = data;
  for (Observation& o : far.observations)
    if (o.direction.x() > 0.99) o.value += 0.3;
  model::MachineModel tight = truth;
  tight.max_correction = 0.1;
  const FitReport r = fit(model::ForwardModel(tight), far);
  bool bounded = false;
  for (const std::string& why : r.refusals) bounded = bounded || why.find("max_correction") != std::string::npos;
  EXPECT_TRUE(bounded);
}

TEST(Fit, SpikesAreFoundAndNamedByTheirRows) {
  // A laser beam cut gives a few readings far off: named, with or without the robust loss.
  const model::MachineModel truth = geometric();
  MeasurementSet data = measure(truth, {Plan::nine_lines, Plan::grid}, 9);
  const std::vector<std::size_t> spikes = {17, 400, 1203};
  for (std::size_t i : spikes) data.observations[i].value += 0.05;
  for (const Loss loss : {Loss::least_squares, Loss::huber}) {
    FitOptions o;
    o.loss = loss;
    const FitReport r = fit(model::ForwardModel(truth), data, o);
    ASSERT_EQ(r.outliers.size(), spikes.size());
    std::vector<std::uint32_t> rows;
    for (const FitReport::Outlier& out : r.outliers) rows.push_back(out.row);
    for (std::size_t i : spikes)
      EXPECT_NE(std::find(rows.begin(), rows.end(), data.observations[i].row), rows.end()) << "row of reading " << i;
  }
  // Clean data have none.
  EXPECT_TRUE(fit(model::ForwardModel(truth), measure(truth, {Plan::nine_lines}, 10)).outliers.empty());
}

}  // namespace
}  // namespace ccomp::identify
