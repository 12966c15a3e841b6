#pragma once
// Compensation of one straight move: the commanded axis values at its end, and the points
// it must be split at so that the path the machine executes (straight in axis space between
// compensated points) stays within the tolerance of the nominal path. Adaptive: a move is
// split only where the error field bends it away, at the midpoint of the piece that fails.
//
// Reversal (any term whose variable is an axis' approach): the compensator follows the
// play of every axis through what it commands (the same take_up_play the machine model
// applies). When a move needs an axis to travel the other way, it first commands a take-up
// move: at the move's start, from the correction for the old approach to the correction
// for the new one. With backlash (the axis lags its command) the tool does not move while
// the play is taken up, and the move then starts with the error of the new direction
// already corrected.
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <cmath>
#include <vector>

#include "ccomp/axis.hpp"
#include "ccomp/compensate/inverse.hpp"
#include "ccomp/model/forward.hpp"
#include "ccomp/model/variation_bound.hpp"

namespace ccomp::compensate {

/// The share of the tolerance a point's residual may reach where the error field's bound
/// accepts it without evaluating the model (InverseOptions::bounded_tolerance): below a
/// tenth, so that such a point lies within a tenth of the tolerance of the exact solution.
inline constexpr double kBoundedShare = 0.08;

struct CompensationOptions {
  double tolerance = 0.001;  ///< mm: largest distance of the executed path from the nominal one
  int max_depth = 12;        ///< a move is split into at most 2^12 pieces
  /// Every point solved on the model; else a point along a path may be accepted where the
  /// error field's bound proves it within kBoundedShare of the tolerance (InverseOptions::bound).
  bool exact = false;
  model::Conditions conditions;
  /// Per axis, whether the solve may turn it (model::AxisHold; only rotary axes are held).
  /// `free` everywhere unless given: the job sets the model's.
  AxisArray<model::AxisHold> hold = [] {
    AxisArray<model::AxisHold> all{};
    all.fill(model::AxisHold::free);
    return all;
  }();
};

/// A point of a compensated move: the fraction s of the nominal move it ends, and the
/// commanded chain values there.
struct CompensatedPoint {
  double s = 1.0;
  model::ChainQ q;
  bool take_up = false;  ///< a take-up move at a reversal (takes no share of the move)
  /// A take-up's: per axis, the way the axis turns to in it (+1, -1; 0: it does not turn).
  /// The machine must travel at least what was planned, rounded as written, or the play is
  /// left part-taken and the error terms of its approach with it.
  std::array<std::int8_t, 9> turns{};
  /// A take-up's, for the axis that turns in it: how far (mm, rad) its travel may miss the
  /// plan before its terms, switching over the play as it travels, move the tool by
  /// `slack_stray` (mm) from the corner; infinite where they switch at once.
  double travel_slack = std::numeric_limits<double>::infinity();
  double slack_stray = 0.0;
};

/// A point where the uncompensated machine's error is to be taken, with the approach it
/// would have there (see Compensator::defer_error_before).
struct ErrorProbe {
  model::ChainQ nominal;
  AxisArray<double> directions{};
  Eigen::Vector3d tip;  ///< the nominal tool tip there (the compensation knows it already)
};

struct MoveReport {
  double max_deviation_before = 0.0;   ///< mm: the uncompensated path's largest error
  double max_deviation_after = 0.0;    ///< mm: the compensated path's, at the checked points
  double max_correction = 0.0;         ///< mm: largest change of a linear axis
  double max_rotary_correction = 0.0;  ///< rad: largest change of a rotary axis
  double max_orientation_error = 0.0;  ///< rad: what the machine cannot correct
  /// The axes whose reversal could not be taken up (it leads the command, the axis has no
  /// lost motion of its own and its terms switch at once, or they act along it: the tool
  /// strays from the corner during the take-up).
  AxisSet unhidden_reversals;
  /// mm: how far the tool was from the move's start where a move the compensator did not
  /// plan (machine coordinates, a canned cycle) left it; 0 after a planned one.
  double start_error = 0.0;
  /// The control offsets the path (G41/G42): a take-up, re-approach or lead-to-start move
  /// the move needed was not written.
  bool jogs_withheld = false;
  /// The control offsets this move as one piece (G41/G42: the entry move, or an arc of
  /// several turns): it was not split, whatever the error field needs along it.
  bool kept_whole = false;
  /// The rotary axes held at the program's value in a solve (CompensationOptions::hold):
  /// their share of the error is left (orientation error).
  AxisSet held_axes;
};

class Compensator {
 public:
  Compensator(const model::ForwardModel& model, CompensationOptions options);

