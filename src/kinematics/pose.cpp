#include "ccomp/kinematics/pose.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

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

// Below this angle the closed forms lose digits: use their Taylor series.
constexpr double kSmall = 1e-5;

Mat3 so3_right_jacobian(const Vec3& w) {
  const double th = w.norm();
  const Mat3 W = hat(w);
  if (th < kSmall) return Mat3::Identity() - 0.5 * W + W * W / 6.0;
  const double th2 = th * th;
  return Mat3::Identity() - (1.0 - std::cos(th)) / th2 * W + (th - std::sin(th)) / (th2 * th) * W * W;
}

Mat3 so3_right_jacobian_inverse(const Vec3& w) {
  const double th = w.norm();
  const Mat3 W = hat(w);
  if (th < kSmall) return Mat3::Identity() + 0.5 * W + W * W / 12.0;
  const double th2 = th * th;
  return Mat3::Identity() + 0.5 * W +
         (1.0 / th2 - (1.0 + std::cos(th)) / (2.0 * th * std::sin(th))) * W * W;
}

Mat3 so3_exp(const Vec3& w, Mat3* J) {
  const double th = w.norm();
  const Mat3 W = hat(w);
  Mat3 R;
  if (th < kSmall) {
    R = Mat3::Identity() + W + 0.5 * W * W;
  } else {
    R = Mat3::Identity() + std::sin(th) / th * W + (1.0 - std::cos(th)) / (th * th) * W * W;
  }
  if (J) *J = so3_right_jacobian(w);
  return R;
}

Vec3 so3_log(const Mat3& R, Mat3* J) {
  const double c = std::clamp((R.trace() - 1.0) * 0.5, -1.0, 1.0);
  const double th = std::acos(c);
  const Vec3 v(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
  Vec3 w;
  if (th < kSmall) {
    w = 0.5 * (1.0 + th * th / 6.0) * v;
  } else if (th > 3.14159265358979323846 - 1e-6) {
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

Pose plus(const Pose& X, const Vec6& tau) { return compose(X, se3_exp(tau)); }

Vec6 minus(const Pose& Y, const Pose& X) { return se3_log(compose(inverse(X), Y)); }

Pose error_pose(const Vec3& delta, const Vec3& epsilon, Eigen::Matrix<double, 6, 3>* J_delta,
                Eigen::Matrix<double, 6, 3>* J_epsilon) {
  Mat3 Jr;
  const Mat3 R = so3_exp(epsilon, &Jr);
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
