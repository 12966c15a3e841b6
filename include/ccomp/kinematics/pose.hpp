#pragma once
// Rigid transforms (SE(3)) and rotations (SO(3)) with their exact Jacobians, in the
// convention of manif (Solà et al., "A micro Lie theory"): a tangent vector is
// tau = [rho; theta] (translation first), X (+) tau = X * Exp(tau), and every Jacobian is a
// right Jacobian, i.e. d f(X (+) tau) / d tau at tau = 0 expressed in f's right tangent.
// Names carry frames: aMb maps coordinates in frame b to frame a (Pinocchio's oMi).
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ccomp::kinematics {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Mat36 = Eigen::Matrix<double, 3, 6>;

/// A homogeneous transform [R t; 0 1].
struct Pose {
  Mat3 R = Mat3::Identity();
  Vec3 t = Vec3::Zero();

  [[nodiscard]] static Pose identity() { return {}; }
  [[nodiscard]] static Pose translation(const Vec3& t) { return {Mat3::Identity(), t}; }
  [[nodiscard]] Eigen::Matrix4d matrix() const;
};

/// The skew matrix: hat(w) * v == w.cross(v).
[[nodiscard]] Mat3 hat(const Vec3& w);

// --- SO(3)
namespace detail {
/// I + a hat(w) + b hat(w)^2, with hat(w)^2 = w w^T - |w|^2 I written out.
[[nodiscard]] inline Mat3 identity_plus(const Vec3& w, double th2, double a, double b) {
  const double x = w.x(), y = w.y(), z = w.z();
  Mat3 m;
  m << 1.0 + b * (x * x - th2), -a * z + b * x * y, a * y + b * x * z,  //
      a * z + b * x * y, 1.0 + b * (y * y - th2), -a * x + b * y * z,   //
      -a * y + b * x * z, a * x + b * y * z, 1.0 + b * (z * z - th2);
  return m;
}
/// so3_exp() beyond its inline case.
[[nodiscard]] Mat3 so3_exp_general(const Vec3& w, Mat3* J);
}  // namespace detail

/// Exp of a rotation vector; J: its right Jacobian Jr(w).
[[nodiscard]] inline Mat3 so3_exp(const Vec3& w, Mat3* J = nullptr) {
  const double th2 = w.squaredNorm();
  // An error motion's rotation (tens of microradians) at every evaluation of the model, in
  // line: below 1e-4 rad the series' next terms (th^4 / 120 and th^4 / 720) are below 1e-18,
  // a hundredth of the coefficients' last bit.
  if (!J && th2 < 1e-8) return detail::identity_plus(w, th2, 1.0 - th2 * (1.0 / 6), 0.5 - th2 * (1.0 / 24));
  return detail::so3_exp_general(w, J);
}
/// Log of a rotation matrix; J: the inverse right Jacobian Jr^-1(Log R).
[[nodiscard]] Vec3 so3_log(const Mat3& R, Mat3* J = nullptr);
[[nodiscard]] Mat3 so3_right_jacobian(const Vec3& w);
[[nodiscard]] Mat3 so3_right_jacobian_inverse(const Vec3& w);

// --- SE(3)
/// Ad(X): maps a right tangent of X to its left tangent; Ad(X) tau = X tau X^-1.
[[nodiscard]] Mat6 adjoint(const Pose& X);
/// a * b; J_a, J_b: right Jacobians Ad(b^-1) and I.
[[nodiscard]] Pose compose(const Pose& a, const Pose& b, Mat6* J_a, Mat6* J_b = nullptr);
/// X^-1; J: -Ad(X).
[[nodiscard]] Pose inverse(const Pose& X, Mat6* J);
// Without Jacobians, inline: the chain composes these in its innermost loop.
[[nodiscard]] inline Pose compose(const Pose& a, const Pose& b) {
  return Pose{a.R * b.R, a.t + a.R * b.t};
}
[[nodiscard]] inline Pose inverse(const Pose& X) {
  return Pose{X.R.transpose(), -(X.R.transpose() * X.t)};
}
/// X * p; J_X = [R, -R hat(p)], J_p = R.
[[nodiscard]] Vec3 act(const Pose& X, const Vec3& p, Mat36* J_X = nullptr, Mat3* J_p = nullptr);
/// Exp(tau) and Log(X), with right Jacobians (used to perturb and compare poses).
[[nodiscard]] Pose se3_exp(const Vec6& tau);
[[nodiscard]] Vec6 se3_log(const Pose& X);
/// X (+) tau and Y (-) X = Log(X^-1 Y).
[[nodiscard]] Pose plus(const Pose& X, const Vec6& tau);
[[nodiscard]] Vec6 minus(const Pose& Y, const Pose& X);

/// The pose of a small error motion: translation `delta` and rotation vector `epsilon`
/// (the six error motions of a link). J_delta = [R^T; 0], J_epsilon = [0; Jr(epsilon)].
[[nodiscard]] Pose error_pose(const Vec3& delta, const Vec3& epsilon, Eigen::Matrix<double, 6, 3>* J_delta = nullptr,
                              Eigen::Matrix<double, 6, 3>* J_epsilon = nullptr);

}  // namespace ccomp::kinematics
