#pragma once
// The tool's direction, as verify and predict measure the orientation error: the tool's
// axis turned into the table frame by the chain. An axisymmetric tool cuts the same
// whatever its turn about its own axis, so only the angle between the axis the tool has and
// the one the program meant is an error.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

#include "ccomp/kinematics/chain.hpp"
#include "ccomp/model/forward.hpp"

namespace ccomp::compensate {

/// The tool's axis in the tool frame: its tool-length link's direction (-Z where the chain
/// gives none), as the inverse takes it.
[[nodiscard]] inline Eigen::Vector3d tool_axis_of(const model::ForwardModel& model) {
  for (const auto* chain : {&model.chain().workpiece, &model.chain().tool})
    for (const kinematics::Joint& j : chain->joints)
      if (j.type != kinematics::JointType::fixed && j.axis == model::kToolLengthIndex) return j.direction.normalized();
  return -Eigen::Vector3d::UnitZ();
}

/// The angle between two directions (rad), exact for the small angles measured here too
/// (acos of the dot product loses them below 1e-8). Below 10 mrad, the angles verify and
/// predict meet at nearly every point, atan's series to its x^7 term (within 1e-19 rad),
/// cheaper than atan2: verify takes millions of them.
[[nodiscard]] inline double angle_between(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  const double across = u.cross(v).norm(), along = u.dot(v);
  if (along > 0.0 && across < 1e-2 * along) {
    const double x = across / along, x2 = x * x;
    return x * (1.0 - x2 * (1.0 / 3.0 - x2 * (1.0 / 5.0 - x2 / 7.0)));
  }
  return std::atan2(across, along);
}

/// The direction at fraction t between two directions a few microradians apart (the ends
/// of a move whose rotary axes stand still): normalised straight-line interpolation, whose
/// angle differs from the great circle's by far less than a nanoradian at these angles.
[[nodiscard]] inline Eigen::Vector3d direction_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double t) {
  if (t == 0.0) return a;
  if (t == 1.0) return b;
  return (a + t * (b - a)).normalized();
}

}  // namespace ccomp::compensate
