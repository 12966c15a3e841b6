#pragma once
// One verdict on a compensated program, the same wherever it is given: the main job on what
// it has just written, and `ccomp verify` on an output. The contour error left is verify()'s
// (the executed path of the output against the original's path), so the two agree on the
// same output; it passes when within the tolerance, with no cut of the original left out,
// and not worse than the program as written.
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "ccomp/compensate/program_job.hpp"
#include "ccomp/compensate/verify.hpp"

namespace ccomp::compensate {

/// How much worse than the program as written an output may come out before it counts as
/// worse: a tenth of the tolerance, what the written digits may take (number_style), so
/// that a machine already within a hair of the path is not failed for its rounding.
inline constexpr double kWorseMarginOfTolerance = 0.1;

/// mm: the angular tolerance, unless given, is the tolerance over this reach up the tool's
/// flank (1 um: 100 urad), the tilt that moves a point 10 mm up a side-cutting tool's flank
/// by the tolerance.
inline constexpr double kFlankReachMm = 10.0;

/// rad: the angular tolerance that goes with `tolerance` (mm) when none is given.
[[nodiscard]] inline double default_angular_tolerance(double tolerance) { return tolerance / kFlankReachMm; }

struct Verdict {
  PathError after;           ///< verify()'s figures on the output
  double tolerance = 0.001;  ///< mm
  /// rad: how far the tool's direction may be off the program's
  double angular_tolerance = default_angular_tolerance(0.001);
  /// mm: the machine's largest error on the program as written (the main job's, at the
  /// points it checks); NaN where not known, and then not judged.
  double before = std::numeric_limits<double>::quiet_NaN();

  [[nodiscard]] bool over_tolerance() const { return after.max > tolerance; }
  [[nodiscard]] bool over_angular_tolerance() const { return after.orientation_max > angular_tolerance; }
  [[nodiscard]] bool leaves_cuts_out() const { return after.uncut_length > 0.0; }
  [[nodiscard]] bool worse_than_written() const {
    return !std::isnan(before) && after.max > before + kWorseMarginOfTolerance * tolerance;
  }
  [[nodiscard]] bool passed() const { return !over_tolerance() && !over_angular_tolerance() && !leaves_cuts_out() && !worse_than_written(); }
  /// What fails, a sentence each ("the contour error left, 5.00 um, is more than the
  /// tolerance of 1.00 um"); none when it passed.
  [[nodiscard]] std::vector<std::string> failures() const;
};

/// verify() of `compensated` against `original`, judged against `tolerance` (mm),
/// `angular_tolerance` (rad) and `before` (mm, NaN: not judged).
[[nodiscard]] Verdict judge(gcode::LineSource& original, gcode::LineSource& compensated,
                            const model::ForwardModel& model, const CheckOptions& options, double tolerance,
                            double angular_tolerance, double before = std::numeric_limits<double>::quiet_NaN());

/// The main job's output judged as `ccomp verify` judges it, with what the job assumed (its
/// interpreter options, readings and time) and its tolerance; `report` gives the figure of
/// the program as written. `progress` as CheckOptions::progress.
[[nodiscard]] Verdict judge_job_output(gcode::LineSource& original, gcode::LineSource& written,
                                       const model::MachineModel& model, const JobOptions& job,
                                       const JobReport& report, std::function<void(double)> progress = {});

}  // namespace ccomp::compensate
