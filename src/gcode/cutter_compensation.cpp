#include "cutter_compensation.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <numbers>
#include <string_view>

namespace ccomp::gcode {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kHalfPi = kPi / 2;
/// rs274's TOLERANCE_CONCAVE_CORNER (rad): turns smaller than this are no corner.
constexpr double kCorner = 0.05;
/// rs274's TOLERANCE_EQUAL, used on a cosine.
constexpr double kEqual = 0.0001;

/// rs274's find_turn: the angle swept from (x1, y1) to (x2, y2) about (cx, cy), + CCW.
double find_turn(double x1, double y1, double cx, double cy, int turn, double x2, double y2) {
  if (turn == 0) return 0.0;
  double alpha = std::atan2(y1 - cy, x1 - cx);
  double beta = std::atan2(y2 - cy, x2 - cx);
  if (turn > 0) {
    if (beta <= alpha) beta += 2 * kPi;
    return beta - alpha + (turn - 1) * 2 * kPi;
  }
  if (alpha <= beta) alpha += 2 * kPi;
  return beta - alpha + (turn + 1) * 2 * kPi;
}

/// The tool runs inside the arc: on its left going counter-clockwise, or right going clockwise.
bool tool_inside_arc(CompensationSide side, int turn) {
  return (side == CompensationSide::left && turn > 0) || (side == CompensationSide::right && turn < 0);
}

/// rs274's tolerance between an arc's two radii (CENTER_ARC_RADIUS_TOLERANCE), mm.
double spiral_tolerance(double unit) {
  return (unit == 1.0 ? 0.01 : 0.001 * unit) * 2.0 * std::numbers::sqrt2;
}

[[noreturn]] void refuse(const std::string& why) {
  throw CompensationError(why);
}

constexpr const char* kToolTooBig = "tool radius not less than arc radius with cutter radius compensation";

}  // namespace

void CutterCompensation::turn_on(CompensationSide side, double radius_mm, Plane plane, const Axes& tool) {
  on_ = true;
  side_ = side;
  radius_ = radius_mm;
  plane_ = plane;
  axes_ = plane_axes(plane);
  first_move_ = true;
  tool_ = tool;
  issued_ = tool;
  endpoint_valid_ = false;
}

bool CutterCompensation::turn_off(double unit, CanonSink& sink) {
  const bool moved = offsetting() && !first_move_;
  if (offsetting()) {
    const auto [first, second] = plane_of(tool_);
    move_endpoint_and_flush(first, second, unit, sink);
    flush(sink);
  }
  on_ = false;
  first_move_ = true;
  return moved;
}

void CutterCompensation::settle(double unit, CanonSink& sink) {
  if (offsetting()) {
    const auto [first, second] = plane_of(tool_);
    move_endpoint_and_flush(first, second, unit, sink);
  }
  flush(sink);
}

bool CutterCompensation::holds(const CanonCall& call) const {
  static constexpr std::array<std::string_view, 15> kQueued = {"SET_FEED_RATE",
                                                               "DWELL",
                                                               "SET_FEED_MODE",
                                                               "MIST_ON",
                                                               "MIST_OFF",
                                                               "FLOOD_ON",
                                                               "FLOOD_OFF",
                                                               "START_SPINDLE_CLOCKWISE",
                                                               "STOP_SPINDLE_TURNING",
                                                               "SET_SPINDLE_MODE",
                                                               "SET_SPINDLE_SPEED",
                                                               "COMMENT",
                                                               "ORIENT_SPINDLE",
                                                               "WAIT_ORIENT_SPINDLE_COMPLETE",
                                                               "START_SPINDLE_COUNTERCLOCKWISE"};
  if (queue_.empty()) return false;
  if (path_ != CutterPath::tool_centre) return true;
  for (std::string_view name : kQueued)
    if (name == call.name) return true;
  return false;
}

void CutterCompensation::hold(const CanonCall& call) {
  Queued q;
  q.kind = Queued::Kind::call;
  q.call = call;
  queue_.push_back(std::move(q));
}

