#include "ccomp/compensate/machine_coordinates.hpp"

#include <charconv>
#include <string>

namespace ccomp::compensate {

void set_work_offsets(const model::WorkOffsets& offsets, gcode::InterpreterOptions& into) {
  for (std::size_t s = 0; s < model::kCoordinateSystems; ++s)
    if (offsets.systems[s]) into.work_offsets[s] = *offsets.systems[s];
}

gcode::InterpreterOptions with_model_offsets(gcode::InterpreterOptions options, const model::MachineModel& model) {
  for (std::size_t s = 0; s < model::kCoordinateSystems; ++s)
    if (!options.work_offsets[s] && model.work_offsets.systems[s]) options.work_offsets[s] = *model.work_offsets.systems[s];
  return options;
}

model::WorkOffsets starting_work_offsets(const gcode::InterpreterOptions& options) {
  model::WorkOffsets out;
  for (std::size_t s = 0; s < model::kCoordinateSystems; ++s)
    if (options.work_offsets[s]) out.systems[s] = *options.work_offsets[s];
  const double unit = options.machine_units == gcode::Units::inch ? 25.4 : 1.0;
  for (const auto& [name, value] : options.parameters) {
    int n = 0;
    const auto [end, ec] = std::from_chars(name.data(), name.data() + name.size(), n);
    if (ec != std::errc() || end != name.data() + name.size() || n < 5221 || n > 5389) continue;
    const auto field = static_cast<std::size_t>((n - 5221) % 20);
    if (field >= gcode::kAxisCount) continue;
    const auto system = static_cast<std::size_t>((n - 5221) / 20);
    if (!out.systems[system]) out.systems[system] = model::WorkOrigin{};
    (*out.systems[system])[field] = gcode::is_rotary(field) ? value : value * unit;
  }
  return out;
}

}  // namespace ccomp::compensate
