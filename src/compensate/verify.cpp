#include "ccomp/compensate/verify.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <exception>
#include <functional>
#include <limits>
#include <numbers>
#include <optional>
#include <tuple>
#include <vector>

#include "ccomp/constants.hpp"
#include "ccomp/model/chain_values.hpp"
#include "ccomp/util/handoff.hpp"
#include "ccomp/util/parallel.hpp"
#include "executed_tip.hpp"

namespace ccomp::compensate {

using model::chain_of;
using model::controlled_of_chain;
namespace {

/// A piece of the nominal path in the table frame: a straight segment, or an arc/helix (the
/// nominal map is rigid while the rotary axes hold still, so an arc stays an arc).
struct Piece {
  bool arc = false;
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();  // ends (an arc's too)
  Eigen::Vector3d centre = Eigen::Vector3d::Zero(), e1 = Eigen::Vector3d::Zero(), e2 = Eigen::Vector3d::Zero(),
                  n = Eigen::Vector3d::Zero();       // arc frame (unit in-plane axes and normal)
  double r0 = 0, r1 = 0, a0 = 0, sweep = 0, dw = 0;  // radius from r0 to r1, rise dw along n
  bool ccw = true;
  std::uint32_t line = 0;  ///< the original's block it is part of
  /// A canned cycle's: the block's words move its pecks with the hole's correction, so
  /// they need not meet the original's piece for piece (what is uncut does not count them).
  bool cycle = false;

  [[nodiscard]] double length() const { return arc ? std::hypot(sweep * 0.5 * (r0 + r1), dw) : (b - a).norm(); }

  /// The distance from p to the piece: for an arc, across to the turn nearest p (the
  /// radius and the rise taken where p's angle is), or to the nearer end.
  [[nodiscard]] double distance(const Eigen::Vector3d& p) const {
    if (!arc) {
      const Eigen::Vector3d ab = b - a;
      const double len2 = ab.squaredNorm();
      const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
      return (a + t * ab - p).norm();
    }
    double best = std::min((p - a).norm(), (p - b).norm());
    const Eigen::Vector3d v = p - centre;
    const double u = v.dot(e1), w = v.dot(e2), h = v.dot(n), radial = std::hypot(u, w);
    double phi = std::atan2(w, u) - a0;
    if (!ccw) phi = -phi;
    phi -= 2 * std::numbers::pi * std::floor(phi / (2 * std::numbers::pi));  // [0, 2 pi)
    // A helix of several turns passes p's angle once a turn: the turn at p's height, and its
    // neighbours, are the candidates.
    const double turns_after = std::floor((sweep - phi) / (2 * std::numbers::pi));  // < 0: p's angle is past the end
    if (turns_after < 0) return best;
    const auto turns = static_cast<long>(turns_after);
    long k0 = 0;
    if (turns >= 1 && dw != 0) k0 = std::clamp(std::lround((h / dw * sweep - phi) / (2 * std::numbers::pi)), 0L, turns);
    for (long k = std::max(0L, k0 - 1); k <= std::min(turns, k0 + 1); ++k) {
      const double f = (phi + 2 * std::numbers::pi * static_cast<double>(k)) / sweep;
      best = std::min(best, std::hypot(radial - (r0 + f * (r1 - r0)), h - dw * f));
    }
    return best;
  }
};

/// Collects what the interpreter does into a callback per motion (with its offsets).
template <typename OnMotion>
class MotionSink : public gcode::CanonSink {
 public:
  explicit MotionSink(OnMotion on) : on_(std::move(on)) {}
  void motion(const gcode::Motion& m) override { on_(m); }

