#pragma once
// Test support: the reference machine's readings (reference_hmc.hpp) as the measurement
// set ccomp reads from a file of the CSV contract: chain values, approach, time, the
// spindle's sensor (`T_spindle`, whether or not a model has it), one source per plan.
#include "ccomp/identify/measurements.hpp"
#include "reference_hmc.hpp"

namespace ccomp::test {

[[nodiscard]] identify::MeasurementSet reference_measurements(const std::vector<ReferenceReading>& readings);

}  // namespace ccomp::test
