#include "ccomp/compensate/verify.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <functional>

namespace ccomp::compensate {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// A piece of the nominal path in the table frame: a straight segment, or an arc/helix (the
/// nominal map is rigid while the rotary axes hold still, so an arc stays an arc).
struct Piece {
  bool arc = false;
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();  // segment
  Eigen::Vector3d centre = Eigen::Vector3d::Zero(), e1 = Eigen::Vector3d::Zero(), e2 = Eigen::Vector3d::Zero(),
                  n = Eigen::Vector3d::Zero();  // arc frame (unit in-plane axes and normal)
  double r = 0, a0 = 0, sweep = 0, dw = 0;
  bool ccw = true;

  [[nodiscard]] double distance(const Eigen::Vector3d& p) const {
    if (!arc) {
      const Eigen::Vector3d ab = b - a;
      const double len2 = ab.squaredNorm();
      const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
      return (a + t * ab - p).norm();
    }
    const Eigen::Vector3d v = p - centre;
    const double u = v.dot(e1), w = v.dot(e2), h = v.dot(n);
    double phi = std::atan2(w, u) - a0;
    if (!ccw) phi = -phi;
    while (phi < 0) phi += 2 * kPi;
    while (phi > 2 * kPi) phi -= 2 * kPi;
    if (phi > sweep) return 1e300;  // off this arc: a neighbouring piece owns the point
    return std::hypot(std::hypot(u, w) - r, h - dw * phi / sweep);
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
  std::array<double, 9> play{};  ///< approach state at the start of the current move
  /// The conditions a fraction t along the move from a to b: the play follows the travel.
  const model::Conditions& along(const model::ChainQ& a, const model::ChainQ& b, double t) {
    conditions.directions = play;
    model::take_up_play(model, conditions, a, a + t * (b - a));
    return conditions;
  }
  void finish_move(const model::ChainQ& a, const model::ChainQ& b) { play = along(a, b, 1.0).directions; }
  Eigen::Vector3d nominal(const model::ChainQ& q) {
    model::forward(model, data, q, conditions);
    return data.nominal;
  }
  Eigen::Vector3d actual(const model::ChainQ& q) {
    model::forward(model, data, q, conditions);
    return data.actual;
  }
};

/// However a motion's callback returns, the play has followed the move.
struct FollowPlay {
  Evaluator& ev;
  const model::ChainQ &a, &b;
  ~FollowPlay() { ev.finish_move(a, b); }
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
    p.r = g.r_start;
    p.a0 = g.a_start;
    p.ccw = g.ccw;
    p.sweep = g.sweep;
    p.dw = m.end[pa.normal] - m.start[pa.normal];
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
  ev.play = options.conditions.directions;
  double sum2 = 0.0;
  each_motion(program, options, [&](const gcode::Motion& m) {
    const model::ChainQ a = chain_of(m.start, *m.offsets), b = chain_of(m.end, *m.offsets);
    const FollowPlay follow{ev, a, b};
    if (m.kind == gcode::MotionKind::traverse || m.kind == gcode::MotionKind::probe) return;
    ++e.moves;
    const int samples = 2 * model.check_points(a, b, options.samples);
    for (int k = 0; k <= samples; ++k) {
      const double t = static_cast<double>(k) / samples;
      const model::ChainQ q = a + (b - a) * t;  // arcs: at their chords' ends
      model::forward(model, ev.data, q, ev.along(a, b, t));
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
  ev.play = options.conditions.directions;
  std::deque<Piece> pieces;
  each_motion(original, options, [&](const gcode::Motion& m) {
    if (m.kind == gcode::MotionKind::feed || m.kind == gcode::MotionKind::arc) nominal_pieces(m, ev, pieces);
  });
  PathError e;
  double sum2 = 0.0;
  std::size_t cursor = 0;
  each_motion(compensated, options, [&](const gcode::Motion& m) {
    const model::ChainQ a = chain_of(m.start, *m.offsets), b = chain_of(m.end, *m.offsets);
    const FollowPlay follow{ev, a, b};
    if (m.kind != gcode::MotionKind::feed && m.kind != gcode::MotionKind::arc) return;
    ++e.moves;
    const int samples = 2 * model.check_points(a, b, options.samples);  // finer than the job checks
    for (int k = 0; k <= samples; ++k) {
      const double t = static_cast<double>(k) / samples;
      ev.along(a, b, t);
      const Eigen::Vector3d p = ev.actual(a + (b - a) * t);
      double best = 1e300;
      std::size_t best_at = cursor;
      const std::size_t from = cursor > 64 ? cursor - 64 : 0;
      const std::size_t to = std::min(pieces.size(), cursor + 4096);
      for (std::size_t i = from; i < to; ++i) {
        const double d = pieces[i].distance(p);
        if (d < best) best = d, best_at = i;
      }
      if (best > 1e299) continue;  // nothing near: not a cut of the original (a lead-in, say)
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
