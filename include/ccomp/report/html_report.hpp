#pragma once
// The check of a model against measurements as one self-contained HTML page (docs/report.md):
// per-source deviation plots with the model's curves and ISO 230-2's figures, polar plots of
// rotary-axis data, volumetric error maps before and after compensation, the terms' shares
// of the error, the spectra of what is left, the missing effects, the parameters, and the
// provenance of it all. Plots are plotly.js, inlined: the page makes no network request.
#include <Eigen/Core>
#include <string>

#include "ccomp/identify/check.hpp"
#include "ccomp/identify/diagnose.hpp"
#include "ccomp/identify/fit.hpp"
#include "ccomp/identify/measurements.hpp"
#include "ccomp/model/machine.hpp"

namespace ccomp::report {

struct CheckReportInput {
  const model::MachineModel& model;      ///< the model checked (its path and SHA-256 name it)
  const identify::MeasurementSet& data;  ///< its files are read again for their SHA-256
  const identify::CheckReport& check;    ///< with the residual of the model as it is
  const identify::Diagnosis& diagnosis;  ///< with the model refitted to the data, and its residual
  std::string command = "check";         ///< what made the page: "check", or "fit" (the fitted model)
  std::string generated_at;              ///< UTC date and time; empty: now
};

[[nodiscard]] std::string html_check_report(const CheckReportInput& in);

}  // namespace ccomp::report