  /// The compensated points of the straight move from `start` to `end` (nominal chain
  /// values), in order; the last one is the move's end. Throws ccomp::Error when the
  /// inverse does not converge.
  void straight(const model::ChainQ& start, const model::ChainQ& end, std::vector<CompensatedPoint>& out,
                MoveReport& report, double tolerance = -1.0);
  /// The compensated end of a rapid to `end` (the control chooses a rapid's path), then
  /// any re-approach an axis needs to leave the rapid with its play settled.
  void rapid(const model::ChainQ& end, std::vector<CompensatedPoint>& out, MoveReport& report);
  /// The compensated end of a move from `start` to `end` (nominal) whose path between the
  /// control makes (an arc kept as an arc): approached as the move travels, no jogs.
  [[nodiscard]] model::ChainQ path_end(const model::ChainQ& start, const model::ChainQ& end, MoveReport& report);
  /// Whether the control offsets the path by the tool's radius (G41/G42) from now on: then
  /// no take-up, re-approach or lead-to-start moves are written (a jog that turns back is
  /// an inside corner the control refuses). The moves given are the tool centre's.
  void offset_by_control(bool on) { offset_by_control_ = on; }
  /// Whether a point may be accepted on the error field's bound (InverseOptions::bound)
  /// rather than solved on the model (as --exact solves them all).
  enum class Shortcut : std::uint8_t { allowed, none };
  /// The compensated values for one point, for the approach the compensator assumes now.
  [[nodiscard]] model::ChainQ point(const model::ChainQ& nominal, MoveReport& report,
                                    Shortcut shortcut = Shortcut::allowed);
  /// A solved point and how far its actual tip can be from the nominal one (mm).
  struct SolvedPoint {
    model::ChainQ q;
    double residual_bound = 0.0;
  };
  /// point() with its residual bound.
  [[nodiscard]] SolvedPoint solve_point(const model::ChainQ& nominal, MoveReport& report,
                                        Shortcut shortcut = Shortcut::allowed);
  /// The nominal pose at `nominal`, known to the caller: the next solve for that point uses
  /// it instead of evaluating it (the same numbers: the caller evaluated it as forward() does).
  void expect(const model::ChainQ& nominal, const NominalPose& pose) {
    expected_ = nominal;
    expected_pose_ = pose;
  }
  /// Tells the compensator the machine was commanded to `q` by something it did not plan (a
  /// move in machine coordinates, a canned cycle's motions, the program's start).
  void moved(const model::ChainQ& q);
  /// Tells the compensator the control moved the axes by `by` (chain values) on a path of
  /// its own with the correction kept: round the corner of a radius-offset path (G41/G42).
  /// An axis that takes up play on the way (it turns round on the corner's arc) does so
  /// where no take-up can be written: what its terms switch meanwhile goes into the report.
  void carried(const model::ChainQ& by, MoveReport& report);
  /// The error of the uncompensated machine at a point: |actual - nominal| (mm).
  [[nodiscard]] double error_at(const model::ChainQ& nominal);
  /// The same for a probe, under its own approach.
  [[nodiscard]] double error_at(const ErrorProbe& probe);
  /// The same where it may exceed `at_least` (mm). Where the error at the probe before it
  /// and the bound of the error's change between them (the point's, and the approach's
  /// where it changed) show it cannot, that bound (<= at_least) without evaluating the
  /// model: a report's maximum over a program stays exactly what evaluating every probe gives.
  [[nodiscard]] double error_at(const ErrorProbe& probe, double at_least);
  /// From now on, the points where a move's error before is taken are appended to `probes`
  /// instead of evaluated (the report's max_deviation_before is then left to the caller,
  /// who may evaluate them elsewhere: they change nothing the compensation decides);
  /// nullptr evaluates them again.
  void defer_error_before(std::vector<ErrorProbe>* probes) { deferred_probes_ = probes; }
  /// A move's error before at `nominal` under the approach assumed now: evaluated into
  /// the report, or deferred.
  void error_before_at(const model::ChainQ& nominal, MoveReport& report);

