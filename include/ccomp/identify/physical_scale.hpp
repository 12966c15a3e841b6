#pragma once
// How large each parameter of a model plausibly is on a real machine: its physical scale.
// The fit measures what the data can determine in these units (a direction whose effect,
// moved by one scale, stays below the noise is not determined and keeps its value), and
// refuses values far beyond them.
#include <Eigen/Core>

#include "ccomp/identify/measurements.hpp"
#include "ccomp/model/forward.hpp"

namespace ccomp::identify {

/// The size a term's value plausibly has: 10 um for a translation, 10 urad for a rotation.
inline constexpr double kPlausibleTranslation = 0.010;  // mm
inline constexpr double kPlausibleRotation = 10e-6;     // rad
/// A value this many scales from where it started is not a machine's: a fit refuses to
/// write it, check does not suggest it.
inline constexpr double kImplausibleScales = 100.0;

/// One scale per parameter of `model` (internal units): a term's plausible value; for a
/// coefficient of v^k that over the k-th power of the variable's reach in `data` (its
/// largest magnitude there, at least 1 mm, 1 rad, 1 s or 1 degC from the reference); a
/// period or a time constant its own value.
[[nodiscard]] Eigen::VectorXd physical_scales(const model::ForwardModel& model, const MeasurementSet& data);

}  // namespace ccomp::identify
