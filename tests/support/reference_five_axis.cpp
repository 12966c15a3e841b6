#include "reference_five_axis.hpp"

#include <Eigen/Geometry>
#include <numbers>

namespace ccomp::test {

namespace {
constexpr double kRadPerDeg = std::numbers::pi / 180.0;

double value_of(const std::function<double(double)>& f, double v) { return f ? f(v) : 0.0; }

/// Base coordinates -> coordinates of a body turned by -angle about the line through
/// `point` along `direction` (the tool turning by +angle about it, the body seen from it),
/// the body's coordinates counted from `origin` (its nominal centre).
Eigen::Vector3d into_turned_body(const Eigen::Vector3d& v, const Eigen::Vector3d& point,
                                 const Eigen::Vector3d& direction, double angle, const Eigen::Vector3d& origin) {
  return Eigen::AngleAxisd(angle, direction.normalized()) * (v - point) + point - origin;
}
}  // namespace

Eigen::Vector3d ReferenceTrunnion::work_offset() const {
  return a_centre + c_from_a + origin_from_c - spindle_nose;
}

PartPose ReferenceTrunnion::pose(const FiveAxisWords& w, double L, bool with_errors) const {
  const double e = with_errors ? 1.0 : 0.0;
  // The machine's positions: the program's words through the work offset, Z raised by the
  // tool length (G43); the tool tip below the nose by L, in the table base's frame.
  const Eigen::Vector3d machine = Eigen::Vector3d(w.x, w.y, w.z) + work_offset() + Eigen::Vector3d(0, 0, L);
  Eigen::Vector3d tip = spindle_nose + machine - Eigen::Vector3d(0, 0, L);
  tip += e * Eigen::Vector3d(value_of(EXX, machine.x()), value_of(EYY, machine.y()), value_of(EZZ, machine.z()));
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  // The trunnion: its real line, displaced against the tool's mean deviation and tilted.
  const Eigen::Vector3d a_point = a_centre - e * Eigen::Vector3d(0, EY0A, EZ0A);
  const Eigen::Vector3d a_line = Eigen::Vector3d(1, e * EC0A, -e * EB0A);
  const double a = w.a * kRadPerDeg + e * value_of(EAA, w.a);
  tip = into_turned_body(tip, a_point, a_line, a, a_centre);
  axis = Eigen::AngleAxisd(a, a_line.normalized()) * axis;
  // The C table on it, in the trunnion's frame from A's centre.
  const Eigen::Vector3d c_point = c_from_a - e * Eigen::Vector3d(EX0C, EY0C, 0);
  const Eigen::Vector3d c_line = Eigen::Vector3d(e * EB0C, -e * EA0C, 1);
  const double c = w.c * kRadPerDeg + e * value_of(ECC, w.c);
  tip = into_turned_body(tip, c_point, c_line, c, c_from_a);
  axis = Eigen::AngleAxisd(c, c_line.normalized()) * axis;
  return {tip - origin_from_c, axis.normalized()};
}

PartPose ReferenceTrunnion::actual(const FiveAxisWords& w, double L) const { return pose(w, L, true); }
PartPose ReferenceTrunnion::nominal(const FiveAxisWords& w, double L) const { return pose(w, L, false); }

}  // namespace ccomp::test
