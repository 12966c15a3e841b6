#include "ccomp/compensate/verify.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <functional>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "ccomp/axis.hpp"
#include "ccomp/compensate/machine_coordinates.hpp"
#include "ccomp/compensate/tcp_kinematics.hpp"
#include "ccomp/constants.hpp"
#include "ccomp/error.hpp"
#include "ccomp/model/term_span.hpp"
#include "ccomp/util/handoff.hpp"
#include "ccomp/util/parallel.hpp"
#include "executed_tip.hpp"
#include "nearest_fraction.hpp"
#include "path_search.hpp"
#include "tool_direction.hpp"

namespace ccomp::compensate {

namespace {

/// How closely verify and predict follow a move under TCP with the axes' straight moves,
/// and in how many pieces at most (the job's, at half its tolerance, are fewer by the
/// square root of the ratio: 7 at the default 1 um).
constexpr double kTcpFollowed = 1e-5;  // mm
constexpr std::size_t kMostTcpPieces = 1'000'000;

/// Collects what the interpreter does into a callback per motion (with its offsets); a move
/// under tool centre point control as the moves of the axes that follow it (tcp_pieces()),
/// each after the first said to continue it (it is no move of its own in the figures).
template <typename OnMotion>
class MotionSink : public gcode::CanonSink {
 public:
  MotionSink(OnMotion on, const model::MachineModel& model, std::string_view file)
      : on_(std::move(on)), model_(model), file_(file) {}
  void motion(const gcode::Motion& m) override {
    if (!m.tcp) return on_(m, false);
    try {
      tcp_pieces(kinematics(), m, kTcpFollowed, pieces_, kMostTcpPieces);
    } catch (const Error& e) {
      if (!e.where().file.empty()) throw;
      throw Error(e.kind(), e.message(), SourceLocation{std::string(file_), m.line, 0});
    }
    for (std::size_t k = 0; k < pieces_.size(); ++k) on_(pieces_[k].motion, k > 0);
  }
  /// InterpreterOptions::tcp_switch.
  gcode::Axes tcp_switch(const gcode::Axes& position, const gcode::Offsets& offsets, bool to_tcp) {
    return kinematics().switched(position, offsets, to_tcp);
  }
  /// InterpreterOptions::tcp_direction.
  std::optional<gcode::Axes> tcp_direction(const std::array<double, 3>& direction, const gcode::Axes& position,
                                           const gcode::Offsets& offsets) {
    return kinematics().turned_to(direction, position, offsets);
  }

 private:
  TcpKinematics& kinematics() {
    if (!tcp_) tcp_.emplace(forward_.emplace(model_));
    return *tcp_;
  }

  OnMotion on_;
  const model::MachineModel& model_;
  std::string_view file_;
  std::optional<model::ForwardModel> forward_;
  std::optional<TcpKinematics> tcp_;
  std::vector<TcpPiece> pieces_;
};

/// Each motion of `program` as the interpreter runs it on `model`'s machine (its work
/// offsets under the options'), a move under TCP in the axes' moves that follow it.
template <typename OnMotion>
void each_motion(gcode::LineSource& program, const model::MachineModel& model, const CheckOptions& options,
                 OnMotion on) {
  MotionSink<OnMotion> sink(std::move(on), model, program.name());
  gcode::InterpreterOptions interpreting = with_model_offsets(options.interpreter, model);
  interpreting.tcp = gcode::TcpCodes::follow;
  interpreting.tcp_switch = [&sink](const gcode::Axes& p, const gcode::Offsets& o, bool to_tcp) {
    return sink.tcp_switch(p, o, to_tcp);
  };
  interpreting.tcp_direction = [&sink](const std::array<double, 3>& d, const gcode::Axes& p, const gcode::Offsets& o) {
    return sink.tcp_direction(d, p, o);
  };
  check_work_offsets(interpreting, model);
  gcode::Interpreter interpreter(interpreting);
  interpreter.run(program, sink);
}

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
  /// The tool's direction the nominal chain gives at q. It turns the tool with the rotary
  /// axes alone, so the last one serves until they move.
  const Eigen::Vector3d& nominal_direction(const model::ChainQ& q) {
    if (q.segment<3>(3) != directed_at) {
      nominal(q);
      directed = data.R_nominal * tool_axis, directed_at = q.segment<3>(3);
    }
    return directed;
  }
  Eigen::Vector3d tool_axis = tool_axis_of(model);
  Eigen::Vector3d directed = Eigen::Vector3d::Zero();
  Eigen::Vector3d directed_at = Eigen::Vector3d::Constant(std::nan(""));
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

/// The orientation error's figures as the points come.
struct OrientationFigures {
  double max = 0.0, sum2 = 0.0;
  std::uint64_t points = 0;
  std::uint32_t worst_line = 0;
  void add(double angle, std::uint32_t line) {
    sum2 += angle * angle;
    ++points;
    if (angle > max) max = angle, worst_line = line;
  }
  void into(PathError& e) const {
    e.orientation_max = max;
    e.orientation_rms = points ? std::sqrt(sum2 / static_cast<double>(points)) : 0.0;
    e.orientation_worst_line = worst_line;
  }
};

/// However a motion's callback returns, the command has gone to its end.
struct FollowPlay {
  Evaluator& ev;
  const model::ChainQ& end;
  ~FollowPlay() { ev.advance(end); }
};

/// A piece's axes at its ends and the direction it means while its rotary axes stand.
void orient(Piece& p, const model::ChainQ& q0, const model::ChainQ& q1, Evaluator& ev) {
  p.q0 = q0, p.q1 = q1;
  p.rotary_turns = q0.segment<3>(3) != q1.segment<3>(3);
  p.direction = ev.nominal_direction(q0);
}

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
    orient(p, chain_of(m.start, o), chain_of(m.end, o), ev);
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
        orient(p, a + (b - a) * t0, a + (b - a) * t1, ev);
        out.push_back(p);
      };
  add(0.0, 1.0, ev.nominal(a), ev.nominal(b), 0);
}

