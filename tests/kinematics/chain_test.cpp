// The kinematic chain and its poses: round trips and the error matrix's meaning. Their
// Jacobians are checked with every other one in tests/jacobian_suite_test.cpp.
#include "ccomp/kinematics/chain.hpp"

#include <gtest/gtest.h>

#include "ccomp/kinematics/pose.hpp"
#include "random_chain.hpp"

namespace ccomp::kinematics {
namespace {

using test::random_vec;
using test::randomise;
using test::sample_chain;
using test::uniform;

/// Every error motion and location of the chain's links set to none.
void without_errors(ChainData& d) {
  for (auto* poses : {&d.work_error, &d.tool_error, &d.work_location, &d.tool_location})
    for (Pose& e : *poses) e = Pose{};
}

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

TEST(Pose, SmallRotationsRoundTripToTheLastDigits) {
  // Error motions and the inverse's orientation residuals are micro- to milliradians: Log
  // takes them by a series, which must hold to double precision up to its limit (1e-2 rad)
  // and meet the closed form there.
  for (const double angle : {1e-9, 1e-7, 1e-5, 3e-5, 1e-4, 1e-3, 5e-3, 9.99e-3, 1.001e-2, 3e-2}) {
    for (int i = 0; i < 20; ++i) {
      const Vec3 w = angle * random_vec(1.0).normalized();
      // Exp without its Jacobian (a shorter series below 1e-4 rad) is Exp with it, to the
      // last bits, and a rotation.
      Mat3 J;
      const Mat3 R = so3_exp(w);
      EXPECT_LT((R - so3_exp(w, &J)).cwiseAbs().maxCoeff(), 2.3e-16) << "angle " << angle;
      EXPECT_LT((R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff(), 5e-16) << "angle " << angle;
      const Vec3 back = so3_log(R);
      // The closed form past the series loses digits as 1 - cos th does: 1e-16 / th^2.
      const double allowed = angle < 1e-2 ? 4e-16 : 1e-16 / (angle * angle);
      EXPECT_LT((back - w).norm(), allowed * angle) << "angle " << angle;
    }
  }
}

TEST(Chain, ErrorMatrixIsIdentityWithoutErrorsAndSeesEachError) {
  ChainModel m = sample_chain();
  ChainData d(m);
  VecQ q;
  randomise(d, q);
  without_errors(d);
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
  // last bits of the sums (1e-15 of the chain's size), on links of every kind (a tilted
  // placement on a rotary axis too), as the rotary axes turn, stand still and come back.
  ChainModel m = sample_chain();
  m.workpiece.joints[2].placement.R = so3_exp(random_vec(1e-3));
  // A head turning about X (a rotary joint before a linear one: the tool's travel W along
  // its turned line) on the tool side.
  m.tool.joints.insert(m.tool.joints.begin() + 2, Joint{"A", JointType::rotary, 3, Vec3::UnitX(), Pose{}});
  m.tool.joints.insert(m.tool.joints.begin() + 3, Joint{"W", JointType::linear, 8, Vec3(0, 0, -1), Pose{}});
  ChainData d(m);
  NominalData nominal(m);
  VecQ q;
  randomise(d, q);
  without_errors(d);
  auto differ = [](const Pose& a, const Pose& b) {  // rotations, translations (mm)
    return std::pair{(a.R - b.R).cwiseAbs().maxCoeff(), (a.t - b.t).cwiseAbs().maxCoeff()};
  };
  for (int k = 0; k < 200; ++k) {
    if (k % 3 == 0) q[4] = uniform(-3, 3);  // else B stands still
    if (k % 5 == 0) q[3] = uniform(-1, 1);  // and A
    q[0] = uniform(-400, 400), q[1] = uniform(-300, 300), q[2] = uniform(-200, 200), q[8] = uniform(-50, 50);
    error_matrix(m, d, q, ChainJacobians::none);
    nominal_poses(m, nominal, q);
    // (Rotations to their last bits; translations to those of the chain's 1000 mm.)
    for (const auto& [what, pair] : {std::pair{"E", differ(nominal.E, d.E)},
                                     std::pair{"oMp", differ(nominal.oMp, d.work_oMi.back())},
                                     std::pair{"oMtool", differ(nominal.oMtool, d.oMtool)}}) {
      ASSERT_LT(pair.first, 1e-15) << what << " at q = " << q.transpose();
      ASSERT_LT(pair.second, 1e-15 * 1000) << what << " at q = " << q.transpose();
    }
  }
}

}  // namespace
}  // namespace ccomp::kinematics
