#pragma once
// What a fit writes into the fitted model file for the trust on programs
// (model/fit_information.hpp): its parameters' covariance, its noise and what it left
// beyond it, and where the data lie along each axis.
#include "ccomp/identify/fit.hpp"
#include "ccomp/identify/measurements.hpp"
#include "ccomp/model/fit_information.hpp"

namespace ccomp::identify {

/// Bins of the coverage: a linear axis' travel (its limits, else the data's range) in ten,
/// a rotary axis' turn in twelve (30 deg), the tool length in four over the data's range.
inline constexpr int kLinearBins = 10, kRotaryBins = 12, kToolLengthBins = 4;

/// Where the readings of `data` lie along each axis of the model and the tool length.
[[nodiscard]] std::vector<model::AxisCoverage> coverage_of(const model::MachineModel& machine,
                                                           const MeasurementSet& data);

/// The fit's information as the model file carries it. `fitted` is the model with the
/// fitted values (its terms are those of the fit's model).
[[nodiscard]] model::FitInformation fit_information(const model::ForwardModel& model, const MeasurementSet& data,
                                                    const FitReport& report);

}  // namespace ccomp::identify
