#pragma once
// The nine-line method (docs/error-model.md Ref 4) as a workflow: from nine laser lines alone (three per axis,
// positioning on all, straightness on lines 1 and 2) the geometric errors of a 3-axis
// machine are fitted; then how far each identified error moves per millimetre that a
// line was placed off its assumed position, and which placement of lines 1 and 3 would
// make that smallest.
#include <string>
#include <vector>

#include "ccomp/identify/fit.hpp"
#include "ccomp/identify/measurements.hpp"
#include "ccomp/model/forward.hpp"

namespace ccomp::identify {

struct PlacementSensitivity {
  std::string parameter;  ///< "EYX.a1", "EC0X"
  double per_mm = 0.0;    ///< change of the fitted value per mm of line misplacement (internal units per mm)
  std::string line;       ///< the source (line) and direction whose misplacement moves it most
};

/// A squareness as the nine-line method reports it: the angle between two axes' lines as the nine lines
/// show them (each straightness against its least-squares line, the slopes between them),
/// drawn by the fitted model through the middle of the measured workspace. Rigid turns of
/// the whole machine (a carriage's constant yaw, the lasers' alignment) do not change it.
struct LineSquareness {
  std::string iso;     ///< EC0X, EB0X, EA0Y: the term that carries it in the reference frame
  std::string seed;    ///< S_xy, S_xz, S_yz: the symbol of docs/error-model.md Ref 1
  double value = 0.0;  ///< rad, in the ISO term's sign (that symbol's value: `seed_sign` times it)
  double seed_sign = 1.0;
};

struct NineLineReport {
  FitReport fit;
  /// The three squareness values between the lines, for a model with the axes X, Y, Z.
  std::vector<LineSquareness> squareness;
  std::vector<PlacementSensitivity> sensitivity;  ///< the identified parameters, largest first
  /// Placement study: lines 1 and 3 at `inset` of the workspace from its edges, and the
  /// root-sum-square sensitivity (scaled by each parameter's effect) that gives.
  std::vector<std::pair<double, double>> placements;
  double recommended_inset = 0.0;
};

/// Fits `model` to the nine-line `data` (sources named like "x-line1") and studies the
/// placement. The model's free terms are what is identified.
[[nodiscard]] NineLineReport nine_line(const model::ForwardModel& model, const MeasurementSet& data);

}  // namespace ccomp::identify
