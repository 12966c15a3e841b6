#pragma once
// The offset bookkeeping: G92 and G10 L20 set an offset so that where the machine is reads
// the values given; G10 L10/L11 set a tool's offsets so (a touch-off). After a compensated
// move the machine is where the rewritten program sent it, off the nominal point by the
// correction: the new offset would take the correction in, and every move after it would
// be off by as much. So each value given is moved by what the machine's position reads
// beyond the nominal one, and the offset comes out as the original's. What cannot be
// rewritten so is refused.
#include <string_view>
#include <vector>

#include "ccomp/gcode/block.hpp"
#include "ccomp/gcode/canon.hpp"
#include "ccomp/gcode/writer.hpp"
#include "move_rewriter.hpp"
#include "program_coordinates.hpp"

namespace ccomp::compensate {

/// Whether the block may set an offset from the machine's position (G92; G10 L20, L10, L11,
/// or G10 with an L only the run shows).
[[nodiscard]] bool sets_offset_from_position(const gcode::Block& b);

/// Where the block runs: what the original and the rewritten program have done before it.
struct OffsetContext {
  const gcode::Offsets& offsets;   ///< in force (the interpreter's, as of the last motion)
  gcode::Units units;              ///< of the original's last motion
  const gcode::Axes& nominal_end;  ///< where the original's last motion ended
  const WrittenPosition& written;  ///< where the rewritten program left the machine
  bool runs_again = false;         ///< the line ran before, or is in another file
  DecimalsOption decimals;
  std::string_view file;
};

/// The edits of the block's axis words that make the offset it sets the original's (none
/// when the machine is where the original has it). Throws Error(unsupported) at the block
/// when no edit of its words can.
[[nodiscard]] std::vector<gcode::Edit> offset_keeping_edits(const gcode::Block& b, const OffsetContext& at);

}  // namespace ccomp::compensate
