#pragma once
// Private to the interpreter: cutter radius compensation (G41/G42) computed as LinuxCNC's
// rs274ngc computes it. The tool centre runs one radius to the side of the programmed path:
// the entry move reaches the offset path, a convex corner gets an arc about the programmed
// corner, and a concave corner pulls the previous move's end back to where the two offset
// paths meet. That end is known only when the next move arrives, so moves wait in a queue,
// with the calls that came between them (in the order rs274 keeps), until the next move, a
// stop or G40 settles them.
//
// Points are in the interpreter's frame (program + origin, unrotated) in mm; the offset is
// computed in the plane's two axes (XY, or ZX as Z then X), as rs274 does.
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "ccomp/gcode/canon.hpp"
#include "ccomp/gcode/interpreter.hpp"

namespace ccomp::gcode {

enum class CompensationSide : std::uint8_t { left, right };

/// A move the offset cannot make, in rs274's words; the interpreter adds the block's position.
class CompensationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A programmed arc in the plane: its centre (interpreter frame) and signed turns (+ CCW).
struct PlaneArc {
  double center_first = 0, center_second = 0;
  int turns = 1;
};

class CutterCompensation {
 public:
  /// What goes to the sink (CutterPath): the offset path as rs274 issues it, or block by
  /// block, or the programmed path with the tool centre's moves.
  explicit CutterCompensation(CutterPath path = CutterPath::tool_centre) : path_(path) {}

  /// G41/G42 with the radius already made positive (a negative one swaps the side).
  void turn_on(CompensationSide side, double radius_mm, Plane plane, const Axes& tool);
  /// G40: the last move ends where its own offset put it; the queue is emptied into `sink`.
  /// Returns whether an offset was in force (then the next move may not be an arc).
  bool turn_off(double unit, CanonSink& sink);
  [[nodiscard]] bool on() const { return on_; }
  /// An offset is applied (rs274 ignores G41/G42 with a zero radius).
  [[nodiscard]] bool offsetting() const { return on_ && radius_ > 0.0; }
  [[nodiscard]] CompensationSide side() const { return side_; }
  [[nodiscard]] double radius() const { return radius_; }
  [[nodiscard]] bool first_move() const { return first_move_; }
  /// The tool centre after the last move taken (interpreter frame).
  [[nodiscard]] const Axes& tool() const { return tool_; }

  /// A straight move (traverse or feed) of the programmed point from `from` to `m.end`
  /// (m in the interpreter frame). `unit` is mm per program unit, for rs274's tolerances.
  void straight(const Motion& m, const Axes& from, double unit, CanonSink& sink);
  /// A programmed arc from `from` to `m.end` about `arc` (from the programmed start, or for
  /// the entry move from the tool centre: rs274 measures I J from where the tool is).
  void arc(const Motion& m, const Axes& from, const PlaneArc& arc, double unit, CanonSink& sink);
  /// rs274 refuses an entry arc ending within a radius of the tool before finding its centre.
  void check_entry_arc(const Axes& end) const;

  /// Whether `call` waits behind queued moves: rs274 queues some calls and issues the others
  /// at once, ahead of the moves still waiting; block by block, every call waits.
  [[nodiscard]] bool holds(const CanonCall& call) const;
  void hold(const CanonCall& call);
  /// Nothing waits in the queue.
  [[nodiscard]] bool idle() const { return queue_.empty(); }
  /// A move waits for the next to settle it.
  [[nodiscard]] bool move_waits() const { return first_queued_move() != nullptr; }
  /// Whether a block waits in the queue (block by block, under an offset: it comes before its
  /// own moves, which wait for the next, and a sink reads it until the next block comes).
  /// `turns_on`: the block has G41/G42, and its move may wait.
  [[nodiscard]] bool holds_blocks(bool turns_on) const {
    return path_ != CutterPath::tool_centre && (turns_on || offsetting() || !queue_.empty());
  }
  void hold(const Block& block, const SourceLine& line);
  /// The programmed path: `programmed` (machine frame) goes out with the last queued move,
  /// the tool centre's move, when that is settled.
  void attach(const Motion& programmed);
  /// G20/G21 while moves wait: rs274 converts them, so they are issued in the new units
  /// (block by block, a move is written in its own block's units).
  void print_in(Units units) {
    if (path_ != CutterPath::tool_centre) return;
    for (Queued& q : queue_) q.motion.units = units;
  }
  /// Issues everything queued, in order (a stop, the program's end, G40).
  void flush(CanonSink& sink);
  /// The program ends at its closing %: the moves that wait are not run (as in rs274), the
  /// blocks and calls held are still issued.
  void flush_held(CanonSink& sink) {
    std::erase_if(queue_, [](const Queued& q) { return q.kind == Queued::Kind::motion; });
    flush(sink);
  }
  /// A stop (M0, M1, M60): the waiting moves end where the tool is and are issued.
  void settle(double unit, CanonSink& sink);
  /// The program's end (M2, M30): settled as at a stop, and the offset is off.
  void stop(double unit, CanonSink& sink) {
    settle(unit, sink);
    on_ = false;
    first_move_ = true;
  }