void CutterCompensation::hold(const Block& block, const SourceLine& line) {
  Queued q;
  q.kind = Queued::Kind::block;
  q.block = std::make_unique<HeldBlock>();
  HeldBlock& h = *q.block;
  h.block = block;
  h.text.assign(block.text);
  h.line = line;
  h.line_text.assign(line.text);
  h.terminator.assign(line.terminator);
  h.file.assign(line.file);
  queue_.push_back(std::move(q));
}

void CutterCompensation::attach(const Motion& programmed) {
  for (auto q = queue_.rbegin(); q != queue_.rend(); ++q)
    if (q->kind == Queued::Kind::motion) {
      q->has_programmed = true;
      q->programmed = programmed;
      return;
    }
}

// ----------------------------------------------------------------------------------------
// The queue

std::pair<double, double> CutterCompensation::plane_of(const Axes& p) const {
  return {p[axes_.first], p[axes_.second]};
}

void CutterCompensation::set_plane(Axes& p, double first, double second) const {
  p[axes_.first] = first;
  p[axes_.second] = second;
}

void CutterCompensation::enqueue_straight(const Motion& m, double dir_first, double dir_second) {
  Queued q;
  q.kind = Queued::Kind::motion;
  q.motion = m;
  q.dir_first = dir_first;
  q.dir_second = dir_second;
  queue_.push_back(std::move(q));
}

void CutterCompensation::enqueue_arc(const Motion& m, double original_turn) {
  Queued q;
  q.kind = Queued::Kind::motion;
  q.motion = m;
  q.original_turn = original_turn;
  queue_.push_back(std::move(q));
}

void CutterCompensation::set_endpoint(double first, double second) {
  endpoint_first_ = first;
  endpoint_second_ = second;
  endpoint_valid_ = true;
}

double CutterCompensation::radius_of(const Motion& arc) const {
  const auto [e1, e2] = plane_of(arc.end);
  return std::hypot(e1 - arc.arc.center_first, e2 - arc.arc.center_second);
}

const CutterCompensation::Queued* CutterCompensation::first_queued_move() const {
  for (const Queued& q : queue_)
    if (q.kind == Queued::Kind::motion) return &q;
  return nullptr;
}

const Motion* CutterCompensation::front_arc() const {
  // rs274's queue starts with a move (it queues calls only behind one); blocks and calls
  // held here before it are not in rs274's. Emptied (after a stop), rs274 still reads its
  // front: the move that was there last, left in the vector's storage. Its corner rules
  // take that move as the one before, so they do here.
  const Queued* q = first_queued_move();
  const Motion* front = q != nullptr ? &q->motion : (last_front_valid_ ? &last_front_ : nullptr);
  return front != nullptr && front->kind == MotionKind::arc ? front : nullptr;
}

void CutterCompensation::move_endpoint_and_flush(double first, double second, double unit, CanonSink& sink) {
  if (first_queued_move() == nullptr) {  // rs274's queue is empty: nothing moves, no endpoint is set
    flush(sink);
    return;
  }
  // Every queued move ends here: moving into a concave corner, then up and down again,
  // leaves three moves to change.
  for (Queued& q : queue_) {
    if (q.kind != Queued::Kind::motion) continue;
    Motion& m = q.motion;
    if (m.kind == MotionKind::arc) {
      const auto [e1, e2] = plane_of(m.end);
      const double r1 = std::hypot(e1 - m.arc.center_first, e2 - m.arc.center_second);
      const double r2 = std::hypot(first - m.arc.center_first, second - m.arc.center_second);
      const double sweep = find_turn(endpoint_first_, endpoint_second_, m.arc.center_first, m.arc.center_second,
                                     m.arc.turns, first, second);
      if (std::abs(r1 - r2) > 0.01 * unit)
        refuse(fmt::format("cutter compensation made an arc whose radii differ ({:.4f} and {:.4f}): a bug in ccomp",
                           r1 / unit, r2 / unit));
      // rs274's allowance on the sweep (rad) depends on the program's units.
      const double allowance = unit == 1.0 ? 0.0254 : 0.001;
      if (q.original_turn != 0.0 && endpoint_valid_ && std::abs(sweep) > std::abs(q.original_turn) + allowance)
        refuse("arc move in a concave corner cannot be reached by the tool without gouging");
    } else {
      const double dot = q.dir_first * (first - endpoint_first_) + q.dir_second * (second - endpoint_second_);
      // The move would run backwards: the corner pulled back further than the line is long.
      if (endpoint_valid_ && dot < 0)
        refuse(fmt::format("straight {} in a concave corner cannot be reached by the tool without gouging",
                           m.kind == MotionKind::traverse ? "traverse" : "feed"));
    }
    set_plane(m.end, first, second);
  }
  flush(sink);
  set_endpoint(first, second);
}

