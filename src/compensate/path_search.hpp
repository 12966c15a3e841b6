#pragma once
// How verify measures an executed point against the original's path: the path as pieces
// (segments, arcs and helices in the table frame), kept in a window with boxes around groups
// of them, and the search that finds the pieces near each point in turn, following the
// path's order. The path's pieces come from a source of the caller's (verify's reads the
// original program on a thread of its own); a source is a class with
//   PieceWindow& window();                  the pieces kept
//   std::size_t available(std::size_t end); makes pieces up to `end` available, as far as
//                                           the path has them; the index one past the last
//                                           available (at most `end`). The window's end
//                                           never moves back: an end once reached stays.
//   std::pair<double, std::uint32_t> rest_from(std::size_t i);  the length of the path from
//                                           piece i on, and the line of piece i (0: none)
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <utility>
#include <vector>

#include "ccomp/model/forward.hpp"
#include "sliding_vector.hpp"

namespace ccomp::compensate {

/// mm: a stretch of the original's path passed over by less than this is a matter of where
/// points fall, not a cut missing.
constexpr double kUncutMm = 0.01;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

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
  /// The original's axes at the piece's ends (chain variables: an arc's at its start and
  /// end), and the tool's direction it means along the piece where its rotary axes stand
  /// still (`rotary_turns` false: the nominal chain turns the tool only with them). Where they
  /// turn, verify finds the direction at the point (verify.cpp, MeantDirection).
  model::ChainQ q0 = model::ChainQ::Zero(), q1 = model::ChainQ::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();
  bool rotary_turns = false;

  /// An arc's fraction (0 to 1, its first turn where it makes several) at p's angle about
  /// its axis; a segment's, p projected on it.
  [[nodiscard]] double fraction_at(const Eigen::Vector3d& p) const {
    if (!arc) {
      const Eigen::Vector3d ab = b - a;
      const double len2 = ab.squaredNorm();
      return len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    }
    const Eigen::Vector3d v = p - centre;
    double phi = std::atan2(v.dot(e2), v.dot(e1)) - a0;
    if (!ccw) phi = -phi;
    phi -= 2 * std::numbers::pi * std::floor(phi / (2 * std::numbers::pi));
    return sweep > 0 ? std::clamp(phi / sweep, 0.0, 1.0) : 0.0;
  }

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

  /// An arc's angle at p (rad), counted from its start in its own sense, in [0, 2 pi).
  [[nodiscard]] double turned_to(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d v = p - centre;
    double phi = std::atan2(v.dot(e2), v.dot(e1)) - a0;
    if (!ccw) phi = -phi;
    return phi - 2 * std::numbers::pi * std::floor(phi / (2 * std::numbers::pi));
  }

  /// An arc's chord of the helix (from its frame, not a and b) and how far the helix strays
  /// from it, for arc_lower_distance(); set by prepare_bounds() (strays < 0: none).
  Eigen::Vector3d chord_from = Eigen::Vector3d::Zero(), chord_to = Eigen::Vector3d::Zero();
  double strays = -1.0;
  /// A segment's ball: its middle, and a radius that holds it whole (half its length, and a
  /// picometre for the rounding of millimetres); set by prepare_bounds() (radius < 0: none).
  Eigen::Vector3d middle = Eigen::Vector3d::Zero();
  double ball = -1.0;

  /// A segment's ball; for an arc of at most half a turn: its chord, and how far the helix
  /// strays from it at the same fraction, r (1 - cos(sweep/2)) across (the sagitta, at
  /// most) plus |r1 - r0| sin(sweep/2) / 2 for a spiral, the rise the same on both.
  void prepare_bounds() {
    if (!arc) {
      middle = 0.5 * (a + b);
      ball = 0.5 * (b - a).norm() + 1e-9;
      return;
    }
    if (sweep > std::numbers::pi) return;
    const double end_angle = a0 + (ccw ? sweep : -sweep);
    chord_from = centre + r0 * (std::cos(a0) * e1 + std::sin(a0) * e2);
    chord_to = centre + r1 * (std::cos(end_angle) * e1 + std::sin(end_angle) * e2) + dw * n;
    strays = 1.001 * std::max(r0, r1) * (1.0 - std::cos(0.5 * sweep)) +
             0.5 * std::abs(r1 - r0) * std::sin(0.5 * sweep) + 1e-12;
  }