 private:
  /// A block held back, its text and line owned (views into them set when it is issued).
  struct HeldBlock {
    Block block;
    std::string text, line_text, terminator, file;
    SourceLine line;
  };
  struct Queued {
    enum class Kind : std::uint8_t { motion, call, block } kind = Kind::motion;
    Motion motion;         ///< interpreter frame; kind arc or straight
    double dir_first = 0;  ///< straight: programmed direction in the plane
    double dir_second = 0;
    double original_turn = 0;     ///< arc: sweep (rad) when queued; 0 = never moved
    bool has_programmed = false;  ///< the programmed move it carries (CutterPath::programmed)
    Motion programmed;
    CanonCall call;
    std::unique_ptr<HeldBlock> block;
  };
  void issue_motion(Queued& q, CanonSink& sink);
  [[nodiscard]] std::pair<double, double> plane_of(const Axes& p) const;
  void set_plane(Axes& p, double first, double second) const;
  void enqueue_straight(const Motion& m, double dir_first, double dir_second);
  void enqueue_arc(const Motion& m, double original_turn);
  /// rs274's move_endpoint_and_flush: every queued move now ends at (first, second).
  void move_endpoint_and_flush(double first, double second, double unit, CanonSink& sink);
  void set_endpoint(double first, double second);
  [[nodiscard]] const Queued* first_queued_move() const;
  /// The radius a queued arc ends at (the offset one).
  [[nodiscard]] double radius_of(const Motion& arc) const;
  [[nodiscard]] const Motion* front_arc() const;
  void entry_straight(const Motion& m);
  void middle_straight(const Motion& m, const Axes& from, double unit, CanonSink& sink);
  void concave_after_arc(const Motion& prev, double from1, double from2, double to1, double to2, double unit,
                         CanonSink& sink);
  void entry_arc(const Motion& m, const PlaneArc& arc, double unit);
  void middle_arc(const Motion& m, const Axes& from, const PlaneArc& arc, double unit, CanonSink& sink);
  void concave_arc_after_arc(const Motion& prev, double ccx, double ccy, double new_radius, int turns, double unit,
                             CanonSink& sink);
  Motion corner_arc(const Motion& m, const Axes& from, double end1, double end2) const;

  CutterPath path_ = CutterPath::tool_centre;
  bool on_ = false;
  CompensationSide side_ = CompensationSide::left;
  double radius_ = 0.0;
  Plane plane_ = Plane::xy;
  PlaneAxes axes_{0, 1, 2};
  bool first_move_ = true;
  Axes tool_{};    ///< rs274's current point: the tool centre after the last queued move
  Axes issued_{};  ///< where the last issued move ended, the start of the next one issued
  std::vector<Queued> queue_;
  std::unique_ptr<HeldBlock> last_block_;  ///< the last block issued from the queue
  Motion last_front_;                      ///< the move at the queue's front when it was last emptied
  bool last_front_valid_ = false;
  double endpoint_first_ = 0, endpoint_second_ = 0;  ///< start of the first queued move
  bool endpoint_valid_ = false;
};

}  // namespace ccomp::gcode
