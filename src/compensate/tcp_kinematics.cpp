#include "ccomp/compensate/tcp_kinematics.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "ccomp/compensate/machine_coordinates.hpp"
#include "ccomp/error.hpp"
#include "ccomp/compensate/verdict.hpp"
#include "move_solver.hpp"
#include "tool_direction.hpp"

namespace ccomp::compensate {

namespace {

/// The great circle from `a` to `b` (unit directions) at fraction t; a pair of opposite
/// directions has none (ccomp::Error, program).
Eigen::Vector3d on_great_circle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double t) {
  const double angle = angle_between(a, b);
  if (angle < 1e-12) return a;
  if (!(std::numbers::pi - angle > 1e-9))
    throw Error(ErrorKind::program, "a move under G43.5 that turns the tool's direction to its opposite: no great "
                                    "circle joins the two");
  return ((std::sin((1.0 - t) * angle) * a + std::sin(t * angle) * b) / std::sin(angle)).normalized();
}

}  // namespace

TcpKinematics::TcpKinematics(const model::ForwardModel& model)
    : model_(model), data_(model), tool_axis_(tool_axis_of(model)) {
  for (const auto* chain : {&model.chain().workpiece, &model.chain().tool})
    for (const kinematics::Joint& j : chain->joints) {
      if (j.type == kinematics::JointType::fixed || j.axis == model::kToolLengthIndex) continue;
      (j.type == kinematics::JointType::rotary ? rotary_ : linear_).push_back(static_cast<int>(j.axis));
    }
  if (rotary_.empty()) return;  // the tip in the part is where the axes are: nothing to turn
  if (linear_.size() != 3)
    throw Error(ErrorKind::unsupported,
                fmt::format("model '{}' has {} linear axes: ccomp follows tool-centre-point programs on machines "
                            "with three",
                            model.machine().name, linear_.size()));
  const model::ChainQ zero = model::ChainQ::Zero();
  if (!(std::abs(linear_columns(zero, tip(zero)).determinant()) > 1e-9))
    throw Error(ErrorKind::unsupported,
                fmt::format("model '{}': its linear axes do not move the tip in three directions", model.machine().name));
}

Eigen::Vector3d TcpKinematics::tip(const model::ChainQ& q) {
  model::forward(model_, data_, q, conditions_, false, model::Evaluate::nominal);
  return data_.nominal;
}

Eigen::Vector3d TcpKinematics::direction(const model::ChainQ& q) {
  model::forward(model_, data_, q, conditions_, false, model::Evaluate::nominal);
  return -(data_.R_nominal * tool_axis_).normalized();
}

std::optional<model::ChainQ> TcpKinematics::rotary_for(const Eigen::Vector3d& target, model::ChainQ q) {
  if (!(target.norm() > 1e-9) || !target.allFinite() || rotary_.empty()) return std::nullopt;
  const Eigen::Vector3d want = target.normalized();
  if (std::optional<model::ChainQ> found = solve_rotary(want, q)) return found;
  // From the singular pose (or a saddle) the steps go nowhere: start again a little turned
  // each way about each axis, and keep the angles nearest the ones before.
  constexpr double kNudge = 0.2;  // rad
  // Two sets of angles this much or less apart in their distance from q's are a tie: which
  // one a control takes is its own setting's choice.
  constexpr double kTie = 1e-3;  // rad
  std::vector<std::pair<double, model::ChainQ>> found_all;  // (distance from q, angles)
  for (const int place : rotary_)
    for (const double sign : {1.0, -1.0}) {
      model::ChainQ start = q;
      start[place] += sign * kNudge;
      const std::optional<model::ChainQ> found = solve_rotary(want, start);
      if (!found) continue;
      double d = 0.0;
      for (const int k : rotary_) d += std::abs((*found)[k] - q[k]);
      found_all.emplace_back(d, *found);
    }
  if (found_all.empty()) return std::nullopt;
  const auto& [distance, nearest] = *std::min_element(
      found_all.begin(), found_all.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [d, other] : found_all) {
    double apart = 0.0;
    for (const int k : rotary_) apart = std::max(apart, std::abs(other[k] - nearest[k]));
    if (apart > 1e-6 && d - distance < kTie)
      throw Error(ErrorKind::unsupported,
                  "from the singular pose two sets of rotary angles turn the tool to this direction, as near the "
                  "angles before: which one the control takes is its own setting's choice; turn the rotary axes "
                  "towards it before G43.5 (A B C words, or G43.4)");
  }
  return nearest;
}

