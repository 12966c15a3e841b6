#pragma once
// Private to diagnose(): how the model's predictions move when the readings' program zero
// moves. A file read with the wrong work offset puts every reading at the wrong place: its
// rotary errors at the wrong lever, its screws' errors at the wrong turn. The columns below
// let the diagnosis weigh a shift of the origin as it weighs a missing effect, and say so
// rather than let harmonics absorb it.
#include <Eigen/Core>

#include "ccomp/identify/measurements.hpp"
#include "ccomp/model/forward.hpp"

namespace ccomp::identify::detail {

/// mm: a shift of program zero smaller than this is within how well an origin is set
/// (probing, a tool setter); it is not reported.
inline constexpr double kSmallestOriginShift = 1.0;
/// mm: a shift along an axis is weighed only where the data place the origin along it to
/// within this (one standard deviation of the noise); elsewhere it is not said.
inline constexpr double kOriginResolution = 10.0;

/// n x 3: d prediction / d (program zero's shift along X, Y, Z), mm per mm, with the
/// model's parameters `parameters`, by central differences. Zero on rows of a file in
/// machine coordinates (they have no program zero to be off).
[[nodiscard]] Eigen::MatrixXd origin_shift_columns(const model::ForwardModel& model, const Eigen::VectorXd& parameters,
                                                   const MeasurementSet& data);

}  // namespace ccomp::identify::detail
