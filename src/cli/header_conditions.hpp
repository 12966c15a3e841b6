#pragma once
// What a compensated program's ccomp header says its run assumed (the tolerance, the work
// offsets, the sensor readings, the time), with the command line's over it: verify and
// predict measure the run the program was made for unless told otherwise, and say so when
// told otherwise.
#include <limits>
#include <optional>
#include <vector>

#include "ccomp/gcode/source.hpp"
#include "ccomp/model/conditions.hpp"
#include "ccomp/model/machine.hpp"
#include "commands.hpp"

namespace ccomp::cli {

struct Assumed {
  double header_tolerance = std::numeric_limits<double>::quiet_NaN();  ///< mm; NaN: no header says one
  model::WorkOffsets work_offsets;            ///< the model's, the header's over them (--work-offset's apply later)
  std::vector<model::SensorReading> sensors;  ///< the header's, --sensor's over them
  std::optional<double> time;                 ///< --time, else the header's
};

/// Reads `program`'s header (its first two lines; none: the command line alone) and warns on
/// stderr, at the header's line, of each of --work-offset, --sensor and --time that differs
/// from what it records, and of another model's header.
[[nodiscard]] Assumed assumed_by(const CheckArgs& args, const model::MachineModel& m,
                                 const gcode::LineSource& program);

}  // namespace ccomp::cli
