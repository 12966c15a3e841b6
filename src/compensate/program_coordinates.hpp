#pragma once
// The coordinates the rewritten program writes (program units and degrees, in the frame of
// the offsets in force) against the chain's values and the controlled point: what every
// stage that writes words converts through.
#include "ccomp/gcode/canon.hpp"
#include "ccomp/model/forward.hpp"

namespace ccomp::compensate {

/// Program coordinates (program units, degrees) of chain values; `unit` is mm per program unit.
[[nodiscard]] gcode::Axes program_of(const model::ChainQ& q, const gcode::Offsets& offsets, double unit);
/// The controlled point of program coordinates (program units, degrees): program_of()'s inverse.
[[nodiscard]] gcode::Axes controlled_of_program(const gcode::Axes& p, const gcode::Offsets& offsets, double unit);
/// The controlled point (program frame, machine units) the machine is at after commanding q.
[[nodiscard]] gcode::Axes controlled_of(const model::ChainQ& q, const gcode::Offsets& offsets);
/// mm per unit of a program in `units`.
[[nodiscard]] double mm_per_unit(gcode::Units units);

/// Where the rewritten program has sent the machine: what its incremental words count from
/// and what an offset set from the position reads.
struct WrittenPosition {
  gcode::Axes commanded{};  ///< the controlled point the rewritten program commanded
  /// `commanded` is a TCP program's point (tcp_kinematics.hpp), not the axes' positions.
  bool tcp = false;
  /// Per axis, program units: where the written digits put the machine less `commanded`.
  gcode::Axes rounding{};
};

}  // namespace ccomp::compensate
