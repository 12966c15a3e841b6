#pragma once
// What no control's table may hold: a correction that is not a number, or one beyond the
// model's max_correction, which the main job refuses too (exit 7). An exported table is
// what the control applies without ccomp: it gets the same bound as a compensated program.
#include <string_view>

#include "ccomp/model/machine.hpp"

namespace ccomp::controller {

/// Throws ccomp::Error (safety) naming `where` ("X at -1000 mm travelling up") when
/// `correction` (mm, or rad where `rotary`: its bound is kRotaryBoundPerMm of
/// max_correction) is not finite or beyond the model's bound. `what` names the
/// correction ("the correction of X").
void check_correction(const model::MachineModel& machine, double correction, bool rotary, std::string_view what,
                      std::string_view where);

/// Throws ccomp::Error (safety) when `value`, about to be written into `file_kind`'s table
/// at `where`, is not finite: the last guard before a writer prints it.
void check_written(double value, std::string_view file_kind, std::string_view where);

}  // namespace ccomp::controller
