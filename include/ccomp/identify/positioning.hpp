#pragma once
// Positioning of a linear or rotary axis by ISO 230-2 (docs/error-model.md Ref 3): per target
// the mean deviations in each approach direction, their spread, the reversal and the
// repeatability; for the axis the accuracy A, systematic deviation E and repeatability R each
// way and bidirectional, the range of the mean bidirectional deviation M and the reversal B
// and its mean. A figure the runs cannot give (a direction never approached, a spread from one
// run) is not stated (nullopt), never a number made up. Then Ref 3's split of the mean
// deviation into a cumulative part (a smooth curve), a periodic part (the screw's or scale's
// pitch, a worm's tooth) and the reversal.
#include <cstddef>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "ccomp/identify/measurements.hpp"

namespace ccomp::model {
class ForwardModel;
}

namespace ccomp::identify {

/// Arcseconds in a radian: ISO 230-2 gives a rotary axis' figures in arcseconds.
inline constexpr double kArcsecPerRad = 180.0 * 3600.0 / std::numbers::pi;

/// Deviations are in mm on a linear axis and in rad on a rotary one; positions in mm or deg,
/// as the files give them (program coordinates in each file's frame).
struct PositioningTarget {
  double position = 0.0;
  int runs_up = 0, runs_down = 0;                       ///< approaches read each way
  std::optional<double> mean_up, mean_down;             ///< x_i up, x_i down: a direction read at all
  std::optional<double> mean;                           ///< x_i = (up + down) / 2: both directions
  std::optional<double> reversal;                       ///< B_i = mean_up - mean_down: both directions
  std::optional<double> s_up, s_down;                   ///< estimators of the standard uncertainty: 2 runs that way
  std::optional<double> repeatability_up, repeatability_down;  ///< R_i up = 4 s_i up ...
  std::optional<double> repeatability;  ///< R_i = max(2 s_up + 2 s_down + |B_i|, R_i up, R_i down)
};

/// The axis' figures; each is nullopt where the runs do not give it, and `not_stated` says why.
struct PositioningReport {
  std::size_t axis = 0;  ///< 0..5: X Y Z A B C
  bool rotary = false;
  std::vector<PositioningTarget> targets;
  int runs_up = 0, runs_down = 0;  ///< fewest runs at a target approached that way (0: never)
  std::size_t one_way_targets = 0;  ///< approached one way only: outside the bidirectional figures
  std::optional<double> A, A_up, A_down;  ///< accuracy
  std::optional<double> E, E_up, E_down;  ///< systematic positional deviation
  std::optional<double> R, R_up, R_down;  ///< repeatability
  std::optional<double> M;                ///< range of the mean bidirectional positional deviation
  std::optional<double> B;                ///< reversal value: the largest |B_i|
  std::optional<double> B_signed;         ///< that B_i with its sign
  std::optional<double> B_at;             ///< where it is
  std::optional<double> B_mean;           ///< mean reversal value (signed)
  std::vector<std::string> not_stated;    ///< each missing figure and the runs it needs
  // Ref 3's decomposition of the mean deviation (bidirectional where there is one, else the
  // one direction's), in the units above
  std::vector<double> cumulative;   ///< cubic in the position (per unit^k), k = 0..3
  double period = 0.0;              ///< the periodic part's (0: none significant)
  double periodic_amplitude = 0.0;
  double rms_left = 0.0;            ///< what cumulative + periodic (+ reversal) leave of the means
  /// Said when the targets are too few for the cubic to mean much (empty otherwise).
  std::string split_caveat;
};

/// Analyses the readings of `data` along axis `axis` (0..5: X Y Z A B C) that carry an
/// approach direction (v<axis>), grouped by target (to 0.001 mm or deg) and approach.
/// A linear axis' readings are those along it; a rotary axis' are those along the path its
/// turning moves the reading's point (as `ccomp import` writes a rotary calibrator's runs),
/// their angle the deviation over the lever, for which `forward` (the machine's kinematics)
/// is needed. `source` empty takes every source. Throws ccomp::Error (data) when there are no
/// such rows, (usage) for a rotary axis without `forward`.
[[nodiscard]] PositioningReport analyse_positioning(const MeasurementSet& data, std::size_t axis,
                                                    const std::string& source = {},
                                                    const model::ForwardModel* forward = nullptr);

/// Ref 3's split of the means into cumulative, periodic and what is left (fills the report's
/// last four fields from its targets). Called by analyse_positioning.
void split_mean_deviation(PositioningReport& report);

}  // namespace ccomp::identify
