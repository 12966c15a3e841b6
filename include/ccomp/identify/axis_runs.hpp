#pragma once
// Runs along one axis, as an instrument measures them: a laser's positioning runs on a
// linear axis, a rotary calibrator's on a rotary one. The readers of such files
// (identify/measurement_formats) fill AxisRuns with the units the file states; append_axis_runs
// turns them into the measurement contract's observations: units converted, the approach
// direction worked out from the run order where the file does not state it, the reading
// placed where the other axes stood, and a file without a unit checked for plausibility.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ccomp/identify/measurements.hpp"
#include "ccomp/identify/stated_conditions.hpp"

namespace ccomp::identify {

/// A unit a file may state for its targets or deviations.
enum class Unit : std::uint8_t { mm, um, nm, inch, deg, arcsec, urad };

/// "mm", "um", "µm", "micron", "nm", "in", "inch", "deg", "°", "arcsec", "\"", "urad"... (any case); nullopt otherwise.
[[nodiscard]] std::optional<Unit> parse_unit(std::string_view text);
[[nodiscard]] std::string_view unit_name(Unit unit);

struct AxisReading {
  double target = 0.0;     ///< in AxisRuns::target_unit
  double deviation = 0.0;  ///< actual - target, in AxisRuns::deviation_unit
  int run = 0;             ///< 0: the file does not say
  int approach = 0;        ///< +1, -1; 0: the file does not say (worked out from the run order)
  std::uint32_t line = 0;  ///< in the file
};

struct AxisRuns {
  char axis = 0;  ///< upper case, as the file names it; 0: it does not
  std::optional<Unit> target_unit, deviation_unit;
  std::uint32_t unit_line = 0;  ///< where the file states a unit (0: nowhere)
  std::optional<MeasurementFrame> frame;  ///< its own '# frame:' line, if it has one
  std::vector<AxisReading> readings;  ///< in the file's order
  std::vector<StatedField> stated;    ///< the file's other settings (the report's)
};

/// Appends `runs` (read from the file `name`) to `into` as the contract's observations along
/// the axis (ReadOptions::axis, else the file's), each on the row of its reading. Throws
/// ccomp::Error: usage when no axis is known or the options contradict the file, data (at
/// the file's line) for an axis the machine lacks, a unit that does not fit the axis, and a
/// file without a unit whose deviations are implausible in the contract's (mm, deg).
void append_axis_runs(const AxisRuns& runs, const std::string& name, const model::MachineModel& model,
                      const ReadOptions& options, MeasurementSet& into);

/// Fills each reading's unknown approach from the order of its run: the direction of the
/// move that arrived at it, or (first of a pass, a repeated target at a turn) of the one that
/// leaves it. A move that passes over other targets is a return to the start, not a pass.
void approach_from_run_order(std::vector<AxisReading>& readings);

}  // namespace ccomp::identify