void CutterCompensation::flush(CanonSink& sink) {
  endpoint_valid_ = false;
  if (queue_.empty()) return;  // (the common case, on every move and block outside G41/G42)
  if (const Queued* front = first_queued_move()) {
    last_front_ = front->motion;
    last_front_valid_ = true;
  }
  for (Queued& q : queue_) {
    switch (q.kind) {
      case Queued::Kind::call:
        sink.call(q.call);
        break;
      case Queued::Kind::block: {
        // Kept until the next is issued: a sink reads a block until the next one comes.
        last_block_ = std::move(q.block);
        HeldBlock& h = *last_block_;
        h.block.text = h.text;
        h.line.text = h.line_text;
        h.line.terminator = h.terminator;
        h.line.file = h.file;
        sink.block(h.block, h.line);
        break;
      }
      case Queued::Kind::motion:
        issue_motion(q, sink);
        break;
    }
  }
  queue_.clear();
}

void CutterCompensation::issue_motion(Queued& q, CanonSink& sink) {
  // Settled: the move starts where the last one issued ended (its corner's arc, or a
  // concave corner's meeting point) and ends where the next move left it.
  Motion m = q.motion;
  m.start = issued_;
  issued_ = m.end;
  const Offsets& o = *m.offsets;
  if (path_ == CutterPath::programmed) {
    if (!q.has_programmed) return;  // a corner's arc: the control's own
    Motion programmed = q.programmed;
    programmed.offset = true;
    programmed.arc.plane = plane_;  // (a straight move's too: the plane it is offset in)
    programmed.tool_start = o.to_machine(m.start);
    programmed.tool_end = o.to_machine(m.end);
    sink.motion(programmed);
    return;
  }
  if (m.kind == MotionKind::arc) {
    Axes centre = m.end;
    set_plane(centre, m.arc.center_first, m.arc.center_second);
    centre = o.to_machine(centre);
    m.arc.center_first = centre[axes_.first];
    m.arc.center_second = centre[axes_.second];
  }
  m.start = o.to_machine(m.start);
  m.end = o.to_machine(m.end);
  // Block by block the offset path is written with the offset taken out.
  if (path_ == CutterPath::tool_centre_by_block) m.radius_compensation = false;
  sink.motion(m);
}

// ----------------------------------------------------------------------------------------
// Straight moves

void CutterCompensation::straight(const Motion& m, const Axes& from, double unit, CanonSink& sink) {
  if (first_move_)
    entry_straight(m);
  else
    middle_straight(m, from, unit, sink);
}

void CutterCompensation::entry_straight(const Motion& m) {
  // A line from the target tangent to the tool's circle where it stands; the tool ends one
  // radius to the side of that line at the target.
  const auto [cx, cy] = plane_of(tool_);
  const auto [px, py] = plane_of(m.end);
  if (std::hypot(px - cx, py - cy) <= radius_)
    refuse("length of cutter compensation entry move is not greater than the tool radius");
  const double alpha = std::atan2(py - cy, px - cx) + (side_ == CompensationSide::left ? kHalfPi : -kHalfPi);
  Motion q = m;
  set_plane(q.end, px + radius_ * std::cos(alpha), py + radius_ * std::sin(alpha));
  set_endpoint(cx, cy);
  // rs274 records the offset's direction for this move: it is long enough never to reverse.
  enqueue_straight(q, std::cos(alpha), std::sin(alpha));
  first_move_ = false;
  tool_ = q.end;
}