  /// Whether the piece is shown farther than `d` from p by its ball alone (no root, no
  /// division: most pieces near a point are, and distance() need not be asked of them).
  /// Never for an arc.
  [[nodiscard]] bool farther_than(const Eigen::Vector3d& p, double d) const {
    if (ball < 0.0) return false;
    const double reach = d + ball;
    return (p - middle).squaredNorm() > reach * reach;
  }

  /// No more than distance(p) to the helix' points, and changing no faster than p moves:
  /// the larger of two distances to sets that hold the arc, each a true distance: the solid
  /// ring of its radii and rise, all round its axis, and (prepare_bounds()) its chord
  /// widened by how far it strays. (Its ends, which a table turning with the arc can move
  /// off it, distance() takes as they are.)
  [[nodiscard]] double arc_lower_distance(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d v = p - centre;
    // (sqrt, not hypot: millimetres neither overflow nor underflow, and hypot is slow)
    const double u = v.dot(e1), w = v.dot(e2), h = v.dot(n), radial = std::sqrt(u * u + w * w);
    const double across = std::max({0.0, std::min(r0, r1) - radial, radial - std::max(r0, r1)});
    const double along = std::max({0.0, std::min(0.0, dw) - h, h - std::max(0.0, dw)});
    const double ring = std::sqrt(across * across + along * along);
    if (strays < 0.0) return ring;
    const Eigen::Vector3d chord = chord_to - chord_from;
    const double t = std::clamp((p - chord_from).dot(chord) / std::max(chord.squaredNorm(), 1e-300), 0.0, 1.0);
    return std::max(ring, (chord_from + t * chord - p).norm() - strays);
  }
};

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
    // The circle reaches r sqrt(e1_i^2 + e2_i^2) along axis i from its centre; the ends too,
    // which a table turning with the arc can take off the circle.
    const Eigen::Vector3d r = std::max(p.r0, p.r1) * (p.e1.cwiseAbs2() + p.e2.cwiseAbs2()).cwiseSqrt();
    const Eigen::Vector3d top = p.centre + p.dw * p.n;
    low = low.cwiseMin(p.centre - r).cwiseMin(top - r).cwiseMin(p.a).cwiseMin(p.b);
    high = high.cwiseMax(p.centre + r).cwiseMax(top + r).cwiseMax(p.a).cwiseMax(p.b);
  }
  /// The distance from p to the box: at most the distance to anything inside it.
  [[nodiscard]] double distance(const Eigen::Vector3d& p) const {
    return (low - p).cwiseMax(p - high).cwiseMax(0.0).norm();
  }
};

/// The pieces of a path kept for searching, numbered from the path's start, in groups of
/// kGroup with a box around each and groups of groups with a box too, so a search skips
/// the groups far from a point; dropped from the front once the search is past them, so
/// memory does not grow with the path.
class PieceWindow {
 public:
  static constexpr std::size_t kGroup = 32;
  /// Groups of groups, each with a box too: most of a point's window is far from it, and
  /// one box skips sixteen groups.
  static constexpr std::size_t kSuper = 16 * kGroup;

  void append(Piece piece) {
    piece.prepare_bounds();
    const std::size_t index = end();
    if (boxes_.empty() || index % kGroup == 0) boxes_.emplace_back();
    boxes_.back().add(piece);
    if (super_boxes_.empty()) first_super_ = index / kSuper;
    while (first_super_ + super_boxes_.size() <= index / kSuper) super_boxes_.emplace_back();
    super_boxes_.back().add(piece);
    pieces_.push_back(std::move(piece));
  }
  /// Drops the groups wholly before piece `i`.
  void drop_before(std::size_t i) {
    while (first_ + kGroup <= i && pieces_.size() >= kGroup) {
      pieces_.drop_front(kGroup);
      boxes_.drop_front(1);
      first_ += kGroup;
    }
    while (!super_boxes_.empty() && (first_super_ + 1) * kSuper <= first_) super_boxes_.drop_front(1), ++first_super_;
  }
  /// Drops every piece: the next one appended is piece `next` (the rest of a path counted,
  /// no longer searched).
  void restart_at(std::size_t next) {
    pieces_.clear();
    boxes_.clear();
    super_boxes_.clear();
    first_ = next;
  }
  [[nodiscard]] std::size_t first() const { return first_; }
  /// One past the last piece kept.
  [[nodiscard]] std::size_t end() const { return first_ + pieces_.size(); }
  [[nodiscard]] const Piece& operator[](std::size_t i) const { return pieces_[i - first_]; }
  [[nodiscard]] const Box& group_box(std::size_t i) const { return boxes_[(i - first_) / kGroup]; }
  /// The box of piece i's group of groups: around every piece of it still kept, and maybe
  /// around some already dropped (it only ever grows), so nothing kept lies outside it.
  [[nodiscard]] const Box& super_box(std::size_t i) const { return super_boxes_[i / kSuper - first_super_]; }

