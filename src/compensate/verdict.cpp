#include "ccomp/compensate/verdict.hpp"

#include <fmt/format.h>

#include "ccomp/model/conditions.hpp"

namespace ccomp::compensate {
namespace {

/// As many digits as show a difference ("1.0004 um is more than 1.00 um", not 1.00 and 1.00).
int digits_apart(double a_um, double b_um) {
  int digits = 2;
  while (digits < 6 && fmt::format("{:.{}f}", a_um, digits) == fmt::format("{:.{}f}", b_um, digits)) ++digits;
  return digits;
}

}  // namespace

std::vector<std::string> Verdict::failures() const {
  std::vector<std::string> out;
  const double after_um = after.max * 1000.0, tolerance_um = tolerance * 1000.0, before_um = before * 1000.0;
  if (leaves_cuts_out())
    out.push_back(fmt::format("it leaves {:.3f} mm of the original's cuts uncut, the first at line {} of the original",
                              after.uncut_length, after.uncut_line));
  if (over_tolerance())
    out.push_back(fmt::format("the contour error left, {:.{}f} um, is more than the tolerance of {:.2f} um",
                              after_um, digits_apart(after_um, tolerance_um), tolerance_um));
  if (over_angular_tolerance())
    out.push_back(fmt::format("the tool's direction is off by {:.{}f} urad, more than the angular tolerance of {:.2f} urad",
                              after.orientation_max * 1e6,
                              digits_apart(after.orientation_max * 1e6, angular_tolerance * 1e6), angular_tolerance * 1e6));
  if (worse_than_written())
    out.push_back(fmt::format("the contour error left, {:.2f} um, is worse than the program as written ({:.2f} um)",
                              after_um, before_um));
  return out;
}

Verdict judge(gcode::LineSource& original, gcode::LineSource& compensated, const model::ForwardModel& model,
              const CheckOptions& options, double tolerance, double angular_tolerance, double before) {
  Verdict v;
  v.after = verify(original, compensated, model, options);
  v.tolerance = tolerance;
  v.angular_tolerance = angular_tolerance;
  v.before = before;
  return v;
}

Verdict judge_job_output(gcode::LineSource& original, gcode::LineSource& written, const model::MachineModel& model,
                         const JobOptions& job, const JobReport& report, std::function<void(double)> progress) {
  CheckOptions options;
  options.interpreter = job.interpreter;  // verify() puts the model's work offsets under them, as the job does
  options.conditions = model::conditions_for(model, job.sensors, job.time);
  options.progress = std::move(progress);
  const model::ForwardModel forward(model);
  return judge(original, written, forward, options, job.tolerance, default_angular_tolerance(job.tolerance),
               report.max_error_before);
}

}  // namespace ccomp::compensate
