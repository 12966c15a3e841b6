#pragma once
// The JSON documents of fit, nine-line, simulate and positioning (docs/json.md), numbers
// in the units their text output uses: um, urad, the model file's units for parameters.
#include <string>

#include "ccomp/identify/check.hpp"
#include "ccomp/identify/diagnose.hpp"
#include "ccomp/identify/fit.hpp"
#include "ccomp/identify/measurements.hpp"
#include "ccomp/identify/nine_line.hpp"
#include "ccomp/identify/positioning.hpp"
#include "ccomp/identify/stated_conditions.hpp"
#include "ccomp/model/forward.hpp"

namespace ccomp::cli {

[[nodiscard]] std::string fit_json(const model::ForwardModel& forward, const identify::MeasurementSet& data,
                                   const identify::FitReport& r, const std::string& output, bool written);
[[nodiscard]] std::string nine_line_json(const model::ForwardModel& forward, const identify::MeasurementSet& data,
                                         const identify::NineLineReport& r, const std::string& output);
[[nodiscard]] std::string simulate_json(const model::MachineModel& m, const identify::MeasurementSet& set,
                                        const std::string& output);
[[nodiscard]] std::string check_json(const model::MachineModel& m, const identify::CheckReport& r,
                                     const identify::Diagnosis& d);
/// `angle_unit`: a rotary axis' deviations in "arcsec" or "urad" (src/cli/positioning.cpp).
[[nodiscard]] std::string positioning_json(const std::string& axis, const identify::PositioningReport& r,
                                           const std::string& angle_unit, const identify::StatedConditions& stated);

}  // namespace ccomp::cli
