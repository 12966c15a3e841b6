#include "ccomp/compensate/compensator.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <span>
#include <utility>

#include "axis_travel.hpp"
#include "ccomp/axis.hpp"
#include "ccomp/error.hpp"

namespace ccomp::compensate {

using model::ChainQ;

Compensator::Compensator(const model::ForwardModel& model, CompensationOptions options)
    : model_(model),
      options_(std::move(options)),
      problem_(model),
      data_(model),
      check_(model),
      bound_(model, options_.conditions) {
  for (const int k : problem_.rotary_unknowns) rotary_axes_.insert_at(static_cast<std::size_t>(k));
  held_rotary_ = rotary_axes_to_hold();
  if (!held_rotary_.empty()) problem_ = InverseProblem(model_, held_rotary_);
}

ChainQ Compensator::point(const ChainQ& nominal, MoveReport& report, Shortcut shortcut) {
  return solve_point(nominal, report, shortcut).q;
}

Compensator::SolvedPoint Compensator::solve_point(const ChainQ& nominal, MoveReport& report, Shortcut shortcut) {
  // A move usually starts where the last one ended: that point is solved already.
  if (nominal == workspace_.memory.last_nominal && options_.conditions.directions == workspace_.memory.last_directions)
    return {workspace_.last_answer, workspace_.last_answer_bound};
  // A point along a path may be accepted without evaluating the model where its residual
  // is bounded below this share of the tolerance: the point then lands within a tenth of
  // the tolerance of where an evaluated solve puts it.
  follow_holds(nominal);
  report.held_axes |= held_rotary_;
  InverseOptions inverse;
  inverse.bound = options_.exact || shortcut == Shortcut::none ? nullptr : &bound_;
  inverse.bounded_tolerance = kBoundedShare * options_.tolerance;
  const InverseResult r = solve_inverse(model_, problem_, data_, nominal, options_.conditions, inverse, nullptr,
                                        &workspace_, nominal == expected_ ? &expected_pose_ : nullptr);
  if (!r.converged) {
    // An error beyond any machine's (a term in the wrong unit, say) is said as such.
    if (const double error = error_at(nominal); !(error <= model_.machine().max_correction))
      throw Error(ErrorKind::safety, fmt::format("the model's error here is {:.4g} mm, beyond its bound of {} mm "
                                                 "(max_correction): is the model right for this machine?",
                                                 error, model_.machine().max_correction));
    throw Error(ErrorKind::safety, fmt::format("the inverse did not converge in {} iterations (residual {:.3g} mm)",
                                               r.iterations, r.position_residual.norm()));
  }
  remember_tip(nominal, r.target);
  report.max_correction = std::max(report.max_correction, (r.q - nominal).head<3>().cwiseAbs().maxCoeff());
  report.max_rotary_correction =
      std::max(report.max_rotary_correction, (r.q - nominal).segment<3>(3).cwiseAbs().maxCoeff());
  report.max_orientation_error = std::max(report.max_orientation_error, r.orientation_error.norm());
  return {r.q, r.residual_bound};
}

AxisSet Compensator::rotary_axes_to_hold() const {
  AxisSet axes;
  for (const Axis a : rotary_axes_) {
    const model::AxisHold hold = options_.hold[a];
    if (hold == model::AxisHold::clamped || (hold == model::AxisHold::automatic && !turned_.contains(a)))
      axes.insert(a);
  }
  return axes;
}

void Compensator::follow_holds(const ChainQ& nominal) {
  if (held_rotary_.empty()) return;  // nothing held (an axis once free stays free)
  if (!first_nominal_.allFinite()) first_nominal_ = nominal;
  for (const Axis a : held_rotary_) {
    const std::size_t i = index(a);
    const auto k = static_cast<Eigen::Index>(i);
    if (options_.hold[a] == model::AxisHold::automatic && std::abs(nominal[k] - first_nominal_[k]) > still(i))
      turned_.insert(a);
  }
  const AxisSet axes = rotary_axes_to_hold();
  if (axes == held_rotary_) return;
  problem_ = InverseProblem(model_, axes);
  held_rotary_ = axes;
  workspace_.forget_problem();
}

void Compensator::moved(const ChainQ& q) {
  command(q);
  uncompensated_ = true;
}

void Compensator::command(const ChainQ& q) {
  uncompensated_ = false;
  if (commanded_.allFinite()) model::take_up_play(model_, play_, commanded_, q);
  commanded_ = q;
}

void Compensator::approach(const ChainQ& start, const ChainQ& end) {
  auto& need = options_.conditions.directions;
  for (std::size_t i = 0; i < need.size(); ++i) {
    if (!model_.reads_approach(i)) continue;
    const double delta = end[static_cast<Eigen::Index>(i)] - start[static_cast<Eigen::Index>(i)];
    need[i] = std::abs(delta) > still(i) && !held(i) ? (delta > 0 ? 1.0 : -1.0) : play_[i];
  }
}

bool Compensator::approach_by_travel(const ChainQ& from, const ChainQ& to) {
  // An axis the move barely names still travels by its correction: that travel decides
  // which way it approaches.
  auto& need = options_.conditions.directions;
  bool changed = false;
  for (std::size_t i = 0; i < need.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    if (!model_.reads_approach(i) || std::abs(to[k] - from[k]) <= 10 * still(i)) continue;
    const double travel = to[k] > from[k] ? 1.0 : -1.0;
    if (travel != need[i] && !held(i)) need[i] = travel, changed = true;
  }
  return changed;
}

ChainQ Compensator::path_end(const ChainQ& start, const ChainQ& end, MoveReport& report) {
  if (!commanded_.allFinite()) commanded_ = start;
  approach(start, end);
  ChainQ q = point(end, report);
  if (approach_by_travel(commanded_, q)) q = point(end, report);
  command(q);
  report.unhidden_reversals |= unhidden(options_.conditions.directions);
  return q;
}

void Compensator::rapid(const ChainQ& end, std::vector<CompensatedPoint>& out, MoveReport& report) {
  out.clear();
  if (!commanded_.allFinite()) commanded_ = end;
  approach(commanded_, end);
  ChainQ q = point(end, report);
  if (approach_by_travel(commanded_, q)) q = point(end, report);
  auto& need = options_.conditions.directions;
  out.push_back({1.0, q, false});
  command(q);
  // A rapid shorter than an axis' play leaves it part-way through: the axis goes back
  // past it and approaches again (the control's path does not matter between rapids).
  const AxisArray<double> target = need;
  for (std::size_t i = 0; i < need.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    // (A held axis does not move: its play stays where it was, keep_still() says.)
    if (!model_.reads_approach(i) || model_.lost_motion()[i] <= 0 || held(i) || std::abs(play_[i] - target[i]) <= 0.02)
      continue;
    if (offset_by_control_) {
      report.jogs_withheld = true;
      continue;
    }
    need[i] = -target[i];
    ChainQ back = commanded_;
    back[k] = point(end, report)[k];
    need[i] = target[i];
    for (const auto& [step, way] : {std::pair{back, -target[i]}, std::pair{q, target[i]}}) {
      CompensatedPoint& point = out.emplace_back(CompensatedPoint{1.0, step, true});
      point.turns[i] = static_cast<std::int8_t>(way);
      if (way == target[i]) set_travel_slack(i, point);  // (going back, nothing is cut: no slack to keep)
      command(step);
    }
  }
  report.unhidden_reversals |= unhidden(target);
}

void Compensator::carried(const ChainQ& by, MoveReport& report) {
  const AxisArray<double> before = play_;
  command(commanded_ + by);
  for (std::size_t i = 0; i < play_.size(); ++i) {
    // (as unhidden() counts a play left short: the switch times the share of it taken up)
    const double shown = 0.5 * model_.reversal_size()[i] * std::abs(play_[i] - before[i]);
    if (!(shown > 0.0)) continue;
    report.max_deviation_after = std::max(report.max_deviation_after, shown);
    if (shown > 0.25 * options_.tolerance) report.jogs_withheld = true;  // worth the warning
  }
}

AxisSet Compensator::unhidden(const AxisArray<double>& target) const {
  // What a play left short of its target costs: the switch of the axis' terms (mm at the
  // tool) times the shortfall. Worth a warning at a quarter of the tolerance.
  AxisSet axes;
  for (std::size_t i = 0; i < target.size(); ++i) {
    if (0.5 * model_.reversal_size()[i] * std::abs(play_[i] - target[i]) > 0.25 * options_.tolerance)
      axes.insert_at(i);
  }
  return axes;
}

double Compensator::keep_still(const ChainQ& at, const AxisArray<double>& play_before, const ChainQ& start,
                               const ChainQ& end, bool feed, std::vector<CompensatedPoint>& points,
                               MoveReport& report) {
  auto kept = [this](Eigen::Index k) { return held(static_cast<std::size_t>(k)); };
  // Still, they approach as their play before the move has them, and turn nowhere.
  for (std::size_t i = 0; i < play_before.size(); ++i)
    if (held(i)) options_.conditions.directions[i] = play_before[i];
  report.unhidden_reversals -= held_axes_;
  ChainQ from_nominal = start, from = at;
  for (CompensatedPoint& point : points) {
    for (Eigen::Index k = 0; k < point.q.size(); ++k)
      if (kept(k)) point.q[k] = at[k];
    if (!feed) continue;
    const ChainQ to_nominal = along(start, end, point.s);
    for (const double t : {0.5, 1.0})
      report.max_deviation_after =
          std::max(report.max_deviation_after, executed_deviation(from_nominal, to_nominal, from, point.q, t));
    from_nominal = to_nominal, from = point.q;
  }
  for (Eigen::Index k = 0; k < commanded_.size(); ++k) {
    if (!kept(k)) continue;
    commanded_[k] = at[k];
    if (static_cast<std::size_t>(k) < play_.size())
      play_[static_cast<std::size_t>(k)] = play_before[static_cast<std::size_t>(k)];
  }
  held_axes_ = {};
  // Where the move leaves the machine: a cut after it starts there, as its plan does not know.
  return points.empty() ? 0.0 : executed_deviation(end, end, points.back().q, points.back().q, 1.0);
}

Eigen::Vector3d Compensator::nominal_tip(const ChainQ& q) {
  for (const auto& [at, tip] : tips_)
    if (at == q) return tip;
  model::forward(model_, check_, q, options_.conditions, false, model::Evaluate::nominal);
  remember_tip(q, check_.nominal);
  return check_.nominal;
}

void Compensator::remember_tip(const ChainQ& q, const Eigen::Vector3d& tip) {
  tips_[next_tip_] = {q, tip};
  next_tip_ = (next_tip_ + 1) % tips_.size();
}

double Compensator::error_at(const ChainQ& nominal) {
  const Eigen::Vector3d tip = nominal_tip(nominal);
  model::forward(model_, check_, nominal, options_.conditions, false, model::Evaluate::actual);
  return (check_.actual - tip).norm();
}

double Compensator::error_at(const ErrorProbe& probe) {
  const AxisArray<double> need = options_.conditions.directions;
  options_.conditions.directions = probe.directions;
  model::forward(model_, check_, probe.nominal, options_.conditions, false, model::Evaluate::actual);
  options_.conditions.directions = need;
  return (check_.actual - probe.tip).norm();
}

double Compensator::error_at(const ErrorProbe& probe, double at_least) {
  if (!std::isnan(last_probe_error_)) {
    const auto tool = static_cast<Eigen::Index>(model::kToolLengthIndex);
    const double tool_length = probe.nominal[tool];
    if (probe_slopes_.tool_length != tool_length) probe_slopes_ = bound_.error_slopes(tool_length);
    double change = last_probe_.nominal[tool] == tool_length ? probe_slopes_.change(last_probe_.nominal, probe.nominal)
                                                             : bound_.error_change(last_probe_.nominal, probe.nominal);
    // An approach changed since (a take-up, an axis reversed): what its terms switch.
    if (probe.directions != last_probe_.directions)
      change += bound_.direction_change(last_probe_.directions, probe.directions, tool_length);
    const double bound = last_probe_error_ + change;
    if (bound <= at_least) {
      last_probe_ = probe;
      last_probe_error_ = bound;
      return bound;
    }
  }
  last_probe_ = probe;
  last_probe_error_ = error_at(probe);
  return last_probe_error_;
}

void Compensator::error_before_at(const ChainQ& nominal, MoveReport& report) {
  if (deferred_probes_)
    deferred_probes_->push_back({nominal, options_.conditions.directions, nominal_tip(nominal)});
  else
    report.max_deviation_before = std::max(report.max_deviation_before, error_at(nominal));
}

bool Compensator::nominal_affine(const ChainQ& a, const ChainQ& b) {
  return a.segment<3>(3) == b.segment<3>(3) && a[model::kToolLengthIndex] == b[model::kToolLengthIndex];
}

double Compensator::executed_deviation(const ChainQ& a_nominal, const ChainQ& b_nominal, const ChainQ& a_comp,
                                       const ChainQ& b_comp, double t) {
  // The machine interpolates the commanded axis values linearly; the program meant the
  // nominal tool tip at the same fraction of the nominal move. With the rotary axes and
  // the tool length still, that tip is affine in the linear axes: between the ends' tips.
  const ChainQ executed = a_comp + t * (b_comp - a_comp);
  Eigen::Vector3d target;
  if (nominal_affine(a_nominal, b_nominal)) {
    const Eigen::Vector3d a_tip = nominal_tip(a_nominal);
    target = a_tip + t * (nominal_tip(b_nominal) - a_tip);
  } else {
    model::forward(model_, check_, a_nominal + t * (b_nominal - a_nominal), options_.conditions, false,
                   model::Evaluate::nominal);
    target = check_.nominal;
  }
  model::forward(model_, check_, executed, options_.conditions, false, model::Evaluate::actual);
  return (check_.actual - target).norm();
}

double Compensator::deviation_across(const ChainQ& a_nominal, const ChainQ& b_nominal, const ChainQ& a_comp,
                                     const ChainQ& b_comp, double t) {
  const ChainQ executed = a_comp + t * (b_comp - a_comp);
  const Eigen::Vector3d a_tip = nominal_tip(a_nominal), b_tip = nominal_tip(b_nominal);
  const Eigen::Vector3d target = a_tip + t * (b_tip - a_tip);
  model::forward(model_, check_, executed, options_.conditions, false, model::Evaluate::actual);
  const Eigen::Vector3d off = check_.actual - target, line = b_tip - a_tip;
  if (line.norm() < 1e-12) return off.norm();  // (a hole of no depth: no line to be across)
  const Eigen::Vector3d along = line.normalized();
  return (off - off.dot(along) * along).norm();
}

void Compensator::split(const ChainQ& a_nominal, const ChainQ& b_nominal, const SolvedPoint& a,
                        const SolvedPoint& b, double s0, double s1, int depth, double tolerance,
                        std::vector<CompensatedPoint>& out, MoveReport& report) {
  const ChainQ &a_comp = a.q, &b_comp = b.q;
  // A piece shorter than the error field's finest feature (the highest harmonic's period
  // / 8, a table's knot spacing / 4) bends like a parabola or, across a table's knot, like
  // a kink: the midpoint sees at least half the worst deviation, so half the tolerance
  // there is enough. Otherwise at the quarters, or densely enough not to step over a short
  // periodic error. A piece the error field cannot bend by a tenth of the tolerance (most of
  // a finishing program's short moves) needs no check at all: its bound is what it reports.
  if (nominal_affine(a_nominal, b_nominal)) {
    const double bound = bound_.chord_deviation(a_comp, b_comp) + std::max(a.residual_bound, b.residual_bound);
    if (bound <= 0.1 * tolerance) {
      report.max_deviation_after = std::max(report.max_deviation_after, bound);
      out.push_back({s1, b_comp});
      return;
    }
  }
  const int n = model_.check_points(a_nominal, b_nominal, 1, 64);
  double worst = executed_deviation(a_nominal, b_nominal, a_comp, b_comp, 0.5);
  if (n > 1 || worst > 0.5 * tolerance) {
    const int dense = std::max(n, 3) | 1;  // odd: the midpoint is one of them, already checked
    for (int k = 1; k <= dense; ++k)
      if (2 * k != dense + 1)
        worst = std::max(
            worst, executed_deviation(a_nominal, b_nominal, a_comp, b_comp, static_cast<double>(k) / (dense + 1)));
  }
  if (worst <= tolerance || depth >= options_.max_depth) {
    report.max_deviation_after = std::max(report.max_deviation_after, worst);
    out.push_back({s1, b_comp});
    return;
  }
  const ChainQ m_nominal = 0.5 * (a_nominal + b_nominal);
  const SolvedPoint m = solve_point(m_nominal, report);
  const double sm = 0.5 * (s0 + s1);
  split(a_nominal, m_nominal, a, m, s0, sm, depth + 1, tolerance, out, report);
  split(m_nominal, b_nominal, m, b, sm, s1, depth + 1, tolerance, out, report);
}

void Compensator::straight(const ChainQ& start, const ChainQ& end, std::vector<CompensatedPoint>& out,
                           MoveReport& report, double tolerance) {
  out.clear();
  if (tolerance <= 0) tolerance = options_.tolerance;
  // Uncompensated, each axis' play is what the nominal travel leaves: the error before is
  // taken with it once the points are solved (their nominal tips serve both).
  const AxisArray<double> uncompensated = play_;
  stretch({start, end, tolerance}, 0.0, 1.0, kMostTurns, out, report);
  error_before(start, end, uncompensated, report);
}

namespace {
/// The larger of two reports' figures of the solution (what point() and split() set).
void take_solution(MoveReport& into, const MoveReport& from) {
  into.max_deviation_after = std::max(into.max_deviation_after, from.max_deviation_after);
  into.max_correction = std::max(into.max_correction, from.max_correction);
  into.max_rotary_correction = std::max(into.max_rotary_correction, from.max_rotary_correction);
  into.max_orientation_error = std::max(into.max_orientation_error, from.max_orientation_error);
  into.held_axes |= from.held_axes;
}
}  // namespace

void Compensator::stretch(const StraightMove& move, double s0, double s1, int turns_left,
                          std::vector<CompensatedPoint>& out, MoveReport& report) {
  const ChainQ from = along(move.start, move.end, s0), to = along(move.start, move.end, s1);
  options_.conditions.directions = play_;
  approach(from, to);
  SolvedPoint start = solve_point(from, report), end = solve_point(to, report);
  if (approach_by_travel(start.q, end.q)) {
    start = solve_point(from, report);
    end = solve_point(to, report);
  }
  ChainQ& a = start.q;
  if (offset_by_control_) {
    // Where the control offsets the path, the move given is the tool centre's as the control
    // settles it between its corners: pieces of it stay within them, so the control offsets
    // each the same way, and no piece is one it refuses. No take-up can be written in it.
    lead_in(from, a, move.tolerance, out, report);
    const std::size_t first = out.size();
    split(from, to, start, end, s0, s1, 0, move.tolerance, out, report);
    // No take-up either where a play runs out along the cut: what it leaves is counted.
    report.max_deviation_after = std::max(report.max_deviation_after, play_stray(move, s0, a, out, first));
    for (std::size_t k = first; k < out.size(); ++k) command(out[k].q);
    return;
  }
  MoveReport solved;
  const std::size_t first = out.size();
  split(from, to, start, end, s0, s1, 0, move.tolerance, out, solved);
  const std::span<const CompensatedPoint> pieces(out.begin() + static_cast<std::ptrdiff_t>(first), out.end());
  if (const std::optional<Turn> turn = correction_turn(s0, a, pieces, turns_left == 0)) {
    if (turns_left > 0) {
      // An axis whose correction turns round inside the move (a bow of straightness along
      // it, B's harmonics) turns there: each side is a move of its own, the second starting
      // with its take-up.
      out.resize(first);
      const double at = extremum(move, *turn, solved);
      stretch(move, s0, at, turns_left - 1, out, report);
      stretch(move, at, s1, turns_left - 1, out, report);
      return;
    }
    // Past the turns a move is cut at, what the play leaves is said.
    report.unhidden_reversals.insert_at(turn->axis);
    solved.max_deviation_after = std::max(solved.max_deviation_after, turn->left);
  }
  take_solution(report, solved);
  // The take-ups go in front of the pieces (at s0: they take no share of the move).
  lead_.clear();
  lead_in(from, a, move.tolerance, lead_, report);
  for (CompensatedPoint& step : lead_) step.s = s0;
  out.insert(out.begin() + static_cast<std::ptrdiff_t>(first), lead_.begin(), lead_.end());
  for (std::size_t k = first + lead_.size(); k < out.size(); ++k) command(out[k].q);
}

AxisSet Compensator::unsettled_axes() const {
  // Settled within 1% of the play: the take-up's travel differs from the lost motion by
  // what the rest of the error field changes with the approach.
  const auto& need = options_.conditions.directions;
  AxisSet axes;
  for (std::size_t i = 0; i < need.size(); ++i)
    if (model_.reads_approach(i) && std::abs(play_[i] - need[i]) > 0.02) axes.insert_at(i);
  return axes;
}

void Compensator::lead_in(const ChainQ& start, ChainQ& a, double tolerance, std::vector<CompensatedPoint>& out,
                          MoveReport& report) {
  if (!commanded_.allFinite()) {  // the first move: the machine is taken to be at its start
    commanded_ = a;
    return;
  }
  const bool unsettled = !unsettled_axes().empty();
  if (unsettled && offset_by_control_) {
    // No take-ups where the control offsets the path: the move starts where the last one
    // left the machine, its play as it is, and what that leaves is in the report.
    a = commanded_;
    report.jogs_withheld = true;
    report.max_deviation_after = std::max(report.max_deviation_after, deviation_at_play(start, a));
  } else if (unsettled) {
    take_up(start, a, out, report);
  } else if (const double off = start_error(start, a); off > 0.25 * tolerance && offset_by_control_) {
    report.jogs_withheld = true;  // the cut starts where the machine was left
    report.max_deviation_after = std::max(report.max_deviation_after, off);
    report.start_error = std::max(report.start_error, off);
  } else if (off > 0.25 * tolerance) {
    // The machine was left off this move's compensated start by a move not compensated (in
    // machine coordinates, a canned cycle's): it goes there first, or the cut would begin
    // with the machine's whole error and taper it out along the move. Where it begins is
    // still off by that error: the report says so.
    out.push_back({0.0, a, true});
    command(a);
    report.max_deviation_after = std::max(report.max_deviation_after, off);
    report.start_error = std::max(report.start_error, off);
  }
}

double Compensator::deviation_at_play(const ChainQ& start, const ChainQ& a) {
  model::Conditions now = options_.conditions;
  now.directions = play_;
  model::forward(model_, check_, a, now, false, model::Evaluate::actual);
  return (check_.actual - nominal_tip(start)).norm();
}

/// One turning axis at a time: it travels what its play needs (the tool holds still against
/// its own backlash) while the settled axes follow the error motions that switch with its
/// play; each step is solved for the play it leaves. A settled axis that would have to
/// follow against its approach (B turning the table to correct a pitch that switched, say)
/// could not: the play would eat it. So it turns round first, follows freely, and turns
/// back: a machinist's re-approach from one side.
void Compensator::take_up(const ChainQ& start, const ChainQ& a, std::vector<CompensatedPoint>& out,
                          MoveReport& report) {
  auto& need = options_.conditions.directions;
  const AxisArray<double> target = need;
  // How far the tool leaves the corner on the way, and whose switch it shows. After a move
  // not planned here the machine starts off the corner anyway: what shows is counted, but
  // not as a reversal's.
  const bool planned = !uncompensated_;
  double stray = 0.0;
  AxisSet strayed;
  auto go = [&](const ChainQ& q, std::size_t turning, double way) {
    if ((q - commanded_).cwiseAbs().maxCoeff() <= 1e-9) return;  // a zero move takes nothing up
    stray = std::max(stray, take_up_stray(start, q, need, strayed));
    CompensatedPoint& step = out.emplace_back(CompensatedPoint{0.0, q, true});
    if (turning < step.turns.size()) {
      step.turns[turning] = static_cast<std::int8_t>(way);
      set_travel_slack(turning, step);
    }
    command(q);
  };
  std::vector<std::size_t> turning, re_approach;
  for (std::size_t i = 0; i < need.size(); ++i) {
    if (!model_.reads_approach(i)) continue;
    const auto k = static_cast<Eigen::Index>(i);
    if (std::abs(play_[i] - target[i]) > 0.02)
      turning.push_back(i), need[i] = play_[i];
    else if ((a[k] - commanded_[k]) * target[i] < -10 * still(i))
      re_approach.push_back(i);
  }
  auto switch_to = [&](std::size_t i, double direction) {
    need[i] = direction;
    go(point(start, report), i, direction);
  };
  for (std::size_t i : re_approach) switch_to(i, -target[i]);
  for (std::size_t i : turning) switch_to(i, target[i]);
  for (std::size_t i : re_approach) switch_to(i, target[i]);
  go(a, need.size(), 0.0);
  if (!strayed.empty()) {
    // The error switched faster than the take-up could follow: part of the turn shows.
    if (planned) report.unhidden_reversals |= strayed;
    report.max_deviation_after = std::max(report.max_deviation_after, stray);
  }
  if (const AxisSet short_of = unhidden(target); !short_of.empty()) {
    report.unhidden_reversals |= short_of;
    // What is left shows where the move starts, the play still short of its target.
    report.max_deviation_after = std::max(report.max_deviation_after, deviation_at_play(start, a));
  }
}

void Compensator::set_travel_slack(std::size_t axis, CompensatedPoint& point) const {
  // Its terms switch at reversal_size() over lost_motion() of travel: a travel off by the
  // slack moves the tool by an eighth of the tolerance, half what a warning takes.
  const double lost = model_.lost_motion()[axis], size = model_.reversal_size()[axis];
  if (lost <= 0.0 || size <= 0.0) return;
  point.slack_stray = 0.125 * options_.tolerance;
  point.travel_slack = point.slack_stray * lost / size;
}

namespace {
/// About how far the axes' travel from fraction t of a step to its end moves the tool (a
/// rotary axis' seen model::kSwitchLever out, as reversal_size() sees an angular switch).
double reach_after(const ChainQ& delta, double t) {
  double reach = 0.0;
  for (std::size_t i = 0; i < model::kToolLengthIndex; ++i)
    reach += std::abs(delta[static_cast<Eigen::Index>(i)]) * (angular_at(i) ? model::kSwitchLever : 1.0);
  return (1.0 - t) * reach;
}
}  // namespace

double Compensator::switch_reach(const AxisArray<double>& from, const AxisArray<double>& to) const {
  double reach = 0.0;
  for (std::size_t i = 0; i < from.size(); ++i)
    if (model_.reads_approach(i)) reach += 0.5 * model_.reversal_size()[i] * std::abs(to[i] - from[i]);
  return reach;
}

double Compensator::take_up_stray(const ChainQ& start, const ChainQ& q, const AxisArray<double>& solved_for,
                                  AxisSet& axes) {
  // Terms linear in the approach switch linearly while an axis travels its play, so the
  // tool's course bends only where a play runs out, where an axis without lost motion
  // switches (as it starts), and at the step's end: the tool is checked there, where what
  // can show there is worth it (half the warning's share of the tolerance).
  const double worth = 0.125 * options_.tolerance;
  struct Bend {
    double t;
    AxisSet axes;  ///< whose switch it shows
  };
  std::array<Bend, 11> bends{};
  std::size_t n = 0;
  AxisSet at_once, switching;
  AxisArray<double> started = play_;  // an instant after the step starts
  const ChainQ delta = q - commanded_;
  for (std::size_t i = 0; i < play_.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    // An unknown approach (the axis' first travel in the program) is no turn.
    if (!model_.reads_approach(i) || std::abs(delta[k]) <= still(i) || play_[i] == 0.0) continue;
    const double travel = delta[k] > 0 ? 1.0 : -1.0, w = model_.lost_motion()[i];
    if (play_[i] == travel) continue;  // settled: its terms do not switch here
    switching.insert_at(i);
    if (w <= 0) {
      at_once.insert_at(i), started[i] = travel;
    } else if (const double t = (travel - play_[i]) * w / (2.0 * delta[k]); reach_after(delta, t) > worth) {
      bends[n++] = {t, AxisSet{*axis_at(i)}};  // where its play runs out, the carriage moving on from there
    }
  }
  if (switching.empty()) return 0.0;
  if (!at_once.empty() && switch_reach(play_, started) > worth) bends[n++] = {0.0, at_once};
  // At the end the tool is at q's solution, unless the play ends off what it was solved for.
  model::Conditions end = options_.conditions;
  end.directions = play_;
  model::take_up_play(model_, end, commanded_, q);
  if (switch_reach(end.directions, solved_for) > worth) bends[n++] = {1.0, switching};
  if (n == 0) return 0.0;
  double stray = 0.0;
  const Eigen::Vector3d corner = nominal_tip(start);
  for (std::size_t b = 0; b < n; ++b) {
    model::Conditions at = options_.conditions;
    at.directions = play_;
    const ChainQ where = commanded_ + bends[b].t * delta;
    model::take_up_play(model_, at, commanded_, where);
    for (std::size_t i = 0; i < play_.size(); ++i)  // switched the instant they start
      if (at_once.contains_at(i)) at.directions[i] = started[i];
    model::forward(model_, check_, where, at, false, model::Evaluate::actual);
    const double d = (check_.actual - corner).norm();
    stray = std::max(stray, d);
    if (d > 0.25 * options_.tolerance) axes |= bends[b].axes;
  }
  return stray;
}

double Compensator::start_error(const ChainQ& start, const ChainQ& a) {
  // Where a compensated move left it, the machine is at this move's start as the
  // compensation reckons it: only a move it did not plan can leave it elsewhere.
  if (!uncompensated_ || (a - commanded_).cwiseAbs().maxCoeff() <= 1e-9) return 0.0;
  model::Conditions now = options_.conditions;
  now.directions = play_;
  model::forward(model_, check_, commanded_, now, false, model::Evaluate::actual);
  return (check_.actual - nominal_tip(start)).norm();
}

void Compensator::error_before(const ChainQ& start, const ChainQ& end, const AxisArray<double>& play,
                               MoveReport& report) {
  const AxisArray<double> need = options_.conditions.directions;
  options_.conditions.directions = play;
  if (start != last_straight_end_) error_before_at(start, report);
  if (model_.check_points(start, end, 1) > 1) error_before_at(0.5 * (start + end), report);
  error_before_at(end, report);
  last_straight_end_ = end;
  options_.conditions.directions = need;
}

}  // namespace ccomp::compensate
