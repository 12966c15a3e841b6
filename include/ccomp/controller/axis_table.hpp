#pragma once
// What a control's own compensation tables can hold of a machine model: for one linear
// axis, the correction of its position against its own position, for each direction of
// travel (pitch error and backlash), and the corrections of the other linear axes against
// it (straightness), sampled on a grid as a control interpolates them (linearly between
// points, constant beyond the ends). Angular errors act through the tool's offset and
// vary over the whole workspace, so a table along one line carries them only on that
// line; rotary axes' location errors and thermal drift it cannot carry at all:
// table_residual() measures what is left, the part only ccomp's rewriting corrects.
//
// Every table is 0 at the reference position (the axis at 0 on the line, as Fanuc's
// tables are by construction and Siemens' should be, so that switching them on moves
// nothing): the machine's error at the reference point is what a work offset probed there
// takes, and tables made so add up across axes instead of counting it once per axis.
#include <array>
#include <cstddef>
#include <functional>
#include <vector>

#include "ccomp/model/forward.hpp"

namespace ccomp::controller {

/// Where the table is sampled and what the machine is doing meanwhile.
struct TableOptions {
  char axis = 'X';
  double from = 0.0, to = 0.0;  ///< mm: the span the table covers (multiples of step through 0)
  double step = 1.0;            ///< mm between points
  double reference = 0.0;       ///< mm: where the table is 0 (inside [from, to])
  /// The other axes' positions on the line the table is taken along (mm, rad) and the
  /// tool length (mm, index model::kToolLengthIndex); the axis' own entry is ignored.
  model::ChainQ line = model::ChainQ::Zero();
  model::Conditions conditions;  ///< time and temperatures; directions are set per table
};

/// The corrections a control adds to the commanded position (mm) so the tool lands where
/// it was commanded: correction = -(error) where the correction is applied.
struct AxisTable {
  char axis = 'X';
  std::size_t axis_index = 0;     ///< into the chain variables (X Y Z A B C U V W)
  bool rotary = false;            ///< positions and corrections in degrees (else mm)
  std::vector<double> positions;  ///< mm, the commanded positions of the points, ascending
  double reference = 0.0;         ///< mm: the position where every correction is 0 (a point of the grid)
  std::vector<double> forward;    ///< correction of the axis itself while it travels up
  std::vector<double> reverse;    ///< the same while it travels down
  /// Corrections of another linear axis as this axis moves (mean of both directions).
  struct Cross {
    char axis = 'Y';
    std::size_t axis_index = 1;
    std::vector<double> correction;
  };
  std::vector<Cross> cross;
  /// Whether the axis' own corrections differ by direction (a reversal term in the model).
  [[nodiscard]] bool bidirectional() const;
  /// Chain units (mm, rad) per table unit (mm, deg).
  [[nodiscard]] double scale() const;
};

/// Samples the model along the line: at each point p the correction t with which the
/// commanded p + t puts the tool at p along the axis (solved to 1e-9 mm), for each
/// direction of travel, and the other linear axes' errors there; all less their values at
/// the reference position (travelling up). For a rotary axis (positions in degrees), t
/// turns the tool's orientation relative to the table back to the commanded angle about
/// the axis (its angular positioning error); the rest of its errors move the part, which
/// no table of the axis' own position carries (no cross tables). Throws ccomp::Error
/// (usage) for an axis the model lacks, or a grid that is empty or not finite; (safety,
/// exit 7, naming the point) for a correction beyond the model's max_correction or not
/// finite, which the main job refuses as well.
[[nodiscard]] AxisTable sample_axis_table(const model::ForwardModel& model, const TableOptions& options);

/// The grid of `options` for an axis spanning [lo, hi]: points at multiples of `step`
/// (so 0, a control's reference position, is a point when it is inside), covering the
/// span, at most `max_points`: the step grows to the next multiple of `granularity` until
/// they fit. Throws ccomp::Error (usage) for a span that is not finite.
struct Grid {
  double from = 0.0, to = 0.0, step = 1.0;
  [[nodiscard]] std::size_t points() const;
};
[[nodiscard]] Grid grid_for(double lo, double hi, double step, std::size_t max_points, double granularity);

/// The table's correction at commanded position p of the axis, travelling up (direction
/// +1) or down (-1), interpolated as the controls do.
[[nodiscard]] double correction_at(const AxisTable& table, double p, int direction);
/// The correction of cross table k at commanded position p.
[[nodiscard]] double cross_correction_at(const AxisTable& table, std::size_t k, double p);

/// What the tables leave of the model's error: the tool tip's deviation (um, length of
/// the vector) over the points given, less its deviation at `reference` travelling up
/// (what a work offset probed there takes), without tables and with every table applied
/// as a control applies them (its own axis' correction and its cross corrections, at the
/// commanded positions, in the direction the axes are travelling).
struct Residual {
  double max_before_um = 0.0, rms_before_um = 0.0;
  double max_after_um = 0.0, rms_after_um = 0.0;
  double reference_um = 0.0;  ///< the deviation at the reference point (its length, component or turn)
  std::size_t points = 0;
};
/// `component` 0 1 2 measures only the deviation along that machine axis; -1 its length;
/// a rotary axis' index (3 to 8) the turn about that axis, in arcseconds (the fields named
/// _um then hold arcseconds).
[[nodiscard]] Residual table_residual(const model::ForwardModel& model, const std::vector<AxisTable>& tables,
                                      const std::vector<model::ChainQ>& points, const model::ChainQ& reference,
                                      const model::Conditions& conditions, int component = -1);
/// What a control adds to the commanded axes (chain units: mm, rad) at commanded q,
/// travelling up (+1) or down (-1).
using Corrector = std::function<model::ChainQ(const model::ChainQ& q, int direction)>;
/// table_residual() for any corrector, `moving_axes` travelling together.
[[nodiscard]] Residual corrected_residual(const model::ForwardModel& model, const Corrector& corrector,
                                          const std::vector<std::size_t>& moving_axes,
                                          const std::vector<model::ChainQ>& points, const model::ChainQ& reference,
                                          const model::Conditions& conditions, int component = -1);
/// The line's reference point: the line with the table's axis at its reference position.
[[nodiscard]] model::ChainQ reference_point(const AxisTable& table, const TableOptions& options);

/// Points along the table's own line (every step / 8) and a grid over the workspace of
/// the model's axes (`per_axis` positions of each axis within its limits, a rotary axis
/// over a turn or its limits), with the tool length of `line`. With `rotaries` false,
/// rotary axes stay where `line` has them.
[[nodiscard]] std::vector<model::ChainQ> line_points(const AxisTable& table, const TableOptions& options);
[[nodiscard]] std::vector<model::ChainQ> workspace_points(const model::MachineModel& machine, const model::ChainQ& line,
                                                          std::size_t per_axis, bool rotaries = true);

}  // namespace ccomp::controller