 private:
  OnMotion on_;
};

template <typename OnMotion>
void each_motion(gcode::LineSource& program, const CheckOptions& options, OnMotion on) {
  MotionSink<OnMotion> sink(std::move(on));
  gcode::Interpreter interpreter(options.interpreter);
  interpreter.run(program, sink);
}

/// mm: a stretch of the original's path passed over by less than this is a matter of where
/// points fall, not a cut missing.
constexpr double kUncutMm = 0.01;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

struct Evaluator {
  const model::ForwardModel& model;
  model::ForwardData data;
  model::Conditions conditions;
  model::ChainQ at = model::ChainQ::Constant(std::nan(""));  ///< the command so far
  /// The conditions with the command moved on to q: the play follows the travel.
  const model::Conditions& advance(const model::ChainQ& q) {
    if (at.hasNaN()) at = q;  // the program's first command: the play as the options say
    model::take_up_play(model, conditions, at, q);
    at = q;
    return conditions;
  }
  Eigen::Vector3d nominal(const model::ChainQ& q) {
    model::forward(model, data, q, conditions, false, model::Evaluate::nominal);
    return data.nominal;
  }
};

/// The command along one motion, as the control interpolates it: straight in the axes, or
/// along the arc.
class MotionPath {
 public:
  explicit MotionPath(const gcode::Motion& m)
      : m_(m), a_(chain_of(m.start, *m.offsets)), b_(chain_of(m.end, *m.offsets)) {
    if (m.kind == gcode::MotionKind::arc) arc_ = gcode::arc_geometry(m);
  }
  [[nodiscard]] const model::ChainQ& start() const { return a_; }
  [[nodiscard]] const model::ChainQ& end() const { return b_; }
  [[nodiscard]] model::ChainQ at(double t) const {
    return arc_ ? chain_of(gcode::arc_point(m_, *arc_, t), *m_.offsets) : model::ChainQ(a_ + (b_ - a_) * t);
  }
  /// How many steps to look at it in: twice the model's check points over the travel of
  /// each axis (an arc's in-plane axes travel up to its length), and 16 a turn of an arc.
  [[nodiscard]] int steps(const model::ForwardModel& model, int minimum) const {
    if (!arc_) return 2 * model.check_points(a_, b_, minimum);
    model::ChainQ travel = b_ - a_;
    const double length = arc_->sweep * std::max(arc_->r_start, arc_->r_end);
    travel[static_cast<Eigen::Index>(arc_->axes.first)] = length;
    travel[static_cast<Eigen::Index>(arc_->axes.second)] = length;
    const auto per_turn = static_cast<int>(std::ceil(arc_->sweep / (2 * std::numbers::pi) * 16));
    return 2 * std::max(model.check_points(a_, a_ + travel, minimum, 1 << 16), per_turn);
  }