/// The nominal path of the original program, piece by piece, made on a thread of its own
/// as the executed path needs it and dropped once the executed path is past it: memory
/// does not grow with the program. Pieces are numbered from the program's start, in
/// groups of kGroup with a box around each, so a search skips the groups far from a point.
class NominalPath {
 public:
  NominalPath(gcode::LineSource& original, const model::ForwardModel& model, const CheckOptions& options)
      : reader_(kQueued,
                [&original, &model, &options](util::Handoff<Piece>& out) { produce(original, model, options, out); }) {}

  [[nodiscard]] PieceWindow& window() { return window_; }

  /// Makes pieces up to `end` (exclusive) available, as far as the program has them; the
  /// number of pieces available from window().first() on.
  std::size_t available(std::size_t end) {
    while (window_.end() < end && !exhausted_) {
      if (!reader_.pop(batch_)) {
        exhausted_ = true;
        break;
      }
      for (Piece& p : batch_) window_.append(std::move(p));
    }
    return std::min(end, window_.end());
  }
  /// Reads the rest of the original: the length of its path from piece `i` on, and the line
  /// of piece `i` (0 if there is none).
  std::pair<double, std::uint32_t> rest_from(std::size_t i) {
    double length = 0;
    std::uint32_t line = 0;
    auto count = [&] {
      for (std::size_t k = std::max(i, window_.first()); k < window_.end(); ++k) {
        const Piece& p = window_[k];
        if (p.cycle) continue;
        if (line == 0) line = p.line;
        length += p.length();
      }
    };
    count();
    while (!exhausted_) {
      window_.restart_at(window_.end());  // no longer searched: only counted
      available(window_.end() + 1);
      count();
    }
    return {length, line};
  }

 private:
  static void produce(gcode::LineSource& original, const model::ForwardModel& model, const CheckOptions& options,
                      util::Handoff<Piece>& out) {
    Evaluator ev{model, model::ForwardData(model), options.conditions};
    std::vector<Piece> batch;
    each_motion(original, model.machine(), options, [&](const gcode::Motion& m, bool /*continues*/) {
      if (m.kind == gcode::MotionKind::feed || m.kind == gcode::MotionKind::arc) nominal_pieces(m, ev, batch);
      if (batch.size() >= kBatch) out.push(batch);
    });
    if (!batch.empty()) out.push(batch);
  }

  static constexpr std::size_t kBatch = 256, kQueued = 16;
  PieceWindow window_;
  bool exhausted_ = false;
  std::vector<Piece> batch_;                ///< the last batch handed over
  util::BackgroundProducer<Piece> reader_;  // last: stopped and joined first, while what it uses exists
};

}  // namespace

