#include "executed_tip.hpp"

namespace ccomp::compensate {

ExecutedTip::ExecutedTip(const model::ForwardModel& model, const model::Conditions& conditions)
    : model_(model), bound_(model, conditions), data_(model), tool_axis_(tool_axis_of(model)) {}

bool ExecutedTip::same_approach(const AxisArray<double>& a, const AxisArray<double>& b) const {
  for (std::size_t i = 0; i < a.size(); ++i)
    if (model_.reads_approach(i) && a[i] != b[i]) return false;
  return true;
}

bool ExecutedTip::start_move(const model::ChainQ& a, const model::ChainQ& b, const model::Conditions& conditions,
                             bool with_nominal) {
  // The play is followed point by point along the move: where it ends as it started, it
  // stood still all along (it moves one way only, towards the travel). An axis whose
  // approach no term reads may turn round: nothing changes with it.
  model::Conditions after = conditions;
  model::take_up_play(model_, after, a, b);
  on_chord_ = same_approach(after.directions, conditions.directions) && bound_.chord_deviation(a, b) <= kChordBound;
  // The nominal chain with its rotary axes still is a translation in the linear axes and
  // the tool length: its tip is affine along the move.
  if (with_nominal && a.segment<3>(3) != b.segment<3>(3)) on_chord_ = false;
  if (on_chord_) {
    start_ = tip_at(a, conditions, start_direction_, with_nominal ? &nominal_start_ : nullptr);
    end_ = tip_at(b, conditions, end_direction_, with_nominal ? &nominal_end_ : nullptr);
  }
  return on_chord_;
}

Eigen::Vector3d ExecutedTip::tip_at(const model::ChainQ& q, const model::Conditions& conditions,
                                    Eigen::Vector3d& direction, Eigen::Vector3d* nominal) {
  if (q != last_q_ || !same_approach(conditions.directions, last_directions_) || (nominal && !last_has_nominal_)) {
    model::forward(model_, data_, q, conditions, false, nominal ? model::Evaluate::both : model::Evaluate::actual);
    last_q_ = q, last_directions_ = conditions.directions, last_tip_ = data_.actual;
    last_direction_ = data_.R_actual * tool_axis_;
    last_has_nominal_ = nominal != nullptr;
    if (nominal) last_nominal_ = data_.nominal, last_nominal_direction_ = data_.R_nominal * tool_axis_;
  }
  direction = last_direction_;
  if (nominal) *nominal = last_nominal_, nominal_direction_ = last_nominal_direction_;
  return last_tip_;
}

}  // namespace ccomp::compensate