Motion CutterCompensation::corner_arc(const Motion& m, const Axes& from, double end1, double end2) const {
  // About the programmed corner, at the height the tool is at; rotary axes end here.
  Motion arc = m;
  arc.kind = MotionKind::arc;
  arc.end = tool_;
  for (std::size_t i = 3; i < kAxisCount; ++i) arc.end[i] = m.end[i];
  set_plane(arc.end, end1, end2);
  const auto [c1, c2] = plane_of(from);
  arc.arc = Arc{plane_, c1, c2, side_ == CompensationSide::left ? -1 : 1};
  return arc;
}

void CutterCompensation::middle_straight(const Motion& m, const Axes& from, double unit, CanonSink& sink) {
  const auto [cx, cy] = plane_of(tool_);
  const auto [opx, opy] = plane_of(from);
  const auto [px, py] = plane_of(m.end);
  Motion q = m;
  if (px == opx && py == opy) {  // no motion in the plane: the tool stays where it is
    set_plane(q.end, cx, cy);
    enqueue_straight(q, 0.0, 0.0);
    tool_ = q.end;
    return;
  }
  const bool left = side_ == CompensationSide::left;
  double theta = std::atan2(cy - opy, cx - opx);
  double alpha = std::atan2(py - opy, px - opx);
  double beta = 0.0;
  if (left) {
    if (theta < alpha) theta += 2 * kPi;
    beta = theta - alpha - kHalfPi;
  } else {
    if (alpha < theta) alpha += 2 * kPi;
    beta = alpha - theta - kHalfPi;
  }
  const double gamma = left ? kHalfPi : -kHalfPi;
  const double end_x = px + radius_ * std::cos(alpha + gamma), end_y = py + radius_ * std::sin(alpha + gamma);
  const double mid_x = opx + radius_ * std::cos(alpha + gamma), mid_y = opy + radius_ * std::sin(alpha + gamma);
  const Motion* arc_before = front_arc();
  // Over the round top of an "h" from its right, staying right means staying above (rs274
  // asks this of a queue that holds a move).
  const bool h_shape =
      beta > kPi - kCorner && move_waits() && arc_before != nullptr && tool_inside_arc(side_, -arc_before->arc.turns);
  const bool concave = beta < -kCorner || beta > kPi + kCorner || h_shape;
  if (!concave && beta > kCorner) {  // convex: around the corner first
    move_endpoint_and_flush(cx, cy, unit, sink);
    if (m.kind == MotionKind::feed) {
      enqueue_arc(corner_arc(m, from, mid_x, mid_y), 0.0);
    } else {  // no arc traverse: a rapid to the corner's far side, parallel to the program
      Motion t = m;
      t.end = tool_;
      for (std::size_t i = 3; i < kAxisCount; ++i) t.end[i] = m.end[i];
      set_plane(t.end, mid_x, mid_y);
      enqueue_straight(t, 0.0, 0.0);
    }
    flush(sink);
    set_endpoint(mid_x, mid_y);
  } else if (concave && arc_before == nullptr) {
    const double half_corner = (beta + kPi) / 2.0;
    if (half_corner == 0.0) refuse("a zero degree inside corner is invalid for cutter compensation");
    const double retreat = radius_ / std::tan(half_corner);
    move_endpoint_and_flush(cx + retreat * std::cos(theta + gamma), cy + retreat * std::sin(theta + gamma), unit, sink);
  } else if (concave) {
    const Motion prev = *arc_before;
    concave_after_arc(prev, opx, opy, px, py, unit, sink);
  } else {  // in line, or leaving an arc along its tangent
    flush(sink);
    set_endpoint(cx, cy);
  }
  set_plane(q.end, end_x, end_y);
  enqueue_straight(q, px - opx, py - opy);
  tool_ = q.end;
}

