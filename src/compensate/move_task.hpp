#pragma once
// A move on its way from the interpreter, through the compensation, to the writer: the data
// the job's stages hand on (reading fills it, solving adds the compensated points, the
// writer turns them into edits).
#include <algorithm>
#include <cstdint>
#include <exception>
#include <string>
#include <vector>

#include "ccomp/compensate/compensator.hpp"
#include "ccomp/gcode/block.hpp"
#include "ccomp/gcode/canon.hpp"

namespace ccomp::compensate {

/// Which of a move's chords a task compensates: all of them (count 0), or [begin, end) of
/// `count`. An arc of more chords than a task may hold is compensated in parts.
struct ChordRange {
  std::size_t begin = 0, end = 0, count = 0;
  [[nodiscard]] bool whole() const { return count == 0; }
  [[nodiscard]] bool first() const { return begin == 0; }
  [[nodiscard]] bool last() const { return whole() || end == count; }
};

/// The share of its block's move a task is, and how its points are written: a move under
/// tool centre point control goes in pieces the axes move straight along
/// (tcp_kinematics.hpp), each a task of the block whose points are written as TCP words.
struct MovePiece {
  double from = 0.0, to = 1.0;
  bool tcp = false;
  double deviation = 0.0;  ///< mm: how far the axes' straight move leaves the control's line
  /// The block is an arc under TCP, followed as straight pieces: its own line becomes a G1.
  bool of_arc = false;
};

struct MoveTask {
  // what its block said
  gcode::Motion motion;  ///< its offsets point to `offsets`
  gcode::Offsets offsets;
  bool first = false;  ///< the program's first motion: the play is followed from its start
  std::string text, terminator;
  gcode::Block block;  ///< the words, and the text (in `text`), for the writer
  std::uint64_t offset = 0;
  ChordRange chords;             ///< this task's part of the move's chords
  MovePiece piece;               ///< this task's share of the block's move
  bool adds_lines_only = false;  ///< not the block's first move: its line is the first's
  /// The nominal tool pose at its end, where the reading thread took it (end_pose_known);
  /// else the worker takes it.
  NominalPose end_pose;
  bool end_pose_known = false;
  // what the compensation made of it
  std::vector<CompensatedPoint> points;
  std::vector<gcode::Axes> arc_starts;  ///< an arc under the control's offset: each piece's programmed start
  MoveReport report;
  /// Where the uncompensated machine's error is taken: left for the writing side, or
  /// taken by the worker already (MoveBatch::probes_on_worker) and then empty.
  std::vector<ErrorProbe> probes;
  std::exception_ptr error;
};

/// A batch of moves: the interpreter's thread fills one while another is compensated.
/// Each on cache lines of its own, as the two threads write them at once.
struct alignas(64) MoveBatch {
  std::vector<MoveTask> tasks;
  std::size_t filled = 0;
  bool probes_on_worker = false;  ///< the worker takes the error before at its moves' probes
};

/// The uncompensated machine's error at a move's probes, into its report, the probes then
/// dropped. Only what may raise `largest`, the largest error before taken so far, or the
/// move's own, is evaluated (Compensator::error_at): the largest over the program comes
/// out the same whichever thread takes which moves, each with a compensator of its own.
inline void take_error_before(Compensator& error_before, double largest, std::vector<ErrorProbe>& probes,
                              MoveReport& move) {
  for (const ErrorProbe& p : probes) {
    const double at_least = std::max(largest, move.max_deviation_before);
    move.max_deviation_before = std::max(move.max_deviation_before, error_before.error_at(p, at_least));
  }
  probes.clear();
}

}  // namespace ccomp::compensate