 private:
  const gcode::Motion& m_;
  model::ChainQ a_, b_;
  std::optional<gcode::ArcGeometry> arc_;
};

/// However a motion's callback returns, the command has gone to its end.
struct FollowPlay {
  Evaluator& ev;
  const model::ChainQ& end;
  ~FollowPlay() { ev.advance(end); }
};

/// The nominal pieces of one motion: an arc, or a straight move sampled (a move of the
/// rotary axes curves in the table frame).
void nominal_pieces(const gcode::Motion& m, Evaluator& ev, std::vector<Piece>& out) {
  const gcode::Offsets& o = *m.offsets;
  if (m.kind == gcode::MotionKind::arc) {
    const gcode::PlaneAxes pa = gcode::plane_axes(m.arc.plane);
    gcode::Axes c = m.start;
    c[pa.first] = m.arc.center_first;
    c[pa.second] = m.arc.center_second;
    Piece p;
    p.arc = true;
    p.centre = ev.nominal(chain_of(c, o));
    gcode::Axes c1 = c, c2 = c, cn = c;
    c1[pa.first] += 1, c2[pa.second] += 1, cn[pa.normal] += 1;
    p.e1 = ev.nominal(chain_of(c1, o)) - p.centre;
    p.e2 = ev.nominal(chain_of(c2, o)) - p.centre;
    p.n = ev.nominal(chain_of(cn, o)) - p.centre;
    const gcode::ArcGeometry g = gcode::arc_geometry(m);
    p.r0 = g.r_start;
    p.r1 = g.r_end;
    p.a0 = g.a_start;
    p.ccw = g.ccw;
    p.sweep = g.sweep;
    p.dw = m.end[pa.normal] - m.start[pa.normal];
    p.a = ev.nominal(chain_of(m.start, o));
    p.b = ev.nominal(chain_of(m.end, o));
    p.line = m.line;
    p.cycle = m.source == gcode::MotionSource::canned_cycle;
    out.push_back(p);
    return;
  }
  const model::ChainQ a = chain_of(m.start, o), b = chain_of(m.end, o);
  // A move of a rotary axis curves in the table frame: bisect until each chord is within
  // 0.01 um of the path, so the reference is much finer than any tolerance checked.
  std::function<void(double, double, const Eigen::Vector3d&, const Eigen::Vector3d&, int)> add =
      [&](double t0, double t1, const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, int depth) {
        const bool rotary_moves = (b.segment<3>(3) - a.segment<3>(3)).norm() > 1e-12;
        if (rotary_moves && depth < 24) {
          const double tm = 0.5 * (t0 + t1);
          const Eigen::Vector3d pm = ev.nominal(a + (b - a) * tm);
          Piece chord;
          chord.a = p0;
          chord.b = p1;
          if (depth < 4 || chord.distance(pm) > 1e-5) {
            add(t0, tm, p0, pm, depth + 1);
            add(tm, t1, pm, p1, depth + 1);
            return;
          }
        }
        Piece p;
        p.a = p0;
        p.b = p1;
        p.line = m.line;
        p.cycle = m.source == gcode::MotionSource::canned_cycle;
        out.push_back(p);
      };
  add(0.0, 1.0, ev.nominal(a), ev.nominal(b), 0);
}

/// A box around a piece (an arc's: around its whole circle, and the circle moved by its
/// rise): no point of the piece is outside it.
struct Box {
  // Empty: every point is infinitely far from it.
  Eigen::Vector3d low = Eigen::Vector3d::Constant(kInfinity), high = Eigen::Vector3d::Constant(-kInfinity);
  void add(const Piece& p) {
    if (!p.arc) {
      low = low.cwiseMin(p.a).cwiseMin(p.b), high = high.cwiseMax(p.a).cwiseMax(p.b);
      return;
    }
    // The circle reaches r sqrt(e1_i^2 + e2_i^2) along axis i from its centre.
    const Eigen::Vector3d r = std::max(p.r0, p.r1) * (p.e1.cwiseAbs2() + p.e2.cwiseAbs2()).cwiseSqrt();
    const Eigen::Vector3d top = p.centre + p.dw * p.n;
    low = low.cwiseMin(p.centre - r).cwiseMin(top - r), high = high.cwiseMax(p.centre + r).cwiseMax(top + r);
  }
  /// The distance from p to the box: at most the distance to anything inside it.
  [[nodiscard]] double distance(const Eigen::Vector3d& p) const {
    return (low - p).cwiseMax(p - high).cwiseMax(0.0).norm();
  }
};

/// The nominal path of the original program, piece by piece, made on a thread of its own
/// as the executed path needs it and dropped once the executed path is past it: memory
/// does not grow with the program. Pieces are numbered from the program's start, in
/// groups of kGroup with a box around each, so a search skips the groups far from a point.
class NominalPath {
 public:
  static constexpr std::size_t kGroup = 32;
  /// Groups of groups, each with a box too: most of a point's window is far from it, and
  /// one box skips sixteen groups.
  static constexpr std::size_t kSuper = 16 * kGroup;

  NominalPath(gcode::LineSource& original, const model::ForwardModel& model, const CheckOptions& options) {
    reader_.run([this, &original, &model, &options] {
      handoff_.produce([&](util::Handoff<Piece>& out) { produce(original, model, options, out); });
    });
  }
  NominalPath(const NominalPath&) = delete;
  NominalPath& operator=(const NominalPath&) = delete;
  /// Stops the reading where it is; reader_, destroyed first, then waits for it.
  ~NominalPath() { handoff_.cancel(); }

