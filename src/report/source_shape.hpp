#pragma once
// What a source of readings is, from what varies in its rows: a line along one linear axis
// (a laser line), readings as a rotary axis turns (a sphere probed, a table's test), or
// points spread over the workspace (a volumetric grid).
#include <cstddef>
#include <string>
#include <vector>

#include "ccomp/identify/measurements.hpp"
#include "ccomp/model/machine.hpp"

namespace ccomp::report {

enum class SourceKind { line, rotary, volumetric };

struct SourceShape {
  SourceKind kind = SourceKind::volumetric;
  std::size_t axis = 0;               ///< line: the linear axis moving; rotary: the rotary axis turning (X..W: 0..8)
  std::vector<std::size_t> readings;  ///< indices into the observations, in file order
};

/// Readings grouped by the direction they read along: +-X, +-Y, +-Z as X, Y, Z (the value
/// turned to the positive axis), any other direction on its own.
struct ReadingDirection {
  std::string label;  ///< "X", "Y", "Z", or "(0.707, 0.707, 0)"
  int axis = -1;      ///< 0..2 for a machine axis, -1 otherwise
  std::vector<std::size_t> readings;
  std::vector<double> sign;  ///< per reading: +1 or -1, turning the value to the label's direction
};

[[nodiscard]] std::vector<SourceShape> source_shapes(const identify::MeasurementSet& data,
                                                     const model::MachineModel& model);
[[nodiscard]] std::vector<ReadingDirection> reading_directions(const identify::MeasurementSet& data,
                                                               const std::vector<std::size_t>& readings);
/// An axis' position at a reading in the machine's frame, as the model's terms read it (mm,
/// deg): Z is the axis itself (the tool length in it), not the tool tip a program commands.
[[nodiscard]] double axis_value(const identify::Observation& o, std::size_t axis);
/// The title of a plot's position axis: "Z axis position, machine (mm)".
[[nodiscard]] std::string position_title(std::size_t axis);
/// A sentence saying which frame the plots' positions are in, and how the file of `reading`
/// writes them (its frame, its origin, the tool length).
[[nodiscard]] std::string frame_note(const identify::MeasurementSet& data, std::size_t reading);
[[nodiscard]] char axis_letter(std::size_t axis);
[[nodiscard]] std::string kind_name(SourceKind kind);

}  // namespace ccomp::report
