#pragma once
// The main job on one program: read it, interpret it block by block, and write it back in
// file order with ccomp's header, changing only what the machine model asks to change.
#include <cstdint>
#include <cstdio>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ccomp/axis.hpp"
#include "ccomp/compensate/program_header.hpp"
#include "ccomp/compensate/work_split.hpp"
#include "ccomp/gcode/interpreter.hpp"
#include "ccomp/gcode/source.hpp"
#include "ccomp/model/machine.hpp"

namespace ccomp::compensate {

struct JobOptions {
  gcode::InterpreterOptions interpreter;
  /// mm: the largest distance the executed path may keep from the nominal one.
  double tolerance = 0.001;
  /// Temperature sensor readings (degC) by name, and the time since the warm-up started
  /// (s), for the model's thermal terms; a term over the time without one is refused. Both
  /// go into the output's header.
  std::vector<std::pair<std::string, double>> sensors;
  std::optional<double> time;
  /// Compensate even when the input already carries ccomp's header (double compensation).
  bool force = false;
  /// Write each canned cycle (G73 G81 G83 G85) as the G0/G1 moves it makes, each one
  /// compensated like any move, instead of compensating the cycle block's words. Takes
  /// what the block form cannot: L repeats, G91 cycles, and a hole whose correction
  /// differs between its R plane and its bottom.
  bool expand_cycles = false;
  /// Under cutter radius compensation (G41/G42), write the path the tool centre runs (as
  /// LinuxCNC offsets it, its corners' arcs included) with the offset taken out (G41/G42
  /// and their D words go): each move then compensated and split like any, take-ups and
  /// all, where the control's own offset would run each block as one piece.
  bool resolve_cutter_comp = false;
  /// Compensate the program as it runs (gcode::flatten(): loops and subroutine calls
  /// unrolled, expressions replaced by their values) instead of line for line: a line that
  /// runs more than once may need a different correction each time, which one line cannot
  /// carry. Errors and warnings still name the original's lines.
  bool flatten = false;
  /// Decimals of the compensated coordinates, for a control that wants a fixed count (one
  /// that alarms on more digits than its resolution, say). -1 keeps the program's style: as
  /// many as it wrote, at least 4 in mm and 5 in inches and degrees. `decimals` is for the
  /// linear axes, in the program's units; `rotary_decimals` for the rotary axes, in degrees.
  int decimals = -1;
  int rotary_decimals = -1;
  /// Solve every point on the model (Newton to below 1 nm), none accepted on the error
  /// field's bound within a share of the tolerance (CompensationOptions::exact).
  bool exact = false;
  /// 2: the moves are compensated on a thread of their own while this one reads, interprets
  /// and writes the program (what either may do goes as `split` says). The output is the
  /// same for 1 and 2: the same work is done in the same order.
  int threads = 1;
  /// On two threads, which does the work either may (each move's nominal end pose, the
  /// uncompensated machine's error at its probes): by default the one with time to spare,
  /// judged batch by batch. The output and the report are the same whichever does it; the
  /// others are there to show that, and to measure.
  WorkSplit split = WorkSplit::adaptive;
  /// Called with the fraction of the input read, at most about a hundred times.
  std::function<void(double)> progress;
  /// Called for every warning, with the line it concerns.
  std::function<void(const std::string&, std::uint32_t)> warning;
};

struct JobReport {
  std::uint64_t blocks = 0;   ///< blocks executed
  std::uint64_t motions = 0;  ///< canonical motions
  std::uint64_t bytes = 0;    ///< input size
  std::uint64_t compensated_moves = 0;
  std::uint64_t added_lines = 0;       ///< segments added by splitting moves and take-ups
  std::uint64_t take_up_moves = 0;     ///< moves added at reversals to take up lost motion
  double max_error_before = 0.0;       ///< mm: the uncompensated machine's largest error
  double max_error_after = 0.0;        ///< mm: the compensated path's, at the checked points
  double max_correction = 0.0;         ///< mm
  double max_orientation_error = 0.0;  ///< rad: what the machine cannot correct
  /// The rotary axes held at the program's values (their hold, model::AxisHold): what they
  /// would have corrected is in max_orientation_error.
  AxisSet held_axes;
};

/// Throws Error(usage) naming the option and its value when `options` cannot be right: a
/// tolerance not positive and finite (NaN included), decimals outside -1..9, a thread
/// count other than 1 or 2, a time or sensor reading that is not finite.
void validate(const JobOptions& options);

/// Runs the job. Throws ccomp::Error; on error part of the output may have been written
/// (the CLI writes to a temporary file and renames it only on success).
JobReport run_program_job(gcode::LineSource& input, std::FILE* out, const model::MachineModel& model,
                          const JobOptions& options);

}  // namespace ccomp::compensate
