// One parametrised suite checks every analytic Jacobian of the kinematics layer against
// central finite differences, at random points, in the right-tangent convention of
// pose.hpp: inputs perturbed by X (+) tau, outputs compared by Y (-) Y0.
#include <gtest/gtest.h>

#include <functional>
#include <random>

#include "ccomp/kinematics/chain.hpp"
#include "ccomp/kinematics/pose.hpp"

namespace ccomp::kinematics {
namespace {

using Matrix = Eigen::MatrixXd;

std::mt19937& rng() {
  static std::mt19937 g(20261122);
  return g;
}
double uniform(double a, double b) {
  return std::uniform_real_distribution<double>(a, b)(rng());
}
Vec3 random_vec(double scale) {
  return Vec3(uniform(-scale, scale), uniform(-scale, scale), uniform(-scale, scale));
}
Pose random_pose() {
  return Pose{so3_exp(random_vec(2.0)), random_vec(300.0)};
}

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

/// A test case: an analytic Jacobian and its numeric twin, at the same random point.
struct JacobianCase {
  const char* name;
  std::function<std::pair<Matrix, Matrix>()> make;
};
void PrintTo(const JacobianCase& c, std::ostream* os) {
  *os << c.name;
}

/// A machine-like chain: W -> X -> Z -> offset d -> B on the workpiece side, W -> Y ->
/// spindle offset -> tool length on the tool side, with random placements and errors.
ChainModel sample_chain() {
  ChainModel m;
  auto joint = [](const char* name, JointType type, std::size_t axis, Vec3 dir, Pose placement) {
    return Joint{name, type, axis, dir.normalized(), placement};
  };
  m.workpiece.joints = {joint("X", JointType::linear, 0, Vec3(-1, 0, 0), Pose{}),
                        joint("Z", JointType::linear, 2, Vec3(0, 0, -1), Pose{so3_exp(random_vec(1e-3)), Vec3::Zero()}),
                        joint("B", JointType::rotary, 4, Vec3(0, -1, 0), Pose::translation(Vec3(0, 0, 350))),
                        joint("p", JointType::fixed, 0, Vec3::UnitX(), Pose{})};
  m.tool.joints = {joint("Y", JointType::linear, 1, Vec3(0, 1, 0), Pose{}),
                   joint("S", JointType::fixed, 0, Vec3::UnitX(), Pose::translation(Vec3(0, 0, 600))),
                   joint("tool", JointType::fixed, 0, Vec3::UnitX(), Pose::translation(Vec3(0, 0, -100)))};
  return m;
}

void randomise(ChainData& d, VecQ& q) {
  for (Pose& e : d.work_error) e = error_pose(random_vec(0.05), random_vec(1e-4));
  for (Pose& e : d.tool_error) e = error_pose(random_vec(0.05), random_vec(1e-4));
  for (Pose& e : d.work_location) e = error_pose(random_vec(0.05), random_vec(1e-4));
  for (Pose& e : d.tool_location) e = error_pose(random_vec(0.05), random_vec(1e-4));
  q = VecQ::Zero(9);
  q << uniform(-400, 400), uniform(-300, 300), uniform(-200, 200), 0, uniform(-3, 3), 0, 0, 0, 0;
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

const JacobianCase kCases[] = {
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
       return std::pair{Matrix(J), numeric_vec_vec([&](const Eigen::VectorXd& x) { return Eigen::VectorXd(act(a, x)); },
                                                   Eigen::VectorXd(p))};
     }},
    {"so3_exp",
     [] {
       const Vec3 w = random_vec(2.0);
       Mat3 J;
       (void)so3_exp(w, &J);
       // right Jacobian: Exp(w + dw) = Exp(w) Exp(J dw)
       auto f = [&](const Eigen::VectorXd& x) { return Eigen::VectorXd(so3_log(so3_exp(w).transpose() * so3_exp(x))); };
       return std::pair{Matrix(J), numeric_vec_vec(f, Eigen::VectorXd(w))};
     }},
    {"so3_exp_small_angle",
     [] {
       const Vec3 w = random_vec(1e-6);
       Mat3 J;
       (void)so3_exp(w, &J);
       auto f = [&](const Eigen::VectorXd& x) { return Eigen::VectorXd(so3_log(so3_exp(w).transpose() * so3_exp(x))); };
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
    {"chain_tool_locations", [] { return chain_pose_inputs(&ChainData::tool_location, &ChainData::J_tool_location); }},
};

class Jacobians : public ::testing::TestWithParam<JacobianCase> {};

TEST_P(Jacobians, MatchFiniteDifferences) {
  for (int trial = 0; trial < 5; ++trial) {
    const auto [analytic, numeric] = GetParam().make();
    ASSERT_EQ(analytic.rows(), numeric.rows());
    ASSERT_EQ(analytic.cols(), numeric.cols());
    const double scale = std::max(1.0, numeric.cwiseAbs().maxCoeff());
    EXPECT_LT((analytic - numeric).cwiseAbs().maxCoeff() / scale, 1e-6)
        << GetParam().name << " trial " << trial << "\nanalytic\n"
        << analytic << "\nnumeric\n"
        << numeric;
  }
}

INSTANTIATE_TEST_SUITE_P(Kinematics, Jacobians, ::testing::ValuesIn(kCases),
                         [](const auto& test) { return std::string(test.param.name); });

TEST(Pose, ExpLogRoundTrip) {
  for (int i = 0; i < 20; ++i) {
    // Rotation vectors shorter than pi: Log returns the shortest rotation.
    // (Halves assigned one by one: GCC 12 takes the comma initializer's packet load of
    // a 3-vector temporary for a read past it and warns with -Warray-bounds.)
    Vec6 tau;
    tau.head<3>() = random_vec(100);
    tau.tail<3>() = random_vec(1.5);
    EXPECT_LT((se3_log(se3_exp(tau)) - tau).norm(), 1e-9);
  }
}

TEST(Chain, ErrorMatrixIsIdentityWithoutErrorsAndSeesEachError) {
  ChainModel m = sample_chain();
  ChainData d(m);
  VecQ q;
  randomise(d, q);
  for (Pose& e : d.work_error) e = Pose{};
  for (Pose& e : d.tool_error) e = Pose{};
  for (Pose& e : d.work_location) e = Pose{};
  for (Pose& e : d.tool_location) e = Pose{};
  // The workpiece point p is where the error-free tool tip is, in the table's frame.
  error_matrix(m, d, q, ChainJacobians::none);
  m.workpiece.joints.back().placement = compose(inverse(d.work_oMi[2]), d.oMtool);
  d = ChainData(m);  // data belongs to the model as it was built from
  error_matrix(m, d, q, ChainJacobians::none);
  EXPECT_LT((d.E.matrix() - Eigen::Matrix4d::Identity()).norm(), 1e-9);
  // A 10 um positioning error of the tool side's first link shows in E's translation.
  d.tool_error[0] = error_pose(Vec3(0, 0.010, 0), Vec3::Zero());
  error_matrix(m, d, q, ChainJacobians::none);
  EXPECT_NEAR((d.E.t - Vec3(0, 0, 0)).norm(), 0.010, 1e-9);
}

TEST(Chain, NominalPosesAreTheErrorMatrixWithoutErrors) {
  // The compensation asks for the perfect machine at every move, by the shorter products
  // of nominal_poses(): they must be error_matrix()'s with identity error poses, to the
  // bit, on links of every kind (a tilted placement on a rotary axis too), as the rotary
  // axes turn, stand still and come back.
  ChainModel m = sample_chain();
  m.workpiece.joints[2].placement.R = so3_exp(random_vec(1e-3));
  ChainData d(m);
  NominalData nominal(m);
  VecQ q;
  randomise(d, q);
  for (Pose& e : d.work_error) e = Pose{};
  for (Pose& e : d.tool_error) e = Pose{};
  for (Pose& e : d.work_location) e = Pose{};
  for (Pose& e : d.tool_location) e = Pose{};
  for (int k = 0; k < 200; ++k) {
    if (k % 3 == 0) q[4] = uniform(-3, 3);  // else B stands still
    q[0] = uniform(-400, 400), q[1] = uniform(-300, 300), q[2] = uniform(-200, 200);
    error_matrix(m, d, q, ChainJacobians::none);
    nominal_poses(m, nominal, q);
    ASSERT_EQ(nominal.E.matrix(), d.E.matrix()) << "at q = " << q.transpose();
    ASSERT_EQ(nominal.oMp.matrix(), d.work_oMi.back().matrix());
    ASSERT_EQ(nominal.oMtool.matrix(), d.oMtool.matrix());
  }
}

}  // namespace
}  // namespace ccomp::kinematics
