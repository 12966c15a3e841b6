// Every analytic Jacobian of ccomp, checked against central finite differences by this one
// parametrised suite (as manif does): the kinematics layer's (poses, the chain's error
// matrix with respect to its axes, error motions and locations, in the right-tangent
// convention of pose.hpp: inputs perturbed by X (+) tau, outputs compared by Y (-) Y0), the
// forward model's (the tool tip with respect to the axes and to every parameter, through a
// parsed model file) and every error-term form's (value with respect to its variables and
// its parameters).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "ccomp/kinematics/chain.hpp"
#include "ccomp/kinematics/pose.hpp"
#include "ccomp/model/error_term.hpp"
#include "ccomp/model/forward.hpp"
#include "ccomp/model/machine.hpp"
#include "ccomp/model/model_file.hpp"
#include "ccomp/model/term_forms.hpp"
#include "random_chain.hpp"
#include "sample_models.hpp"
#include "term_shapes.hpp"

namespace ccomp::test {
namespace {

using namespace kinematics;
using Matrix = Eigen::MatrixXd;

constexpr double kStep = 1e-6;

/// Numeric Jacobian of a function of a pose, output a pose.
Matrix numeric_pose_pose(const std::function<Pose(const Pose&)>& f, const Pose& X) {
  Matrix J(6, 6);
  const Pose Y0 = f(X);
  for (int k = 0; k < 6; ++k) {
    Vec6 d = Vec6::Zero();
    d[k] = kStep;
    J.col(k) = (minus(f(plus(X, d)), Y0) - minus(f(plus(X, -d)), Y0)) / (2 * kStep);
  }
  return J;
}

/// Numeric Jacobian of a function of a vector, output a pose.
Matrix numeric_vec_pose(const std::function<Pose(const Eigen::VectorXd&)>& f, const Eigen::VectorXd& x) {
  Matrix J(6, x.size());
  const Pose Y0 = f(x);
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    Eigen::VectorXd d = Eigen::VectorXd::Zero(x.size());
    d[k] = kStep;
    J.col(k) = (minus(f(x + d), Y0) - minus(f(x - d), Y0)) / (2 * kStep);
  }
  return J;
}

/// Numeric Jacobian of a function of a pose, output a vector.
Matrix numeric_pose_vec(const std::function<Eigen::VectorXd(const Pose&)>& f, const Pose& X) {
  const Eigen::VectorXd y0 = f(X);
  Matrix J(y0.size(), 6);
  for (int k = 0; k < 6; ++k) {
    Vec6 d = Vec6::Zero();
    d[k] = kStep;
    J.col(k) = (f(plus(X, d)) - f(plus(X, -d))) / (2 * kStep);
  }
  return J;
}

/// Numeric Jacobian of a vector function of a vector.
Matrix numeric_vec_vec(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f, const Eigen::VectorXd& x) {
  const Eigen::VectorXd y0 = f(x);
  Matrix J(y0.size(), x.size());
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    Eigen::VectorXd d = Eigen::VectorXd::Zero(x.size());
    d[k] = kStep;
    J.col(k) = (f(x + d) - f(x - d)) / (2 * kStep);
  }
  return J;
}

/// A test case: an analytic Jacobian and its numeric twin, at the same point. They agree
/// when max |analytic - numeric| <= tolerance * max(1, max |numeric|); with `per_column`,
/// when each column does: |a_j - n_j| <= tolerance * max(floor, |n_j|) (a Jacobian whose
/// columns differ by orders of magnitude, as a model's parameters do).
struct JacobianCase {
  std::string name;
  std::function<std::pair<Matrix, Matrix>()> make;
  double tolerance = 1e-6;
  bool per_column = false;
  double floor = 1.0;
};
void PrintTo(const JacobianCase& c, std::ostream* os) {
  *os << c.name;
}