std::optional<model::ChainQ> TcpKinematics::solve_rotary(const Eigen::Vector3d& want, model::ChainQ q) {
  constexpr double kStep = 1e-6;        // rad: central differences of a direction, exact to ~1e-12
  constexpr double kLargestTurn = 0.5;  // rad a step: no leap onto another branch
  // Keeps a rotary axis that turns the direction nowhere (at the pole) still, and no other:
  // near the pole the last axis turns it by the tilt's sine, which may be 1e-6 and less.
  constexpr double kDamping = 1e-20;
  const auto n = static_cast<Eigen::Index>(rotary_.size());
  for (int iteration = 0; iteration < 60; ++iteration) {
    const Eigen::Vector3d d = direction(q);
    if (angle_between(d, want) < 1e-12) return q;
    Eigen::Matrix<double, 3, Eigen::Dynamic> columns(3, n);
    for (Eigen::Index k = 0; k < n; ++k) {
      const int place = rotary_[static_cast<std::size_t>(k)];
      model::ChainQ ahead = q, behind = q;
      ahead[place] += kStep, behind[place] -= kStep;
      columns.col(k) = (direction(ahead) - direction(behind)) / (2.0 * kStep);
    }
    const Eigen::MatrixXd normal = columns.transpose() * columns + kDamping * Eigen::MatrixXd::Identity(n, n);
    Eigen::VectorXd turn = normal.ldlt().solve(columns.transpose() * (want - d));
    if (!turn.allFinite()) return std::nullopt;
    if (turn.cwiseAbs().maxCoeff() > kLargestTurn) turn *= kLargestTurn / turn.cwiseAbs().maxCoeff();
    for (Eigen::Index k = 0; k < n; ++k) q[rotary_[static_cast<std::size_t>(k)]] += turn[k];
  }
  return angle_between(direction(q), want) < 1e-12 ? std::optional<model::ChainQ>(q) : std::nullopt;
}

std::optional<gcode::Axes> TcpKinematics::turned_to(const std::array<double, 3>& direction,
                                                    const gcode::Axes& position, const gcode::Offsets& offsets) {
  const Eigen::Vector3d target(direction[0], direction[1], direction[2]);
  if (!(target.norm() > 1e-9) || !target.allFinite()) return std::nullopt;
  std::optional<model::ChainQ> q = chain_of(position, offsets);
  const Eigen::Vector3d from = this->direction(*q), to = target.normalized();
  const double turn = angle_between(from, to);
  constexpr double kLargestStep = 0.1;  // rad along the great circle
  const int steps = std::min(1000, static_cast<int>(std::ceil(turn / kLargestStep)));
  for (int k = 1; k < steps && q; ++k)
    if (std::numbers::pi - turn > 1e-9) q = rotary_for(on_great_circle(from, to, static_cast<double>(k) / steps), *q);
  if (q) q = rotary_for(to, *q);
  if (!q) return std::nullopt;
  const gcode::Axes angles = controlled_of_chain(*q, offsets);
  gcode::Axes turned = position;
  for (std::size_t i = 0; i < turned.size(); ++i)
    if (gcode::is_rotary(i)) turned[i] = angles[i];
  return turned;
}

Eigen::Matrix3d TcpKinematics::linear_columns(const model::ChainQ& q, const Eigen::Vector3d& at) {
  // Affine in the linear axes with the rest held: the columns by unit steps are exact (up to
  // rounding).
  Eigen::Matrix3d columns;
  for (int c = 0; c < 3; ++c) {
    model::ChainQ moved = q;
    moved[linear_[static_cast<std::size_t>(c)]] += 1.0;
    columns.col(c) = tip(moved) - at;
  }
  return columns;
}