 private:
  SlidingVector<Piece> pieces_;
  SlidingVector<Box> boxes_;
  SlidingVector<Box> super_boxes_;
  std::size_t first_super_ = 0;  ///< the group of groups super_boxes_.front() is
  std::size_t first_ = 0;
};

/// Whether the search keeps the pieces near a point for the points after it (what verify
/// does), or searches the window's boxes for every point: the same results, which is what
/// the second is there to show.
enum class Candidates : std::uint8_t { kept, none };

/// Where each executed point is on the nominal path. The programs run in the same order, so
/// each point is searched for in a window of the nominal path around the piece it was last
/// found nearest (the cursor); pieces the search moves past without a point near them are
/// not cut.
template <class Path>
class PathSearch {
 public:
  explicit PathSearch(Path& path, Candidates candidates = Candidates::kept) : path_(path), reuse_(candidates) {}

  /// A rapid: pieces passed over before the next cut's first point were not cut.
  void rapid() { after_rapid_ = true; }

  /// The distance of executed point p from the nominal path, the cursor moved to where p
  /// is; nothing where there is no nominal path (a program without cuts).
  std::optional<double> distance(const Eigen::Vector3d& p) {
    const std::size_t from = std::max(window().first(), behind());
    const std::size_t to = available(cursor_ + kAhead);
    if (from >= to) return std::nullopt;
    const double best = search_near_then_ahead(p, from, to);
    move_cursor(p);
    // A piece is cut once a point near it is past its start (a point where one piece ends
    // and the next begins has cut only the first), and the search has come to it (a closed
    // contour's last piece ends where its first begins). Past: beyond the slack of its start,
    // or nearer its end (a piece shorter than the machine's error, as a table turning near
    // its axis makes, was never past its start: its last 17 um were said to be uncut).
    for (const auto& [i, d] : near_)
      if (i <= cursor_ && i >= uncut_from_ && past_start(p, i, best)) uncut_from_ = i + 1;
    note_passed_over(p, best);
    window().drop_before(behind());
    return best;
  }

  /// Whether point p, on piece i, is past the piece's start: beyond the slack of it, or
  /// nearer its end; on a closed arc (a full circle, its end its start), once the points
  /// have turned on it.
  [[nodiscard]] bool past_start(const Eigen::Vector3d& p, std::size_t i, double best) {
    const Piece& piece = window()[i];
    if (piece.arc && (piece.b - piece.a).norm() <= kUncutMm)
      return i == cursor_ && turned_ * 0.5 * (piece.r0 + piece.r1) > slack(best);
    const double from_start = (p - piece.a).norm();
    return from_start > slack(best) || (p - piece.b).norm() < from_start;
  }

  /// The piece the last point was found at (the cursor), after distance() gave a value.
  [[nodiscard]] const Piece& at_piece() { return window()[cursor_]; }