/// dE / d(each link's pose of one kind: error motions or locations) of the sample chain at
/// a random point, analytic and numeric side by side.
std::pair<Matrix, Matrix> chain_pose_inputs(std::vector<Pose> ChainData::*input,
                                            std::vector<Mat6> ChainData::*jacobian) {
  const ChainModel m = sample_chain();
  ChainData d(m);
  VecQ q;
  randomise(d, q);
  error_matrix(m, d, q);
  const std::size_t links = (d.*input).size();
  Matrix analytic(6, 6 * static_cast<Eigen::Index>(links));
  Matrix numeric(6, analytic.cols());
  for (std::size_t i = 0; i < links; ++i) {
    analytic.middleCols<6>(static_cast<Eigen::Index>(6 * i)) = (d.*jacobian)[i];
    numeric.middleCols<6>(static_cast<Eigen::Index>(6 * i)) = numeric_pose_pose(
        [&](const Pose& x) {
          ChainData e = d;
          (e.*input)[i] = x;
          error_matrix(m, e, q, ChainJacobians::none);
          return e.E;
        },
        (d.*input)[i]);
  }
  return std::pair{analytic, numeric};
}

std::vector<JacobianCase> kinematics_cases() {
  return {
      {"compose_a",
       [] {
         const Pose a = random_pose(), b = random_pose();
         Mat6 Ja;
         (void)compose(a, b, &Ja);
         return std::pair{Matrix(Ja), numeric_pose_pose([&](const Pose& x) { return compose(x, b); }, a)};
       }},
      {"compose_b",
       [] {
         const Pose a = random_pose(), b = random_pose();
         Mat6 Jb;
         (void)compose(a, b, nullptr, &Jb);
         return std::pair{Matrix(Jb), numeric_pose_pose([&](const Pose& x) { return compose(a, x); }, b)};
       }},
      {"inverse",
       [] {
         const Pose a = random_pose();
         Mat6 J;
         (void)inverse(a, &J);
         return std::pair{Matrix(J), numeric_pose_pose([](const Pose& x) { return inverse(x); }, a)};
       }},
      {"act_pose",
       [] {
         const Pose a = random_pose();
         const Vec3 p = random_vec(500);
         Mat36 J;
         (void)act(a, p, &J);
         return std::pair{Matrix(J), numeric_pose_vec([&](const Pose& x) { return Eigen::VectorXd(act(x, p)); }, a)};
       }},
      {"act_point",
       [] {
         const Pose a = random_pose();
         const Vec3 p = random_vec(500);
         Mat3 J;
         (void)act(a, p, nullptr, &J);
         return std::pair{
             Matrix(J),
             numeric_vec_vec([&](const Eigen::VectorXd& x) { return Eigen::VectorXd(act(a, x)); }, Eigen::VectorXd(p))};
       }},
      {"so3_exp",
       [] {
         const Vec3 w = random_vec(2.0);
         Mat3 J;
         (void)so3_exp(w, &J);
         // right Jacobian: Exp(w + dw) = Exp(w) Exp(J dw)
         auto f = [&](const Eigen::VectorXd& x) {
           return Eigen::VectorXd(so3_log(so3_exp(w).transpose() * so3_exp(x)));
         };
         return std::pair{Matrix(J), numeric_vec_vec(f, Eigen::VectorXd(w))};
       }},
      {"so3_exp_small_angle",
       [] {
         const Vec3 w = random_vec(1e-6);
         Mat3 J;
         (void)so3_exp(w, &J);
         auto f = [&](const Eigen::VectorXd& x) {
           return Eigen::VectorXd(so3_log(so3_exp(w).transpose() * so3_exp(x)));
         };
         return std::pair{Matrix(J), numeric_vec_vec(f, Eigen::VectorXd(w))};
       }},
      {"so3_log",
       [] {
         const Mat3 R = so3_exp(random_vec(2.0));
         Mat3 J;
         (void)so3_log(R, &J);
         auto f = [&](const Eigen::VectorXd& x) { return Eigen::VectorXd(so3_log(R * so3_exp(x))); };
         return std::pair{Matrix(J), numeric_vec_vec(f, Eigen::VectorXd(Vec3::Zero()))};
       }},
      {"error_pose_delta",
       [] {
         const Vec3 delta = random_vec(0.05), eps = random_vec(1e-3);
         Eigen::Matrix<double, 6, 3> J;
         (void)error_pose(delta, eps, &J);
         return std::pair{Matrix(J), numeric_vec_pose([&](const Eigen::VectorXd& x) { return error_pose(x, eps); },
                                                      Eigen::VectorXd(delta))};
       }},
      {"error_pose_epsilon",
       [] {
         const Vec3 delta = random_vec(0.05), eps = random_vec(1e-3);
         Eigen::Matrix<double, 6, 3> J;
         (void)error_pose(delta, eps, nullptr, &J);
         return std::pair{Matrix(J), numeric_vec_pose([&](const Eigen::VectorXd& x) { return error_pose(delta, x); },
                                                      Eigen::VectorXd(eps))};
       }},
      {"chain_axes",
       [] {
         const ChainModel m = sample_chain();
         ChainData d(m);
         VecQ q;
         randomise(d, q);
         error_matrix(m, d, q);
         const Matrix analytic = d.J_q;
         auto f = [&](const Eigen::VectorXd& x) {
           ChainData e = d;
           error_matrix(m, e, x, ChainJacobians::none);
           return e.E;
         };
         return std::pair{analytic, numeric_vec_pose(f, q)};
       }},
      {"chain_workpiece_errors", [] { return chain_pose_inputs(&ChainData::work_error, &ChainData::J_work_error); }},
      {"chain_tool_errors", [] { return chain_pose_inputs(&ChainData::tool_error, &ChainData::J_tool_error); }},
      {"chain_workpiece_locations",
       [] { return chain_pose_inputs(&ChainData::work_location, &ChainData::J_work_location); }},
      {"chain_tool_locations",
       [] { return chain_pose_inputs(&ChainData::tool_location, &ChainData::J_tool_location); }},
  };
}