  /// How far the machine, commanded along the straight line a_comp -> b_comp, is at fraction
  /// t from the straight nominal line a_nominal -> b_nominal (the rotary axes and the tool
  /// length still), across it: a drilled hole's straightness and place, not its depth (mm).
  [[nodiscard]] double deviation_across(const model::ChainQ& a_nominal, const model::ChainQ& b_nominal,
                                        const model::ChainQ& a_comp, const model::ChainQ& b_comp, double t);
  [[nodiscard]] const model::ForwardModel& model() const { return model_; }
  /// The rotary axes the solve keeps at the program's values now.
  [[nodiscard]] AxisSet held_rotary() const { return held_rotary_; }

  model::Conditions& conditions() { return options_.conditions; }
  /// Where the machine was sent last (chain values; NaN before the first command).
  [[nodiscard]] const model::ChainQ& commanded() const { return commanded_; }
  /// Sets the approach the next points are solved for: each axis whose approach a term reads
  /// travels the way `end - start` goes (or keeps its state when it does not move).
  void approach(const model::ChainQ& start, const model::ChainQ& end);
  /// Sets each such axis' approach from its compensated travel `from` -> `to` where it
  /// moves at all; true when that changed an approach (the points must be solved again).
  /// Within an axis' play the tool does not follow a small travel against its approach: a
  /// correction that asks for one is only reached by travelling through the play.
  bool approach_by_travel(const model::ChainQ& from, const model::ChainQ& to);
  /// The approach state of each axis after what was commanded so far.
  [[nodiscard]] const AxisArray<double>& play() const { return play_; }
  /// The control keeps `axes` still through the next move (see MoveSolver: a move under its
  /// radius offset with no travel in the plane): their approach stays as their play has it
  /// while the move is solved, whatever the correction's travel. keep_still() then holds their values and ends the hold.
  void hold(AxisSet axes) { held_axes_ = axes; }
  /// The axes hold() named stay still through the straight move from `start` to `end`
  /// (nominal) whose points were just solved into `points`: they
  /// keep those values at `at`, where the machine was before the move, and so do the last
  /// command and those axes' play (`play_before`, theirs before the move); no reversal of
  /// theirs is reported. Where the move cuts (`feed`), the error that leaves at each point and
  /// half-way to it goes into the report's figure after. Returns the error where the move
  /// leaves the machine (mm): the start of a cut after it (the caller's to count there).
  double keep_still(const model::ChainQ& at, const AxisArray<double>& play_before, const model::ChainQ& start,
                    const model::ChainQ& end, bool feed, std::vector<CompensatedPoint>& points, MoveReport& report);

