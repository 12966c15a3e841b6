#pragma once
// Solving, the job's third stage: the compensated points of each move (the inverse, moves
// split where the error field needs it, arcs as chords). It runs on the worker thread when
// the job has one, so it keeps everything it writes to itself.
#include <cstddef>
#include <optional>
#include <vector>

#include "ccomp/compensate/compensator.hpp"
#include "ccomp/gcode/canon.hpp"
#include "ccomp/model/forward.hpp"
#include "move_task.hpp"

namespace ccomp::compensate {

/// The most chords one arc is written as: beyond, the arc is refused (exit 3) rather than
/// written as millions of lines (some 40 MB) or, where the count overflows, as nothing (a huge
/// radius, a tolerance of 1e-320 mm: docs/input-limits.md).
inline constexpr double kMostArcChords = 1'000'000;

/// How many chords an arc takes to stay within `tolerance` of it (sagitta r (1 - cos(step / 2))).
/// Throws ccomp::Error (program, no position: the caller's block gives it) for a count that
/// is not finite or above kMostArcChords.
[[nodiscard]] std::size_t arc_chord_count(const gcode::ArcGeometry& g, double tolerance);

/// On cache lines of its own: the interpreter's thread goes on writing its own state while
/// the worker runs this.
class alignas(64) MoveSolver {
 public:
  MoveSolver(const model::ForwardModel& model, const CompensationOptions& options);

  /// Compensates the batch's moves in order, up to the first that fails (its error kept):
  /// each from its nominal end pose (taken here where the reading thread left it), the
  /// error before taken at its probes where the batch leaves that to the worker.
  void solve_batch(MoveBatch& batch);

  /// The compensated points of a motion into `points`: a rapid's end (its path is the
  /// control's), a feed move split as its error field needs, an arc as chords within half
  /// the tolerance, each compensated within the other half; `range`, the chords of an arc
  /// in parts. Under the control's radius offset (G41/G42) the error is that of the tool
  /// centre's path: it is compensated, and each point written where the control's offset
  /// puts it there.
  /// `arc_starts`: for an arc under the control's offset, the programmed start of each piece
  /// it is written in (machine frame), for their centre words.
  /// A piece of a move under tool centre point control (`tcp_piece`) is compensated within
  /// half the tolerance: the other half is the piece's own (tcp_split()).
  void solve(const gcode::Motion& m, const gcode::Offsets& offsets, MoveReport& move,
             std::vector<CompensatedPoint>& points, const ChordRange& range = {},
             std::vector<gcode::Axes>* arc_starts = nullptr, bool tcp_piece = false);

  /// Its compensator: followed by the job's other stages only while no batch is in flight.
  Compensator compensator;

 private:
  void solve_path(const gcode::Motion& m, const gcode::Offsets& offsets, MoveReport& move,
                  std::vector<CompensatedPoint>& points, const ChordRange& range, bool tcp_piece);
  void solve_arc_kept(const gcode::Motion& m, const gcode::Offsets& offsets, MoveReport& move,
                      std::vector<CompensatedPoint>& points);
  void solve_arc_chords(const gcode::Motion& m, const gcode::Offsets& offsets, MoveReport& move,
                        std::vector<CompensatedPoint>& points, const ChordRange& range);
  [[nodiscard]] int arc_pieces(const gcode::Motion& m, const gcode::ArcGeometry& g, const gcode::Offsets& offsets);
  [[nodiscard]] double kept_arc_deviation(const gcode::Motion& m, const gcode::ArcGeometry& g,
                                          const gcode::Offsets& offsets, const model::ChainQ& from,
                                          const model::ChainQ& to, int n);

  const model::ForwardModel& model_;
  model::ForwardData data_;  ///< scratch for the nominal end poses and kept_arc_deviation()
  /// The error before at the probes of the batches the worker takes them for, and the
  /// largest it found (the writing side's compensator and figure are its own). Built at the
  /// first such batch: on one thread, or where the writing side takes them all, never.
  /// (From the job's options as given: the compensator's own follow the play as it moves.)
  CompensationOptions options_;
  std::optional<Compensator> error_before_;
  double largest_before_ = 0.0;
  bool offset_before_ = false;  ///< the last move was under the control's radius offset
  /// Where the last move's tool centre ended under the control's radius offset, as the
  /// control offsets it alone (chain values; NaN when there was none).
  model::ChainQ tool_end_ = model::ChainQ::Constant(std::nan(""));
  /// mm: how far off its plan the last move, a rapid with axes the control held still
  /// (Compensator::keep_still), left the machine: the error where a cut after it starts.
  double held_off_ = 0.0;
  std::vector<gcode::Axes> chords_;
  std::vector<CompensatedPoint> pieces_;
};

}  // namespace ccomp::compensate
