#pragma once
// G-code's axes in the chain's terms: the controlled point of a program (machine frame, mm
// and degrees, the tool's offsets apart) as the chain's variables (the machine axes that
// carry the tool, in mm and rad, and the tool length), and back.
#include "ccomp/gcode/canon.hpp"
#include "ccomp/model/forward.hpp"

namespace ccomp::model {

/// Chain values (axes in mm and rad, tool length) of a controlled point and its offsets.
[[nodiscard]] ChainQ chain_of(const gcode::Axes& controlled, const gcode::Offsets& offsets);
/// chain_of()'s inverse: the controlled point (machine frame, mm and deg) of chain values.
[[nodiscard]] gcode::Axes controlled_of_chain(const ChainQ& q, const gcode::Offsets& offsets);

}  // namespace ccomp::model