/// The forward model of the seed's HMC with a term of every form and every location.
const model::ForwardModel& forward_model() {
  static const model::MachineModel machine = model::parse_machine_model(std::string(kHmcChain) + R"(terms:
  - {name: EXX, form: polynomial, coefficients: [1, 0.02, -3.0e-5], fit: true}
  - {name: EXX, form: periodic, period: 10 mm, harmonics: [[2, -1], [0.5, 0.3]], fit: true}
  - {name: ECX, form: polynomial, coefficients: [0, 0.05], fit: true}
  - {name: EBZ, form: table, interpolation: cubic, at: [-300, -100, 0, 200, 300], values: [1, -2, 0, 3, 1], fit: true}
  - {name: EYZ, form: cross_axis, other: x, coefficients: [[1.0e-3, 2.0e-6]], fit: true}
  - {name: EAY, value: 12, fit: true}
  - {name: EZS, variable: T_spindle, form: thermal, coefficient: 1.5, fit: true}
  - {name: EBB, form: periodic, period: 90 deg, harmonics: [[5, 3]], fit: true}
  - {name: EC0X, value: 15, fit: true}
  - {name: EA0B, value: 8, fit: true}
  - {name: EXB, form: polynomial, coefficients: [2, 0.01], fit: true}
  - {name: EX0B, value: 9, fit: true}
  - {name: EZ0B, value: -4, fit: true}
  - {name: EA0Y, value: 6, fit: true}
  - {name: EB0X, value: -7, fit: true}
  - {name: EXX, variable: vx, form: reversal, along: x, reversal: [3, 0.005], fit: true}
  - {name: EBB, variable: vb, form: reversal, reversal: 9, fit: true}
  - {name: EYY, form: cross_axis, other: x, coefficients: [[0, 3.0e-6], [0, 1.0e-9]], fit: true}
)",
                                                                        "m.yaml");
  static const model::ForwardModel m(machine);
  return m;
}

model::ChainQ forward_point() {
  model::ChainQ q = model::ChainQ::Zero();
  q << 137.0, -58.0, 71.0, 0, 0.7, 0, 0, 0, 0, 123.0;
  return q;
}

