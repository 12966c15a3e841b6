// The compensator's turns inside a move: where an axis' correction turns round along the
// pieces of a straight move (to cut the move there), and what the plays do along pieces no
// take-up may be written in (under the control's radius offset).
#include <algorithm>
#include <cmath>
#include <optional>
#include <span>

#include "axis_travel.hpp"
#include "ccomp/axis.hpp"
#include "ccomp/compensate/compensator.hpp"

namespace ccomp::compensate {

using model::ChainQ;

double Compensator::play_stray(const StraightMove& move, double s0, const ChainQ& a,
                               const std::vector<CompensatedPoint>& out, std::size_t first) {
  // Each play runs out somewhere along the pieces, the terms of its approach switching
  // linearly until then: the tool's course bends there, and at the pieces' ends. Only the
  // pieces up to the last whose travel moves a play are looked at (mostly none).
  std::size_t last = first;
  {
    AxisArray<double> plays = play_;
    ChainQ from_q = a;
    for (std::size_t k = first; k < out.size(); ++k) {
      const AxisArray<double> before = plays;
      model::take_up_play(model_, plays, from_q, out[k].q);
      for (std::size_t i = 0; i < before.size(); ++i)
        if (model_.reads_approach(i) && std::abs(plays[i] - before[i]) > 0.02) last = k + 1;
      from_q = out[k].q;
    }
  }
  model::Conditions at = options_.conditions;
  AxisArray<double> state = play_;
  ChainQ from_q = a;
  double from_s = s0, stray = 0.0;
  for (std::size_t k = first; k < last; ++k) {
    const ChainQ delta = out[k].q - from_q;
    std::array<double, 10> bends{};
    std::size_t n = 0;
    for (std::size_t i = 0; i < state.size(); ++i) {
      const auto j = static_cast<Eigen::Index>(i);
      const double w = model_.lost_motion()[i];
      if (!model_.reads_approach(i) || w <= 0 || std::abs(delta[j]) <= still(i)) continue;
      const double t = ((delta[j] > 0 ? 1.0 : -1.0) - state[i]) * w / (2.0 * delta[j]);
      if (t > 0 && t < 1) bends[n++] = t;
    }
    bends[n++] = 1.0;
    for (std::size_t b = 0; b < n; ++b) {
      at.directions = state;
      const ChainQ q = b + 1 < n ? ChainQ(from_q + bends[b] * delta) : out[k].q;  // (the last: the piece's end)
      model::take_up_play(model_, at, from_q, q);
      model::forward(model_, check_, q, at, false, model::Evaluate::actual);
      const Eigen::Vector3d seen = check_.actual;
      stray = std::max(stray, (seen - nominal_tip(along(move.start, move.end, from_s + bends[b] * (out[k].s - from_s))))
                                  .norm());
    }
    state = at.directions;  // the play at the piece's end, where the last bend is
    from_q = out[k].q, from_s = out[k].s;
  }
  return stray;
}

std::optional<Compensator::Turn> Compensator::correction_turn(double s0, const ChainQ& a,
                                                               std::span<const CompensatedPoint> pieces,
                                                               bool whole) const {
  const auto& need = options_.conditions.directions;
  std::optional<Turn> worst;
  if (pieces.size() < 2) return worst;  // one piece travels one way
  for (std::size_t i = 0; i < need.size(); ++i) {
    if (!model_.reads_approach(i)) continue;
    const auto k = static_cast<Eigen::Index>(i);
    // The pieces' travel of axis i, significant where the approach would read it (10 nm):
    // how far it runs back against the way it went first, from the piece before it did.
    double way = 0.0, back = 0.0, from = s0, before = s0, turn_from = s0;
    ChainQ last = a;
    for (const CompensatedPoint& piece : pieces) {
      const double travel = piece.q[k] - last[k];
      last = piece.q;
      if (std::abs(travel) > 10 * still(i)) {
        const double sign = travel > 0 ? 1.0 : -1.0;
        if (way == 0.0) {
          way = sign;
        } else if (sign == way) {
          back = 0.0;
        } else {
          if (back == 0.0) turn_from = from;
          back += std::abs(travel);
          if (const double left = turn_left(i, back); left > 0.125 * options_.tolerance) {
            // The first is where the stretch is cut; `whole`: the largest of all, for the count.
            if (!whole) return Turn{i, way, turn_from, piece.s, left};
            if (!worst || left > worst->left) worst = Turn{i, way, turn_from, piece.s, left};
          }
        }
      }
      from = before, before = piece.s;
    }
  }
  return worst;
}

double Compensator::turn_left(std::size_t axis, double back) const {
  // Travelling `back` against its approach, the axis' terms switch by their share of it:
  // its own reversal keeps the carriage where it was while the command goes back (that is
  // its share of reversal_size()), the others move the tool besides.
  const double lost = model_.lost_motion()[axis], size = model_.reversal_size()[axis];
  return lost > 0 ? std::min(back, lost) * size / lost : size;
}

double Compensator::extremum(const StraightMove& move, const Turn& turn, MoveReport& report) {
  // Golden-section search for where the axis' correction is furthest its first way, the
  // pieces showing it between turn.from and turn.to.
  const auto k = static_cast<Eigen::Index>(turn.axis);
  // Every point solved on the model: the search compares solutions nanometres apart.
  auto value = [&](double s) {
    return turn.way * point(along(move.start, move.end, s), report, Shortcut::none)[k];
  };
  double lo = turn.from, hi = turn.to;
  constexpr double kGolden = 0.6180339887498949;
  double x1 = hi - kGolden * (hi - lo), x2 = lo + kGolden * (hi - lo);
  double f1 = value(x1), f2 = value(x2);
  for (int n = 0; n < 16; ++n) {
    if (f1 > f2) {
      hi = x2, x2 = x1, f2 = f1;
      x1 = hi - kGolden * (hi - lo), f1 = value(x1);
    } else {
      lo = x1, x1 = x2, f1 = f2;
      x2 = lo + kGolden * (hi - lo), f2 = value(x2);
    }
  }
  return 0.5 * (lo + hi);
}

}  // namespace ccomp::compensate
