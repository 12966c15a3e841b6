#pragma once
// Program coordinates to machine coordinates, in one place: the work offsets a program
// starts with (the model's, the user's, the control's parameters) as the interpreter holds
// them, back as the one set of offsets a compensated program's header records; and a
// controlled point (machine frame, the tool's offsets apart) as the chain's variables (the
// machine axes that carry the tool, in mm and rad, and the tool length), and back.
#include "ccomp/gcode/canon.hpp"
#include "ccomp/gcode/interpreter.hpp"
#include "ccomp/model/forward.hpp"
#include "ccomp/model/machine.hpp"
#include "ccomp/model/work_offsets.hpp"

namespace ccomp::compensate {

/// Chain values (axes in mm and rad, tool length) of a controlled point and its offsets.
[[nodiscard]] model::ChainQ chain_of(const gcode::Axes& controlled, const gcode::Offsets& offsets);
/// chain_of()'s inverse: the controlled point (machine frame, mm and deg) of chain values.
[[nodiscard]] gcode::Axes controlled_of_chain(const model::ChainQ& q, const gcode::Offsets& offsets);

/// Puts `offsets`' known systems into the interpreter's starting offsets (each replaces
/// the system it names; parameters given by number still win over them).
void set_work_offsets(const model::WorkOffsets& offsets, gcode::InterpreterOptions& into);

/// `options` with the model's work offsets under them: a system the options leave unknown
/// takes the model's (what the machine's control holds), one they give stays theirs.
[[nodiscard]] gcode::InterpreterOptions with_model_offsets(gcode::InterpreterOptions options,
                                                           const model::MachineModel& model);

/// Refuses (usage) a starting work offset that moves an axis `model` lacks.
void check_work_offsets(const gcode::InterpreterOptions& options, const model::MachineModel& model);

/// The offsets the interpreter starts with: its `work_offsets`, with parameters
/// #5221-#5389 given by number over them (in the machine units), as the program sees them
/// before its first block.
[[nodiscard]] model::WorkOffsets starting_work_offsets(const gcode::InterpreterOptions& options);

}  // namespace ccomp::compensate