namespace {

/// The share of `program` read so far, for the caller's progress report (-1: it takes none).
double progress_of(const CheckOptions& options, const gcode::LineSource& program) {
  if (!options.progress || program.size() == 0) return -1.0;
  return static_cast<double>(program.tell().offset) / static_cast<double>(program.size());
}

/// A motion of the program as its reader hands it over, with the offsets it points to.
struct ReadMotion {
  gcode::Motion motion;
  gcode::Offsets offsets;
  double progress = -1;  ///< the share of the program read (-1: none to report)
  bool continues = false;  ///< a piece after the first of a move under TCP
};

/// The program's motions, read on a thread of their own while the caller evaluates them.
void produce_motions(gcode::LineSource& program, const model::MachineModel& machine, const CheckOptions& options,
                     util::Handoff<ReadMotion>& out) {
  // (Each batch handed over wakes the other thread: 1024 motions against 256 cut predict's
  // time on the 1M-line finishing program by 8%, peak RSS 9 -> 13 MB.)
  constexpr std::size_t kBatch = 1024;
  std::vector<ReadMotion> batch;
  each_motion(program, machine, options, [&](const gcode::Motion& m, bool continues) {
    batch.push_back({m, *m.offsets, progress_of(options, program), continues});
    if (batch.size() >= kBatch) out.push(batch);
  });
  if (!batch.empty()) out.push(batch);
}

}  // namespace

namespace {

/// predict's word on a term used beyond where it was fitted (held there), once a term: the
/// points a move is looked at in, an arc's included.
void warn_beyond_spans(const MotionPath& path, int steps, const model::Conditions& conditions, std::uint32_t line,
                       model::SpanWatch& spans, const CheckOptions& options) {
  model::ChainQ low = path.start().cwiseMin(path.end()), high = path.start().cwiseMax(path.end());
  for (int k = 1; k < steps; ++k) {
    const model::ChainQ q = path.at(static_cast<double>(k) / steps);
    low = low.cwiseMin(q), high = high.cwiseMax(q);
  }
  for (const std::string& message : spans.beyond(low, high, conditions)) options.warning(message, line);
}

}  // namespace

PathError predict(gcode::LineSource& program, const model::ForwardModel& model, const CheckOptions& options) {
  PathError e;
  const Eigen::Vector3d tool_axis = tool_axis_of(model);
  OrientationFigures orientation;
  Evaluator ev{model, model::ForwardData(model), options.conditions};
  ExecutedTip tip(model, options.conditions);
  model::SpanWatch spans(model.machine());
  double sum2 = 0.0;
  util::BackgroundProducer<ReadMotion> reader(
      4, [&program, &model, &options](util::Handoff<ReadMotion>& out) { produce_motions(program, model.machine(), options, out); });
  std::vector<ReadMotion> motions;
  while (reader.pop(motions)) {
    for (ReadMotion& read : motions) {
      if (read.progress >= 0) options.progress(read.progress);
      gcode::Motion& m = read.motion;
      m.offsets = &read.offsets;
      const MotionPath path(m);
      ev.advance(path.start());
      const FollowPlay follow{ev, path.end()};
      if (m.kind == gcode::MotionKind::traverse || m.kind == gcode::MotionKind::probe) continue;
      if (!read.continues) ++e.moves;
      const int steps = path.steps(model, options.samples);
      if (!spans.empty() && options.warning) warn_beyond_spans(path, steps, ev.conditions, m.line, spans, options);
      if (m.kind == gcode::MotionKind::feed)
        tip.start_move(path.start(), path.end(), ev.conditions, true);
      else
        tip.other_move();
      for (int k = 0; k <= steps; ++k) {
        const double t = static_cast<double>(k) / steps;
        Eigen::Vector3d actual, nominal, direction, meant;
        if (options.pose) options.pose(path.at(t), ev.conditions, m.line);
        if (tip.on_chord()) {  // within a nanometre (executed_tip.hpp)
          actual = tip.on_chord(t), nominal = tip.nominal_on_chord(t);
          direction = tip.direction_on_chord(t), meant = tip.nominal_direction();
        } else {
          const model::ChainQ q = path.at(t);
          model::forward(model, ev.data, q, ev.advance(q));
          actual = ev.data.actual, nominal = ev.data.nominal;
          direction = ev.data.R_actual * tool_axis, meant = ev.data.R_nominal * tool_axis;
        }
        const double d = (actual - nominal).norm();
        sum2 += d * d;
        ++e.points;
        if (d > e.max) e.max = d, e.worst_line = m.line, e.worst_point = nominal;
        orientation.add(angle_between(direction, meant), m.line);
      }
    }
  }
  e.rms = e.points ? std::sqrt(sum2 / static_cast<double>(e.points)) : 0.0;
  orientation.into(e);
  if (options.progress) options.progress(1.0);
  return e;
}