  /// The length (mm) of the original's cuts never come to, and the line of the first.
  std::pair<double, std::uint32_t> uncut() {
    auto [length, line] = path_.rest_from(uncut_from_);
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
  static constexpr std::size_t kMostCandidates = 1024;
  /// Pieces past those reachable that the first search near the cursor takes too: the ones
  /// just ahead, which move_cursor() follows across junctions.
  static constexpr std::size_t kNearAhead = 8;
  /// Pieces behind the cursor the first search takes at least: a point just past a
  /// junction, or one that turned back a little.
  static constexpr std::size_t kNearBehind = 4;
  /// mm: the least slack a nearest distance gives the pieces near with it (slack()).
  static constexpr double kLeastSlack = 0.5e-3;
  [[nodiscard]] std::size_t behind() const { return cursor_ > kBehind ? cursor_ - kBehind : 0; }
  /// The path's available(end), asked again only when the end moved or fell short: the
  /// window's end only grows, so an end once reached stays reached (and the cursor stands
  /// still over most of a move's points).
  std::size_t available(std::size_t end) {
    if (end != asked_end_ || available_to_ < end) asked_end_ = end, available_to_ = path_.available(end);
    return available_to_;
  }
  static double slack(double d) { return d + std::max(d, kLeastSlack); }

  /// The pieces near the cursor first: those just behind it and those the point can have
  /// come to from it without passing over a cut (and a few more). One of them within 0.5 um
  /// (the least slack, kLeastSlack) settles it: a piece of the window nearer still would
  /// find it near too, and where the cursor goes is decided among the pieces it can reach,
  /// all of them here. Else the whole window is searched (a cut
  /// missing, a point far off its path); where the piece near the cursor is within the slack
  /// of the nearest it finds, the near one is kept, as the cut the point makes (a later pass
  /// over the same place is not what it cuts). A path that comes back to the same place
  /// (repeated circles, a contour traced many times) would otherwise be searched piece by
  /// piece along the whole window at every point.
  double search_near_then_ahead(const Eigen::Vector3d& p, std::size_t from, std::size_t to) {
    const std::size_t local_from = behind_from(from), local_to = reachable_end(p, to);
    if (local_from == from && local_to == to) return gather_near(p, from, to);
    const double near = gather_near(p, local_from, local_to);
    if (!near_.empty() && near <= kLeastSlack) return near;
    local_near_.assign(near_.begin(), near_.end());
    const double far = gather(p, from, to);
    if (local_near_.empty() || near > slack(far)) return far;
    near_.swap(local_near_);
    return near;
  }

  /// The first piece the search near the cursor takes: kNearBehind pieces back, and on back
  /// until they are kCandidateRadius long (a table turning near its axis makes pieces of
  /// tenths of a micrometre); not before `from`.
  [[nodiscard]] std::size_t behind_from(std::size_t from) {
    std::size_t first = cursor_;
    for (double length = 0.0; first > from && (cursor_ - first < kNearBehind || length < kCandidateRadius);) {
      --first;
      length += window()[first].length();
    }
    return first;
  }

  /// One past the last piece the point can have come to without passing over more cut than
  /// passable(), and kNearAhead more; at most `to`.
  [[nodiscard]] std::size_t reachable_end(const Eigen::Vector3d& p, std::size_t to) {
    const double reach = passable(p);
    std::size_t end = std::max(cursor_, next_piece_) + 1;
    for (double passed = 0.0; end < to && passed <= reach; ++end)
      passed += window()[end].cycle ? 0.0 : window()[end].length();
    return std::min(end + kNearAhead, to);
  }

  /// The pieces (in program order) nearly as near p as the nearest (within the distance
  /// again, or 0.5 um), into near_; the nearest one's distance. Taken from the candidates
  /// of the last gathering while they hold all that can be that near, else gathered anew.
  double gather_near(const Eigen::Vector3d& p, std::size_t from, std::size_t to) {
    if (reuse_ == Candidates::kept)
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
      best = std::min(best, window()[i].distance(p));
    near_.clear();
    candidates_.clear();
    for (std::size_t g = from - from % PieceWindow::kGroup; g < to; g += PieceWindow::kGroup) {
      const std::size_t start = std::max(g, from);
      // A group of groups farther than the reach holds no piece nearer: all skipped (the
      // same pieces as their own boxes would skip, the nearest found as before).
      if ((start == from || g % PieceWindow::kSuper == 0) && window().super_box(start).distance(p) > reach(best)) {
        g = (start / PieceWindow::kSuper + 1) * PieceWindow::kSuper - PieceWindow::kGroup;
        continue;
      }
      if (window().group_box(start).distance(p) > reach(best)) continue;
      for (std::size_t i = std::max(g, from); i < std::min(g + PieceWindow::kGroup, to); ++i) {
        // (Beyond the reach: not a candidate, a segment being no nearer than its ball shows.)
        if (window()[i].farther_than(p, reach(best))) continue;
        const double d = window()[i].distance(p);
        if (reuse_ == Candidates::kept && candidate(window()[i], p, d)) candidates_.push_back(i);
        if (d > reach(best)) continue;
        best = std::min(best, d);
        near_.emplace_back(i, d);
      }
    }
    gathered_ = true, gathered_at_ = p, certified_from_ = from, certified_to_ = to;
    std::erase_if(near_, [&](const auto& candidate) { return candidate.second > slack(best); });
    return best;
  }

  /// Whether a piece at distance d from point p (Piece::distance) is kept as a candidate:
  /// within kCandidateRadius of it. For an arc, Piece::distance is to the helix' point at
  /// p's angle, which moves faster than p where the arc rises or spirals, so a lower bound
  /// that moves no faster than p is asked too (Piece::arc_lower_distance; its ends are in d,
  /// which does not either).
  static bool candidate(const Piece& piece, const Eigen::Vector3d& p, double d) {
    return d <= kCandidateRadius || (piece.arc && piece.arc_lower_distance(p) <= kCandidateRadius);
  }

  /// near_ and the nearest distance from the candidates alone, where they settle it: p is
  /// s from where they were gathered, so any other piece is farther than the radius less
  /// s (the triangle inequality, on its distance or its box's: see candidate()); when that
  /// is beyond the slack of the nearest candidate, near_ is what a gathering at p would
  /// find, piece for piece. Pieces come into the window ahead one by one as the cursor
  /// moves, each tried against the gathering point.
  std::optional<double> near_from_candidates(const Eigen::Vector3d& p, std::size_t from, std::size_t to) {
    // (Pieces dropped since, behind the window, can no longer be tried: none are, as the
    // window ahead is 4,096 pieces long, but that is not this function's to assume.)
    if (!gathered_ || from < certified_from_ || certified_to_ < window().first()) return std::nullopt;
    // Kept while the point stays near: a path that lingers gathers no more (its candidates
    // stay few), one that runs on along many pieces that close together starts afresh.
    if (candidates_.size() > kMostCandidates) return std::nullopt;
    for (; certified_to_ < to; ++certified_to_) {
      const Piece& piece = window()[certified_to_];
      if (candidate(piece, gathered_at_, piece.distance(gathered_at_))) candidates_.push_back(certified_to_);
    }
    const double margin = kCandidateRadius - (p - gathered_at_).norm() - 1e-9;  // 1e-9: the distances' rounding
    // The cursor's piece first, most often the nearest: a candidate its ball shows farther
    // than the slack of the nearest so far is neither the nearest nor near.
    double best = kInfinity, cursor_distance = kInfinity;
    const bool cursor_kept = cursor_ >= from && cursor_ < to && std::binary_search(candidates_.begin(), candidates_.end(), cursor_);
    if (cursor_kept) best = cursor_distance = window()[cursor_].distance(p);
    near_.clear();
    const auto first = std::lower_bound(candidates_.begin(), candidates_.end(), from);
    const auto last = std::lower_bound(first, candidates_.end(), to);
    for (auto it = first; it != last; ++it) {
      const std::size_t i = *it;
      if (i != cursor_ || !cursor_kept) {
        if (window()[i].farther_than(p, slack(best))) continue;
      }
      const double d = i == cursor_ && cursor_kept ? cursor_distance : window()[i].distance(p);
      best = std::min(best, d);
      near_.emplace_back(i, d);
    }
    if (!(slack(best) <= margin)) return std::nullopt;
    std::erase_if(near_, [&](const auto& candidate) { return candidate.second > slack(best); });
    return best;
  }

  /// Where the cursor goes, the programs running in the same order:
  ///  - it stays on its piece while a cut goes on near it (a pass over the same line again,
  ///    a spring pass, must not pull it ahead);
  ///  - else, to the first near piece ahead that the point can have come to without passing
  ///    over a cut: ahead of the cursor, or after a rapid, of the pieces already cut (a path
  ///    that turns back over itself, as a table turning back with the tool moving on does,
  ///    leaves the point near the pieces out and the pieces back; a rapid back to the start
  ///    of a second pass is on it);
  ///  - where none is, to the near piece closest to it.
  /// Then on along the near pieces that follow, across junctions the point is at.
  void move_cursor(const Eigen::Vector3d& p) {
    std::size_t at = near_.size();  // in near_, which is in program order
    if (!after_rapid_)
      for (std::size_t c = 0; c < near_.size(); ++c)
        if (near_[c].first == cursor_) at = c;
    if (at == near_.size())
      at = after_rapid_ ? first_reachable(p, next_piece_, next_piece_) : first_reachable(p, cursor_, cursor_ + 1);
    if (at == near_.size()) {
      auto gap = static_cast<std::size_t>(-1);
      for (std::size_t c = 0; c < near_.size(); ++c) {
        const std::size_t i = near_[c].first, apart = i > cursor_ ? i - cursor_ : cursor_ - i;
        if (apart < gap) gap = apart, at = c;
      }
    }
    // On along the run only across junctions the point is at (a pass over the same line
    // again is the next piece but not joined to this one where the point is).
    // (Within where points fall of the junction, kUncutMm: a corner written short of the
    // nominal one along a path that runs back over its line is still at it.)
    const double at_most = std::max(slack(near_[at].second), kUncutMm);
    follow_turning(p, near_[at].first);
    while (at + 1 < near_.size() && near_[at + 1].first == near_[at].first + 1 &&
           (p - window()[near_[at].first].b).norm() <= at_most &&
           (p - window()[near_[at + 1].first].a).norm() <= at_most && turned_round(p, near_[at].first, at_most))
      ++at;
    if (near_[at].first != cursor_) {
      if (near_[at].first > cursor_) note_left_round(p, at_most);
      turned_ = 0.0, turned_at_ = -1.0;
    }
    cursor_ = near_[at].first;
    follow_turning(p, cursor_);
  }

  /// The cursor leaves its closed arc for a piece ahead: what the points did not go round of
  /// it is not cut (a circle of two turns cut once). (Left at its start, the whole arc is
  /// passed over, which note_passed_over() counts.)
  void note_left_round(const Eigen::Vector3d& p, double at_most) {
    const Piece& piece = window()[cursor_];
    if (!piece.arc || (piece.b - piece.a).norm() > at_most || next_piece_ <= cursor_) return;
    const double left = (piece.sweep - turned_) * 0.5 * (piece.r0 + piece.r1);
    if (left <= passable(p)) return;
    skipped_length_ += left;
    if (skipped_line_ == 0) skipped_line_ = piece.line;
  }

  /// A closed arc (a full circle, its ends one point) is passed at its end only once the
  /// points have gone round it: its end is its start, where a point that never cut it
  /// stands too (an output with the circle deleted). What it has gone round is the angle the
  /// points near it turned, in its sense, while the cursor was on it.
  [[nodiscard]] bool turned_round(const Eigen::Vector3d& p, std::size_t i, double at_most) {
    const Piece& piece = window()[i];
    if (!piece.arc || (piece.b - piece.a).norm() > at_most) return true;
    if (i != cursor_) return false;  // just come to: at its start
    const double r = 0.5 * (piece.r0 + piece.r1);
    return (piece.sweep - turned_) * r <= passable(p);
  }

  /// The angle turned on the cursor's arc, with point p on piece i.
  void follow_turning(const Eigen::Vector3d& p, std::size_t i) {
    if (i != cursor_ || !window()[i].arc) return;
    const double phi = window()[i].turned_to(p);
    if (turned_at_ >= 0.0) {
      double step = phi - turned_at_;  // the shorter way, in (-pi, pi]
      step -= 2 * std::numbers::pi * std::ceil((step - std::numbers::pi) / (2 * std::numbers::pi));
      turned_ += std::max(step, 0.0);
    }
    turned_at_ = phi;
  }

  /// The first near piece (its place in near_) from piece `first` on with no more of the
  /// cuts from piece `from` on before it than the point can have passed over; near_.size()
  /// where there is none.
  [[nodiscard]] std::size_t first_reachable(const Eigen::Vector3d& p, std::size_t first, std::size_t from) {
    const double reach = passable(p);
    double passed = 0.0;
    std::size_t k = from;
    for (std::size_t c = 0; c < near_.size(); ++c) {
      const std::size_t i = near_[c].first;
      if (i < first) continue;
      for (; k < i && passed <= reach; ++k) passed += window()[k].cycle ? 0.0 : window()[k].length();
      if (passed > reach) break;
      return c;
    }
    return near_.size();
  }

  /// mm: the length of cuts a point may pass over since the search was last at its frontier
  /// (a rapid passes over none): the executed path since then, not only from the last point.
  /// A path that turns back over itself leaves the executed points, off the nominal one by
  /// the machine's error, nearer the way out than the way back for a few points; the way
  /// back they went along meanwhile is not passed over (at 100 mm from B's axis a table
  /// turning back was said to leave 1.3 mm uncut on the program against itself).
  [[nodiscard]] double passable(const Eigen::Vector3d& p) const {
    return (after_rapid_ ? 0.0 : 1.01 * (travelled_ + (p - last_point_).norm())) + kUncutMm;
  }

  /// Pieces passed over between one point and the next must be no longer than the path
  /// between them (straight on, within 1%); after a rapid, none may be (a cut missing).
  void note_passed_over(const Eigen::Vector3d& p, double best) {
    const std::size_t reached = first_reached(p, best);
    if (reached > next_piece_) {
      double passed = 0.0;
      for (std::size_t i = next_piece_; i < reached; ++i) passed += window()[i].cycle ? 0.0 : window()[i].length();
      if (passed > passable(p)) {
        skipped_length_ += passed;
        for (std::size_t i = next_piece_; i < reached && skipped_line_ == 0; ++i)
          if (!window()[i].cycle) skipped_line_ = window()[i].line;
      }
    }
    // The cursor's piece is cut once the point is past its start.
    if (next_piece_ <= cursor_) next_piece_ = cursor_ + ((p - window()[cursor_].a).norm() <= slack(best) ? 0 : 1);
    // At the frontier (the cursor on the last piece come to) the travel starts again; behind
    // it, it goes on adding up.
    travelled_ = after_rapid_ || cursor_ + 1 >= next_piece_ ? 0.0 : travelled_ + (p - last_point_).norm();
    last_point_ = p;
    after_rapid_ = false;
  }

  /// The first piece the point is on; after a rapid, not one it is at the end of (a rapid
  /// that lands where a piece ends has not cut it), unless that is all it is on.
  [[nodiscard]] std::size_t first_reached(const Eigen::Vector3d& p, double best) {
    if (after_rapid_)
      for (const auto& [i, d] : near_)
        if (i >= next_piece_ && (p - window()[i].b).norm() > slack(best)) return i;
    return near_.front().first;
  }

  PieceWindow& window() { return path_.window(); }

  Path& path_;
  Candidates reuse_;
  std::size_t cursor_ = 0;
  std::size_t asked_end_ = 0, available_to_ = 0;      ///< available()'s last question and answer
  std::size_t uncut_from_ = 0;                        ///< the first piece after the furthest the search has been
  std::vector<std::pair<std::size_t, double>> near_;  ///< pieces near the point, and their distances
  std::vector<std::pair<std::size_t, double>> local_near_;  ///< near_ of the search near the cursor, kept
  // The last gathering: where, the window it searched (certified_to_ grows with the window),
  // and the pieces within kCandidateRadius of its point, in program order.
  bool gathered_ = false;
  Eigen::Vector3d gathered_at_ = Eigen::Vector3d::Zero();
  std::size_t certified_from_ = 0, certified_to_ = 0;
  std::vector<std::size_t> candidates_;
  std::size_t next_piece_ = 0;  ///< the piece after the last point's
  double turned_ = 0.0;         ///< rad the points went round the cursor's arc
  double turned_at_ = -1.0;     ///< the last point's angle on it (< 0: none yet)
  Eigen::Vector3d last_point_ = Eigen::Vector3d::Zero();
  double travelled_ = 0.0;  ///< mm the executed points went since the search was at its frontier
  bool after_rapid_ = true;
  double skipped_length_ = 0.0;
  std::uint32_t skipped_line_ = 0;
};

}  // namespace ccomp::compensate
