#pragma once
// Positioning of a linear axis by ISO 230-2 from bidirectional runs (docs/error-model.md Ref 3): per target
// the mean deviations in each approach direction, their spread and the reversal; for the
// axis the accuracy A, reversal B, systematic deviation E, mean deviation M and
// repeatability R; and Ref 3's split of the mean deviation into a cumulative part (a
// smooth curve), a periodic part (the screw's or scale's pitch) and the reversal.
#include <cstddef>
#include <string>
#include <vector>

#include "ccomp/identify/measurements.hpp"

namespace ccomp::identify {

struct PositioningTarget {
  double position = 0.0;  ///< mm
  int runs_up = 0, runs_down = 0;
  double mean_up = 0.0, mean_down = 0.0;  ///< mean positional deviation approaching upward, downward (mm)
  double s_up = 0.0, s_down = 0.0;        ///< their standard uncertainties (mm; 0 with one run)
  double reversal = 0.0;                  ///< B_i = mean_up - mean_down
  double repeatability = 0.0;             ///< R_i, bidirectional
};

struct PositioningReport {
  std::size_t axis = 0;  ///< 0 1 2: X Y Z
  std::vector<PositioningTarget> targets;
  int runs = 0;                        ///< fewest runs at a target in one direction
  double A = 0, A_up = 0, A_down = 0;  ///< accuracy
  double B = 0, B_mean = 0;            ///< reversal: largest |B_i|, mean B_i
  double E = 0, E_up = 0, E_down = 0;  ///< systematic positional deviation
  double M = 0;                        ///< mean bidirectional positional deviation
  double R = 0, R_up = 0, R_down = 0;  ///< repeatability
  // Ref 3's decomposition of the mean bidirectional deviation
  std::vector<double> cumulative;   ///< cubic in the position (mm per mm^k), k = 0..3
  double period = 0.0;              ///< mm, the periodic part's (0: none significant)
  double periodic_amplitude = 0.0;  ///< mm
  double rms_left = 0.0;            ///< mm: what cumulative + periodic + reversal leave of the means
};

/// Analyses the readings of `data` along axis `axis` (0..2): rows whose direction is the
/// axis, grouped by target (to 1 um) and approach (vx.. of the axis; rows without one are
/// skipped). `source` empty takes every source. Throws ccomp::Error (data) when there are
/// no such rows, or no target approached from both sides.
[[nodiscard]] PositioningReport analyse_positioning(const MeasurementSet& data, std::size_t axis,
                                                    const std::string& source = {});

}  // namespace ccomp::identify
