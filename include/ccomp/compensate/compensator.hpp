#pragma once
// Compensation of one straight move: the commanded axis values at its end, and the points
// it must be split at so that the path the machine executes (straight in axis space between
// compensated points) stays within the tolerance of the nominal path. Adaptive: a move is
// split only where the error field bends it away, at the midpoint of the piece that fails.
#include <array>
#include <cmath>
#include <vector>

#include "ccomp/compensate/inverse.hpp"
#include "ccomp/model/forward.hpp"

namespace ccomp::compensate {

struct CompensationOptions {
  double tolerance = 0.001;  ///< mm: largest distance of the executed path from the nominal one
  int max_depth = 12;        ///< a move is split into at most 2^12 pieces
  model::Conditions conditions;
};

/// A point of a compensated move: the fraction s of the nominal move it ends, and the
/// commanded chain values there.
struct CompensatedPoint {
  double s = 1.0;
  model::ChainQ q;
};

struct MoveReport {
  double max_deviation_before = 0.0;  ///< mm: the uncompensated path's largest error
  double max_deviation_after = 0.0;   ///< mm: the compensated path's, at the checked points
  double max_correction = 0.0;        ///< mm: largest change of a linear axis
  double max_orientation_error = 0.0;  ///< rad: what the machine cannot correct
};

class Compensator {
 public:
  Compensator(const model::ForwardModel& model, CompensationOptions options);

  /// The compensated points of the straight move from `start` to `end` (nominal chain
  /// values), in order; the last one is the move's end. Throws ccomp::Error when the
  /// inverse does not converge.
  void straight(const model::ChainQ& start, const model::ChainQ& end, std::vector<CompensatedPoint>& out,
                MoveReport& report, double tolerance = -1.0);
  /// The compensated values for one point (used for a move's start).
  [[nodiscard]] model::ChainQ point(const model::ChainQ& nominal, MoveReport& report);
  /// The error of the uncompensated machine at a point: |actual - nominal| (mm).
  [[nodiscard]] double error_at(const model::ChainQ& nominal);

  model::Conditions& conditions() { return options_.conditions; }

 private:
  void split(const model::ChainQ& a_nominal, const model::ChainQ& b_nominal, const model::ChainQ& a_comp,
             const model::ChainQ& b_comp, double s0, double s1, int depth, double tolerance,
             std::vector<CompensatedPoint>& out, MoveReport& report);
  double executed_deviation(const model::ChainQ& a_nominal, const model::ChainQ& b_nominal,
                            const model::ChainQ& a_comp, const model::ChainQ& b_comp, double t);

  const model::ForwardModel& model_;
  CompensationOptions options_;
  // The last point solved: its nominal values, solution and directions. A move usually
  // starts where the last one ended (reused), and its points are near (warm start).
  model::ChainQ last_nominal_ = model::ChainQ::Constant(std::nan(""));
  model::ChainQ last_solution_ = model::ChainQ::Zero();
  std::array<double, 9> last_directions_{};
  InverseProblem problem_;
  model::ForwardData data_, check_;
};

}  // namespace ccomp::compensate
