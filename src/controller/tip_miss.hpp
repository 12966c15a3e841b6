#pragma once
// What the controller tables are measured by: where the tool tip lands for commanded axis
// values against where a perfect machine puts it, shared by the axis and volume tables.
#include <array>
#include <initializer_list>
#include <span>

#include "ccomp/axis.hpp"
#include "ccomp/kinematics/pose.hpp"
#include "ccomp/model/forward.hpp"

namespace ccomp::controller {

/// Approach states with `axes` travelling `direction` (+1 up, -1 down) and every other
/// axis in the middle of its play (0), as TipMiss takes them.
inline AxisArray<double> travelling(std::span<const std::size_t> axes, int direction) {
  AxisArray<double> d{};
  for (const std::size_t axis : axes) d[axis] = direction;
  return d;
}
inline AxisArray<double> travelling(std::initializer_list<std::size_t> axes, int direction) {
  return travelling(std::span<const std::size_t>(axes.begin(), axes.size()), direction);
}

/// The tool tip's miss, in machine-axis directions: where it is with the axes commanded
/// to `commanded`, against where a perfect machine puts it at `target`.
class TipMiss {
 public:
  TipMiss(const model::ForwardModel& model, const model::Conditions& conditions)
      : model_(model), data_(model), conditions_(conditions) {}

  /// Parameters [offset, offset + count) of the model taken as 0 from now on (a term left
  /// out of what is sampled).
  void zero_parameters(std::size_t offset, std::size_t count) {
    data_.edit_parameters().segment(static_cast<Eigen::Index>(offset), static_cast<Eigen::Index>(count)).setZero();
  }

  /// `directions`: each axis' approach state (+1 up, -1 down, 0 the middle of its play):
  /// an axis not moving is in the middle, so its backlash is no one else's.
  Eigen::Vector3d operator()(const model::ChainQ& commanded, const model::ChainQ& target,
                             const AxisArray<double>& directions) {
    model::forward(model_, data_, target, conditions_, false, model::Evaluate::nominal);
    const Eigen::Vector3d wanted = data_.nominal;
    conditions_.directions = directions;
    model::forward(model_, data_, commanded, conditions_, false, model::Evaluate::both);
    return data_.nominal_chain.oMp.R * (data_.actual - wanted);
  }

  /// How far the tool turns relative to the table about `u` (rad): commanded against the
  /// perfect machine at target.
  double turn(const model::ChainQ& commanded, const model::ChainQ& target, const AxisArray<double>& directions,
              const Eigen::Vector3d& u) {
    model::forward(model_, data_, target, conditions_, false, model::Evaluate::nominal);
    const Eigen::Matrix3d wanted = data_.R_nominal;
    conditions_.directions = directions;
    model::forward(model_, data_, commanded, conditions_, false, model::Evaluate::both);
    return u.dot(kinematics::so3_log(wanted.transpose() * data_.R_actual));
  }

  /// The direction the tool turns (in its own frame) as rotary axis j turns up at q.
  Eigen::Vector3d turn_axis(const model::ChainQ& q, std::size_t j) {
    constexpr double kStep = 1e-4;  // rad
    model::ChainQ moved = q;
    moved[static_cast<Eigen::Index>(j)] += kStep;
    model::forward(model_, data_, q, conditions_, false, model::Evaluate::nominal);
    const Eigen::Matrix3d at = data_.R_nominal;
    model::forward(model_, data_, moved, conditions_, false, model::Evaluate::nominal);
    return kinematics::so3_log(at.transpose() * data_.R_nominal).normalized();
  }

  /// How far the tip moves along machine axis j when axis j is commanded 1 mm further:
  /// +1 or -1, as the chain carries the tool or the workpiece.
  double sense(const model::ChainQ& q, std::size_t j) {
    model::ChainQ moved = q;
    moved[static_cast<Eigen::Index>(j)] += 1.0;
    model::forward(model_, data_, q, conditions_, false, model::Evaluate::nominal);
    const Eigen::Vector3d at = data_.nominal_chain.oMp.R * data_.nominal;
    model::forward(model_, data_, moved, conditions_, false, model::Evaluate::nominal);
    const Eigen::Vector3d there = data_.nominal_chain.oMp.R * data_.nominal;
    return there[static_cast<Eigen::Index>(j)] - at[static_cast<Eigen::Index>(j)];
  }

 private:
  const model::ForwardModel& model_;
  model::ForwardData data_;
  model::Conditions conditions_;
};

}  // namespace ccomp::controller