  /// Makes pieces up to `end` (exclusive) available, as far as the program has them; the
  /// number of pieces available from first() on.
  std::size_t available(std::size_t end) {
    while (first_ + pieces_.size() < end && !exhausted_) {
      if (!handoff_.pop(batch_)) {
        exhausted_ = true;
        break;
      }
      for (Piece& p : batch_) {
        const std::size_t index = first_ + pieces_.size();
        if (boxes_.empty() || index % kGroup == 0) boxes_.emplace_back();
        boxes_.back().add(p);
        if (super_boxes_.empty()) first_super_ = index / kSuper;
        while (first_super_ + super_boxes_.size() <= index / kSuper) super_boxes_.emplace_back();
        super_boxes_.back().add(p);
        pieces_.push_back(std::move(p));
      }
    }
    return std::min(end, first_ + pieces_.size());
  }
  /// Reads the rest of the original: the length of its path from piece `i` on, and the line
  /// of piece `i` (0 if there is none).
  std::pair<double, std::uint32_t> rest_from(std::size_t i) {
    double length = 0;
    std::uint32_t line = 0;
    auto count = [&](std::size_t index, const Piece& p) {
      if (index < i || p.cycle) return;
      if (line == 0) line = p.line;
      length += p.length();
    };
    for (std::size_t k = 0; k < pieces_.size(); ++k) count(first_ + k, pieces_[k]);
    while (!exhausted_) {
      const std::size_t next = first_ + pieces_.size();
      pieces_.clear();  // no longer searched: only counted
      boxes_.clear();
      super_boxes_.clear();
      first_ = next;
      available(next + 1);
      for (std::size_t k = 0; k < pieces_.size(); ++k) count(first_ + k, pieces_[k]);
    }
    return {length, line};
  }
  /// Drops the groups wholly before piece `i`.
  void drop_before(std::size_t i) {
    while (first_ + kGroup <= i && pieces_.size() >= kGroup) {
      pieces_.erase(pieces_.begin(), pieces_.begin() + kGroup);
      boxes_.pop_front();
      first_ += kGroup;
    }
    while (!super_boxes_.empty() && (first_super_ + 1) * kSuper <= first_) super_boxes_.pop_front(), ++first_super_;
  }
  [[nodiscard]] std::size_t first() const { return first_; }
  [[nodiscard]] const Piece& operator[](std::size_t i) const { return pieces_[i - first_]; }
  [[nodiscard]] const Box& group_box(std::size_t i) const { return boxes_[(i - first_) / kGroup]; }
  /// The box of piece i's group of groups: around every piece of it still kept, and maybe
  /// around some already dropped (it only ever grows), so nothing kept lies outside it.
  [[nodiscard]] const Box& super_box(std::size_t i) const { return super_boxes_[i / kSuper - first_super_]; }

 private:
  static void produce(gcode::LineSource& original, const model::ForwardModel& model, const CheckOptions& options,
                      util::Handoff<Piece>& out) {
    Evaluator ev{model, model::ForwardData(model), options.conditions};
    std::vector<Piece> batch;
    each_motion(original, options, [&](const gcode::Motion& m) {
      if (m.kind == gcode::MotionKind::feed || m.kind == gcode::MotionKind::arc) nominal_pieces(m, ev, batch);
      if (batch.size() >= kBatch) out.push(batch);
    });
    if (!batch.empty()) out.push(batch);
  }

