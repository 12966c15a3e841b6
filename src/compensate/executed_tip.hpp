#pragma once
// Where the machine's tool tip is along a straight move, for verify and predict: on a
// move whose play stays as it is and whose error field the model bounds to bend by less
// than a nanometre (a finishing program's short moves), the tip at a fraction of the move
// is taken on the chord between its two ends, each evaluated exactly (the start is the
// last move's end): it is within that bound of the model's tip there
// (model/variation_bound.hpp), and so is every distance measured from it. Other moves are
// evaluated point by point by the caller.
#include <Eigen/Core>
#include <array>
#include <cmath>

#include "ccomp/axis.hpp"
#include "ccomp/model/forward.hpp"
#include "ccomp/model/variation_bound.hpp"
#include "tool_direction.hpp"

namespace ccomp::compensate {

class ExecutedTip {
 public:
  /// mm: a thousandth of the default tolerance and a tenth of the last digit verify prints
  /// (0.01 um); a 0.05 mm move of the full sample HMC is bounded by 0.25 nm.
  static constexpr double kChordBound = 1e-6;

  /// `conditions`: the temperatures and time the bound holds for.
  ExecutedTip(const model::ForwardModel& model, const model::Conditions& conditions);

  /// A straight move from a to b, the play at a as `conditions` has it: whether its points
  /// lie on its chord (then on_chord() gives them). `with_nominal` (predict's): the nominal
  /// tip too, on a move where it is affine (no rotary axis turns), else the move is
  /// evaluated point by point. The temperatures and the time must be those the tip was
  /// made for (they are not part of what a kept end is looked up by).
  bool start_move(const model::ChainQ& a, const model::ChainQ& b, const model::Conditions& conditions,
                  bool with_nominal = false);
  /// A move that is not straight: its points are evaluated.
  void other_move() { on_chord_ = false; }
  [[nodiscard]] bool on_chord() const { return on_chord_; }
  /// The tip at fraction t of the move on its chord (the ends exactly as evaluated).
  [[nodiscard]] Eigen::Vector3d on_chord(double t) const { return between(start_, end_, t); }
  /// The nominal tip at fraction t, after start_move(..., true).
  [[nodiscard]] Eigen::Vector3d nominal_on_chord(double t) const { return between(nominal_start_, nominal_end_, t); }
  /// The chord's ends (the move's tips there), for a caller that makes the points itself.
  [[nodiscard]] const Eigen::Vector3d& chord_start() const { return start_; }
  [[nodiscard]] const Eigen::Vector3d& chord_end() const { return end_; }
  /// The tool's actual direction at the chord's ends (tool_direction.hpp), and at fraction
  /// t between them: the rotary axes stand still along a move on its chord (a turn bends
  /// the tip's path beyond the bound), so the direction moves by the linear axes' angular
  /// errors alone, microradians, and is interpolated between its ends.
  [[nodiscard]] const Eigen::Vector3d& chord_start_direction() const { return start_direction_; }
  [[nodiscard]] const Eigen::Vector3d& chord_end_direction() const { return end_direction_; }
  [[nodiscard]] Eigen::Vector3d direction_on_chord(double t) const {
    return direction_between(start_direction_, end_direction_, t);
  }
  /// The direction the program means along the move, after start_move(..., true): the
  /// nominal chain's turns only with the rotary axes, which stand still on it.
  [[nodiscard]] const Eigen::Vector3d& nominal_direction() const { return nominal_direction_; }

  /// The point at fraction t of the chord from a to b, its ends exactly a and b: what
  /// on_chord() gives, for whoever holds the ends.
  static Eigen::Vector3d between(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double t) {
    if (t == 1.0) return b;
    return t == 0.0 ? a : Eigen::Vector3d(a + t * (b - a));
  }

 private:
  /// The actual tip at q and the tool's direction there into `direction` (and the nominal
  /// tip into `nominal`, when given, its direction into nominal_direction_).
  Eigen::Vector3d tip_at(const model::ChainQ& q, const model::Conditions& conditions, Eigen::Vector3d& direction,
                         Eigen::Vector3d* nominal);
  /// Whether a and b are alike in every approach a term reads (ForwardModel::reads_approach;
  /// the others change nothing).
  [[nodiscard]] bool same_approach(const AxisArray<double>& a, const AxisArray<double>& b) const;

  const model::ForwardModel& model_;
  model::VariationBound bound_;
  model::ForwardData data_;
  bool on_chord_ = false;
  Eigen::Vector3d start_ = Eigen::Vector3d::Zero(), end_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d nominal_start_ = Eigen::Vector3d::Zero(), nominal_end_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d tool_axis_;
  Eigen::Vector3d start_direction_ = Eigen::Vector3d::Zero(), end_direction_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d nominal_direction_ = Eigen::Vector3d::Zero();
  // The last end evaluated: the next move's start.
  model::ChainQ last_q_ = model::ChainQ::Constant(std::nan(""));
  AxisArray<double> last_directions_{};
  Eigen::Vector3d last_tip_ = Eigen::Vector3d::Zero(), last_nominal_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d last_direction_ = Eigen::Vector3d::Zero(), last_nominal_direction_ = Eigen::Vector3d::Zero();
  bool last_has_nominal_ = false;
};

}  // namespace ccomp::compensate