model::ChainQ TcpKinematics::solve_linear(model::ChainQ q, const Eigen::Vector3d& target) {
  // A second step takes up the rounding of the first.
  const Eigen::Vector3d at = tip(q);
  const Eigen::PartialPivLU<Eigen::Matrix3d> lu(linear_columns(q, at));
  Eigen::Vector3d residual = target - at;
  for (int step = 0; step < 2; ++step) {
    const Eigen::Vector3d dq = lu.solve(residual);
    for (int c = 0; c < 3; ++c) q[linear_[static_cast<std::size_t>(c)]] += dq[c];
    residual = target - tip(q);
  }
  return q;
}

Eigen::Vector3d TcpKinematics::part_point(const gcode::Axes& world, const gcode::Offsets& offsets) {
  gcode::Axes level = world;  // the same X Y Z with the rotary axes at zero
  for (const int k : rotary_) level[static_cast<std::size_t>(k)] = 0.0;
  return tip(chain_of(level, offsets));
}

model::ChainQ TcpKinematics::joints_of(const gcode::Axes& world, const gcode::Offsets& offsets) {
  if (identity()) return chain_of(world, offsets);
  return solve_linear(chain_of(world, offsets), part_point(world, offsets));
}

gcode::Axes TcpKinematics::world_of(const model::ChainQ& q, const gcode::Offsets& offsets) {
  if (identity()) return controlled_of_chain(q, offsets);
  const Eigen::Vector3d target = tip(q);
  const gcode::Axes turned = controlled_of_chain(q, offsets);
  gcode::Axes level = turned;
  for (const int k : rotary_) level[static_cast<std::size_t>(k)] = 0.0;
  gcode::Axes world = controlled_of_chain(solve_linear(chain_of(level, offsets), target), offsets);
  for (const int k : rotary_) world[static_cast<std::size_t>(k)] = turned[static_cast<std::size_t>(k)];
  return world;
}

gcode::Axes TcpKinematics::switched(const gcode::Axes& position, const gcode::Offsets& offsets, bool to_tcp) {
  return to_tcp ? world_of(chain_of(position, offsets), offsets)
                : controlled_of_chain(joints_of(position, offsets), offsets);
}

namespace {

gcode::Axes lerp(const gcode::Axes& a, const gcode::Axes& b, double s) {
  gcode::Axes out;
  for (std::size_t i = 0; i < a.size(); ++i) out[i] = a[i] + s * (b[i] - a[i]);
  return out;
}

}  // namespace

TcpLine::TcpLine(TcpKinematics& kinematics, const gcode::Axes& start, const gcode::Axes& end,
                 const gcode::Offsets& offsets, bool great_circle)
    : kinematics_(kinematics), start_(start), end_(end), offsets_(offsets), great_circle_(great_circle) {
  if (!great_circle_) return;
  from_ = kinematics_.direction(kinematics_.joints_of(start_, offsets_));
  to_ = kinematics_.direction(kinematics_.joints_of(end_, offsets_));
}

Eigen::Vector3d TcpLine::direction_at(double f) const { return on_great_circle(from_, to_, f); }

gcode::Axes TcpLine::at(double f) {
  gcode::Axes p = lerp(start_, end_, f);
  if (!great_circle_ || f == 0.0 || f == 1.0) return p;
  // From the angles nearest before f: the branch the interpolation has been on.
  auto before = solved_.lower_bound(f);
  gcode::Axes guess = before == solved_.begin() ? start_ : std::prev(before)->second;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!gcode::is_rotary(i)) guess[i] = p[i];
  const std::optional<model::ChainQ> turned = kinematics_.rotary_for(direction_at(f), chain_of(guess, offsets_));
  if (!turned)
    throw Error(ErrorKind::program, "a move under G43.5 whose tool direction on the way is none the machine can take");
  const gcode::Axes angles = controlled_of_chain(*turned, offsets_);
  for (std::size_t i = 0; i < p.size(); ++i)
    if (gcode::is_rotary(i)) p[i] = angles[i];
  solved_.emplace(f, p);
  return p;
}

