#include "ccomp/compensate/verify.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <functional>
#include <optional>

namespace ccomp::compensate {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// A piece of the nominal path in the table frame: a straight segment, or an arc/helix (the
/// nominal map is rigid while the rotary axes hold still, so an arc stays an arc).
struct Piece {
  bool arc = false;
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();  // ends (an arc's too)
  Eigen::Vector3d centre = Eigen::Vector3d::Zero(), e1 = Eigen::Vector3d::Zero(), e2 = Eigen::Vector3d::Zero(),
                  n = Eigen::Vector3d::Zero();       // arc frame (unit in-plane axes and normal)
  double r0 = 0, r1 = 0, a0 = 0, sweep = 0, dw = 0;  // radius from r0 to r1, rise dw along n
  bool ccw = true;

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
    phi -= 2 * kPi * std::floor(phi / (2 * kPi));  // [0, 2 pi)
    // A helix of several turns passes p's angle once a turn: the turn at p's height, and its
    // neighbours, are the candidates.
    const double turns = std::floor((sweep - phi) / (2 * kPi));
    double k0 = 0;
    if (turns >= 1 && dw != 0) k0 = std::clamp(std::round((h / dw * sweep - phi) / (2 * kPi)), 0.0, turns);
    for (double k = std::max(0.0, k0 - 1); k <= std::min(turns, k0 + 1); ++k) {
      const double f = (phi + 2 * kPi * k) / sweep;
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

constexpr double kRadPerDeg = kPi / 180.0;

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
    model::forward(model, data, q, conditions);
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
    const auto per_turn = static_cast<int>(std::ceil(arc_->sweep / (2 * kPi) * 16));
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
void nominal_pieces(const gcode::Motion& m, Evaluator& ev, std::deque<Piece>& out) {
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
        out.push_back(p);
      };
  add(0.0, 1.0, ev.nominal(a), ev.nominal(b), 0);
}

}  // namespace

model::ChainQ chain_of(const gcode::Axes& controlled, const gcode::Offsets& o) {
  model::ChainQ q = model::ChainQ::Zero();
  for (std::size_t i = 0; i < gcode::kAxisCount; ++i) {
    const double axis = controlled[i] + o.tool[i];  // the machine axis carries the tool
    q[static_cast<Eigen::Index>(i)] = gcode::is_rotary(i) ? axis * kRadPerDeg : axis;
  }
  q[static_cast<Eigen::Index>(model::kToolLengthIndex)] = o.tool[2];
  return q;
}

PathError predict(gcode::LineSource& program, const model::ForwardModel& model, const CheckOptions& options) {
  PathError e;
  Evaluator ev{model, model::ForwardData(model), options.conditions};
  double sum2 = 0.0;
  each_motion(program, options, [&](const gcode::Motion& m) {
    const MotionPath path(m);
    ev.advance(path.start());
    const FollowPlay follow{ev, path.end()};
    if (m.kind == gcode::MotionKind::traverse || m.kind == gcode::MotionKind::probe) return;
    ++e.moves;
    const int steps = path.steps(model, options.samples);
    for (int k = 0; k <= steps; ++k) {
      const model::ChainQ q = path.at(static_cast<double>(k) / steps);
      model::forward(model, ev.data, q, ev.advance(q));
      const double d = (ev.data.actual - ev.data.nominal).norm();
      sum2 += d * d;
      ++e.points;
      if (d > e.max) e.max = d, e.worst_line = m.line, e.worst_point = ev.data.nominal;
    }
  });
  e.rms = e.points ? std::sqrt(sum2 / static_cast<double>(e.points)) : 0.0;
  return e;
}

PathError verify(gcode::LineSource& original, gcode::LineSource& compensated, const model::ForwardModel& model,
                 const CheckOptions& options) {
  // The nominal path, piece by piece, in order. The programs run in the same order, so each
  // executed point is searched in a window around the piece that fitted the last one.
  Evaluator ev{model, model::ForwardData(model), options.conditions};
  std::deque<Piece> pieces;
  each_motion(original, options, [&](const gcode::Motion& m) {
    if (m.kind == gcode::MotionKind::feed || m.kind == gcode::MotionKind::arc) nominal_pieces(m, ev, pieces);
  });
  PathError e;
  double sum2 = 0.0;
  std::size_t cursor = 0;
  each_motion(compensated, options, [&](const gcode::Motion& m) {
    const MotionPath path(m);
    ev.advance(path.start());
    const FollowPlay follow{ev, path.end()};
    if (m.kind != gcode::MotionKind::feed && m.kind != gcode::MotionKind::arc) return;
    ++e.moves;
    const int steps = path.steps(model, options.samples);  // finer than the job checks
    for (int k = 0; k <= steps; ++k) {
      const model::ChainQ q = path.at(static_cast<double>(k) / steps);
      model::forward(model, ev.data, q, ev.advance(q), false, model::Evaluate::actual);
      const Eigen::Vector3d p = ev.data.actual;
      double best = 1e300;
      std::size_t best_at = cursor;
      const std::size_t from = cursor > 64 ? cursor - 64 : 0;
      const std::size_t to = std::min(pieces.size(), cursor + 4096);
      for (std::size_t i = from; i < to; ++i) {
        const double d = pieces[i].distance(p);
        if (d < best) best = d, best_at = i;
      }
      if (best > 1e299) continue;  // no nominal path (a program without cuts)
      cursor = best_at;
      sum2 += best * best;
      ++e.points;
      if (best > e.max) e.max = best, e.worst_line = m.line, e.worst_point = p;
    }
  });
  e.rms = e.points ? std::sqrt(sum2 / static_cast<double>(e.points)) : 0.0;
  return e;
}

}  // namespace ccomp::compensate