  static constexpr std::size_t kBatch = 256, kQueued = 16;
  // the consumer's
  std::deque<Piece> pieces_;
  std::deque<Box> boxes_;
  std::deque<Box> super_boxes_;
  std::size_t first_super_ = 0;  ///< the group of groups super_boxes_.front() is
  std::size_t first_ = 0;
  bool exhausted_ = false;
  std::vector<Piece> batch_;  ///< the last batch handed over
  util::Handoff<Piece> handoff_{kQueued};
  util::BackgroundThread reader_;  // last: destroyed (joined) first, while what it uses exists
};

}  // namespace

namespace {

/// The share of `program` read so far, for the caller's progress report (-1: it takes none).
double progress_of(const CheckOptions& options, const gcode::LineSource& program) {
  if (!options.progress || program.size() == 0) return -1.0;
  return static_cast<double>(program.tell().offset) / static_cast<double>(program.size());
}

/// The share of `program` read so far, to the caller's progress report.
void report_progress(const CheckOptions& options, const gcode::LineSource& program) {
  if (const double share = progress_of(options, program); share >= 0) options.progress(share);
}

}  // namespace

PathError predict(gcode::LineSource& program, const model::ForwardModel& model, const CheckOptions& options) {
  PathError e;
  Evaluator ev{model, model::ForwardData(model), options.conditions};
  ExecutedTip tip(model, options.conditions);
  double sum2 = 0.0;
  each_motion(program, options, [&](const gcode::Motion& m) {
    report_progress(options, program);
    const MotionPath path(m);
    ev.advance(path.start());
    const FollowPlay follow{ev, path.end()};
    if (m.kind == gcode::MotionKind::traverse || m.kind == gcode::MotionKind::probe) return;
    ++e.moves;
    const int steps = path.steps(model, options.samples);
    if (m.kind == gcode::MotionKind::feed)
      tip.start_move(path.start(), path.end(), ev.conditions, true);
    else
      tip.other_move();
    for (int k = 0; k <= steps; ++k) {
      const double t = static_cast<double>(k) / steps;
      Eigen::Vector3d actual, nominal;
      if (tip.on_chord()) {  // within a nanometre (executed_tip.hpp)
        actual = tip.on_chord(t), nominal = tip.nominal_on_chord(t);
      } else {
        const model::ChainQ q = path.at(t);
        model::forward(model, ev.data, q, ev.advance(q));
        actual = ev.data.actual, nominal = ev.data.nominal;
      }
      const double d = (actual - nominal).norm();
      sum2 += d * d;
      ++e.points;
      if (d > e.max) e.max = d, e.worst_line = m.line, e.worst_point = nominal;
    }
  });
  e.rms = e.points ? std::sqrt(sum2 / static_cast<double>(e.points)) : 0.0;
  if (options.progress) options.progress(1.0);
  return e;
}

namespace {

/// Where each executed point is on the nominal path. The programs run in the same order, so
/// each point is searched for in a window of the nominal path around the piece it was last
/// found nearest (the cursor); pieces the search moves past without a point near them are
/// not cut.
class PathSearch {
 public:
  explicit PathSearch(NominalPath& nominal) : nominal_(nominal) {}

  /// A rapid: pieces passed over before the next cut's first point were not cut.
  void rapid() { after_rapid_ = true; }

  /// The distance of executed point p from the nominal path, the cursor moved to where p
  /// is; nothing where there is no nominal path (a program without cuts).
  std::optional<double> distance(const Eigen::Vector3d& p) {
    const std::size_t from = std::max(nominal_.first(), behind());
    const std::size_t to = nominal_.available(cursor_ + kAhead);
    if (from >= to) return std::nullopt;
    const double best = gather_near(p, from, to);
    move_cursor();
    // A piece is cut once a point near it is past its start (a point where one piece ends
    // and the next begins has cut only the first), and the search has come to it (a closed
    // contour's last piece ends where its first begins).
    for (const auto& [i, d] : near_)
      if (i <= cursor_ && (p - nominal_[i].a).norm() > slack(best)) uncut_from_ = std::max(uncut_from_, i + 1);
    note_passed_over(p);
    nominal_.drop_before(behind());
    return best;
  }

  /// The length (mm) of the original's cuts never come to, and the line of the first.
  std::pair<double, std::uint32_t> uncut() {
    auto [length, line] = nominal_.rest_from(uncut_from_);
    if (length <= kUncutMm) length = 0.0, line = 0;  // where sampling ends, not a missing cut
    length += skipped_length_;
    if (skipped_line_ != 0) line = skipped_line_;
    return {length, line};
  }

