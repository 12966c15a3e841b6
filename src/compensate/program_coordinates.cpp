#include "program_coordinates.hpp"

#include "ccomp/constants.hpp"
#include "ccomp/compensate/machine_coordinates.hpp"

namespace ccomp::compensate {

gcode::Axes program_of(const model::ChainQ& q, const gcode::Offsets& offsets, double unit) {
  gcode::Axes p = offsets.program_of(controlled_of_chain(q, offsets));
  if (unit == 1.0) return p;  // (a division by 1 changes nothing, and costs as much as any)
  for (std::size_t i = 0; i < gcode::kAxisCount; ++i)
    if (!gcode::is_rotary(i)) p[i] /= unit;
  return p;
}

gcode::Axes controlled_of_program(const gcode::Axes& p, const gcode::Offsets& offsets, double unit) {
  gcode::Axes controlled{};
  for (std::size_t i = 0; i < gcode::kAxisCount; ++i)
    controlled[i] = (gcode::is_rotary(i) ? p[i] : p[i] * unit) + offsets.origin(i);
  return offsets.to_machine(controlled);
}

gcode::Axes controlled_of(const model::ChainQ& q, const gcode::Offsets& offsets) {
  return offsets.from_machine(offsets.to_machine(controlled_of_chain(q, offsets)));
}

double mm_per_unit(gcode::Units units) {
  return units == gcode::Units::inch ? kMmPerInch : 1.0;
}

}  // namespace ccomp::compensate
