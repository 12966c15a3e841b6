#include "ccomp/compensate/machine_coordinates.hpp"

#include <array>
#include <charconv>
#include <string>

#include "ccomp/constants.hpp"
#include "ccomp/error.hpp"

namespace ccomp::compensate {

namespace {
/// Each axis' chain unit per program unit: radians per degree for the rotary axes, 1 for
/// the others (a product or quotient by 1 is exact: one branch-free loop serves all nine,
/// at every point a program moves to).
constexpr std::array<double, gcode::kAxisCount> kChainPerAxisUnit = [] {
  std::array<double, gcode::kAxisCount> scale{};
  for (std::size_t i = 0; i < gcode::kAxisCount; ++i) scale[i] = gcode::is_rotary(i) ? kRadPerDeg : 1.0;
  return scale;
}();
}  // namespace

model::ChainQ chain_of(const gcode::Axes& controlled, const gcode::Offsets& o) {
  model::ChainQ q;
  for (std::size_t i = 0; i < gcode::kAxisCount; ++i)  // the machine axis carries the tool
    q[static_cast<Eigen::Index>(i)] = (controlled[i] + o.tool[i]) * kChainPerAxisUnit[i];
  q[static_cast<Eigen::Index>(model::kToolLengthIndex)] = o.tool[Axis::Z];  // the tool length, along Z
  return q;
}

gcode::Axes controlled_of_chain(const model::ChainQ& q, const gcode::Offsets& o) {
  gcode::Axes controlled;
  for (std::size_t i = 0; i < gcode::kAxisCount; ++i)
    controlled[i] = q[static_cast<Eigen::Index>(i)] / kChainPerAxisUnit[i] - o.tool[i];
  return controlled;
}

void set_work_offsets(const model::WorkOffsets& offsets, gcode::InterpreterOptions& into) {
  for (std::size_t s = 0; s < model::kCoordinateSystems; ++s)
    if (offsets.systems[s]) into.work_offsets[s] = *offsets.systems[s];
}

gcode::InterpreterOptions with_model_offsets(gcode::InterpreterOptions options, const model::MachineModel& model) {
  for (std::size_t s = 0; s < model::kCoordinateSystems; ++s)
    if (!options.work_offsets[s] && model.work_offsets.systems[s]) options.work_offsets[s] = *model.work_offsets.systems[s];
  return options;
}

void check_work_offsets(const gcode::InterpreterOptions& options, const model::MachineModel& model) {
  std::vector<char> axes;
  for (const model::AxisSpec& a : model.axes) axes.push_back(a.letter);
  const model::WorkOffsets offsets = starting_work_offsets(options);
  for (std::size_t s = 0; s < model::kCoordinateSystems; ++s)
    if (offsets.systems[s])
      model::check_on_machine(*offsets.systems[s], s + 1, axes, ErrorKind::usage, "the work offsets");
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
