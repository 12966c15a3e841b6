#include "ccomp/kinematics/pose.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numbers>

namespace ccomp::kinematics {

Eigen::Matrix4d Pose::matrix() const {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = R;
  m.topRightCorner<3, 1>() = t;
  return m;
}

Mat3 hat(const Vec3& w) {
  Mat3 m;
  m << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return m;
}

// Below this angle the closed forms lose digits, and their Taylor series are exact to
// double precision when taken to th^6 (the next term is below 1e-21 of the first): error
// motions are microradians, so the series also spares a sine and a cosine.
constexpr double kSeries = 1e-2;

namespace {
/// The coefficients of W and W^2 in Exp and Jr: sin(th)/th, (1 - cos th)/th^2 and
/// (th - sin th)/th^3.
struct So3Coefficients {
  double a, b, c;
};
So3Coefficients so3_coefficients(double th2) {
  if (th2 < kSeries * kSeries)
    // Reciprocals multiplied, not divided (a division is several times slower): the error
    // motions' tiny angles come here at every evaluation of the model.
    return {1.0 - th2 * (1.0 / 6) * (1.0 - th2 * (1.0 / 20) * (1.0 - th2 * (1.0 / 42))),
            0.5 - th2 * (1.0 / 24) * (1.0 - th2 * (1.0 / 30) * (1.0 - th2 * (1.0 / 56))),
            1.0 / 6.0 - th2 * (1.0 / 120) * (1.0 - th2 * (1.0 / 42) * (1.0 - th2 * (1.0 / 72)))};
  const double th = std::sqrt(th2), s = std::sin(th), co = std::cos(th);
  return {s / th, (1.0 - co) / th2, (th - s) / (th2 * th)};
}
using detail::identity_plus;
}  // namespace

Mat3 so3_right_jacobian(const Vec3& w) {
  const double th2 = w.squaredNorm();
  const So3Coefficients k = so3_coefficients(th2);
  return identity_plus(w, th2, -k.b, k.c);
}

Mat3 so3_right_jacobian_inverse(const Vec3& w) {
  const double th2 = w.squaredNorm();
  // 1/th^2 - (1 + cos th) / (2 th sin th) = 1/12 + th^2/720 + th^4/30240 + ...
  const double c = th2 < kSeries * kSeries ? 1.0 / 12.0 + th2 / 720.0 + th2 * th2 / 30240.0
                                           : 1.0 / th2 - (1.0 + std::cos(std::sqrt(th2))) /
                                                             (2.0 * std::sqrt(th2) * std::sin(std::sqrt(th2)));
  return identity_plus(w, th2, 0.5, c);
}

Mat3 detail::so3_exp_general(const Vec3& w, Mat3* J) {
  const double th2 = w.squaredNorm();
  const So3Coefficients k = so3_coefficients(th2);
  if (J) *J = identity_plus(w, th2, -k.b, k.c);
  return identity_plus(w, th2, k.a, k.b);
}

Vec3 so3_log(const Mat3& R, Mat3* J) {
  const double c = std::clamp((R.trace() - 1.0) * 0.5, -1.0, 1.0);
  const Vec3 v(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));  // 2 sin(th) axis
  // Small angles (the inverse compares orientations that differ by tens of microradians at
  // every iteration): th / sin th = asin(s) / s in s^2 = sin^2 th, whose series taken to s^6
  // is exact to double precision below s = 1e-2 (the next term, 35/1152 s^8, is below
  // 1e-17). It spares an acos and a sine, a few percent of the whole main job.
  if (const double s2 = 0.25 * v.squaredNorm(); c > 0.0 && s2 < 1e-4) {
    const Vec3 w = 0.5 * (1.0 + s2 * (1.0 / 6 + s2 * (3.0 / 40 + s2 * (5.0 / 112)))) * v;
    if (J) *J = so3_right_jacobian_inverse(w);
    return w;
  }
  const double th = std::acos(c);
  Vec3 w;
  if (th < 1e-5) {  // (only a matrix not quite a rotation comes here: its skew part large)
    w = 0.5 * (1.0 + th * th / 6.0) * v;
  } else if (th > std::numbers::pi - 1e-6) {
    // Near pi: from the symmetric part, R ~ 2 a a^T - I.
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(0.5 * (R + Mat3::Identity()));
    Vec3 a = eig.eigenvectors().col(2);
    if (a.dot(v) < 0) a = -a;
    w = th * a;
  } else {
    w = th / (2.0 * std::sin(th)) * v;
  }
  if (J) *J = so3_right_jacobian_inverse(w);
  return w;
}

Mat6 adjoint(const Pose& X) {
  Mat6 A = Mat6::Zero();
  A.topLeftCorner<3, 3>() = X.R;
  A.topRightCorner<3, 3>() = hat(X.t) * X.R;
  A.bottomRightCorner<3, 3>() = X.R;
  return A;
}

Pose compose(const Pose& a, const Pose& b, Mat6* J_a, Mat6* J_b) {
  if (J_a) *J_a = adjoint(inverse(b));
  if (J_b) J_b->setIdentity();
  return Pose{a.R * b.R, a.t + a.R * b.t};
}

Pose inverse(const Pose& X, Mat6* J) {
  if (J) *J = -adjoint(X);
  return Pose{X.R.transpose(), -(X.R.transpose() * X.t)};
}

Vec3 act(const Pose& X, const Vec3& p, Mat36* J_X, Mat3* J_p) {
  if (J_X) {
    J_X->leftCols<3>() = X.R;
    J_X->rightCols<3>() = -X.R * hat(p);
  }
  if (J_p) *J_p = X.R;
  return X.t + X.R * p;
}

Pose se3_exp(const Vec6& tau) {
  const Vec3 theta = tau.tail<3>();
  // The left Jacobian of SO(3) is Jr(-theta) = Jr(theta)^T.
  return Pose{so3_exp(theta), so3_right_jacobian(theta).transpose() * tau.head<3>()};
}

Vec6 se3_log(const Pose& X) {
  const Vec3 theta = so3_log(X.R);
  Vec6 tau;
  tau.head<3>() = so3_right_jacobian_inverse(theta).transpose() * X.t;
  tau.tail<3>() = theta;
  return tau;
}

Pose plus(const Pose& X, const Vec6& tau) {
  return compose(X, se3_exp(tau));
}

Vec6 minus(const Pose& Y, const Pose& X) {
  return se3_log(compose(inverse(X), Y));
}

Pose error_pose(const Vec3& delta, const Vec3& epsilon, Eigen::Matrix<double, 6, 3>* J_delta,
                Eigen::Matrix<double, 6, 3>* J_epsilon) {
  Mat3 Jr;
  const Mat3 R = so3_exp(epsilon, J_epsilon ? &Jr : nullptr);
  if (J_delta) {
    J_delta->topRows<3>() = R.transpose();
    J_delta->bottomRows<3>().setZero();
  }
  if (J_epsilon) {
    J_epsilon->topRows<3>().setZero();
    J_epsilon->bottomRows<3>() = Jr;
  }
  return Pose{R, delta};
}

}  // namespace ccomp::kinematics
