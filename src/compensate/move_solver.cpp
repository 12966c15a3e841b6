#include "move_solver.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "ccomp/model/chain_values.hpp"

namespace ccomp::compensate {

using model::chain_of;
using model::controlled_of_chain;

std::size_t arc_chord_count(const gcode::ArcGeometry& g, double tolerance) {
  const double r = std::max(g.r_start, g.r_end);
  const double step = r > tolerance ? 2.0 * std::acos(1.0 - tolerance / r) : 2.0 * std::numbers::pi;
  return static_cast<std::size_t>(std::max(1.0, std::ceil(g.sweep / step)));
}

namespace {

/// Points along an arc (controlled points, machine frame) whose chords stay within
/// `tolerance` of it: the ends of the chords in `range` (all: start and end included).
void arc_chords(const gcode::Motion& m, double tolerance, const ChordRange& range, std::vector<gcode::Axes>& out) {
  const gcode::ArcGeometry g = gcode::arc_geometry(m);
  const std::size_t n = range.whole() ? arc_chord_count(g, tolerance) : range.count;
  const std::size_t begin = range.whole() ? 0 : range.begin, end = range.whole() ? n : range.end;
  out.resize(end - begin + 1);
  for (std::size_t k = begin; k <= end; ++k)
    out[k - begin] = gcode::arc_point(m, g, static_cast<double>(k) / static_cast<double>(n));
}

}  // namespace

MoveSolver::MoveSolver(const model::ForwardModel& model, const CompensationOptions& options)
    : compensator(model, options), model_(model), data_(model), tolerance_(options.tolerance) {}

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
      if (t.first) compensator.moved(chain_of(t.motion.start, t.offsets));
      compensator.expect(chain_of(t.motion.end, t.offsets), t.end_pose);
      solve(t.motion, t.offsets, t.report, t.points, t.chords);
    } catch (...) {
      t.error = std::current_exception();
      failed = true;
    }
  }
  compensator.defer_error_before(nullptr);
}

void MoveSolver::solve(const gcode::Motion& m, const gcode::Offsets& offsets, MoveReport& move,
                       std::vector<CompensatedPoint>& points, const ChordRange& range) {
  compensator.offset_by_control(m.radius_compensation);
  // The move that starts the control's offset must stay one line longer than the tool's
  // radius (LinuxCNC refuses a shorter one): its end is compensated, as a rapid's.
  const bool entry = m.radius_compensation && !offset_before_;
  offset_before_ = m.radius_compensation;
  if (m.kind == gcode::MotionKind::traverse || (entry && m.kind == gcode::MotionKind::feed)) {
    const model::ChainQ end = chain_of(m.end, offsets);
    compensator.error_before_at(end, move);
    compensator.rapid(end, points, move);
  } else if (m.kind == gcode::MotionKind::arc && m.radius_compensation) {
    solve_arc_kept(m, offsets, move, points);
  } else if (m.kind == gcode::MotionKind::arc) {
    solve_arc_chords(m, offsets, move, points, range);
  } else {
    compensator.straight(chain_of(m.start, offsets), chain_of(m.end, offsets), points, move);
  }
}

/// The control offsets an arc as one piece; its chords would be pieces shorter than the
/// radius at inside corners, which it refuses. So it stays an arc, its end compensated (its
/// centre words count from its start, as written), and what the arc does between is measured.
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
  compensator.rapid(end, points, move);
  move.max_deviation_after =
      std::max(move.max_deviation_after, kept_arc_deviation(m, g, offsets, from, points.back().q, n));
}

void MoveSolver::solve_arc_chords(const gcode::Motion& m, const gcode::Offsets& offsets, MoveReport& move,
                                  std::vector<CompensatedPoint>& points, const ChordRange& range) {
  arc_chords(m, tolerance_ / 2.0, range, chords_);
  points.clear();
  const auto n = static_cast<double>(range.whole() ? chords_.size() - 1 : range.count);
  for (std::size_t k = 1; k < chords_.size(); ++k) {
    compensator.straight(chain_of(chords_[k - 1], offsets), chain_of(chords_[k], offsets), pieces_, move,
                         tolerance_ / 2.0);
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