std::vector<double> tcp_split(TcpKinematics& kinematics, const gcode::Axes& start, const gcode::Axes& end,
                              const gcode::Offsets& offsets, double tolerance, std::size_t most,
                              std::vector<double>* deviations, bool great_circle) {
  if (deviations) deviations->clear();
  if (kinematics.identity()) {
    if (deviations) deviations->push_back(0.0);
    return {0.0, 1.0};
  }
  TcpLine line(kinematics, start, end, offsets, great_circle);
  const double angular = default_angular_tolerance(tolerance);
  if (great_circle) {
    // Leaving the singular pose (the tool along the last rotary line) towards a direction its
    // angle there does not point to, the control swings that axis at once, the tip standing.
    constexpr double kSwing = 0.01;  // deg a millionth into the move: more is no motion of the path
    const gcode::Axes leaving = line.at(1e-6);
    for (std::size_t i = 0; i < leaving.size(); ++i)
      if (gcode::is_rotary(i) && std::abs(leaving[i] - start[i]) > kSwing)
        throw Error(ErrorKind::unsupported,
                    "a move under G43.5 that leaves the singular pose (the tool along the last rotary axis) in a "
                    "direction the axis' angle there does not point to: the control swings the axis at once, which "
                    "ccomp does not follow (a point just off the pole before it does)");
  }
  const model::ChainQ q_start = kinematics.joints_of(start, offsets), q_end = kinematics.joints_of(end, offsets);
  std::vector<double> cuts{0.0};
  // Depth first over [a, b], the left half first: the cuts come out in order.
  struct Piece {
    double a, b;
    model::ChainQ qa, qb;
  };
  std::vector<Piece> stack{{0.0, 1.0, q_start, q_end}};
  while (!stack.empty()) {
    const Piece p = stack.back();
    stack.pop_back();
    bool within = true;
    double largest = 0.0;
    for (const double f : {0.25, 0.5, 0.75}) {
      const double at = p.a + f * (p.b - p.a);
      const model::ChainQ straight = p.qa + f * (p.qb - p.qa);
      // (The tip's path is the line whichever way the direction turns: part_point() takes
      // the X Y Z alone.)
      const Eigen::Vector3d drawn = kinematics.part_point(lerp(start, end, at), offsets);
      const double off = (kinematics.tip(straight) - drawn).norm();
      if (!std::isfinite(off))
        throw Error(ErrorKind::program,
                    "a tool-centre-point move whose axes' positions are not finite numbers (a point far beyond "
                    "the machine?)");
      // Under G43.5 the axes' straight move turns the tool off the great circle, too.
      const bool turned_off =
          great_circle && !(angle_between(kinematics.direction(straight), line.direction_at(at)) <= angular);
      if (!(off <= tolerance) || turned_off) {
        within = false;
        break;
      }
      largest = std::max(largest, off);
    }
    if (within) {
      cuts.push_back(p.b);
      if (deviations) deviations->push_back(largest);
      if (cuts.size() > most + 1)
        throw Error(ErrorKind::program,
                    fmt::format("a tool-centre-point move that needs more than {} pieces to follow within {} mm", most,
                                tolerance));
      continue;
    }
    if (!(p.b - p.a > 1e-9) && great_circle)
      throw Error(ErrorKind::unsupported,
                  "a move whose tool direction turns along a great circle (G43.5, Siemens' ORIWKS with ORIVECT) "
                  "past the singular pose so near that the control swings the last rotary axis round within a "
                  "billionth of the move: ccomp does not follow it (keep the direction off the pole, or split the "
                  "move there)");
    if (!(p.b - p.a > 1e-9))  // the rounding of the points, not the path, is what is left
      throw Error(ErrorKind::program,
                  fmt::format("a tool-centre-point move that cannot be followed within {} mm by the axes' straight "
                              "moves (a point far beyond the machine, or a tolerance below the arithmetic's)",
                              tolerance));
    const double mid = 0.5 * (p.a + p.b);
    const model::ChainQ q_mid = kinematics.joints_of(line.at(mid), offsets);
    stack.push_back({mid, p.b, q_mid, p.qb});  // the right half after the left
    stack.push_back({p.a, mid, p.qa, q_mid});
  }
  return cuts;
}