model::Conditions forward_conditions() {
  model::Conditions c;
  c.temperatures = {20.0, 27.0};  // bed, spindle
  c.directions[0] = -1.0, c.directions[4] = 1.0;  // X approached downward, B upward: the reversals switched
  return c;
}

/// The tool tip with respect to the moving axes (X Y Z B) and the tool length.
std::pair<Matrix, Matrix> forward_axes() {
  const model::ForwardModel& m = forward_model();
  const model::ChainQ q = forward_point();
  model::ForwardData d(m);
  model::forward(m, d, q, forward_conditions(), true);
  const std::vector<Eigen::Index> axes{0, 1, 2, 4, 9};
  Matrix analytic(3, static_cast<Eigen::Index>(axes.size())), numeric(3, analytic.cols());
  const double h = 1e-5;
  for (std::size_t c = 0; c < axes.size(); ++c) {
    model::ChainQ up = q, down = q;
    up[axes[c]] += h;
    down[axes[c]] -= h;
    model::ForwardData a(m), b(m);
    model::forward(m, a, up, forward_conditions());
    model::forward(m, b, down, forward_conditions());
    analytic.col(static_cast<Eigen::Index>(c)) = d.J_q.col(axes[c]);
    numeric.col(static_cast<Eigen::Index>(c)) = (a.actual - b.actual) / (2 * h);
  }
  return {analytic, numeric};
}

/// The tool tip with respect to every parameter of every term. Positions are hundreds of
/// mm: a step of 1e-5 keeps rounding (1e-16 x 400 / 1e-5) far below the tolerance, and the
/// model is nearly linear in its parameters.
std::pair<Matrix, Matrix> forward_parameters() {
  const model::ForwardModel& m = forward_model();
  const model::ChainQ q = forward_point();
  model::ForwardData d(m);
  model::forward(m, d, q, forward_conditions(), true);
  Matrix numeric(3, d.parameters().size());
  const double step = 1e-5;
  for (Eigen::Index k = 0; k < d.parameters().size(); ++k) {
    model::ForwardData a(m), b(m);
    a.edit_parameters()[k] += step;
    b.edit_parameters()[k] -= step;
    model::forward(m, a, q, forward_conditions());
    model::forward(m, b, q, forward_conditions());
    numeric.col(k) = (a.actual - b.actual) / (2 * step);
  }
  return {Matrix(d.J_parameters), numeric};
}

/// A term form at a point: value with respect to its primary and secondary variables, then
/// its parameters, as one row.
struct FormCase {
  const char* name;
  TermShape shape;
  Eigen::VectorXd parameters;
  model::TermInputs at;
};

std::pair<Matrix, Matrix> term_derivatives(const FormCase& c) {
  EXPECT_EQ(static_cast<std::size_t>(c.parameters.size()), model::parameter_count(c.shape)) << c.name;
  const model::TermValue v = model::evaluate(c.shape, c.parameters, c.at, true);
  const Eigen::Index n = c.parameters.size();
  Matrix analytic(1, 2 + n), numeric(1, 2 + n);
  const double h = 1e-4;
  auto at = [&](double dp, double ds) {
    return model::evaluate(c.shape, c.parameters, model::TermInputs{c.at.primary + dp, c.at.secondary + ds}).value;
  };
  analytic(0, 0) = v.d_primary;
  analytic(0, 1) = v.d_secondary;
  numeric(0, 0) = (at(h, 0) - at(-h, 0)) / (2 * h);
  numeric(0, 1) = (at(0, h) - at(0, -h)) / (2 * h);
  for (Eigen::Index k = 0; k < n; ++k) {
    const double step = 1e-6 * std::max(1.0, std::abs(c.parameters[k]));
    Eigen::VectorXd up = c.parameters, down = c.parameters;
    up[k] += step;
    down[k] -= step;
    analytic(0, 2 + k) = v.d_parameters[k];
    numeric(0, 2 + k) =
        (model::evaluate(c.shape, up, c.at).value - model::evaluate(c.shape, down, c.at).value) / (2 * step);
  }
  return {analytic, numeric};
}

