#pragma once
// A bound on how far the actual tool tip strays from a straight line while the axes move
// linearly between two commanded points: what lets the compensation accept a short move
// without evaluating the model inside it.
//
// Along a path q(t) = a + t (b - a), t in [0, 1], the tip is the rigid chain's f0(q(t))
// plus the error field e(q(t)). Where nothing turns, f0 is affine in t and the tip leaves
// the chord between its ends by at most max |d2e/dt2| / 8 (the chord error of a function
// with bounded curvature), plus a quarter of a slope jump times the travel for a linear
// table's knot or end crossed on the way. Each term's value, slope and curvature are
// bounded once over the axes' limits (the conditions fix the temperatures and the time);
// an angular term acts through a lever no longer than the chain's offsets, strokes and the
// tool length. A move that turns an axis (by a correction, microradians) adds the rigid
// chain's own bending and the terms' turning with it. Products of two error motions are
// smaller than the first-order terms by the largest error angle; they are covered by a
// factor 1 + 4 (E + T / lever), E the sum of the angular terms' bounds (rad), T that of the
// translations (mm); a model whose terms may reach 0.01 rad or 1 mm gets no bound.
//
// The same bounds give how much the tip's error (actual - nominal) can change between two
// points, and as the approach directions change (the terms reading them, each by its slope
// in them): what lets a report skip evaluating a point that cannot raise its maximum.
//
// Nominal points may lie outside the limits by their correction: the ranges are widened
// by the model's max_correction. The bound is +inf where none holds: an axis without limits under a term that grows
// with it, a move longer than a table's knot spacing, a term in a variable with no range.
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "ccomp/axis.hpp"
#include "ccomp/model/forward.hpp"

namespace ccomp::model {

class VariationBound {
 public:
  VariationBound(const ForwardModel& model, const Conditions& conditions);

  /// Upper bound (mm) of the distance of the actual tip from the chord between its
  /// positions at `a` and `b` (commanded chain values), while the axes move linearly
  /// from a to b; +inf when the model gives no bound.
  [[nodiscard]] double chord_deviation(const ChainQ& a, const ChainQ& b) const;
  /// Upper bound (mm) of |e(b) - e(a)|, e the tip's error (actual - nominal position) under
  /// the conditions the bound was made for; +inf when the model gives no bound.
  [[nodiscard]] double error_change(const ChainQ& a, const ChainQ& b) const;
  /// How far the move from a to b may be stretched (b' = a + k (b - a), k >= 1) before the
  /// chord bound is lost on a table's knots: the chord bound of the stretched move is then at
  /// most k^2 times this one's (each of its terms grows with the travel or its square).
  [[nodiscard]] double stretch_limit(const ChainQ& a, const ChainQ& b) const;
  /// mm: the longest lever an error angle acts through at a or b (the chain's offsets and
  /// strokes, and the longer tool): an angle's bound times it bounds what it moves the tip.
  [[nodiscard]] double lever(const ChainQ& a, const ChainQ& b) const;
  /// error_change() for a tool of one length at both points, as the sum over the chain
  /// variables of a slope times each one's travel, plus its rounding: what a caller taking
  /// many bounds under one tool keeps (+inf slopes where the model gives no bound).
  struct ErrorSlopes {
    double tool_length = std::numeric_limits<double>::quiet_NaN();
    std::array<double, kChainVariables> per_variable{};
    double rounding = 0.0;
    /// The bound of |e(b) - e(a)| (a and b of this tool length).
    [[nodiscard]] double change(const ChainQ& a, const ChainQ& b) const {
      double sum = rounding;
      for (Eigen::Index i = 0; i < a.size(); ++i)
        if (const double d = std::abs(b[i] - a[i]); d != 0.0) sum += per_variable[static_cast<std::size_t>(i)] * d;
      return sum;
    }
  };
  [[nodiscard]] ErrorSlopes error_slopes(double tool_length) const;
  /// Upper bound (mm) of |e(q, b) - e(q, a)| at any one point q, of the exact errors: the
  /// tip's as the approach directions (each axis' in [-1, 1], Conditions::directions)
  /// change from `a` to `b`, with a tool of `tool_length`; +inf when the model gives no
  /// bound. Added to error_change() (which holds the computed errors' rounding), it bounds
  /// a change of both the point and the approach between two computed errors.
  [[nodiscard]] double direction_change(const AxisArray<double>& a, const AxisArray<double>& b,
                                        double tool_length) const;
  /// rad: the sum of the angular terms' bounds, the largest error angle the chain can make.
  [[nodiscard]] double largest_error_angle() const { return angular_sum_; }

 private:
  /// Each chain variable's travel from a to b, their sums over the linear and the rotary
  /// ones, and the lever with the tool length of a and b.
  struct Travel {
    std::array<double, kChainVariables> by_variable{};
    double linear = 0.0, turning = 0.0, lever = 0.0;
  };
  [[nodiscard]] Travel travel(const ChainQ& a, const ChainQ& b) const;
  /// 1 + 4 (E + T / lever): what products of two error motions may add.
  [[nodiscard]] double second_order(double lever) const;

  /// What the terms of one chain variable add up to, per unit travel of it (squared for
  /// the curvatures): translations in mm, rotations in rad (times the lever).
  struct AlongVariable {
    double translation_curvature = 0.0, angular_curvature = 0.0;
    double translation_slope = 0.0, angular_slope = 0.0;
    double translation_kink = 0.0, angular_kink = 0.0;
    double knot_gap = std::numeric_limits<double>::infinity();  ///< the shortest of its tables'
  };
  /// A term of two chain variables (a cross-axis term of two axes): its own bounds.
  struct TwoVariables {
    std::size_t u = 0, w = 0;
    bool angular = false;
    double slope_u = 0.0, slope_w = 0.0, curvature_uu = 0.0, curvature_uw = 0.0, curvature_ww = 0.0;
  };
  std::array<AlongVariable, kChainVariables> along_{};
  std::vector<TwoVariables> two_variables_;
  /// What the terms reading axis i's approach direction add up to, per unit of it:
  /// translations in mm, rotations in rad (times the lever).
  AxisArray<double> direction_translation_{}, direction_angular_{};
  bool directions_bounded_ = true;  ///< false: a term reads a direction the bound cannot place
  std::array<bool, kChainVariables> rotary_{};
  double lever_ = 0.0;               ///< mm, without the tool length
  double angular_sum_ = 0.0;      ///< E (rad)
  double translation_sum_ = 0.0;  ///< T (mm)
  bool bounded_ = false;
};

}  // namespace ccomp::model