namespace {

/// The share of a TCP arc's tolerance its chords' sagitta takes: the rest is each chord's
/// own split into the axes' straight moves (tcp_split()).
constexpr double kArcChordShare = 0.5;

/// How far an arc's chords of `count` equal steps bulge from it at most (mm).
double chord_sagitta(const gcode::ArcGeometry& g, std::size_t count) {
  const double step = g.sweep / static_cast<double>(count);
  return 2.0 * std::max(g.r_start, g.r_end) * std::pow(std::sin(step / 4.0), 2);
}

/// The pieces of the straight TCP move from `a` to `b`, which is the share [from, to] of the
/// block's move `m`, onto `out`; each piece's deviation plus `bulge` (an arc's chord off the
/// arc).
void straight_pieces(TcpKinematics& kinematics, const gcode::Motion& m, const gcode::Axes& a, const gcode::Axes& b,
                     double from, double to, double tolerance, double bulge, std::size_t most,
                     std::vector<TcpPiece>& out) {
  const gcode::Offsets& offsets = *m.offsets;
  std::vector<double> deviations{0.0};
  const std::vector<double> cuts =
      m.kind == gcode::MotionKind::traverse
          ? std::vector<double>{0.0, 1.0}
          : tcp_split(kinematics, a, b, offsets, tolerance, most, &deviations, m.tcp_great_circle);
  TcpLine line(kinematics, a, b, offsets, m.tcp_great_circle);
  gcode::Motion piece = m;
  piece.kind = m.kind == gcode::MotionKind::arc ? gcode::MotionKind::feed : m.kind;
  piece.tcp = false;
  piece.end = out.empty() ? controlled_of_chain(kinematics.joints_of(a, offsets), offsets) : out.back().motion.end;
  for (std::size_t c = 1; c < cuts.size(); ++c) {
    piece.start = piece.end;
    piece.end = controlled_of_chain(kinematics.joints_of(line.at(cuts[c]), offsets), offsets);
    out.push_back({piece, from + cuts[c - 1] * (to - from), from + cuts[c] * (to - from), deviations[c - 1] + bulge});
  }
}

}  // namespace

void tcp_pieces(TcpKinematics& kinematics, const gcode::Motion& m, double tolerance, std::vector<TcpPiece>& out,
                std::size_t most) {
  using gcode::MotionKind;
  out.clear();
  if (kinematics.identity()) {  // a machine without rotary axes: the program's points are the axes'
    gcode::Motion joints = m;
    joints.tcp = false;
    out.push_back({joints, 0.0, 1.0});
    return;
  }
  if (m.kind == MotionKind::probe) throw Error(ErrorKind::unsupported, "a probe move (G38.x) cannot be compensated");
  if (m.source != gcode::MotionSource::program)
    throw Error(ErrorKind::unsupported,
                "a canned cycle, G28/G30 or G53 under tool centre point control: ccomp follows the program's own "
                "moves under TCP");
  if (m.radius_compensation || m.offset)
    throw Error(ErrorKind::unsupported, "cutter radius compensation (G41/G42) under tool centre point control");
  if (m.kind != MotionKind::arc) return straight_pieces(kinematics, m, m.start, m.end, 0.0, 1.0, tolerance, 0.0, most, out);
  // An arc: the control moves the tip along it in the part. It is followed as chords within
  // a share of the tolerance, each chord as a straight TCP move within the rest.
  const gcode::ArcGeometry g = gcode::arc_geometry(m);
  const std::size_t chords = arc_chord_count(g, kArcChordShare * tolerance);
  const double bulge = chord_sagitta(g, chords);
  gcode::Axes a = m.start;
  for (std::size_t k = 1; k <= chords; ++k) {
    const double from = static_cast<double>(k - 1) / static_cast<double>(chords);
    const double to = static_cast<double>(k) / static_cast<double>(chords);
    const gcode::Axes b = gcode::arc_point(m, g, to);
    straight_pieces(kinematics, m, a, b, from, to, (1.0 - kArcChordShare) * tolerance, bulge, most, out);
    if (out.size() > most)
      throw Error(ErrorKind::program,
                  fmt::format("a tool-centre-point arc that needs more than {} pieces to follow within {} mm", most,
                              tolerance));
    a = b;
  }
}

}  // namespace ccomp::compensate
