// Five-axis compensation held to reference machines written apart from ccomp's model code
// (tests/support/reference_five_axis.hpp): a trunnion table (XYZAC, C on A) and a head-head
// machine (XYZBC, B on C), with each location and motion error alone and all together. The
// model file is this test's description of the reference in ccomp's terms (its chain offsets
// from the reference's geometry, its linear terms moved from machine positions to program
// ones through the work offset); a program tilting the tool through the singular pose (A 0,
// B 0: the tool along C's line) as C turns is compensated point by point as the job does, and
// each corrected pose is run on the reference.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <functional>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "ccomp/compensate/inverse.hpp"
#include "ccomp/compensate/program_job.hpp"
#include "ccomp/compensate/verify.hpp"
#include "ccomp/model/model_file.hpp"
#include "job_runner.hpp"
#include "parsed_block.hpp"
#include "reference_five_axis.hpp"

namespace ccomp::compensate {
namespace {

using test::FiveAxisWords;
using test::PartPose;
using test::ReferenceHeads;
using test::ReferenceTrunnion;

constexpr double kRadPerDeg = std::numbers::pi / 180.0;
constexpr double kToolLength = 120.0;

/// Positioning errors of the linear axes on the reference (mm, of the machine position):
/// slope and curvature of each.
struct LinearErrors {
  double slope = 0.0, curvature = 0.0;
};

/// A polynomial term of `name` (um, of the program's coordinate) equal to the reference's
/// error at the machine position the work offset `shift` away.
std::string moved_polynomial(const char* name, const LinearErrors& e, double shift) {
  std::ostringstream out;
  out.precision(17);
  out << "  - {name: " << name << ", form: polynomial, unit: um, coefficients: ["
      << 1e3 * (e.slope * shift + e.curvature * shift * shift) << ", " << 1e3 * (e.slope + 2 * e.curvature * shift)
      << ", " << 1e3 * e.curvature << "]}\n";
  return out.str();
}

/// One error of a reference, as the test sets it there and writes it in the model (a line, or
/// for the linear axes one made from the reference's work offset).
template <typename Reference>
struct MachineError {
  const char* name;
  std::function<void(Reference&)> set;
  std::string term;
  std::string (*terms)(const Reference&) = nullptr;
};

constexpr LinearErrors kX{12e-6, -1.5e-8}, kY{-9e-6, 2e-8}, kZ{7e-6, 1e-8};

/// The linear axes' positioning errors, on either reference.
template <typename Reference>
std::vector<MachineError<Reference>> linear_errors() {
  return {
      {"EXX", [](Reference& r) { r.EXX = [](double m) { return kX.slope * m + kX.curvature * m * m; }; }, "",
       [](const Reference& r) { return moved_polynomial("EXX", kX, r.work_offset().x()); }},
      {"EYY", [](Reference& r) { r.EYY = [](double m) { return kY.slope * m + kY.curvature * m * m; }; }, "",
       [](const Reference& r) { return moved_polynomial("EYY", kY, r.work_offset().y()); }},
      {"EZZ", [](Reference& r) { r.EZZ = [](double m) { return kZ.slope * m + kZ.curvature * m * m; }; }, "",
       [](const Reference& r) { return moved_polynomial("EZZ", kZ, r.work_offset().z()); }},
  };
}

/// A location error: `value` um or urad on the reference's member and in the model.
template <typename Reference>
MachineError<Reference> located(const char* name, double Reference::*member, double value, bool length) {
  std::ostringstream term;
  term << "  - {name: " << name << ", value: " << value << ", unit: " << (length ? "um" : "urad") << "}\n";
  return {name, [member, v = value * (length ? 1e-3 : 1e-6)](Reference& r) { r.*member = v; }, term.str()};
}

/// A worm gear's angular positioning error: a first harmonic (sine) of `urad` on the
/// reference's member and in the model.
template <typename Reference>
MachineError<Reference> worm_gear(const char* name, std::function<double(double)> Reference::*member, double urad) {
  std::ostringstream term;
  term << "  - {name: " << name << ", form: periodic, period: 360 deg, unit: urad, harmonics: [[0, " << urad << "]]}\n";
  return {name,
          [member, urad](Reference& r) {
            r.*member = [urad](double deg) { return urad * 1e-6 * std::sin(deg * kRadPerDeg); };
          },
          term.str()};
}

std::vector<MachineError<ReferenceTrunnion>> trunnion_errors() {
  using R = ReferenceTrunnion;
  std::vector<MachineError<R>> errors{
      located<R>("EY0A", &R::EY0A, 12, true),  located<R>("EZ0A", &R::EZ0A, -8, true),
      located<R>("EB0A", &R::EB0A, 15, false), located<R>("EC0A", &R::EC0A, -10, false),
      located<R>("EX0C", &R::EX0C, -9, true),  located<R>("EY0C", &R::EY0C, 7, true),
      located<R>("EA0C", &R::EA0C, 12, false), located<R>("EB0C", &R::EB0C, -9, false),
      worm_gear<R>("EAA", &R::EAA, 14),        worm_gear<R>("ECC", &R::ECC, -11),
  };
  for (auto& e : linear_errors<R>()) errors.push_back(e);
  return errors;
}

std::vector<MachineError<ReferenceHeads>> head_errors() {
  using R = ReferenceHeads;
  std::vector<MachineError<R>> errors{
      located<R>("EX0C", &R::EX0C, 10, true),   located<R>("EY0C", &R::EY0C, -6, true),
      located<R>("EA0C", &R::EA0C, -11, false), located<R>("EB0C", &R::EB0C, 8, false),
      located<R>("EX0B", &R::EX0B, -7, true),   located<R>("EZ0B", &R::EZ0B, 11, true),
      located<R>("EA0B", &R::EA0B, 13, false),  located<R>("EC0B", &R::EC0B, -12, false),
      worm_gear<R>("EBB", &R::EBB, 16),         worm_gear<R>("ECC", &R::ECC, -9),
  };
  for (auto& e : linear_errors<R>()) errors.push_back(e);
  return errors;
}

/// A five-axis finishing pass: the tool tilts from -35 to 40 degrees through 0 (A on the
/// trunnion, B on the head) while C turns 210 degrees and the tip runs over the part; then a
/// stretch at the singular pose itself, C turning.
std::vector<FiveAxisWords> sweep(bool head) {
  std::vector<FiveAxisWords> points;
  auto tilted = [head](FiveAxisWords w, double tilt) {
    (head ? w.b : w.a) = tilt;
    return w;
  };
  const int n = 300;
  for (int k = 0; k <= n; ++k) {
    const double s = static_cast<double>(k) / n;
    points.push_back(tilted({-40 + 90 * s, 30 * std::sin(3 * s), 25 - 20 * s, 0, 0, -60 + 210 * s}, -35 + 75 * s));
  }
  for (int k = 0; k <= 60; ++k) points.push_back({50.0 - k, -10 + 0.5 * k, 5, 0, 0, 150 - 2.0 * k});
  return points;
}

model::ChainQ chain_of(const FiveAxisWords& w) {
  model::ChainQ q = model::ChainQ::Zero();
  q << w.x, w.y, w.z + kToolLength, w.a * kRadPerDeg, w.b * kRadPerDeg, w.c * kRadPerDeg, 0, 0, 0, kToolLength;
  return q;
}

FiveAxisWords words_of(const model::ChainQ& q) {
  return {q[0], q[1], q[2] - kToolLength, q[3] / kRadPerDeg, q[4] / kRadPerDeg, q[5] / kRadPerDeg};
}

/// How far the tilt stands from the singular pose (0) where the tool's direction is held to
/// the full tolerance: within it the rotary axes turn the tool by sin(tilt) per radian of
/// C, and the damped solve leaves part of that direction as it is (the share
/// kSingularDamping allows), reported.
constexpr double kAwayFromSingular = 2.0;  // deg

struct Landing {
  double tip = 0.0;            ///< mm: the worst tip error on the reference
  double direction = 0.0;      ///< rad: the worst tool direction error, the tilt beyond kAwayFromSingular
  double near_singular = 0.0;  ///< rad: the same within it
  double beyond_zone = 0.0;    ///< rad: the same where the solve is exact (kSingularZone)
  /// rad: how much worse the tool's direction is than without compensation, at worst (<= 0:
  /// never worse)
  double made_worse = -1.0;
  double rotary_correction = 0.0;          ///< rad: the largest change of a rotary axis
  double direction_left_unreported = 0.0;  ///< rad: the reference's direction error less the reported one
  int unconverged = 0;
};

double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

/// A reference with some of its errors, and the model that describes it.
struct FiveAxisCase {
  std::string name;
  bool head = false;
  std::string model;
  std::function<PartPose(const FiveAxisWords&, bool actual)> pose;
};

void PrintTo(const FiveAxisCase& c, std::ostream* os) {
  *os << c.name;
}

template <typename Reference>
FiveAxisCase case_of(std::string name, const std::vector<MachineError<Reference>>& errors) {
  Reference reference;
  std::string terms;
  for (const MachineError<Reference>& e : errors) {
    e.set(reference);
    terms += e.terms ? e.terms(reference) : e.term;
  }
  return {std::move(name), std::is_same_v<Reference, ReferenceHeads>, test::ccomp_model(reference) + terms,
          [reference](const FiveAxisWords& w, bool actual) {
            return actual ? reference.actual(w, kToolLength) : reference.nominal(w, kToolLength);
          }};
}

/// Each error alone, then all together, on both references.
std::vector<FiveAxisCase> five_axis_cases() {
  std::vector<FiveAxisCase> cases;
  for (const auto& e : trunnion_errors())
    cases.push_back(case_of<ReferenceTrunnion>(std::string("Trunnion") + e.name, {e}));
  cases.push_back(case_of("TrunnionAll", trunnion_errors()));
  for (const auto& e : head_errors()) cases.push_back(case_of<ReferenceHeads>(std::string("Heads") + e.name, {e}));
  cases.push_back(case_of("HeadsAll", head_errors()));
  return cases;
}

Landing compensate_on(const FiveAxisCase& c) {
  const model::MachineModel mm = model::parse_machine_model(c.model, c.name + ".yaml");
  const model::ForwardModel m(mm);
  const InverseProblem problem(m);
  EXPECT_EQ(problem.orientation, OrientationEquations::tool_direction);
  model::ForwardData d(m);
  InverseWorkspace ws;
  Landing out;
  for (const FiveAxisWords& w : sweep(c.head)) {
    const model::ChainQ q = chain_of(w);
    const InverseResult r = solve_inverse(m, problem, d, q, {}, {}, nullptr, &ws);
    if (!r.converged) {
      ++out.unconverged;
      continue;
    }
    const PartPose meant = c.pose(w, false), got = c.pose(words_of(r.q), true);
    const double direction = angle_between(meant.axis, got.axis);
    const double uncompensated = angle_between(meant.axis, c.pose(w, true).axis);
    out.tip = std::max(out.tip, (got.tip - meant.tip).norm());
    double& worst = std::abs(c.head ? w.b : w.a) >= kAwayFromSingular ? out.direction : out.near_singular;
    worst = std::max(worst, direction);
    if (std::sin(std::abs(c.head ? w.b : w.a) * kRadPerDeg) >= kSingularZone)
      out.beyond_zone = std::max(out.beyond_zone, direction);
    out.made_worse = std::max(out.made_worse, direction - uncompensated);
    out.direction_left_unreported =
        std::max(out.direction_left_unreported, std::abs(direction - r.orientation_error.norm()));
    for (const int k : problem.rotary_unknowns)
      out.rotary_correction = std::max(out.rotary_correction, std::abs(r.q[k] - q[k]));
  }
  return out;
}

class FiveAxis : public testing::TestWithParam<FiveAxisCase> {};

// Every pose within 1 um of its tip, its tool direction within 10 urad away from the
// singular pose (within 10 nrad beyond the damped zone) and never worse than uncompensated
// near it; what is left there is what the
// solve reported, and no rotary axis is corrected by more than 1 mrad (no flip, no absurd
// correction).
TEST_P(FiveAxis, LandsWithinAMicrometreAndTenMicroradiansOnTheReference) {
  const Landing l = compensate_on(GetParam());
  EXPECT_EQ(l.unconverged, 0);
  EXPECT_LT(l.tip, 1e-3);
  EXPECT_LT(l.direction, 10e-6);
  EXPECT_LT(l.beyond_zone, 1e-8) << "exact where the rotary axes turn the tool well";
  EXPECT_LT(l.made_worse, 0.1e-6);
  EXPECT_LT(l.direction_left_unreported, 0.1e-6) << "what is left is what is reported";
  EXPECT_LT(l.rotary_correction, 1e-3);
}

INSTANTIATE_TEST_SUITE_P(Errors, FiveAxis, testing::ValuesIn(five_axis_cases()),
                         [](const auto& param_info) { return param_info.param.name; });

TEST(FiveAxis, WhatTheSingularPoseLeavesIsThere) {
  // C's tilt turns the tool across C's line, which at the singular pose only a turn of C by
  // up to 180 degrees could answer: it stays, and the check above holds it to what is reported.
  EXPECT_GT(compensate_on(case_of("TrunnionAll", trunnion_errors())).near_singular, 10e-6);
  EXPECT_GT(compensate_on(case_of("HeadsAll", head_errors())).near_singular, 10e-6);
}

// ----------------------------------------------------------------------------------------
// predict and verify measure the tool's direction beside its tip: the sweep above as a
// program, run through ccomp's commands, against the reference.

/// The sweep's words as a program writes them (to 1e-6 mm and degree), so the reference
/// runs what the program says.
std::vector<FiveAxisWords> written(const std::vector<FiveAxisWords>& points) {
  auto r = [](double v) { return std::round(v * 1e6) / 1e6; };
  std::vector<FiveAxisWords> out;
  for (const FiveAxisWords& w : points) out.push_back({r(w.x), r(w.y), r(w.z), r(w.a), r(w.b), r(w.c)});
  return out;
}

/// The sweep as a program: the test's tool as H2 (under G43, or under G43.4 for a
/// tool-centre-point program, ended by G49), a rapid to the first point, a feed move to each
/// of the others.
std::string program_of(const std::vector<FiveAxisWords>& points, bool head, bool tcp = false) {
  std::string text = tcp ? "G21 G90 G94 G17\nG43.4 H2\n" : "G21 G90 G94 G17\nG43 H2\n";
  for (std::size_t k = 0; k < points.size(); ++k) {
    const FiveAxisWords& w = points[k];
    text += fmt::format("{} X{:.6f} Y{:.6f} Z{:.6f} {}{:.6f} C{:.6f}{}\n", k == 0 ? "G0" : "G1", w.x, w.y, w.z,
                        head ? 'B' : 'A', head ? w.b : w.a, w.c, k == 0 ? "" : " F1000");
  }
  return text + (tcp ? "G49\nM2\n" : "M2\n");
}

gcode::InterpreterOptions with_test_tool() {
  gcode::InterpreterOptions o;
  o.tools.tools[2] = gcode::ToolEntry{2, 2, {0, 0, kToolLength}, 10, ""};
  return o;
}

FiveAxisWords between(const FiveAxisWords& a, const FiveAxisWords& b, double t) {
  auto at = [t](double u, double v) { return u + (v - u) * t; };
  return {at(a.x, b.x), at(a.y, b.y), at(a.z, b.z), at(a.a, b.a), at(a.b, b.b), at(a.c, b.c)};
}

// predict's tool direction is the reference's: the angle between the axis the reference's
// errors give the tool and the one its perfect machine would, at least its largest at the
// moves' ends (which predict checks) and at most its largest at 64 points inside each
// move (more than predict checks), within 10 nrad (the model's small-angle terms).
TEST_P(FiveAxis, PredictTellsTheToolDirectionTheReferenceHas) {
  const FiveAxisCase& c = GetParam();
  const std::vector<FiveAxisWords> points = written(sweep(c.head));
  const model::ForwardModel m(model::parse_machine_model(c.model, c.name + ".yaml"));
  CheckOptions o;
  o.interpreter = with_test_tool();
  gcode::LineSource program = gcode::LineSource::from_string(program_of(points, c.head), "sweep.ngc");
  const PathError e = predict(program, m, o);
  double at_ends = 0.0, inside = 0.0;
  for (std::size_t k = 1; k < points.size(); ++k)
    for (int j = 0; j <= 64; ++j) {
      const FiveAxisWords w = between(points[k - 1], points[k], j / 64.0);
      const double angle = angle_between(c.pose(w, true).axis, c.pose(w, false).axis);
      inside = std::max(inside, angle);
      if (j == 0 || j == 64) at_ends = std::max(at_ends, angle);
    }
  EXPECT_EQ(e.moves, points.size() - 1);
  EXPECT_GE(e.orientation_max, at_ends - 1e-8);
  EXPECT_LE(e.orientation_max, inside + 1e-8);
  if (at_ends > 0.0) {
    EXPECT_GT(e.orientation_rms, 0.0);
    EXPECT_GE(e.orientation_worst_line, 4U) << "a feed move's line";
    EXPECT_LE(e.orientation_worst_line, points.size() + 2);
  }
}

// verify finds on the compensated sweep what the reference finds: the solve's points, the
// ends of the output's moves, land with the tool's direction the reference measures there
// (the test above holds it to what the solve reports, within 0.1 urad); verify reports at
// least the largest of those. Between them it takes the direction meant where the tip is,
// so a tip off the path along it by up to the tolerance shows the direction's turn over
// that stretch too (docs/compensation.md): no more than the solve's largest with that turn
// at the sweep's fastest (the reference's turn per mm of the tip's path) and 1 urad.
TEST_P(FiveAxis, VerifyTellsTheToolDirectionTheCompensatedSweepLeaves) {
  const FiveAxisCase& c = GetParam();
  const std::vector<FiveAxisWords> points = written(sweep(c.head));
  const model::MachineModel mm = model::parse_machine_model(c.model, c.name + ".yaml");
  const model::ForwardModel m(mm);
  const std::string original = program_of(points, c.head);
  JobOptions job;
  job.interpreter = with_test_tool();
  JobReport report;
  const std::string compensated = test::compensate(original, mm, job, &report);
  CheckOptions o;
  o.interpreter = with_test_tool();
  gcode::LineSource a = gcode::LineSource::from_string(original, "sweep.ngc");
  gcode::LineSource b = gcode::LineSource::from_string(compensated, "out.ngc");
  const PathError e = verify(a, b, m, o);
  EXPECT_LT(e.max, 1e-3);
  EXPECT_EQ(e.uncut_length, 0.0);
  double turn_per_mm = 0.0;
  for (std::size_t k = 1; k < points.size(); ++k) {
    const PartPose from = c.pose(points[k - 1], false), to = c.pose(points[k], false);
    turn_per_mm = std::max(turn_per_mm, angle_between(from.axis, to.axis) / (to.tip - from.tip).norm());
  }
  EXPECT_GE(e.orientation_max, report.max_orientation_error - 0.1e-6);
  EXPECT_LE(e.orientation_max, report.max_orientation_error + job.tolerance * turn_per_mm + 1e-6)
      << turn_per_mm << " rad/mm";
}

// ----------------------------------------------------------------------------------------
// A tool-centre-point program (G43.4): its X Y Z are the tip in the part, A/B C the rotary
// axes' angles, and the control's kinematics turn them into the axes' positions. Here the
// control is the reference's perfect machine (its own inverse below, not ccomp's), and the
// compensated program is run on the reference as such a control runs it: its words in a
// straight line between its points, the axes wherever the perfect machine's inverse puts
// them, the tool wherever the reference's errors take it.

/// The reference control's TCP inverse: the linear axes that put the perfect machine's tip
/// where the same X Y Z put it with the rotary axes at zero, at the words' angles (Newton on
/// the reference's own pose, affine in the linear axes).
FiveAxisWords reference_joints(const FiveAxisCase& c, const FiveAxisWords& tcp) {
  const Eigen::Vector3d target = c.pose({tcp.x, tcp.y, tcp.z, 0, 0, 0}, false).tip;
  FiveAxisWords j = tcp;
  for (int step = 0; step < 3; ++step) {
    const Eigen::Vector3d at = c.pose(j, false).tip;
    Eigen::Matrix3d columns;
    for (int k = 0; k < 3; ++k) {
      FiveAxisWords moved = j;
      (k == 0 ? moved.x : k == 1 ? moved.y : moved.z) += 1.0;
      columns.col(k) = c.pose(moved, false).tip - at;
    }
    const Eigen::Vector3d d = columns.partialPivLu().solve(target - at);
    j.x += d.x(), j.y += d.y(), j.z += d.z();
  }
  return j;
}

/// A TCP pass over the part: the tip runs a curve while the tool tilts from -35 to 40 degrees
/// through the singular pose and C turns 210 degrees, in moves of 3 mm and a few degrees.
std::vector<FiveAxisWords> tcp_sweep(bool head) {
  std::vector<FiveAxisWords> points;
  const int n = 60;
  for (int k = 0; k <= n; ++k) {
    const double s = static_cast<double>(k) / n;
    FiveAxisWords w{-40 + 90 * s, 30 * std::sin(3 * s), 25 - 20 * s, 0, 0, -60 + 210 * s};
    (head ? w.b : w.a) = -35 + 75 * s;
    points.push_back(w);
  }
  return written(points);
}

/// The feed moves' points of a program as its words say (absolute, modal): each G1 line's
/// point, after the rapid's.
std::vector<FiveAxisWords> points_of(const std::string& program) {
  std::vector<FiveAxisWords> points;
  FiveAxisWords at;
  std::istringstream lines(program);
  std::string line;
  bool moving = false;
  while (std::getline(lines, line)) {
    const test::ParsedBlock parsed(line);
    bool axis = false;
    for (const gcode::Word& w : parsed.block.words) {
      if (!w.has_value || !w.value.is_literal()) continue;
      const double v = w.value.literal;
      switch (w.letter) {
        case 'X': at.x = v, axis = true; break;
        case 'Y': at.y = v, axis = true; break;
        case 'Z': at.z = v, axis = true; break;
        case 'A': at.a = v, axis = true; break;
        case 'B': at.b = v, axis = true; break;
        case 'C': at.c = v, axis = true; break;
        case 'G': moving = moving || v == 0.0 || v == 1.0; break;
        default: break;
      }
    }
    if (axis && moving) points.push_back(at);
  }
  return points;
}

/// How far the tool ends up from where the TCP program means, run on the reference's control
/// in 16 steps a move: the tip from the program's path (the meant tips' polyline), the tool's
/// direction from the program's where the tip is nearest it (beyond kAwayFromSingular of the
/// singular pose).
struct TcpLanding {
  double tip = 0.0, direction = 0.0;
};

TcpLanding run_on_reference(const FiveAxisCase& c, const std::vector<FiveAxisWords>& meant,
                            const std::vector<FiveAxisWords>& run) {
  std::vector<Eigen::Vector3d> path;
  for (const FiveAxisWords& w : meant) path.push_back(c.pose({w.x, w.y, w.z, 0, 0, 0}, false).tip);
  TcpLanding l;
  for (std::size_t k = 1; k < run.size(); ++k)
    for (int j = 0; j <= 16; ++j) {
      const FiveAxisWords words = between(run[k - 1], run[k], j / 16.0);
      const PartPose actual = c.pose(reference_joints(c, words), true);
      double nearest = std::numeric_limits<double>::infinity();
      FiveAxisWords there;
      for (std::size_t m = 1; m < path.size(); ++m) {
        const Eigen::Vector3d d = path[m] - path[m - 1];
        const double f = std::clamp((actual.tip - path[m - 1]).dot(d) / d.squaredNorm(), 0.0, 1.0);
        const double off = (actual.tip - (path[m - 1] + f * d)).norm();
        if (off < nearest) nearest = off, there = between(meant[m - 1], meant[m], f);
      }
      l.tip = std::max(l.tip, nearest);
      if (std::abs(c.head ? there.b : there.a) > kAwayFromSingular)
        l.direction = std::max(l.direction, angle_between(actual.axis, c.pose({0, 0, 0, there.a, there.b, there.c}, false).axis));
    }
  return l;
}

/// verify, following the TCP moves through ccomp's kinematics on the model, agrees: the
/// compensated program within the tolerance of the original's path, nothing left uncut.
void expect_verify_agrees(const std::string& original, const std::string& compensated, const model::MachineModel& mm,
                          const gcode::InterpreterOptions& interpreter, double tolerance, const std::string& name) {
  CheckOptions o;
  o.interpreter = interpreter;
  gcode::LineSource a = gcode::LineSource::from_string(original, "original.ngc");
  gcode::LineSource b = gcode::LineSource::from_string(compensated, "out.ngc");
  const PathError e = verify(a, b, model::ForwardModel(mm), o);
  EXPECT_LT(e.max, tolerance) << name;
  EXPECT_EQ(e.uncut_length, 0.0) << name;
}

/// On the reference, compensated: the tip within the tolerance and the tool within 10 urad,
/// at least 5 times closer in direction than uncompensated (which, with all the reference's
/// errors, leaves the tip 10 tolerances and more off).
void expect_landing(const TcpLanding& after, const TcpLanding& before, double tolerance, const std::string& name,
                    bool all_errors) {
  EXPECT_LT(after.tip, tolerance) << name;
  EXPECT_LT(after.direction, 10e-6) << name;
  EXPECT_LT(after.direction, before.direction / 5) << name;
  if (all_errors) EXPECT_GT(before.tip, 10 * tolerance) << name;
}

TEST_P(FiveAxis, ATcpProgramCutsOnTheReferenceWhereItMeans) {
  const FiveAxisCase& c = GetParam();
  const std::vector<FiveAxisWords> points = tcp_sweep(c.head);
  const model::MachineModel mm = model::parse_machine_model(c.model, c.name + ".yaml");
  const std::string original = program_of(points, c.head, true);
  JobOptions job;
  job.interpreter = with_test_tool();
  JobReport report;
  const std::string compensated = test::compensate(original, mm, job, &report);
  const std::vector<FiveAxisWords> run = points_of(compensated);
  ASSERT_GE(run.size(), points.size()) << compensated;
  // Uncompensated, the reference's errors turn the tool by 1 to 700 urad, and all of them
  // take the tip 25 to 35 um off.
  expect_landing(run_on_reference(c, points, run), run_on_reference(c, points, points), job.tolerance, c.name,
                 c.name.ends_with("All"));
  expect_verify_agrees(original, compensated, mm, with_test_tool(), job.tolerance, c.name);
}

// An arc under TCP, run on the reference's control as its G1 lines (the job writes it so):
// the tip half round a 30 mm circle in the part while the tool tilts from 15 to 30 degrees
// and C turns 90, on each reference with all its errors. The path meant is the arc (720 of
// its points, 0.07 um off it between); the compensated tip stays within the tolerance of it and the tool within
// 10 urad of its direction, where uncompensated they are 10 tolerances and more off.
TEST(FiveAxisTcp, AnArcCutsOnTheReferenceWhereItMeans) {
  for (const FiveAxisCase& c : five_axis_cases()) {
    if (!c.name.ends_with("All")) continue;
    const char rotary = c.head ? 'B' : 'A';
    const std::string original = fmt::format(
        "G21 G90 G94 G17\nG43.4 H2\nG0 X30 Y0 Z10 {0}15 C0\nG3 X-30 Y0 I-30 J0 {0}30 C90 F1000\nG49\nM2\n", rotary);
    std::vector<FiveAxisWords> meant;
    for (int k = 0; k <= 720; ++k) {
      const double s = k / 720.0, angle = std::numbers::pi * s;
      FiveAxisWords w{30 * std::cos(angle), 30 * std::sin(angle), 10, 0, 0, 90 * s};
      (c.head ? w.b : w.a) = 15 + 15 * s;
      meant.push_back(w);
    }
    const model::MachineModel mm = model::parse_machine_model(c.model, c.name + ".yaml");
    JobOptions job;
    job.interpreter = with_test_tool();
    const std::string compensated = test::compensate(original, mm, job);
    EXPECT_EQ(compensated.find("G3"), std::string::npos) << compensated;
    const std::vector<FiveAxisWords> run = points_of(compensated);
    ASSERT_GT(run.size(), 100U) << compensated;
    // Uncompensated, the control runs the arc itself: a point every degree stands for it
    // (1.1 um off the arc between, where the errors take the tip 25 um and more off).
    std::vector<FiveAxisWords> every_degree;
    for (std::size_t k = 0; k < meant.size(); k += 4) every_degree.push_back(meant[k]);
    expect_landing(run_on_reference(c, meant, run), run_on_reference(c, meant, every_degree), job.tolerance, c.name,
                   true);
    expect_verify_agrees(original, compensated, mm, with_test_tool(), job.tolerance, c.name);
  }
}

// A program that gives the tool's direction (G43.5's I J K), run on the reference's control:
// its own inverse for the direction (Newton on the reference's perfect pose, from the angles
// before) and for the tip, the direction turned along the great circle between the written
// points. A sweep like the TCP test's, the tool tilting from 10 to 40 degrees and C turning
// 210 (off the singular pose, where a G43.5 move that leaves it is refused), as directions,
// the rotary axes set to its first angles before G43.5.

/// The reference control's angles for a tool direction: Newton on its perfect machine's tool
/// axis over the two rotary axes (deg), from `near`.
FiveAxisWords reference_angles(const FiveAxisCase& c, const Eigen::Vector3d& axis, FiveAxisWords near) {
  auto direction = [&](const FiveAxisWords& w) { return c.pose({0, 0, 0, w.a, w.b, w.c}, false).axis; };
  for (int step = 0; step < 40; ++step) {
    const Eigen::Vector3d at = direction(near);
    if ((at - axis).norm() < 1e-14) break;
    Eigen::Matrix<double, 3, 2> columns;
    for (int k = 0; k < 2; ++k) {
      FiveAxisWords ahead = near, behind = near;
      double& a = k == 0 ? (c.head ? ahead.b : ahead.a) : ahead.c;
      double& b = k == 0 ? (c.head ? behind.b : behind.a) : behind.c;
      a += 1e-5, b -= 1e-5;
      columns.col(k) = (direction(ahead) - direction(behind)) / 2e-5;
    }
    const Eigen::Matrix2d normal = columns.transpose() * columns + 1e-12 * Eigen::Matrix2d::Identity();
    const Eigen::Vector2d turn = normal.ldlt().solve(columns.transpose() * (axis - at));
    (c.head ? near.b : near.a) += turn[0];
    near.c += turn[1];
  }
  return near;
}

Eigen::Vector3d along_great_circle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double t) {
  const double angle = angle_between(a, b);
  if (angle < 1e-12) return a;
  return ((std::sin((1 - t) * angle) * a + std::sin(t * angle) * b) / std::sin(angle)).normalized();
}

struct TipAndDirection {
  FiveAxisWords tip;  ///< x y z (the angles unused)
  Eigen::Vector3d direction;
};

/// Each G0/G1 point of a G43.5 program: X Y Z and I J K as its words say (absolute, modal).
std::vector<TipAndDirection> direction_points_of(const std::string& program) {
  std::vector<TipAndDirection> points;
  TipAndDirection at{{}, Eigen::Vector3d::UnitZ()};
  std::istringstream lines(program);
  std::string line;
  bool tcp = false;
  while (std::getline(lines, line)) {
    const test::ParsedBlock parsed(line);
    bool moved = false;
    for (const gcode::Word& w : parsed.block.words) {
      if (!w.has_value || !w.value.is_literal()) continue;
      const double v = w.value.literal;
      switch (w.letter) {
        case 'X': at.tip.x = v, moved = true; break;
        case 'Y': at.tip.y = v, moved = true; break;
        case 'Z': at.tip.z = v, moved = true; break;
        case 'I': at.direction.x() = v, moved = true; break;
        case 'J': at.direction.y() = v, moved = true; break;
        case 'K': at.direction.z() = v, moved = true; break;
        case 'G': tcp = (tcp || std::abs(v - 43.5) < 1e-9) && v != 49.0; break;
        default: break;
      }
    }
    if (moved && tcp) points.push_back({at.tip, at.direction.normalized()});
  }
  return points;
}

TcpLanding run_directions_on_reference(const FiveAxisCase& c, const std::vector<TipAndDirection>& meant,
                                       const std::vector<TipAndDirection>& run, FiveAxisWords angles) {
  std::vector<Eigen::Vector3d> path;
  for (const TipAndDirection& p : meant) path.push_back(c.pose({p.tip.x, p.tip.y, p.tip.z, 0, 0, 0}, false).tip);
  TcpLanding l;
  for (std::size_t k = 1; k < run.size(); ++k)
    for (int j = 0; j <= 16; ++j) {
      const double t = j / 16.0;
      angles = reference_angles(c, along_great_circle(run[k - 1].direction, run[k].direction, t), angles);
      FiveAxisWords words = between(run[k - 1].tip, run[k].tip, t);
      words.a = angles.a, words.b = angles.b, words.c = angles.c;
      const PartPose actual = c.pose(reference_joints(c, words), true);
      double nearest = std::numeric_limits<double>::infinity();
      Eigen::Vector3d meant_direction = Eigen::Vector3d::UnitZ();
      for (std::size_t m = 1; m < path.size(); ++m) {
        const Eigen::Vector3d d = path[m] - path[m - 1];
        const double f = std::clamp((actual.tip - path[m - 1]).dot(d) / d.squaredNorm(), 0.0, 1.0);
        const double off = (actual.tip - (path[m - 1] + f * d)).norm();
        if (off < nearest)
          nearest = off, meant_direction = along_great_circle(meant[m - 1].direction, meant[m].direction, f);
      }
      l.tip = std::max(l.tip, nearest);
      if (angle_between(meant_direction, Eigen::Vector3d::UnitZ()) > kAwayFromSingular * kRadPerDeg)
        l.direction = std::max(l.direction, angle_between(actual.axis, meant_direction));
    }
  return l;
}

/// tcp_sweep() with the tool tilting from 10 to 40 degrees: never at the singular pose.
std::vector<FiveAxisWords> off_pole_sweep(bool head) {
  std::vector<FiveAxisWords> sweep = tcp_sweep(head);
  for (std::size_t k = 0; k < sweep.size(); ++k) (head ? sweep[k].b : sweep[k].a) = 10 + 30 * static_cast<double>(k) / 60.0;
  return sweep;
}

TEST(FiveAxisTcp, AG43_5ProgramCutsOnTheReferenceWhereItMeans) {
  for (const FiveAxisCase& c : five_axis_cases()) {
    if (!c.name.ends_with("All")) continue;
    const std::vector<FiveAxisWords> sweep = off_pole_sweep(c.head);
    std::string original = fmt::format("G21 G90 G94 G17\nG0 {}{:.6f} C{:.6f}\nG43.5 H2\n", c.head ? 'B' : 'A',
                                       c.head ? sweep[0].b : sweep[0].a, sweep[0].c);
    for (std::size_t k = 0; k < sweep.size(); ++k) {
      const FiveAxisWords& w = sweep[k];
      const Eigen::Vector3d d = c.pose({0, 0, 0, w.a, w.b, w.c}, false).axis;
      original += fmt::format("{} X{:.6f} Y{:.6f} Z{:.6f} I{:.9f} J{:.9f} K{:.9f}{}\n", k == 0 ? "G0" : "G1", w.x, w.y,
                              w.z, d.x(), d.y(), d.z(), k == 0 ? "" : " F1000");
    }
    original += "G49\nM2\n";
    const model::MachineModel mm = model::parse_machine_model(c.model, c.name + ".yaml");
    JobOptions job;
    job.interpreter = with_test_tool();
    const std::string compensated = test::compensate(original, mm, job);
    const std::vector<TipAndDirection> program = direction_points_of(original), run = direction_points_of(compensated);
    ASSERT_EQ(program.size(), sweep.size());
    ASSERT_GE(run.size(), program.size()) << compensated;
    const std::string under = compensated.substr(compensated.find("G43.5"));
    EXPECT_EQ(under.find_first_of("ABC"), std::string::npos) << "no angle words under G43.5\n" << compensated;
    FiveAxisWords start{};
    (c.head ? start.b : start.a) = c.head ? sweep[0].b : sweep[0].a;
    start.c = sweep[0].c;
    expect_landing(run_directions_on_reference(c, program, run, start),
                   run_directions_on_reference(c, program, program, start), job.tolerance, c.name, true);
    expect_verify_agrees(original, compensated, mm, with_test_tool(), job.tolerance, c.name);
  }
}

// Siemens' TRAORI in its basic settings (ORIWKS, ORIVECT): the program gives the rotary axes'
// angles, the control turns the tool's direction along the great circle between them. The
// same sweep in Siemens syntax, run on the reference's control as the G43.5 program is, the
// directions those of the written angles on the reference's perfect machine.
TEST(FiveAxisTcp, ATraoriProgramOnAGreatCircleCutsOnTheReferenceWhereItMeans) {
  for (const FiveAxisCase& c : five_axis_cases()) {
    if (!c.name.ends_with("All")) continue;
    const std::vector<FiveAxisWords> sweep = off_pole_sweep(c.head);
    const char rotary = c.head ? 'B' : 'A';
    std::string original = "G71 G90 G94 G17\nT2 M6 D1\nTRAORI\n";
    for (std::size_t k = 0; k < sweep.size(); ++k) {
      const FiveAxisWords& w = sweep[k];
      original += fmt::format("{} X{:.6f} Y{:.6f} Z{:.6f} {}{:.6f} C{:.6f}{}\n", k == 0 ? "G0" : "G1", w.x, w.y, w.z,
                              rotary, c.head ? w.b : w.a, w.c, k == 0 ? "" : " F1000");
    }
    original += "TRAFOOF\nM30\n";
    const model::MachineModel mm = model::parse_machine_model(c.model, c.name + ".yaml");
    JobOptions job;
    job.interpreter = with_test_tool();
    job.interpreter.dialect = *gcode::dialect_named("siemens");
    const std::string compensated = test::compensate(original, mm, job);
    auto as_directions = [&](const std::vector<FiveAxisWords>& points) {
      std::vector<TipAndDirection> out;
      for (const FiveAxisWords& w : points) out.push_back({w, c.pose({0, 0, 0, w.a, w.b, w.c}, false).axis});
      return out;
    };
    // (points_of reads RS-274: the lines of TRAORI's commands left out)
    std::string moves;
    std::istringstream lines(compensated);
    for (std::string line; std::getline(lines, line);)
      if (line.find("TRA") == std::string::npos) moves += line + "\n";
    const std::vector<TipAndDirection> meant = as_directions(written(sweep)), run = as_directions(points_of(moves));
    ASSERT_GE(run.size(), meant.size()) << compensated;
    expect_landing(run_directions_on_reference(c, meant, run, sweep[0]),
                   run_directions_on_reference(c, meant, meant, sweep[0]), job.tolerance, c.name, true);
  }
}

// The zero model writes a TCP program back as it is, bar ccomp's header line: nothing is
// corrected, nothing misread.
TEST(FiveAxisTcp, TheZeroModelWritesATcpProgramBackByteForByte) {
  const std::string original = program_of(tcp_sweep(false), false, true);
  const model::MachineModel zero = model::parse_machine_model(
      test::ccomp_model(ReferenceTrunnion{}) + "  []\n", "reference-trunnion.yaml");
  JobOptions job;
  job.interpreter = with_test_tool();
  const std::string written = test::compensate(original, zero, job);
  ASSERT_TRUE(written.starts_with("(ccomp ")) << written;
  EXPECT_EQ(written.substr(written.find('\n') + 1), original);
}

}  // namespace
}  // namespace ccomp::compensate
