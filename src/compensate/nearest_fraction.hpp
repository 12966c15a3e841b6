#pragma once
// Where along a piece of the nominal path a curve g(f), f in [0, 1], comes nearest a point:
// verify's search for the fraction of a turning piece an executed point is at, whose tool
// direction is then the one the program means there (verify.cpp, MeantDirection).
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace ccomp::compensate {

/// The fraction found, and the Gauss-Newton steps it took.
struct NearestFraction {
  double fraction = 0.0;
  int steps = 0;
};

/// What is asked of the fraction. It is settled when a step is below `fraction_step`; or
/// when the tool's direction there moves by less than `settled_turn` over the step (the
/// rotary axes turning at most `turn` rad over the piece); or when g moves by less than
/// `settled_move` over it while the direction moves by less than `direction_noise`; or once
/// g moves by less than `noise_move` and the step no longer shrinks. Where g hardly moves
/// along the piece (a tip standing nearly still while the tool turns), the rounding of g's
/// coordinates in the central difference alone makes steps of 1e-10 to 1e-8 of the
/// fraction, which never get below `fraction_step`: a step that no longer shrinks is that
/// noise while Gauss-Newton converges (its rate, |g - target| |g''| / |g'|^2, below 1).
struct NearestFractionOptions {
  /// rad: the most the tool's direction turns over the piece (its rotary axes' |q1 - q0|
  /// summed); unbounded where not known
  double turn = std::numeric_limits<double>::infinity();
  double fraction_step = 1e-12;
  double settled_turn = 1e-12;     ///< rad: a millionth of a microradian
  double settled_move = 1e-11;     ///< g's unit (mm, or rad for a direction): ten times a coordinate's rounding
  double direction_noise = 1e-9;   ///< rad: a thousandth of a microradian
  double noise_move = 1e-9;        ///< g's unit: a picometre
  int most_steps = 12;
  /// Nothing where `target` is farther from g than g moves over the whole piece (at the
  /// start): g cannot tell where along the piece the target is, and Gauss-Newton, its rate
  /// above 1, wanders from end to end.
  bool only_within_reach = false;
};

/// The fraction in [0, 1] where g (a function double -> Eigen::Vector3d) comes nearest
/// `target`, by Gauss-Newton on |g - target|^2 from `start`, the slope by central
/// differences; nothing where g does not move at the start (or, `only_within_reach`, where
/// the target is beyond what g's move can tell).
template <class G>
[[nodiscard]] std::optional<NearestFraction> nearest_fraction(double start, const Eigen::Vector3d& target, G g,
                                                              const NearestFractionOptions& o = {}) {
  constexpr double h = 1e-5;
  NearestFraction found{start, 0};
  double& f = found.fraction;
  double last_move = std::numeric_limits<double>::infinity();
  while (found.steps < o.most_steps) {
    const Eigen::Vector3d slope = (g(f + h) - g(f - h)) / (2 * h);
    const double slope2 = slope.squaredNorm();
    if (!(slope2 > 1e-24)) {
      if (found.steps == 0) return std::nullopt;
      break;
    }
    const Eigen::Vector3d off = g(f) - target;
    if (found.steps == 0 && o.only_within_reach && off.squaredNorm() > slope2) return std::nullopt;
    const double next = std::clamp(f - off.dot(slope) / slope2, 0.0, 1.0);
    const double step = std::abs(next - f), move = step * std::sqrt(slope2), turned = step * o.turn;
    const bool settled = step < o.fraction_step || turned < o.settled_turn ||
                         (move < o.settled_move && turned < o.direction_noise) ||
                         (move < o.noise_move && !(move < last_move));
    f = next, last_move = move;
    ++found.steps;
    if (settled) break;
  }
  return found;
}

}  // namespace ccomp::compensate