 private:
  static constexpr std::size_t kBehind = 64, kAhead = 4096;
  /// mm: pieces this near a gathering's point are kept for the points after it. A point
  /// moves a few micrometres from the last: one gathering serves tens of them.
  static constexpr double kCandidateRadius = 0.05;
  [[nodiscard]] std::size_t behind() const { return cursor_ > kBehind ? cursor_ - kBehind : 0; }
  static double slack(double d) { return d + std::max(d, 0.5e-3); }

  /// The pieces (in program order) nearly as near p as the nearest (within the distance
  /// again, or 0.5 um), into near_; the nearest one's distance. Taken from the candidates
  /// of the last gathering while they hold all that can be that near, else gathered anew.
  double gather_near(const Eigen::Vector3d& p, std::size_t from, std::size_t to) {
    if (const std::optional<double> best = near_from_candidates(p, from, to)) return *best;
    return gather(p, from, to);
  }

  /// The window searched through its boxes for the pieces within the slack of the nearest,
  /// and within kCandidateRadius of p, which become the candidates of the points after it:
  /// every other piece in the window is farther from p than that radius.
  double gather(const Eigen::Vector3d& p, std::size_t from, std::size_t to) {
    const auto reach = [](double best) { return std::max(slack(best), kCandidateRadius); };
    double best = kInfinity;  // to start with, the pieces just ahead of the cursor
    for (std::size_t i = std::min(cursor_, to - 1); i < std::min(cursor_ + 4, to); ++i)
      best = std::min(best, nominal_[i].distance(p));
    near_.clear();
    for (std::size_t g = from - from % NominalPath::kGroup; g < to; g += NominalPath::kGroup) {
      const std::size_t start = std::max(g, from);
      // A group of groups farther than the reach holds no piece nearer: all skipped (the
      // same pieces as their own boxes would skip, the nearest found as before).
      if ((start == from || g % NominalPath::kSuper == 0) && nominal_.super_box(start).distance(p) > reach(best)) {
        g = (start / NominalPath::kSuper + 1) * NominalPath::kSuper - NominalPath::kGroup;
        continue;
      }
      if (nominal_.group_box(start).distance(p) > reach(best)) continue;
      for (std::size_t i = std::max(g, from); i < std::min(g + NominalPath::kGroup, to); ++i) {
        const double d = nominal_[i].distance(p);
        if (d > reach(best)) continue;
        best = std::min(best, d);
        near_.emplace_back(i, d);
      }
    }
    candidates_.clear();
    for (const auto& [i, d] : near_)
      if (d <= kCandidateRadius) candidates_.push_back(i);
    gathered_ = true, gathered_at_ = p, certified_from_ = from, certified_to_ = to;
    std::erase_if(near_, [&](const auto& candidate) { return candidate.second > slack(best); });
    return best;
  }

  /// near_ and the nearest distance from the candidates alone, where they settle it: p is
  /// s from where they were gathered, so any other piece is farther than the radius less
  /// s (the triangle inequality); when that is beyond the slack of the nearest candidate,
  /// near_ is what a gathering at p would find, piece for piece. Pieces come into the window
  /// ahead one by one as the cursor moves, each tried against the gathering point.
  std::optional<double> near_from_candidates(const Eigen::Vector3d& p, std::size_t from, std::size_t to) {
    // (Pieces dropped since, behind the window, can no longer be tried: none are, as the
    // window ahead is 4,096 pieces long, but that is not this function's to assume.)
    if (!gathered_ || from < certified_from_ || certified_to_ < nominal_.first()) return std::nullopt;
    for (; certified_to_ < to; ++certified_to_)
      if (nominal_[certified_to_].distance(gathered_at_) <= kCandidateRadius) candidates_.push_back(certified_to_);
    const double margin = kCandidateRadius - (p - gathered_at_).norm() - 1e-9;  // 1e-9: the distances' rounding
    double best = kInfinity;
    near_.clear();
    for (const std::size_t i : candidates_) {
      if (i < from || i >= to) continue;
      const double d = nominal_[i].distance(p);
      best = std::min(best, d);
      near_.emplace_back(i, d);
    }
    if (!(slack(best) <= margin)) return std::nullopt;
    std::erase_if(near_, [&](const auto& candidate) { return candidate.second > slack(best); });
    return best;
  }

