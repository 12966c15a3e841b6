#pragma once
// Private to diagnose(): does a candidate predict readings it was not fitted to? Its
// coefficients are fitted with one group of readings left out and scored on that group,
// for every group in turn (leave-one-group-out cross-validation). The groups are the
// sources (laser lines, a grid, a test piece) where two or more of them each carry a fifth
// of what the candidate adds to the base; otherwise interleaved blocks of its readings, so
// a bump or a drift seen in one run is still predicted from its neighbours. The base stays
// fitted to all readings: the question is the candidate's, not the model's.
#include <Eigen/Core>
#include <cstdint>

#include "ccomp/identify/measurements.hpp"

namespace ccomp::identify::detail {

enum class HeldOutBy : std::uint8_t { source, block };

struct HeldOut {
  HeldOutBy by = HeldOutBy::source;
  int groups = 0;
  /// mm^2: the fall in the sum of squares on each group, with the coefficients fitted
  /// without it, summed over the groups (negative: the candidate predicts worse than nothing).
  double gain = 0.0;
  /// mm^2: the same fall on the same readings with the coefficients fitted to all of them.
  double fitted_gain = 0.0;
};

/// `columns`: the candidate's columns per reading less what the base absorbs of them;
/// `r`: the base's residual (orthogonal to the base).
[[nodiscard]] HeldOut held_out_gain(const Eigen::MatrixXd& columns, const Eigen::VectorXd& r,
                                    const MeasurementSet& data);

}  // namespace ccomp::identify::detail
