#pragma once
// An AxisTable written as the compensation tables a control reads: LinuxCNC's
// [JOINT_n]COMP_FILE (both COMP_FILE_TYPEs), Fanuc's pitch-error compensation data and
// parameters, Siemens 840D sl's leadscrew (LEC) and sag/cross (CEC) tables, a
// Heidenhain TNC compensation-value table (*.COM) and Centroid's ballscrew ("laser")
// compensation table (cnc-x.tab). docs/controller-tables.md gives each format's
// parameters, signs and references.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "ccomp/controller/axis_table.hpp"

namespace ccomp::controller {

/// What a control's table can hold: its points at most, and the step it needs (Fanuc's
/// interval is a whole number of detection units; the others take any step, rounded here
/// to 0.5 mm to read well).
struct ControlLimits {
  std::size_t max_points = 256;
  double granularity = 0.5;  ///< mm
  bool cross = true;         ///< whether the format carries other axes' corrections
  /// Whether the table runs from machine home (0) to one end of the travel only (Centroid's
  /// starts at 0), so a span with 0 inside it cannot be one table.
  bool from_zero = false;
};

struct WriteOptions;

/// One control's table format: everything `ccomp export --control NAME` needs of it. Each
/// lives in its own file (src/controller/*_table.cpp); control_tables() lists them, so a
/// new control is one file and one line there.
struct ControlTable {
  std::string_view name;    ///< the --control value
  std::string_view writes;  ///< what the file is, for --help and the docs
  ControlLimits limits;
  /// The file's text; called after the common checks (points, finite values) and `check`.
  std::string (*write)(const AxisTable& table, const WriteOptions& options) = nullptr;
  /// The table as the control applies it once loaded (its digits, units, what it drops).
  AxisTable (*applies)(const AxisTable& table, const WriteOptions& options) = nullptr;
  /// What the format refuses beyond the common checks (throws ccomp::Error); may be null.
  void (*check)(const AxisTable& table, const WriteOptions& options) = nullptr;
};

/// Every control with a per-axis table, in the order --help lists them.
[[nodiscard]] const std::vector<const ControlTable*>& control_tables();
/// The control named so, or null.
[[nodiscard]] const ControlTable* control_named(std::string_view name);

struct WriteOptions {
  int linuxcnc_file_type = 0;     ///< COMP_FILE_TYPE: 0 nominal/actual, 1 nominal/trims
  int axis_number = 0;            ///< Fanuc's axis number, Siemens' AXn; 0: the axis' place in X Y Z
  double fanuc_unit = 0.001;      ///< mm per detection unit (IS-B: 0.001)
  int fanuc_reference_point = 0;  ///< parameter 3620; 0: chosen so the points fit from 1
  int siemens_first_cec_table = 0;
  std::vector<std::string> header;  ///< provenance lines, written as the format's comments
};

/// The text of the table file. Throws ccomp::Error (usage) when the table does not fit
/// the control (too many points; a Fanuc increment beyond 127 units at magnification 1
/// raises the magnification, parameter 3623, instead).
[[nodiscard]] std::string write_table(const ControlTable& control, const AxisTable& table,
                                      const WriteOptions& options);

/// What the control applies once the file is loaded, for the residual: the table as the
/// control's own interpolation and quantisation turn it (Fanuc: whole detection units
/// relative to the reference position; the others as written, to their digits).
[[nodiscard]] AxisTable as_control_applies(const ControlTable& control, const AxisTable& table,
                                           const WriteOptions& options);

}  // namespace ccomp::controller