void CutterCompensation::concave_after_arc(const Motion& prev, double from1, double from2, double to1, double to2,
                                           double unit, CanonSink& sink) {
  // The queued arc is the offset one; find where it meets the new line's offset.
  const Arc& a = prev.arc;
  const double old_radius = radius_of(prev);
  const double base_dir = std::atan2(to2 - from2, to1 - from1);
  const double theta = a.turns > 0 ? base_dir + kHalfPi : base_dir - kHalfPi;
  const double phi = std::atan2(a.center_second - from2, a.center_first - from1);
  const bool inside = tool_inside_arc(side_, a.turns);
  const double programmed_radius = inside ? old_radius + radius_ : old_radius - radius_;
  const double d = programmed_radius * std::cos(theta - phi);  // old centre to the new line
  const double l = (inside ? d - radius_ : d + radius_) / old_radius;
  if (l > 1.0 || l < -1.0)
    refuse("arc to straight motion makes a corner the compensated tool can't fit in without gouging");
  const double turn = (inside == (a.turns > 0)) ? -std::acos(l) : std::acos(l);
  const double angle = turn + theta + kPi;
  move_endpoint_and_flush(a.center_first + old_radius * std::cos(angle), a.center_second + old_radius * std::sin(angle),
                          unit, sink);
}

// ----------------------------------------------------------------------------------------
// Arcs

void CutterCompensation::check_entry_arc(const Axes& end) const {
  const auto [cx, cy] = plane_of(tool_);
  const auto [ex, ey] = plane_of(end);
  if (std::hypot(ex - cx, ey - cy) <= radius_)
    refuse("radius of cutter compensation entry arc is not greater than the tool radius");
}

void CutterCompensation::arc(const Motion& m, const Axes& from, const PlaneArc& arc, double unit, CanonSink& sink) {
  if (first_move_)
    entry_arc(m, arc, unit);
  else
    middle_arc(m, from, arc, unit, sink);
}

void CutterCompensation::entry_arc(const Motion& m, const PlaneArc& arc, double unit) {
  const auto [cx, cy] = plane_of(tool_);
  auto [end_x, end_y] = plane_of(m.end);
  const double arc_radius = std::hypot(arc.center_first - cx, arc.center_second - cy);
  if (arc_radius <= radius_ && tool_inside_arc(side_, arc.turns)) refuse(kToolTooBig);
  // The tool ends one radius from the programmed end, towards the centre or away from it.
  const double gamma = tool_inside_arc(side_, arc.turns)
                           ? std::atan2(arc.center_second - end_y, arc.center_first - end_x)
                           : std::atan2(end_y - arc.center_second, end_x - arc.center_first);
  end_x += radius_ * std::cos(gamma);
  end_y += radius_ * std::sin(gamma);
  // The compensated arc's centre: on the line from its end towards the programmed centre,
  // as far from the end as from the tool's start (triangle end, centre, chord midpoint).
  const double half_chord = std::hypot(cy - end_y, cx - end_x) / 2.0;
  const double to_centre = std::atan2(arc.center_second - end_y, arc.center_first - end_x);
  const double at_end = std::atan2(cy - end_y, cx - end_x) - to_centre;
  if (std::abs(std::cos(at_end)) < kEqual) refuse(kToolTooBig);
  const double distance = half_chord / std::cos(at_end);
  const double c1 = end_x + distance * std::cos(to_centre), c2 = end_y + distance * std::sin(to_centre);
  if (std::abs(std::hypot(c1 - end_x, c2 - end_y) - std::hypot(c1 - cx, c2 - cy)) > spiral_tolerance(unit))
    refuse("cutter compensation made an entry arc whose radii differ: a bug in ccomp");
  Motion q = m;
  set_plane(q.end, end_x, end_y);
  q.arc.center_first = c1;
  q.arc.center_second = c2;
  q.arc.turns = arc.turns;
  enqueue_arc(q, find_turn(cx, cy, c1, c2, arc.turns, end_x, end_y));
  first_move_ = false;
  tool_ = q.end;
}

