#pragma once
// Measurements: the CSV contract of section 6 of docs/error-model.md, read into observations
// the forward model can predict. One row is one scalar observation d along a unit
// direction n (a laser or ballbar reading), or three (a full dx dy dz deviation).
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ccomp/identify/measurement_frame.hpp"
#include "ccomp/identify/stated_conditions.hpp"
#include "ccomp/model/forward.hpp"

namespace ccomp::identify {

/// One scalar observation: the deviation along `direction` at chain values `q`.
struct Observation {
  model::ChainQ q = model::ChainQ::Zero();               ///< axes (mm, rad) and the tool length
  double time = 0.0;                                     ///< s
  std::vector<double> temperatures;                      ///< degC, one per sensor of the set (NaN: not read)
  std::array<std::int8_t, 9> directions{};  ///< approach sign of each axis: +1, -1, 0 unknown (a byte: rows held compactly)
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  ///< unit, machine-axis directions
  double value = 0.0;                                    ///< measured deviation along `direction`, mm
  std::uint32_t source = 0;                              ///< index into MeasurementSet::sources
  std::uint32_t row = 0;                                 ///< line of the file (the header is line 1)
  std::uint32_t file = 0;                                ///< index into MeasurementSet::files
};

/// The range one variable spans in the data.
struct VariableRange {
  std::string name;  ///< "x", "b", "L", "t", "T_bed", "vx"
  double min = 0.0, max = 0.0;
  std::string unit;
};

struct MeasurementSet {
  std::vector<std::string> files;
  /// Each file's frame, as read (parallel to `files`): its observations' q are machine
  /// positions, the frame's origin added.
  std::vector<ResolvedFrame> frames;
  /// Every sensor the files read (their T_<name> columns): the model's first, in its order,
  /// then the others as they appear. A missing effect may depend on one the model lacks.
  std::vector<std::string> sensors;
  std::vector<std::string> sources;  ///< labels from the `source` column (or the file name)
  std::vector<Observation> observations;
  std::vector<std::string> notices;  ///< unknown columns, ignored
  /// What the files state beside the readings (instrument, temperatures, uncertainty, title):
  /// the report's, not the data's.
  std::vector<StatedField> stated;
  std::vector<VariableRange> ranges;

  /// The conditions of an observation, for the forward model.
  [[nodiscard]] static model::Conditions conditions(const Observation& o) {
    model::Conditions c;
    c.time = o.time;
    c.temperatures = o.temperatures;
    for (std::size_t i = 0; i < o.directions.size(); ++i) c.directions[i] = o.directions[i];
    return c;
  }
};

/// Where an axis stood while another was measured (`--at y=100`): mm or deg.
struct AxisPosition {
  char axis = 'Y';  ///< upper case
  double value = 0.0;
};

struct ReadOptions {
  /// Tool length (mm) for rows without an L column.
  double tool_length = 0.0;
  // One-axis files (an instrument's runs along one axis: docs/identification.md)
  /// The axis measured (upper case), where the file does not name it; 0: the file's.
  char axis = 0;
  /// Where the other axes stood; unnamed ones at 0, and for a rotary axis' readings without
  /// any, X at 100 mm (Y for A) from the program origin (docs/identification.md).
  std::vector<AxisPosition> at;
  /// The label of the rows (empty: the file's name).
  std::string source;
  /// The deviations' unit where the file states none ("um", "arcsec"...; empty: none).
  std::string unit;
  /// The frame the user says the files are in (--frame, --work-offset); a file's own
  /// `# frame:` line is taken first (measurement_frame.hpp).
  std::optional<MeasurementFrame> frame;
};

/// Reads a measurement file and appends its rows: the CSV contract or an instrument's file,
/// recognised by its content (identify/measurement_formats.hpp). Throws ccomp::Error (data) naming the
/// file, the row and the column: a missing column, a value that is not a number, NaN, a
/// direction that is not a unit vector, a variable the model needs that the file lacks.
void read_measurements(const std::string& path, const model::MachineModel& model, const ReadOptions& options,
                       MeasurementSet& into);
void parse_measurements(const std::string& text, const std::string& name, const model::MachineModel& model,
                        const ReadOptions& options, MeasurementSet& into);

/// Axis `axis` of a reading as measurement files write it: a rotary axis in degrees, a
/// linear one in mm, Z as the program coordinate (without the tool length, which the
/// reader adds to the chain value).
[[nodiscard]] double file_axis_value(const Observation& o, std::size_t axis, bool rotary);

/// Recomputes `ranges` (after reading all files).
void summarize(MeasurementSet& set, const model::MachineModel& model);

/// What a model predicts for an observation: n . deviation (mm).
[[nodiscard]] double predict(const model::ForwardModel& model, model::ForwardData& data, const Observation& o);

/// Writes observations in the CSV contract (one row per observation, n and d), in `frame`
/// (its `# frame:` line first): program coordinates relative to its origin, or machine ones.
[[nodiscard]] std::string to_csv(const MeasurementSet& set, const model::MachineModel& model,
                                 const ResolvedFrame& frame);

}  // namespace ccomp::identify