/// A case of every shape of every form (model/term_forms.hpp lists the forms).
std::vector<FormCase> form_cases() {
  return {
      {"constant", shape(TermForm::constant), vec({0.004}), {123.0, 0.0}},
      {"polynomial", shape(TermForm::polynomial, 3), vec({1e-3, 2e-5, -3e-8, 4e-11}), {157.0, 0.0}},
      {"table_linear", table(Interpolation::linear), vec({0.001, -0.002, 0.0, 0.003, 0.001, -0.004}), {87.0, 0.0}},
      {"table_cubic", table(Interpolation::cubic), vec({0.001, -0.002, 0.0, 0.003, 0.001, -0.004}), {87.0, 0.0}},
      {"periodic", shape(TermForm::periodic, 2), vec({10.0, 0.003, -0.001, 0.0005, 0.0002}), {37.3, 0.0}},
      {"reversal", shape(TermForm::reversal), vec({0.006}), {-1.0, 0.0}},
      {"reversal_along", reversal_along(), vec({0.003, 6e-6, -4e-9}), {0.4, 215.0}},
      {"thermal_linear", shape(TermForm::thermal_linear), vec({0.0011}), {27.5, 0.0}},
      {"thermal_warmup", shape(TermForm::thermal_warmup), vec({0.015, 1800.0}), {900.0, 0.0}},
      {"scale_expansion", shape(TermForm::scale_expansion), vec({11.5e-6}), {250.0, 24.0}},
      {"cross_axis", cross(), vec({1e-5, 2e-8, -3e-8, 4e-11}), {120.0, -80.0}},
      {"cross_axis_quadratic", cross_quadratic(), vec({1e-5, 2e-8, -3e-8, 4e-11, 5e-11, -2e-13}), {120.0, -80.0}},
      {"bump", shape(TermForm::bump), vec({0.006, 110.0, 12.5}), {118.0, 0.0}},
  };
}

std::vector<JacobianCase> model_cases() {
  std::vector<JacobianCase> cases{{"forward_axes", forward_axes, 1e-7, true, 1.0},
                                  {"forward_parameters", forward_parameters, 1e-6, true, 1e-2}};
  for (const FormCase& form : form_cases()) {
    cases.push_back({std::string("term_") + form.name, [form] { return term_derivatives(form); }, 1e-6, true, 1e-3});
  }
  return cases;
}

std::vector<JacobianCase> all_cases() {
  std::vector<JacobianCase> cases = kinematics_cases();
  for (JacobianCase& c : model_cases()) cases.push_back(std::move(c));
  return cases;
}

class Jacobians : public ::testing::TestWithParam<JacobianCase> {};

TEST_P(Jacobians, MatchFiniteDifferences) {
  for (int trial = 0; trial < 5; ++trial) {  // the kinematics' cases draw a new point each time
    const auto [analytic, numeric] = GetParam().make();
    ASSERT_EQ(analytic.rows(), numeric.rows());
    ASSERT_EQ(analytic.cols(), numeric.cols());
    if (GetParam().per_column) {
      for (Eigen::Index j = 0; j < analytic.cols(); ++j)
        EXPECT_LE((analytic.col(j) - numeric.col(j)).norm(),
                  GetParam().tolerance * std::max(GetParam().floor, numeric.col(j).norm()))
            << GetParam().name << " column " << j << ": analytic " << analytic.col(j).transpose() << ", numeric "
            << numeric.col(j).transpose();
      continue;
    }
    const double scale = std::max(1.0, numeric.cwiseAbs().maxCoeff());
    EXPECT_LT((analytic - numeric).cwiseAbs().maxCoeff() / scale, GetParam().tolerance)
        << GetParam().name << " trial " << trial << "\nanalytic\n"
        << analytic << "\nnumeric\n"
        << numeric;
  }
}