 private:
  /// A straight move as straight() was given it.
  struct StraightMove {
    const model::ChainQ& start;
    const model::ChainQ& end;
    double tolerance;
  };
  /// Turns of corrections one move is cut at, at most.
  static constexpr int kMostTurns = 8;
  /// The part of `move` from fraction s0 to s1 into `out`, its take-ups first, cut where an
  /// axis' correction turns round (at most `turns_left` more times).
  void stretch(const StraightMove& move, double s0, double s1, int turns_left, std::vector<CompensatedPoint>& out,
               MoveReport& report);
  /// An axis' correction turning round inside a stretch: the axis, the way it went first,
  /// the fractions of the move the turn lies between, and what ignoring it leaves (mm).
  struct Turn {
    std::size_t axis = 0;
    double way = 0.0, from = 0.0, to = 0.0, left = 0.0;
  };
  /// How far the tool strays from the path along pieces out[first..] of `move` (from
  /// commanded `a` at s0) while the plays the control's offset kept take-ups from taking up
  /// run out (mm): checked where each runs out and at the pieces' ends, until all have.
  [[nodiscard]] double play_stray(const StraightMove& move, double s0, const model::ChainQ& a,
                                  const std::vector<CompensatedPoint>& out, std::size_t first);
  /// The first turn, in the pieces just split (from compensated `a` at s0), that leaves
  /// more than an eighth of the tolerance (`whole`: the one that leaves most, all of its
  /// travel back counted); nothing where none does.
  [[nodiscard]] std::optional<Turn> correction_turn(double s0, const model::ChainQ& a,
                                                    std::span<const CompensatedPoint> pieces, bool whole) const;
  /// What an axis travelling `back` (mm, rad) against its approach leaves at the tool (mm).
  [[nodiscard]] double turn_left(std::size_t axis, double back) const;
  /// The fraction of the move where the turn's axis' correction is furthest its first way.
  [[nodiscard]] double extremum(const StraightMove& move, const Turn& turn, MoveReport& report);
  void split(const model::ChainQ& a_nominal, const model::ChainQ& b_nominal, const SolvedPoint& a,
             const SolvedPoint& b, double s0, double s1, int depth, double tolerance,
             std::vector<CompensatedPoint>& out, MoveReport& report);
  /// How the move from nominal `start` (compensated `a`) begins from where the machine is:
  /// take-ups (or, under the control's offset, none: `a` becomes where the machine is), a
  /// lead to the start after a move not planned here, or nothing.
  void lead_in(const model::ChainQ& start, model::ChainQ& a, double tolerance, std::vector<CompensatedPoint>& out,
               MoveReport& report);
  void take_up(const model::ChainQ& start, const model::ChainQ& a, std::vector<CompensatedPoint>& out,
               MoveReport& report);
  /// Axes with reversal terms whose play differs from the approach the move needs.
  [[nodiscard]] AxisSet unsettled_axes() const;
  /// How far the tool at commanded `a`, under the play as it is, is from nominal `start`.
  [[nodiscard]] double deviation_at_play(const model::ChainQ& start, const model::ChainQ& a);
  /// Axes whose play is short of `target` by more than the tolerance can bear.
  [[nodiscard]] AxisSet unhidden(const AxisArray<double>& target) const;
  /// The travel slack of a take-up step in which `axis` turns (CompensatedPoint).
  void set_travel_slack(std::size_t axis, CompensatedPoint& point) const;
  /// How far the tool leaves the corner (nominal `start`) while a take-up travels from where
  /// the machine is to `q`: nothing while each turning axis stays in its play and the axes
  /// follow the terms switching with it; where an axis' carriage moves on after its play
  /// (terms that switch with it act along it), where an axis without lost motion switches
  /// its terms the instant it starts back, or where the step ends off the play its point
  /// was solved for, the switch shows. `axes` gets the axes whose switch shows by more than
  /// a quarter of the tolerance. `solved_for`: the approach q was solved for.
  [[nodiscard]] double take_up_stray(const model::ChainQ& start, const model::ChainQ& q,
                                     const AxisArray<double>& solved_for, AxisSet& axes);
  /// About how far the tool moves as the approaches go from `from` to `to`: each axis'
  /// switch (reversal_size()) times the share of it.
  [[nodiscard]] double switch_reach(const AxisArray<double>& from, const AxisArray<double>& to) const;
  /// How far the tool, where a move the compensator did not plan left the machine, is from
  /// the start of a move (nominal `start`, compensated `a`); 0 after a planned one.
  [[nodiscard]] double start_error(const model::ChainQ& start, const model::ChainQ& a);
  /// Commands `q`: the play follows.
  void command(const model::ChainQ& q);
  /// The nominal tool tip at q: from the points solved last, else evaluated.
  Eigen::Vector3d nominal_tip(const model::ChainQ& q);
  void remember_tip(const model::ChainQ& q, const Eigen::Vector3d& tip);
  /// Where a move's error before is taken: its end, its start when the last move did not
  /// end there, and its middle where the error field has features shorter than the move.
  void error_before(const model::ChainQ& start, const model::ChainQ& end, const AxisArray<double>& play,
                    MoveReport& report);
  /// Whether the nominal path from a to b is straight in the workpiece frame as the linear
  /// axes are (the rotary axes and the tool length stand still).
  [[nodiscard]] static bool nominal_affine(const model::ChainQ& a, const model::ChainQ& b);
  double executed_deviation(const model::ChainQ& a_nominal, const model::ChainQ& b_nominal, const model::ChainQ& a_comp,
                            const model::ChainQ& b_comp, double t);