namespace {

/// The tool's direction the original means at the point of a piece an executed point was
/// found at. Along a piece whose rotary axes stand still it is the piece's own. Along one
/// where they turn, the original's axes run straight from the piece's q0 to q1 (an arc's
/// rotary axes with its angle): the direction is the nominal chain's at the fraction whose
/// nominal tip is nearest the point, found by Gauss-Newton from the point's place on the
/// chord until the direction there is settled (nearest_fraction.hpp).
/// Where the piece's tip stands still while the tool turns about it, or moves less over the
/// whole piece than the point is off its path, the tip says nothing of where along the turn
/// the point is: the fraction whose direction is nearest the executed one is taken, as the
/// tip's distance is to the nearest point of the path.
class MeantDirection {
 public:
  explicit MeantDirection(const model::ForwardModel& model)
      : model_(model), data_(model), tool_axis_(tool_axis_of(model)) {}

  Eigen::Vector3d at(const Piece& piece, const Eigen::Vector3d& p, const Eigen::Vector3d& executed) {
    if (!piece.rotary_turns) return piece.direction;
    if (piece.arc) return direction(piece, piece.fraction_at(p));
    NearestFractionOptions o;
    o.turn = rotary_turn(piece);
    o.only_within_reach = true;
    if (const auto s = nearest_fraction(piece.fraction_at(p), p, [&](double f) { return tip(piece, f); }, o))
      return direction(piece, s->fraction);
    o.only_within_reach = false;  // (the direction's own move decides)
    const auto turned = nearest_fraction(0.5, executed, [&](double f) { return direction(piece, f); }, o);
    return direction(piece, turned ? turned->fraction : 0.0);  // (neither moves: the direction is the same all along)
  }

 private:
  [[nodiscard]] static model::ChainQ q_at(const Piece& piece, double f) { return piece.q0 + (piece.q1 - piece.q0) * f; }
  /// rad: the most the nominal tool direction turns along the piece, its rotary axes' turns
  /// summed.
  [[nodiscard]] static double rotary_turn(const Piece& piece) {
    double turn = 0.0;
    for (std::size_t i = 0; i < kAxisCount; ++i)
      if (angular_at(i)) turn += std::abs(piece.q1[static_cast<Eigen::Index>(i)] - piece.q0[static_cast<Eigen::Index>(i)]);
    return turn;
  }
  Eigen::Vector3d tip(const Piece& piece, double f) {
    model::forward(model_, data_, q_at(piece, f), conditions_, false, model::Evaluate::nominal);
    return data_.nominal;
  }
  Eigen::Vector3d direction(const Piece& piece, double f) {
    model::forward(model_, data_, q_at(piece, f), conditions_, false, model::Evaluate::nominal);
    return data_.R_nominal * tool_axis_;
  }

