#include "move_solver.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <utility>

#include "ccomp/axis.hpp"
#include "ccomp/compensate/machine_coordinates.hpp"
#include "ccomp/error.hpp"

namespace ccomp::compensate {


std::size_t arc_chord_count(const gcode::ArcGeometry& g, double tolerance) {
  const double r = std::max(g.r_start, g.r_end);
  // r (1 - cos(step / 2)) = 2 r sin^2(step / 4): the cosine's form rounds 1 - tolerance / r
  // to 1 once the ratio is below the double's epsilon (a 1e13 mm circle at 1 um), a step of
  // 0, a count of infinity converted to an integer (0: the circle vanished).
  const double step = r > tolerance ? 4.0 * std::asin(std::sqrt(tolerance / (2.0 * r))) : 2.0 * std::numbers::pi;
  const double count = std::max(1.0, std::ceil(g.sweep / step));
  if (!(count <= kMostArcChords))  // (NaN too)
    throw Error(ErrorKind::program,
                fmt::format("this arc (radius {:.6g} mm, {:.6g} turns) needs {:.3g} chords to stay within {:.3g} um "
                            "of its path, more than the {:.0f} an arc may be written as: a larger --tolerance, or "
                            "the arc in smaller pieces",
                            r, g.sweep / (2.0 * std::numbers::pi), count, tolerance * 1000.0, kMostArcChords));
  return static_cast<std::size_t>(count);
}

namespace {

/// Points along an arc (controlled points, machine frame) whose chords stay within
/// `tolerance` of it: the ends of the chords in `range` (all: start and end included).
void arc_chords(const gcode::Motion& m, double tolerance, const ChordRange& range, std::vector<gcode::Axes>& out) {
  const gcode::ArcGeometry g = gcode::arc_geometry(m);
  const std::size_t n = range.whole() ? arc_chord_count(g, tolerance) : range.count;
  const std::size_t begin = range.whole() ? 0 : range.begin, end = range.whole() ? n : range.end;
  out.resize(end - begin + 1);
  for (std::size_t k = begin; k <= end; ++k) {
    out[k - begin] = gcode::arc_point(m, g, static_cast<double>(k) / static_cast<double>(n));
    // A point that is not a number would be written as a move to wherever its digits say.
    for (const double v : out[k - begin])
      if (!std::isfinite(v))
        throw Error(ErrorKind::program, fmt::format("this arc's point {} of {} is not a finite number: the arc's "
                                                    "numbers are beyond what can be computed with",
                                                    k, n));
  }
}

gcode::Axes linear_point(const gcode::Motion& m, double s) {
  gcode::Axes p = m.start;
  for (std::size_t i = 0; i < gcode::kAxisCount; ++i) p[i] += s * (m.end[i] - m.start[i]);
  return p;
}

gcode::Axes minus(gcode::Axes a, const gcode::Axes& b) {
  for (std::size_t i = 0; i < gcode::kAxisCount; ++i) a[i] -= b[i];
  return a;
}

/// The tool centre's offset from a straight move's programmed path: across the line (a
/// concave corner takes some of its length, along it). A move with no length in the plane
/// keeps the offset it was left with.
gcode::Axes offset_across(const gcode::Motion& m) {
  // In the plane of the offset only: a ramp's travel along the normal is not the offset's.
  const gcode::PlaneAxes pa = gcode::plane_axes(m.arc.plane);
  gcode::Axes v{};
  v[pa.first] = m.tool_end[pa.first] - m.end[pa.first];
  v[pa.second] = m.tool_end[pa.second] - m.end[pa.second];
  const double d1 = m.end[pa.first] - m.start[pa.first], d2 = m.end[pa.second] - m.start[pa.second];
  const double dd = d1 * d1 + d2 * d2;
  if (dd < 1e-24) return v;
  const double along = (v[pa.first] * d1 + v[pa.second] * d2) / dd;
  v[pa.first] -= along * d1;
  v[pa.second] -= along * d2;
  return v;
}

/// The programmed point the control offsets to `tool` on an arc: on the same radius line,
/// at the programmed radius.
gcode::Axes programmed_under(const gcode::Motion& m, const gcode::Axes& tool) {
  const gcode::PlaneAxes pa = gcode::plane_axes(m.arc.plane);
  const double c1 = m.arc.center_first, c2 = m.arc.center_second;
  const double r_tool = std::hypot(tool[pa.first] - c1, tool[pa.second] - c2);
  const double r_programmed = std::hypot(m.end[pa.first] - c1, m.end[pa.second] - c2);
  gcode::Axes p = tool;
  if (r_tool > 0.0) {
    p[pa.first] = c1 + (tool[pa.first] - c1) * r_programmed / r_tool;
    p[pa.second] = c2 + (tool[pa.second] - c2) * r_programmed / r_tool;
  }
  return p;
}

/// The axes the control keeps still through a move under its radius offset. A straight move with no travel in the offset's plane (a plunge,
/// a retract under G41/G42) keeps the plane's axes still: the control offsets any step in
/// the plane across the step's own direction, a radius from where the correction meant it,
/// and refuses one that turns back as a gouging corner (LinuxCNC does).
AxisSet kept_still_by_offset(const gcode::Motion& m, const gcode::Offsets& offsets) {
  if (!m.radius_compensation || (m.kind != gcode::MotionKind::feed && m.kind != gcode::MotionKind::traverse)) return {};
  // (A rotated frame turns about Z: its XY plane is the machine's, its other planes are not.)
  if (offsets.rotation != 0.0 && m.arc.plane != gcode::Plane::xy) return {};
  const gcode::PlaneAxes pa = gcode::plane_axes(m.arc.plane);
  if (m.end[pa.first] != m.start[pa.first] || m.end[pa.second] != m.start[pa.second]) return {};
  AxisSet still;
  still.insert_at(pa.first), still.insert_at(pa.second);
  return still;
}

}  // namespace

MoveSolver::MoveSolver(const model::ForwardModel& model, const CompensationOptions& options)
    : compensator(model, options),
      model_(model),
      data_(model),
      options_(options) {}

void MoveSolver::solve_batch(MoveBatch& batch) {
  bool failed = false;
  for (std::size_t k = 0; k < batch.filled; ++k) {
    MoveTask& t = batch.tasks[k];
    t.points.clear();
    t.probes.clear();
    t.report = MoveReport{};
    t.error = nullptr;
    if (failed) continue;  // never written: the writing stops at the failure
    try {
      compensator.defer_error_before(&t.probes);
      if (t.first) compensator.moved(chain_of(t.motion.offset ? t.motion.tool_start : t.motion.start, t.offsets));
      const model::ChainQ end = chain_of(t.motion.end, t.offsets);
      if (!t.end_pose_known) {
        model::forward(model_, data_, end, {}, false, model::Evaluate::nominal);
        t.end_pose = {data_.nominal, data_.R_nominal};
        t.end_pose_known = true;
      }
      compensator.expect(end, t.end_pose);
      solve(t.motion, t.offsets, t.report, t.points, t.chords, &t.arc_starts, t.piece.tcp);
      // A piece of a move under TCP: what the control's line is off the axes' straight move
      // adds to what the compensation leaves of the latter (at most).
      if (t.piece.tcp && t.motion.kind != gcode::MotionKind::traverse)
        t.report.max_deviation_after += t.piece.deviation;
      if (batch.probes_on_worker) {
        if (!error_before_) error_before_.emplace(model_, options_);
        take_error_before(*error_before_, largest_before_, t.probes, t.report);
        largest_before_ = std::max(largest_before_, t.report.max_deviation_before);
      }
    } catch (...) {
      t.error = std::current_exception();
      failed = true;
    }
  }
  compensator.defer_error_before(nullptr);
}

void MoveSolver::solve(const gcode::Motion& m, const gcode::Offsets& offsets, MoveReport& move,
                       std::vector<CompensatedPoint>& points, const ChordRange& range,
                       std::vector<gcode::Axes>* arc_starts, bool tcp_piece) {
  if (arc_starts) arc_starts->clear();
  // A cut that starts where a held rapid left the machine starts that far off.
  if (const double left = std::exchange(held_off_, 0.0);
      m.kind == gcode::MotionKind::feed || m.kind == gcode::MotionKind::arc)
    move.max_deviation_after = std::max(move.max_deviation_after, left);
  if (!m.offset) {
    tool_end_.setConstant(std::nan(""));
    solve_path(m, offsets, move, points, range, tcp_piece);
    return;
  }
  // The axes run the tool centre's path: its points are compensated (the compensator follows
  // where the axes are), and each is written as the programmed point the control offsets to
  // it: a line's less its offset across the line, an arc's drawn in to the programmed radius.
  gcode::Motion centre = m;
  centre.start = m.tool_start;
  centre.end = m.tool_end;
  centre.offset = false;
  // Between one offset move's end and the next one's start the control goes round the
  // corner (or cuts it short), the correction with it.
  const model::ChainQ start = chain_of(m.tool_start, offsets);
  if (tool_end_.allFinite() && compensator.commanded().allFinite()) compensator.carried(start - tool_end_, move);
  tool_end_ = m.radius_compensation ? chain_of(m.tool_end, offsets) : model::ChainQ::Constant(std::nan(""));
  const AxisSet still = compensator.commanded().allFinite() ? kept_still_by_offset(m, offsets) : AxisSet{};
  compensator.hold(still);
  if (still.empty()) {
    solve_path(centre, offsets, move, points, range, false);
  } else {  // (where the machine stands before the move: what the held axes keep)
    const model::ChainQ before = compensator.commanded();
    const AxisArray<double> play_before = compensator.play();
    solve_path(centre, offsets, move, points, range, false);
    const double left = compensator.keep_still(before, play_before, start, chain_of(m.tool_end, offsets),
                                               m.kind == gcode::MotionKind::feed, points, move);
    if (m.kind == gcode::MotionKind::traverse) held_off_ = left;
  }
  const bool arc = m.kind == gcode::MotionKind::arc && m.radius_compensation;
  const gcode::ArcGeometry g = arc ? gcode::arc_geometry(centre) : gcode::ArcGeometry{};
  // The move's end is the corner: the programmed end, where the tool is as the control
  // settles the corner (a concave one pulls it back along the move).
  const gcode::Axes across = offset_across(m);
  double s0 = 0.0;
  for (std::size_t k = 0; k < points.size(); ++k) {
    CompensatedPoint& p = points[k];
    const bool end = k + 1 == points.size();
    const gcode::Axes tool = end ? m.tool_end : arc ? gcode::arc_point(centre, g, p.s) : linear_point(centre, p.s);
    const gcode::Axes programmed = end ? m.end : arc ? programmed_under(m, tool) : minus(tool, across);
    p.q -= chain_of(tool, offsets) - chain_of(programmed, offsets);
    if (arc && arc_starts)
      arc_starts->push_back(k == 0 ? m.start : programmed_under(m, gcode::arc_point(centre, g, s0)));
    s0 = p.s;
  }
}

void MoveSolver::solve_path(const gcode::Motion& m, const gcode::Offsets& offsets, MoveReport& move,
                            std::vector<CompensatedPoint>& points, const ChordRange& range, bool tcp_piece) {
  compensator.offset_by_control(m.radius_compensation);
  // The move that starts the control's offset must stay one line longer than the tool's
  // radius (LinuxCNC refuses a shorter one): its end is compensated, as a rapid's.
  const bool entry = m.radius_compensation && !offset_before_;
  offset_before_ = m.radius_compensation;
  move.kept_whole = entry;
  if (m.kind == gcode::MotionKind::traverse || entry) {
    const model::ChainQ end = chain_of(m.end, offsets);
    compensator.error_before_at(end, move);
    compensator.rapid(end, points, move);
  } else if (m.kind == gcode::MotionKind::arc && m.radius_compensation) {
    solve_arc_kept(m, offsets, move, points);
  } else if (m.kind == gcode::MotionKind::arc) {
    solve_arc_chords(m, offsets, move, points, range);
  } else {
    compensator.straight(chain_of(m.start, offsets), chain_of(m.end, offsets), points, move,
                         tcp_piece ? options_.tolerance / 2.0 : -1.0);
  }
}

/// Under the control's radius offset an arc stays arcs: its chords would make corners the
/// control offsets on their own. It is written in as few pieces of the arc as keep each
/// within the tolerance (an arc of several turns as one), each piece's end compensated (its
/// centre words count from its start, as written); what each does between is measured.
void MoveSolver::solve_arc_kept(const gcode::Motion& m, const gcode::Offsets& offsets, MoveReport& move,
                                std::vector<CompensatedPoint>& points) {
  const model::ChainQ start = chain_of(m.start, offsets), end = chain_of(m.end, offsets);
  model::ChainQ from = compensator.commanded();
  if (from.hasNaN()) from = start;
  const gcode::ArcGeometry g = gcode::arc_geometry(m);
  const int n = 2 * std::max(8, static_cast<int>(std::ceil(g.sweep / (std::numbers::pi / 8))));
  for (int k = 1; k < n; ++k)
    compensator.error_before_at(chain_of(gcode::arc_point(m, g, static_cast<double>(k) / n), offsets), move);
  compensator.error_before_at(end, move);
  const int pieces = std::abs(m.arc.turns) == 1 ? arc_pieces(m, g, offsets) : 1;
  move.kept_whole = pieces == 1 && std::abs(m.arc.turns) != 1;
  points.clear();
  for (int k = 1; k <= pieces; ++k) {
    const double f0 = static_cast<double>(k - 1) / pieces, f1 = static_cast<double>(k) / pieces;
    gcode::Motion piece = m;
    piece.start = gcode::arc_point(m, g, f0);
    piece.end = gcode::arc_point(m, g, f1);
    if (pieces > 1) piece.arc.turns = m.arc.turns > 0 ? 1 : -1;
    const model::ChainQ to = compensator.path_end(chain_of(piece.start, offsets), chain_of(piece.end, offsets), move);
    points.push_back({f1, to, false});
    const gcode::ArcGeometry pg = gcode::arc_geometry(piece);
    const int checks = std::max(8, n / pieces);
    move.max_deviation_after =
        std::max(move.max_deviation_after, kept_arc_deviation(piece, pg, offsets, from, to, checks));
    from = to;
  }
}

/// How many equal pieces an arc under the control's offset needs: the uncompensated error's
/// departure from its straight-line blend between a piece's ends is what its compensated
/// ends cannot take out along it; it falls as the square of the piece's sweep.
int MoveSolver::arc_pieces(const gcode::Motion& m, const gcode::ArcGeometry& g, const gcode::Offsets& offsets) {
  constexpr int kMostPieces = 64, kSamples = 8;
  auto error = [&](double f) {
    model::forward(model_, data_, chain_of(gcode::arc_point(m, g, f), offsets), compensator.conditions(), false,
                   model::Evaluate::both);
    return Eigen::Vector3d(data_.actual - data_.nominal);
  };
  for (int pieces = 1;; pieces *= 2) {
    double worst = 0.0;
    for (int k = 0; k < pieces; ++k) {
      const double f0 = static_cast<double>(k) / pieces, f1 = static_cast<double>(k + 1) / pieces;
      const Eigen::Vector3d e0 = error(f0), e1 = error(f1);
      for (int j = 1; j < kSamples; ++j) {
        const double t = static_cast<double>(j) / kSamples;
        worst = std::max(worst, (error(f0 + t * (f1 - f0)) - ((1 - t) * e0 + t * e1)).norm());
      }
    }
    if (worst <= 0.5 * options_.tolerance || pieces >= kMostPieces) return pieces;
  }
}

void MoveSolver::solve_arc_chords(const gcode::Motion& m, const gcode::Offsets& offsets, MoveReport& move,
                                  std::vector<CompensatedPoint>& points, const ChordRange& range) {
  arc_chords(m, options_.tolerance / 2.0, range, chords_);
  points.clear();
  const auto n = static_cast<double>(range.whole() ? chords_.size() - 1 : range.count);
  for (std::size_t k = 1; k < chords_.size(); ++k) {
    compensator.straight(chain_of(chords_[k - 1], offsets), chain_of(chords_[k], offsets), pieces_, move,
                         options_.tolerance / 2.0);
    for (CompensatedPoint& piece : pieces_) {
      piece.s = (static_cast<double>(range.begin + k - 1) + piece.s) / n;
      points.push_back(piece);
    }
  }
  // What is left is measured from the chords; the arc bulges from them by their sagitta.
  const gcode::ArcGeometry g = gcode::arc_geometry(m);
  move.max_deviation_after += std::max(g.r_start, g.r_end) * (1.0 - std::cos(g.sweep / n / 2.0));
}

/// The largest distance, at n + 1 points, between the nominal arc `m` and the arc the
/// control cuts from the compensated `from` to `to` (chain values), its centre moved with
/// its start.
double MoveSolver::kept_arc_deviation(const gcode::Motion& m, const gcode::ArcGeometry& g,
                                      const gcode::Offsets& offsets, const model::ChainQ& from, const model::ChainQ& to,
                                      int n) {
  gcode::Motion cut = m;
  cut.start = controlled_of_chain(from, offsets);
  cut.end = controlled_of_chain(to, offsets);
  cut.arc.center_first += cut.start[g.axes.first] - m.start[g.axes.first];
  cut.arc.center_second += cut.start[g.axes.second] - m.start[g.axes.second];
  const gcode::ArcGeometry cut_g = gcode::arc_geometry(cut);
  double worst = 0.0;
  for (int k = 0; k <= n; ++k) {
    const double f = static_cast<double>(k) / n;
    model::forward(model_, data_, chain_of(gcode::arc_point(m, g, f), offsets), compensator.conditions(), false,
                   model::Evaluate::nominal);
    const Eigen::Vector3d meant = data_.nominal;
    model::forward(model_, data_, chain_of(gcode::arc_point(cut, cut_g, f), offsets), compensator.conditions(), false,
                   model::Evaluate::actual);
    worst = std::max(worst, (data_.actual - meant).norm());
  }
  return worst;
}

}  // namespace ccomp::compensate