void CutterCompensation::middle_arc(const Motion& m, const Axes& from, const PlaneArc& arc, double unit,
                                    CanonSink& sink) {
  const auto [cx, cy] = plane_of(tool_);
  const auto [opx, opy] = plane_of(from);
  const auto [ex, ey] = plane_of(m.end);
  const double ccx = arc.center_first, ccy = arc.center_second;
  const bool left = side_ == CompensationSide::left;
  const bool inside = tool_inside_arc(side_, arc.turns);
  const double arc_radius = std::hypot(ccx - ex, ccy - ey);
  double theta = std::atan2(cy - opy, cx - opx);
  theta = left ? theta - kHalfPi : theta + kHalfPi;  // direction the tool was going
  double delta = std::atan2(ccy - opy, ccx - opx);
  const double alpha = arc.turns > 0 ? delta - kHalfPi : delta + kHalfPi;  // the arc's start tangent
  double beta = left ? theta - alpha : alpha - theta;
  if (beta > 1.5 * kPi)
    beta -= 2 * kPi;
  else if (beta < -kHalfPi)
    beta += 2 * kPi;
  double gamma = 0.0;
  if (inside) {
    gamma = std::atan2(ccy - ey, ccx - ex);
    if (arc_radius <= radius_) refuse(kToolTooBig);
  } else {
    gamma = std::atan2(ey - ccy, ex - ccx);
    delta += kPi;
  }
  const double new_x = ex + radius_ * std::cos(gamma), new_y = ey + radius_ * std::sin(gamma);
  Motion main = m;
  set_plane(main.end, new_x, new_y);
  main.arc.center_first = ccx;
  main.arc.center_second = ccy;
  main.arc.turns = arc.turns;
  const double sweep = find_turn(opx, opy, ccx, ccy, arc.turns, ex, ey);
  // Tangent arc to arc over a convex top (the middle of an "m") counts as a corner too.
  const bool concave = beta < -kCorner || beta > kPi + kCorner || (std::abs(beta - kPi) < kCorner && !inside);
  if (concave) {
    if (const Motion* before = front_arc(); before == nullptr) {
      const double across = arc_radius * std::sin(beta - kHalfPi);
      const double reach = inside ? arc_radius - radius_ : arc_radius + radius_;
      const double l = (inside ? across + radius_ : across - radius_) / reach;
      if (l > 1.0 || l < -1.0) refuse("arc move in a concave corner cannot be reached by the tool without gouging");
      double angle = 0.0;
      if (inside)
        angle = arc.turns > 0 ? theta + std::asin(l) : theta - std::asin(l);
      else
        angle = arc.turns > 0 ? theta + kPi - std::asin(l) : theta + kPi + std::asin(l);
      move_endpoint_and_flush(ccx + reach * std::cos(angle), ccy + reach * std::sin(angle), unit, sink);
    } else {
      const Motion prev = *before;
      concave_arc_after_arc(prev, ccx, ccy, inside ? arc_radius - radius_ : arc_radius + radius_, arc.turns, unit,
                            sink);
    }
    enqueue_arc(main, sweep);
  } else if (beta > kCorner) {  // convex: an arc about the corner, then the arc
    const double mid_x = opx + radius_ * std::cos(delta), mid_y = opy + radius_ * std::sin(delta);
    flush(sink);
    Motion corner = corner_arc(m, from, mid_x, mid_y);
    enqueue_arc(corner, 0.0);
    flush(sink);
    set_endpoint(mid_x, mid_y);
    enqueue_arc(main, sweep);
  } else {
    flush(sink);
    set_endpoint(cx, cy);
    enqueue_arc(main, sweep);
  }
  tool_ = main.end;
}

void CutterCompensation::concave_arc_after_arc(const Motion& prev, double ccx, double ccy, double new_radius, int turns,
                                               double unit, CanonSink& sink) {
  const Arc& a = prev.arc;
  const double old_radius = radius_of(prev);
  const double centres = std::hypot(a.center_second - ccy, a.center_first - ccx);
  if (old_radius == 0.0 || centres == 0.0) refuse("arc to arc motion is invalid because the arcs have the same center");
  const double cosine =
      (old_radius * old_radius + centres * centres - new_radius * new_radius) / (2 * old_radius * centres);
  if (cosine > 1.0 || cosine < -1.0)
    refuse("arc to arc motion makes a corner the compensated tool can't fit in without gouging");
  const double pullback = std::acos(cosine);
  const double towards = std::atan2(ccy - a.center_second, ccx - a.center_first);
  const bool plus = tool_inside_arc(side_, a.turns) == (turns > 0);
  const double dir = plus ? towards + pullback : towards - pullback;
  move_endpoint_and_flush(a.center_first + old_radius * std::cos(dir), a.center_second + old_radius * std::sin(dir),
                          unit, sink);
}

}  // namespace ccomp::gcode