  /// The cursor goes to the near piece closest to it, and on along those that follow it: a
  /// path that runs twice over the same place (a spring pass) must not pull it ahead, and
  /// one that turns back over itself must not hold it.
  void move_cursor() {
    std::size_t at = 0;  // in near_, which is in program order
    auto gap = static_cast<std::size_t>(-1);
    for (std::size_t c = 0; c < near_.size(); ++c) {
      const std::size_t i = near_[c].first, apart = i > cursor_ ? i - cursor_ : cursor_ - i;
      if (apart < gap) gap = apart, at = c;
    }
    while (at + 1 < near_.size() && near_[at + 1].first == near_[at].first + 1) ++at;
    cursor_ = near_[at].first;
  }

  /// Pieces passed over between one point and the next must be no longer than the path
  /// between them (straight on, within 1%); after a rapid, none may be (a cut missing).
  void note_passed_over(const Eigen::Vector3d& p) {
    const std::size_t reached = near_.front().first;  // the first piece the point is on
    if (reached > next_piece_) {
      double passed = 0.0;
      for (std::size_t i = next_piece_; i < reached; ++i) passed += nominal_[i].cycle ? 0.0 : nominal_[i].length();
      const double path_length = after_rapid_ ? 0.0 : 1.01 * (p - last_point_).norm();
      if (passed > path_length + kUncutMm) {
        skipped_length_ += passed;
        for (std::size_t i = next_piece_; i < reached && skipped_line_ == 0; ++i)
          if (!nominal_[i].cycle) skipped_line_ = nominal_[i].line;
      }
    }
    next_piece_ = std::max(next_piece_, cursor_ + 1);
    last_point_ = p;
    after_rapid_ = false;
  }

  NominalPath& nominal_;
  std::size_t cursor_ = 0;
  std::size_t uncut_from_ = 0;                        ///< the first piece after the furthest the search has been
  std::vector<std::pair<std::size_t, double>> near_;  ///< pieces near the point, and their distances
  // The last gathering: where, the window it searched (certified_to_ grows with the window),
  // and the pieces within kCandidateRadius of its point, in program order.
  bool gathered_ = false;
  Eigen::Vector3d gathered_at_ = Eigen::Vector3d::Zero();
  std::size_t certified_from_ = 0, certified_to_ = 0;
  std::vector<std::size_t> candidates_;
  std::size_t next_piece_ = 0;  ///< the piece after the last point's
  Eigen::Vector3d last_point_ = Eigen::Vector3d::Zero();
  bool after_rapid_ = true;
  double skipped_length_ = 0.0;
  std::uint32_t skipped_line_ = 0;
};

/// What the compensated program makes the machine do, as verify measures it, in order: a
/// rapid (the search is told), the start of a cut, and the tool tip at each point checked.
struct ExecutedEvent {
  enum class Kind : std::uint8_t { rapid, cut, tip };
  Kind kind = Kind::tip;
  std::uint32_t line = 0;  ///< a cut's block
  double progress = -1;    ///< a rapid's or a cut's share of the program read (-1: none to report)
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();
};

/// The executed path of the compensated program, read and evaluated on a thread of its own
/// while the caller measures it against the nominal path (the points are the same whichever
/// thread makes them: only the work is shared).
class ExecutedPath {
 public:
  ExecutedPath(gcode::LineSource& compensated, const model::ForwardModel& model, const CheckOptions& options) {
    reader_.run([this, &compensated, &model, &options] {
      handoff_.produce([&](util::Handoff<ExecutedEvent>& out) { produce(compensated, model, options, out); });
    });
  }
  ExecutedPath(const ExecutedPath&) = delete;
  ExecutedPath& operator=(const ExecutedPath&) = delete;
  /// Stops the reading where it is; reader_, destroyed first, then waits for it.
  ~ExecutedPath() { handoff_.cancel(); }

