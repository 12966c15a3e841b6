#pragma once
// The check as one self-contained HTML page (no network: inline SVG, no scripts): the
// residual against every variable before and after refitting, error maps over the
// workspace, spectra along each linear axis, the missing effects (each with the residual
// left once it is added), the regions, the identifiability of the model's parameters.
#include <Eigen/Core>
#include <string>

#include "ccomp/identify/check.hpp"
#include "ccomp/identify/diagnose.hpp"
#include "ccomp/identify/fit.hpp"
#include "ccomp/identify/measurements.hpp"
#include "ccomp/model/machine.hpp"

namespace ccomp::report {

struct CheckReportInput {
  const model::MachineModel& model;
  const identify::MeasurementSet& data;
  const identify::CheckReport& check;    ///< with the residual of the model as it is
  const identify::Diagnosis& diagnosis;  ///< with the model refitted to the data, and its residual
};

[[nodiscard]] std::string html_check_report(const CheckReportInput& in);

}  // namespace ccomp::report