  const model::ForwardModel& model_;
  CompensationOptions options_;
  model::ChainQ commanded_ = model::ChainQ::Constant(std::nan(""));  ///< where the machine was sent last
  AxisArray<double> play_{};                                     ///< approach state after the commands so far
  bool uncompensated_ = false;      ///< the last command was one moved() reported, not one planned here
  bool offset_by_control_ = false;  ///< see offset_by_control()
  AxisSet held_axes_;               ///< see hold()
  [[nodiscard]] bool held(std::size_t i) const { return held_axes_.contains_at(i); }
  model::ChainQ last_straight_end_ = model::ChainQ::Constant(std::nan(""));  ///< its error before is counted
  // The nominal tips of the last points solved (a move's ends and midpoints), round robin.
  /// The last nominal tips taken, by chain values; NaN keys match nothing (Eigen leaves a
  /// fixed-size vector uninitialised: zeroed memory would "match" the chain's zero).
  std::array<std::pair<model::ChainQ, Eigen::Vector3d>, 4> tips_ = {
      std::pair{model::ChainQ::Constant(std::nan("")), Eigen::Vector3d::Zero()},
      std::pair{model::ChainQ::Constant(std::nan("")), Eigen::Vector3d::Zero()},
      std::pair{model::ChainQ::Constant(std::nan("")), Eigen::Vector3d::Zero()},
      std::pair{model::ChainQ::Constant(std::nan("")), Eigen::Vector3d::Zero()}};
  std::size_t next_tip_ = 0;
  std::vector<ErrorProbe>* deferred_probes_ = nullptr;
  model::ChainQ expected_ = model::ChainQ::Constant(std::nan(""));  ///< see expect()
  NominalPose expected_pose_;
  /// The rotary axes held now (CompensationOptions::hold), the `automatic` ones the program
  /// has turned (free from then on), and where the program had them first.
  AxisSet rotary_axes_, held_rotary_, turned_;
  model::ChainQ first_nominal_ = model::ChainQ::Constant(std::nan(""));
  /// Holds before solving at `nominal`: an `automatic` axis the program turns there is free
  /// from then on; where the held axes change, the solve's problem does.
  void follow_holds(const model::ChainQ& nominal);
  [[nodiscard]] AxisSet rotary_axes_to_hold() const;
  InverseProblem problem_;
  InverseWorkspace workspace_;  ///< the last point solved, its solution and the solve matrix
  model::ForwardData data_, check_;
  std::vector<CompensatedPoint> lead_;  ///< a stretch's take-ups, before they go in front of its pieces
  model::VariationBound bound_;  ///< for options_.conditions
  /// The probe error_at(probe, at_least) took last, and the bound of its error.
  ErrorProbe last_probe_;
  double last_probe_error_ = std::nan("");
  model::VariationBound::ErrorSlopes probe_slopes_;  ///< bound_'s, for the probes' tool length
};

}  // namespace ccomp::compensate