  /// The next events; false at the end (where a failure of the reading is rethrown).
  bool next(std::vector<ExecutedEvent>& events) { return handoff_.pop(events); }

 private:
  static void produce(gcode::LineSource& compensated, const model::ForwardModel& model, const CheckOptions& options,
                      util::Handoff<ExecutedEvent>& out) {
    Evaluator ev{model, model::ForwardData(model), options.conditions};
    ExecutedTip tip(model, options.conditions);
    std::vector<ExecutedEvent> batch;
    each_motion(compensated, options, [&](const gcode::Motion& m) {
      const double progress = progress_of(options, compensated);
      const MotionPath path(m);
      ev.advance(path.start());
      const FollowPlay follow{ev, path.end()};
      const bool cut = m.kind == gcode::MotionKind::feed || m.kind == gcode::MotionKind::arc;
      batch.push_back({cut ? ExecutedEvent::Kind::cut : ExecutedEvent::Kind::rapid, m.line, progress});
      if (cut) tips(m, path, model, options, ev, tip, batch);
      if (batch.size() >= kBatch) out.push(batch);
    });
    if (!batch.empty()) out.push(batch);
  }

  /// The tool tip at each point a cut is checked at, finer than the job checks.
  static void tips(const gcode::Motion& m, const MotionPath& path, const model::ForwardModel& model,
                   const CheckOptions& options, Evaluator& ev, ExecutedTip& tip, std::vector<ExecutedEvent>& out) {
    const int steps = path.steps(model, options.samples);
    if (m.kind == gcode::MotionKind::feed)
      tip.start_move(path.start(), path.end(), ev.conditions);
    else
      tip.other_move();
    for (int k = 0; k <= steps; ++k) {
      const double t = static_cast<double>(k) / steps;
      ExecutedEvent& e = out.emplace_back();
      if (tip.on_chord()) {
        e.tip = tip.on_chord(t);  // the play stands still: ev's conditions stay as they are
      } else {
        const model::ChainQ q = path.at(t);
        model::forward(model, ev.data, q, ev.advance(q), false, model::Evaluate::actual);
        e.tip = ev.data.actual;
      }
    }
  }

  static constexpr std::size_t kBatch = 4096, kQueued = 8;
  util::Handoff<ExecutedEvent> handoff_{kQueued};
  util::BackgroundThread reader_;  // last: destroyed (joined) first, while what it uses exists
};

}  // namespace

PathError verify(gcode::LineSource& original, gcode::LineSource& compensated, const model::ForwardModel& model,
                 const CheckOptions& options) {
  NominalPath nominal(original, model, options);
  PathSearch search(nominal);
  ExecutedPath executed(compensated, model, options);
  PathError e;
  double sum2 = 0.0;
  std::uint32_t line = 0;
  std::vector<ExecutedEvent> events;
  while (executed.next(events)) {
    for (const ExecutedEvent& x : events) {
      if (x.kind != ExecutedEvent::Kind::tip) {
        if (x.progress >= 0) options.progress(x.progress);
        if (x.kind == ExecutedEvent::Kind::rapid) search.rapid();
        if (x.kind == ExecutedEvent::Kind::cut) ++e.moves, line = x.line;
        continue;
      }
      const std::optional<double> off = search.distance(x.tip);
      if (!off) continue;
      sum2 += *off * *off;
      ++e.points;
      if (*off > e.max) e.max = *off, e.worst_line = line, e.worst_point = x.tip;
    }
  }
  e.rms = e.points ? std::sqrt(sum2 / static_cast<double>(e.points)) : 0.0;
  std::tie(e.uncut_length, e.uncut_line) = search.uncut();
  if (options.progress) options.progress(1.0);
  return e;
}

}  // namespace ccomp::compensate
