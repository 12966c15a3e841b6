#pragma once
// Private to the candidate library: the families of effects it draws from, one generator
// each. A generator reads the context (the model, the data, the axes they cover) and appends
// its candidates; candidate_library() runs the axis families over each axis the data move,
// then the machine-wide ones. A new family of effects is one generator and one row of its
// table (candidates.cpp).
#include <span>
#include <string>
#include <vector>

#include "candidates.hpp"

namespace ccomp::identify::detail {

/// What every generator reads, and the probes (links and components) the candidates enter
/// through, registered as they are asked for.
struct LibraryContext {
  const model::MachineModel& mm;
  const MeasurementSet& data;
  std::vector<Probe>& probes;
  std::string spindle;  ///< the tool side's last link before the tool: where the spindle tilts and drifts
  bool tool_length_varies = false, time_varies = false;

  LibraryContext(const model::MachineModel& model, const MeasurementSet& measured, std::vector<Probe>& into);
  /// The probe of `link`'s `component` (registered at the first ask).
  std::size_t probe(const std::string& link, int component,
                    model::ErrorPlacement placement = model::ErrorPlacement::motion);
  /// Whether every reading has sensor `sensor` and it changes: a candidate variable (the
  /// model's own sensors, and any other T_<name> column: a suggestion then adds the sensor).
  [[nodiscard]] bool sensor_varies(std::size_t sensor) const;
};

/// A family of effects of one axis (`axes`: all the data cover, for effects of two axes).
using AxisFamily = void (*)(LibraryContext&, const AxisInfo&, std::span<const AxisInfo> axes,
                            std::vector<Candidate>&);
/// A family of effects of the machine as a whole (the spindle, heat).
using MachineFamily = void (*)(LibraryContext&, std::vector<Candidate>&);

// Linear axes.
void screw_pitch(LibraryContext&, const AxisInfo&, std::span<const AxisInfo>, std::vector<Candidate>&);
void reversal(LibraryContext&, const AxisInfo&, std::span<const AxisInfo>, std::vector<Candidate>&);
void higher_order(LibraryContext&, const AxisInfo&, std::span<const AxisInfo>, std::vector<Candidate>&);
void local_defect(LibraryContext&, const AxisInfo&, std::span<const AxisInfo>, std::vector<Candidate>&);
void squareness(LibraryContext&, const AxisInfo&, std::span<const AxisInfo>, std::vector<Candidate>&);
void scale_expansion(LibraryContext&, const AxisInfo&, std::span<const AxisInfo>, std::vector<Candidate>&);
void cross_axis(LibraryContext&, const AxisInfo&, std::span<const AxisInfo>, std::vector<Candidate>&);
// Rotary axes (reversal as well).
void table_harmonics(LibraryContext&, const AxisInfo&, std::span<const AxisInfo>, std::vector<Candidate>&);
void worm_wheel(LibraryContext&, const AxisInfo&, std::span<const AxisInfo>, std::vector<Candidate>&);
void rotary_location(LibraryContext&, const AxisInfo&, std::span<const AxisInfo>, std::vector<Candidate>&);
// The machine.
void spindle_tilt(LibraryContext&, std::vector<Candidate>&);
void spindle_heat(LibraryContext&, std::vector<Candidate>&);

}  // namespace ccomp::identify::detail
