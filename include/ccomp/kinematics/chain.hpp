#pragma once
// The machine's two kinematic chains, from the base frame W to the workpiece point p and to
// the tool tip, and the error matrix of docs/error-model.md (Ref 1, eq. 25):
//   E = (W M p)^-1 * (W M tool)
// Each link has two kinds of error (ISO 230-1), which act in different places:
//  - its LOCATION error (a constant: squareness, where a rotary axis' line is): where the
//    axis' line lies. A linear joint travels along its line turned by the location's
//    rotation (and shifted by its translation), without turning what it carries:
//      placement * Trans(location.t + q * location.R * direction) * motion_error
//    A rotary joint turns about its line displaced and tilted by the location (a point of
//    the table turns about the real line; at q = 0 the location changes nothing):
//      placement * location * Rot(q) * location^-1 * motion_error
//    A fixed joint has no line: its location is one more constant error pose.
//  - its ERROR MOTION (a function of the axis, a temperature...): after the axis' motion,
//    carried along with what the link moves.
// Pinocchio's pattern: an immutable ChainModel, a ChainData scratch built from it, and
// free functions algo(model, data, ...). Jacobians are right Jacobians (see pose.hpp).
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "ccomp/kinematics/pose.hpp"

namespace ccomp::kinematics {

enum class JointType : std::uint8_t { fixed, linear, rotary };

struct Joint {
  std::string name;  ///< "X", "B", "spindle", "tool"...
  JointType type = JointType::fixed;
  std::size_t axis = 0;            ///< index into q (X Y Z A B C U V W) when not fixed
  Vec3 direction = Vec3::UnitX();  ///< unit: motion along it (mm) or about it (rad)
  Pose placement;                  ///< parent frame -> this joint's frame at q = 0
};

/// One side of the machine: base frame W to its end (the workpiece point, or the tool tip).
struct Chain {
  std::vector<Joint> joints;
};

struct ChainModel {
  Chain workpiece;  ///< W -> ... -> p
  Chain tool;       ///< W -> ... -> tool tip
  std::size_t nq = 9;
};

using VecQ = Eigen::VectorXd;  ///< axis values: linear in mm, rotary in rad

/// Scratch for error_matrix(): poses along both chains and the Jacobians of E. It belongs
/// to the model it was built from, as it was then: a changed model needs new data.
struct ChainData {
  explicit ChainData(const ChainModel& model);

  /// Inputs, identity = none: each link's error-motion pose (after its motion) and
  /// location pose (its line's placement error: see the top of this header).
  std::vector<Pose> work_error, tool_error;
  std::vector<Pose> work_location, tool_location;
  std::vector<Pose> work_oMi, tool_oMi;                ///< W -> after link i
  Pose oMp, oMtool;                                    ///< W -> p, W -> tool tip
  Pose E;                                              ///< p -> tool tip: the error matrix
  Eigen::Matrix<double, 6, Eigen::Dynamic> J_q;        ///< dE/dq (6 x nq)
  std::vector<Mat6> J_work_error, J_tool_error;        ///< dE/d(error pose of each link)
  std::vector<Mat6> J_work_location, J_tool_location;  ///< dE/d(location pose of each link)

  // internal: each side's links as last composed, with what they were composed from. A
  // link whose axis value and error pose are unchanged is not composed again, nor are the
  // poses before the first link that changed (in a program most axes stand still).
  struct SideCache {
    std::vector<Pose> links, errors, locations;
    std::vector<double> q;
    std::vector<std::uint8_t> offset_only;  ///< 1: the joint's placement is a translation
    std::vector<std::uint8_t> located;      ///< 1: the location is not the identity
    std::vector<Vec3> lines;                ///< a linear joint's line of motion: location.R * direction
  };
  SideCache work_cache_, tool_cache_;
  Eigen::Matrix<double, 6, Eigen::Dynamic> J_q_work_, J_q_tool_;
};

/// Scratch for nominal_poses(): the perfect machine, which compensation asks for at every
/// move (the pose the inverse aims at). Built from the model, as ChainData is.
struct NominalData {
  explicit NominalData(const ChainModel& model);

  Pose oMp, oMtool;  ///< W -> p, W -> tool tip
  Pose E;            ///< p -> tool tip

  // internal: each side's end pose is affine in its linear joints' values while its rotary
  // joints stand still (an indexing table turns seldom): its rotation, its translation with
  // every linear joint at 0, and each linear joint's column, for the rotary values held.
  struct Side {
    bool composed = false;
    std::vector<double> rotary_q;          ///< the rotary joints' values, in chain order
    std::vector<std::size_t> rotary_axes;  ///< and their variables
    Mat3 R = Mat3::Identity();
    Vec3 t0 = Vec3::Zero();
    std::vector<std::size_t> linear_axes;  ///< each linear joint's variable
    std::vector<Vec3> columns;             ///< and the end's translation per unit of it
  };
  Side work_side_, tool_side_;
};

/// The perfect machine at q: what error_matrix() gives with every error pose the identity
/// (to the last bits of its sums: a side's translation is summed as its affine form in the
/// linear joints, the same at every q).
void nominal_poses(const ChainModel& model, NominalData& data, const Eigen::Ref<const VecQ>& q);

/// Which Jacobians error_matrix() computes: none; dE/dq and dE/d(each link's error pose)
/// (what the inverse needs: error motions vary with the axes); or those and dE/d(each
/// link's location pose) too (what a fit needs).
enum class ChainJacobians : std::uint8_t { none, axes, all };

/// What a caller that sets the poses knows of them since its last error_matrix() on the
/// same data: which links' error poses it set (bit j: joint j of the side) and whether it
/// set any location pose. error_matrix() then compares only those with what it composed
/// last; without it, every pose (24 doubles a link, at every evaluation of the model).
/// Joints past the 64th of a side are always compared.
struct PoseChanges {
  std::uint64_t work_error = 0, tool_error = 0;
  bool locations = false;
};

/// Computes E for axis values q with the error poses in data.work_error / data.tool_error
/// and the location poses in data.work_location / data.tool_location, and the Jacobians
/// `which` asks for.
void error_matrix(const ChainModel& model, ChainData& data, const Eigen::Ref<const VecQ>& q,
                  ChainJacobians which = ChainJacobians::all, const PoseChanges* changes = nullptr);

}  // namespace ccomp::kinematics
