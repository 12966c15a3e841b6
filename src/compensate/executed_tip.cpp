#include "executed_tip.hpp"

#include <cstdint>

namespace ccomp::compensate {

ExecutedTip::ExecutedTip(const model::ForwardModel& model, const model::Conditions& conditions)
    : model_(model), bound_(model, conditions), data_(model) {
  for (const model::ForwardModel::TermSlot& s : model.slots())
    for (const std::int16_t v : {s.primary, s.secondary}) {
      const auto axis = static_cast<std::size_t>(v) - model::ForwardModel::kFirstDirectionVariable;
      if (v >= 0 && axis < approach_read_.size()) approach_read_[axis] = true;
    }
}

bool ExecutedTip::same_approach(const std::array<double, 9>& a, const std::array<double, 9>& b) const {
  for (std::size_t i = 0; i < a.size(); ++i)
    if (approach_read_[i] && a[i] != b[i]) return false;
  return true;
}

bool ExecutedTip::start_move(const model::ChainQ& a, const model::ChainQ& b, const model::Conditions& conditions) {
  // The play is followed point by point along the move: where it ends as it started, it
  // stood still all along (it moves one way only, towards the travel). An axis whose
  // approach no term reads may turn round: nothing changes with it.
  model::Conditions after = conditions;
  model::take_up_play(model_, after, a, b);
  on_chord_ = same_approach(after.directions, conditions.directions) && bound_.chord_deviation(a, b) <= kChordBound;
  if (on_chord_) {
    start_ = tip_at(a, conditions);
    end_ = tip_at(b, conditions);
  }
  return on_chord_;
}

Eigen::Vector3d ExecutedTip::tip_at(const model::ChainQ& q, const model::Conditions& conditions) {
  if (q == last_q_ && same_approach(conditions.directions, last_directions_)) return last_tip_;
  model::forward(model_, data_, q, conditions, false, model::Evaluate::actual);
  last_q_ = q, last_directions_ = conditions.directions, last_tip_ = data_.actual;
  return last_tip_;
}

}  // namespace ccomp::compensate
