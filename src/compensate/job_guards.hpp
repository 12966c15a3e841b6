#pragma once
// Guards, beside every stage of the job: what may not pass (an axis beyond its limits, a
// correction beyond the model's bound, digits too coarse for the tolerance) is refused at
// its line; what the output cannot do (a reversal left in it, the control's offset, a
// rotary axis' rounding) is warned of once. The report's figures are added up here too.
#include <cstdint>
#include <string>
#include <string_view>

#include "ccomp/axis.hpp"
#include "ccomp/compensate/compensator.hpp"
#include "ccomp/compensate/program_job.hpp"
#include "ccomp/gcode/canon.hpp"
#include "ccomp/model/machine.hpp"

namespace ccomp::compensate {

/// The controlled point's extent over a motion (program axes, mm and deg): its end, and for
/// an arc the extremes it passes through (its start is the last motion's end).
void motion_extent(const gcode::Motion& m, gcode::Axes& low, gcode::Axes& high);

/// Throws Error(safety) at the motion's line when the machine axes (controlled point plus
/// tool offset) leave the model's limits: at the move's end, and for arcs at the extremes
/// they pass through.
void check_limits(const gcode::Motion& m, const model::MachineModel& model, std::string_view file,
                  std::string_view text = {});

/// mm: how far the tool may be from a rotary axis, for its rounding: the farthest linear
/// axis limit (100 mm at least, for a model without limits).
[[nodiscard]] double rotary_lever(const model::MachineModel& model);

/// The program's own digits (decimals -1) round by up to half their last place, at least 4
/// decimals in mm, 5 in degrees; where the tolerance is too fine for those to take at most a
/// quarter of it (in mm below 0.35 um on three axes), `options` gets the fewest decimals that
/// do, in inches too (then written for every word, as --decimals does), so the digits alone
/// never make an output verify rejects. Throws Error(usage) where even 9 cannot.
void raise_digits_for_tolerance(JobOptions& options, const model::MachineModel& model);

/// Once the program is done: a tolerance as coarse as the error it is to take out (the
/// error before) lets chords and digits leave the path as far off as the program as written,
/// or further; said as a warning (line 0: the whole program).
void warn_coarse_tolerance(const JobReport& report, const JobOptions& options);

class JobGuards {
 public:
  JobGuards(const model::MachineModel& model, const JobOptions& options, JobReport& report, std::string_view file);

  /// Adds a compensated move's figures to the report (a move in parts counts at its last,
  /// `whole_move`), refuses a correction beyond the model's bound and says once what the
  /// output cannot do.
  void account(const MoveReport& move, gcode::Units units, std::uint32_t line, const std::string& text,
               bool whole_move = true);

 private:
  void check_rounding(gcode::Units units, std::uint32_t line, const std::string& text);
  void check_rotary_rounding(std::uint32_t line);
  void warn_unhidden_reversals(AxisSet axes, std::uint32_t line);
  void warn_once(bool& said, const std::string& message, std::uint32_t line);
  void warn_kept_whole(const MoveReport& move, std::uint32_t line);

  const model::MachineModel& model_;
  const JobOptions& options_;
  JobReport& report_;
  std::string_view file_;
  int linear_axes_ = 0;
  /// mm: how far the tool may be from a rotary axis, for its rounding (the farthest limit).
  double rotary_lever_ = 100.0;
  AxisSet warned_reversals_;  ///< the axes whose reversal was warned of
  bool warned_start_error_ = false;
  bool warned_jogs_ = false;
  int kept_whole_over_ = 0;                 ///< blocks the control's radius offset leaves over the tolerance
  std::array<bool, 2> rounding_checked_{};  ///< check_rounding() done, for mm and for inch
  bool rotary_checked_ = false;
};

}  // namespace ccomp::compensate
