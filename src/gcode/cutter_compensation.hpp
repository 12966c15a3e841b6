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
#include <stdexcept>
#include <string>
#include <vector>

#include "ccomp/gcode/canon.hpp"

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
  /// `issue_offset_path` false: the offset is computed (for its errors) but the moves it
  /// makes are dropped and no call waits: the caller sends the programmed path instead.
  explicit CutterCompensation(bool issue_offset_path = true) : issue_(issue_offset_path) {}

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

  /// Whether `call` waits behind queued moves (rs274 queues these calls only; others it
  /// issues at once, ahead of the moves still waiting).
  [[nodiscard]] bool holds(const CanonCall& call) const;
  void hold(const CanonCall& call);
  /// Issues everything queued, in order (a stop, the program's end, G40).
  void flush(CanonSink& sink);
  /// The program's end: what waits is issued as it stands, and the offset is off.
  void stop(CanonSink& sink) {
    flush(sink);
    on_ = false;
    first_move_ = true;
  }

 private:
  struct Queued {
    Motion motion;         ///< interpreter frame; kind arc or straight
    double dir_first = 0;  ///< straight: programmed direction in the plane
    double dir_second = 0;
    double original_turn = 0;  ///< arc: sweep (rad) when queued; 0 = never moved
    CanonCall call;            ///< when !is_motion
    bool is_motion = true;
  };
  [[nodiscard]] std::pair<double, double> plane_of(const Axes& p) const;
  void set_plane(Axes& p, double first, double second) const;
  void enqueue_straight(const Motion& m, double dir_first, double dir_second);
  void enqueue_arc(const Motion& m, double original_turn);
  /// rs274's move_endpoint_and_flush: every queued move now ends at (first, second).
  void move_endpoint_and_flush(double first, double second, double unit, CanonSink& sink);
  void set_endpoint(double first, double second);
  [[nodiscard]] const Queued* front_arc() const;
  void entry_straight(const Motion& m);
  void middle_straight(const Motion& m, const Axes& from, double unit, CanonSink& sink);
  void concave_after_arc(const Queued& prev, double from1, double from2, double to1, double to2, double unit,
                         CanonSink& sink);
  void entry_arc(const Motion& m, const PlaneArc& arc, double unit);
  void middle_arc(const Motion& m, const Axes& from, const PlaneArc& arc, double unit, CanonSink& sink);
  void concave_arc_after_arc(const Queued& prev, double ccx, double ccy, double new_radius, int turns, double unit,
                             CanonSink& sink);
  Motion corner_arc(const Motion& m, const Axes& from, double end1, double end2) const;

  bool issue_ = true;
  bool on_ = false;
  CompensationSide side_ = CompensationSide::left;
  double radius_ = 0.0;
  Plane plane_ = Plane::xy;
  PlaneAxes axes_{0, 1, 2};
  bool first_move_ = true;
  Axes tool_{};    ///< rs274's current point: the tool centre after the last queued move
  Axes issued_{};  ///< where the last issued move ended, the start of the next one issued
  std::vector<Queued> queue_;
  double endpoint_first_ = 0, endpoint_second_ = 0;  ///< start of the first queued move
  bool endpoint_valid_ = false;
};

}  // namespace ccomp::gcode