  const model::ForwardModel& model_;
  model::ForwardData data_;
  model::Conditions conditions_;  ///< the nominal chain reads none
  Eigen::Vector3d tool_axis_;
};

/// What the compensated program makes the machine do, as verify measures it, in order: a
/// rapid (the search is told), the start of a cut, and the tool tip at each point checked.
struct ExecutedEvent {
  /// A chord: a cut's points on the chord from `tip` to `end`, steps + 1 of them, made by
  /// the caller (ExecutedTip::between: the same points, handed over as one event).
  enum class Kind : std::uint8_t { rapid, cut, tip, chord };
  Kind kind = Kind::tip;
  std::uint32_t line = 0;  ///< a cut's block
  double progress = -1;    ///< a rapid's or a cut's share of the program read (-1: none to report)
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();
  Eigen::Vector3d end = Eigen::Vector3d::Zero();  ///< a chord's
  int steps = 0;                                  ///< a chord's
  /// The tool's actual direction at the tip (a chord's at its start), and at a chord's end.
  Eigen::Vector3d direction = Eigen::Vector3d::Zero(), end_direction = Eigen::Vector3d::Zero();
};

/// The tool tip at each point a cut is checked at, finer than the job checks.
void executed_tips(const gcode::Motion& m, const MotionPath& path, const model::ForwardModel& model,
                   const CheckOptions& options, Evaluator& ev, ExecutedTip& tip, std::vector<ExecutedEvent>& out) {
  const int steps = path.steps(model, options.samples);
  if (m.kind == gcode::MotionKind::feed && tip.start_move(path.start(), path.end(), ev.conditions)) {
    // the play stands still: ev's conditions stay as they are
    ExecutedEvent& e = out.emplace_back();
    e.kind = ExecutedEvent::Kind::chord, e.tip = tip.chord_start(), e.end = tip.chord_end(), e.steps = steps;
    e.direction = tip.chord_start_direction(), e.end_direction = tip.chord_end_direction();
    return;
  }
  for (int k = 0; k <= steps; ++k) {
    const model::ChainQ q = path.at(static_cast<double>(k) / steps);
    model::forward(model, ev.data, q, ev.advance(q), false, model::Evaluate::actual);
    ExecutedEvent& e = out.emplace_back();
    e.tip = ev.data.actual, e.direction = ev.data.R_actual * ev.tool_axis;
  }
}

/// The executed path of the compensated program as events, made on a thread of its own
/// while the caller measures it against the nominal path (the points are the same whichever
/// thread makes them: only the work is shared).
void produce_executed(gcode::LineSource& compensated, const model::ForwardModel& model, const CheckOptions& options,
                      util::Handoff<ExecutedEvent>& out) {
  constexpr std::size_t kBatch = 4096;
  Evaluator ev{model, model::ForwardData(model), options.conditions};
  ExecutedTip tip(model, options.conditions);
  std::vector<ExecutedEvent> batch;
  each_motion(compensated, model.machine(), options, [&](const gcode::Motion& m, bool continues) {
    const double progress = progress_of(options, compensated);
    const MotionPath path(m);
    ev.advance(path.start());
    const FollowPlay follow{ev, path.end()};
    const bool cut = m.kind == gcode::MotionKind::feed || m.kind == gcode::MotionKind::arc;
    if (!continues) batch.push_back({cut ? ExecutedEvent::Kind::cut : ExecutedEvent::Kind::rapid, m.line, progress});
    if (cut) executed_tips(m, path, model, options, ev, tip, batch);
    if (batch.size() >= kBatch) out.push(batch);
  });
  if (!batch.empty()) out.push(batch);
}

}  // namespace

PathError verify(gcode::LineSource& original, gcode::LineSource& compensated, const model::ForwardModel& model,
                 const CheckOptions& options) {
  NominalPath nominal(original, model, options);
  PathSearch<NominalPath> search(nominal);
  util::BackgroundProducer<ExecutedEvent> executed(
      8, [&compensated, &model, &options](util::Handoff<ExecutedEvent>& out) {  // 8 batches waiting at most
        produce_executed(compensated, model, options, out);
      });
  PathError e;
  double sum2 = 0.0;
  std::uint32_t line = 0;
  MeantDirection meant(model);
  OrientationFigures orientation;
  auto measure = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& direction) {
    const std::optional<double> off = search.distance(p);
    if (!off) return;
    sum2 += *off * *off;
    ++e.points;
    if (*off > e.max) e.max = *off, e.worst_line = line, e.worst_point = p;
    orientation.add(angle_between(direction, meant.at(search.at_piece(), p, direction)), line);
  };
  std::vector<ExecutedEvent> events;
  while (executed.pop(events)) {
    for (const ExecutedEvent& x : events) {
      switch (x.kind) {
        case ExecutedEvent::Kind::rapid:
        case ExecutedEvent::Kind::cut:
          if (x.progress >= 0) options.progress(x.progress);
          if (x.kind == ExecutedEvent::Kind::rapid) search.rapid();
          if (x.kind == ExecutedEvent::Kind::cut) ++e.moves, line = x.line;
          break;
        case ExecutedEvent::Kind::tip:
          measure(x.tip, x.direction);
          break;
        case ExecutedEvent::Kind::chord:
          for (int k = 0; k <= x.steps; ++k) {
            const double t = static_cast<double>(k) / x.steps;
            measure(ExecutedTip::between(x.tip, x.end, t), direction_between(x.direction, x.end_direction, t));
          }
          break;
      }
    }
  }
  e.rms = e.points ? std::sqrt(sum2 / static_cast<double>(e.points)) : 0.0;
  orientation.into(e);
  std::tie(e.uncut_length, e.uncut_line) = search.uncut();
  if (options.progress) options.progress(1.0);
  return e;
}

}  // namespace ccomp::compensate