// The suite holds every form the registry lists: a new form without a case here fails.
TEST(JacobianForms, EveryRegisteredFormHasACase) {
  const std::vector<FormCase> cases = form_cases();
  for (const model::TermFormInfo& f : model::term_forms())
    EXPECT_TRUE(std::any_of(cases.begin(), cases.end(), [&f](const FormCase& c) { return c.shape.form == f.form; }))
        << "no Jacobian case of form " << f.names.front();
  EXPECT_EQ(model::term_forms().size(), static_cast<std::size_t>(model::TermForm::bump) + 1)
      << "a form of TermForm the registry lacks";
}

// Each descriptor sits at its form's index and answers every question asked of a form.
TEST(TermFormRegistry, EachDescriptorAtItsFormAndComplete) {
  const auto& forms = model::term_forms();
  for (std::size_t i = 0; i < forms.size(); ++i) {
    const model::TermFormInfo& f = forms[i];
    EXPECT_EQ(static_cast<std::size_t>(f.form), i) << f.names.front();
    EXPECT_FALSE(f.names.empty() || f.keys.empty() || f.physics.empty()) << "form " << i;
    EXPECT_TRUE(f.parameter_count && f.evaluate && f.term_label && f.parameter_label && f.shapes_only && f.place &&
                f.unit_name && f.physical_scale && f.bound && f.shortest_feature)
        << f.names.front() << " lacks a part";
    EXPECT_EQ(model::term_form(f.names.front()), &f);
  }
}

// What a form says of its parameters holds for every case: as many as evaluate() gives
// derivatives for, each with a label and a place of its own (two written to one place would
// lose one in the model file), a place under one of the form's keys, a finite positive
// physical scale, and a bound at least the value everywhere it was evaluated.
TEST(TermFormRegistry, EachParameterHasItsOwnLabelAndPlace) {
  for (const FormCase& c : form_cases()) {
    const model::TermFormInfo& f = model::term_form(c.shape.form);
    model::ErrorTermSpec t;
    t.iso = "EXX";
    t.shape = c.shape;
    t.parameters = c.parameters;
    t.primary = model::Variable{model::VariableKind::axis, 0, "x"};
    t.secondary = model::Variable{model::VariableKind::axis, 2, "z"};
    const std::size_t n = f.parameter_count(c.shape);
    ASSERT_EQ(n, static_cast<std::size_t>(c.parameters.size())) << c.name;
    std::set<std::string> labels;
    std::set<std::tuple<std::string, int, int>> places;
    const model::ReachOf reach = [](const model::Variable&, double) { return 500.0; };
    for (std::size_t k = 0; k < n; ++k) {
      labels.insert(f.parameter_label(t, k));
      const model::ParameterPlace place = f.place(c.shape, k);
      places.insert({std::string(place.key), place.index, place.sub});
      EXPECT_TRUE(std::find(f.keys.begin(), f.keys.end(), place.key) != f.keys.end())
          << c.name << " parameter " << k << " written under '" << place.key << "', not one of its keys";
      const double scale = f.physical_scale(t, k, 0.01, reach);
      EXPECT_TRUE(std::isfinite(scale) && scale > 0) << c.name << " parameter " << k << ": scale " << scale;
    }
    EXPECT_EQ(labels.size(), n) << c.name << ": two parameters share a label";
    EXPECT_EQ(places.size(), n) << c.name << ": two parameters share a place";
    const double v = std::abs(model::evaluate(c.shape, c.parameters, c.at).value);
    const model::TermRange u{c.at.primary, c.at.primary}, w{c.at.secondary, c.at.secondary};
    EXPECT_GE(f.bound(c.shape, c.parameters, u, w).value * (1 + 1e-12), v) << c.name;
  }
}

INSTANTIATE_TEST_SUITE_P(All, Jacobians, ::testing::ValuesIn(all_cases()),
                         [](const ::testing::TestParamInfo<JacobianCase>& p) { return p.param.name; });

}  // namespace
}  // namespace ccomp::test
