// The control's tool-centre-point kinematics (compensate/tcp_kinematics.hpp) held to the
// reference five-axis machines (tests/support/reference_five_axis.hpp), written apart from
// ccomp's model code: a TCP program's point, turned into the axes' positions, puts the
// reference's perfect tip where the same X Y Z put it with the rotary axes at zero, with the
// tool along the reference's axis for the angles; and a TCP move split by tcp_split() keeps
// the reference's tip, moving the axes in straight lines between the cuts, within the
// tolerance of the control's straight line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <memory>
#include <string>
#include <vector>

#include "ccomp/compensate/machine_coordinates.hpp"
#include "ccomp/compensate/tcp_kinematics.hpp"
#include "ccomp/error.hpp"
#include "ccomp/model/model_file.hpp"
#include "reference_five_axis.hpp"

namespace ccomp {
namespace {

using test::FiveAxisWords;
using test::ReferenceFiveAxis;

constexpr double kToolLength = 120.0;

struct Machine {
  std::string name;
  bool head = false;  ///< B on the head (else A on the trunnion)
  std::string model;
  std::shared_ptr<ReferenceFiveAxis> reference;
};

std::vector<Machine> machines() {
  auto trunnion = std::make_shared<test::ReferenceTrunnion>();
  auto heads = std::make_shared<test::ReferenceHeads>();
  return {{"trunnion", false, test::ccomp_model(*trunnion) + "  []\n", trunnion},
          {"heads", true, test::ccomp_model(*heads) + "  []\n", heads}};
}

gcode::Offsets tool_offsets() {
  gcode::Offsets o;
  o.tool[2] = kToolLength;
  return o;
}

gcode::Axes axes_of(const FiveAxisWords& w) {
  return {w.x, w.y, w.z, w.a, w.b, w.c, 0, 0, 0};
}

FiveAxisWords words_of(const gcode::Axes& a) {
  return {a[0], a[1], a[2], a[3], a[4], a[5]};
}

/// TCP points over the part: tilts from -40 to 35 degrees, C over a turn and more.
std::vector<FiveAxisWords> tcp_points(bool head) {
  std::vector<FiveAxisWords> points;
  for (int k = 0; k <= 24; ++k) {
    const double s = k / 24.0;
    FiveAxisWords w{-45 + 80 * s, 20 * std::sin(5 * s), 30 - 25 * s, 0, 0, -170 + 400 * s};
    (head ? w.b : w.a) = -40 + 75 * s;
    points.push_back(w);
  }
  return points;
}

class TcpKinematicsTest : public ::testing::TestWithParam<Machine> {};

TEST_P(TcpKinematicsTest, APointPutsTheReferenceTipOnThePartAndTheToolAlongTheAngles) {
  const Machine& m = GetParam();
  const model::ForwardModel model(model::parse_machine_model(m.model, m.name + ".yaml"));
  compensate::TcpKinematics tcp(model);
  const gcode::Offsets offsets = tool_offsets();
  for (const FiveAxisWords& w : tcp_points(m.head)) {
    const model::ChainQ q = tcp.joints_of(axes_of(w), offsets);
    const FiveAxisWords joints = words_of(compensate::controlled_of_chain(q, offsets));
    const test::PartPose at = m.reference->nominal(joints, kToolLength);
    const test::PartPose level = m.reference->nominal({w.x, w.y, w.z, 0, 0, 0}, kToolLength);
    const test::PartPose turned = m.reference->nominal({0, 0, 0, w.a, w.b, w.c}, kToolLength);
    EXPECT_LT((at.tip - level.tip).norm(), 1e-9) << m.name << " at x " << w.x << " c " << w.c;
    EXPECT_LT((at.axis - turned.axis).norm(), 1e-12) << m.name << " at x " << w.x << " c " << w.c;
    EXPECT_DOUBLE_EQ(joints.c, w.c);
    // And back: the same point.
    const gcode::Axes back = tcp.world_of(q, offsets);
    for (std::size_t i = 0; i < 6; ++i) EXPECT_NEAR(back[i], axes_of(w)[i], 1e-9) << m.name << " axis " << i;
  }
}

TEST_P(TcpKinematicsTest, AMoveSplitKeepsTheReferenceTipOnTheControlsLine) {
  const Machine& m = GetParam();
  const model::ForwardModel model(model::parse_machine_model(m.model, m.name + ".yaml"));
  compensate::TcpKinematics tcp(model);
  const gcode::Offsets offsets = tool_offsets();
  const std::vector<FiveAxisWords> points = tcp_points(m.head);
  constexpr double kTolerance = 0.5e-3;
  std::size_t pieces = 0;
  for (std::size_t k = 1; k < points.size(); ++k) {
    const gcode::Axes a = axes_of(points[k - 1]), b = axes_of(points[k]);
    const std::vector<double> cuts = compensate::tcp_split(tcp, a, b, offsets, kTolerance);
    ASSERT_GE(cuts.size(), 2U);
    EXPECT_EQ(cuts.front(), 0.0);
    EXPECT_EQ(cuts.back(), 1.0);
    pieces += cuts.size() - 1;
    // Between two cuts the axes move in a straight line; the reference's tip stays within the
    // tolerance of the control's line (the part points of the words in a straight line).
    double worst = 0.0;
    for (std::size_t c = 1; c < cuts.size(); ++c) {
      auto world = [&](double s) {
        gcode::Axes p;
        for (std::size_t i = 0; i < p.size(); ++i) p[i] = a[i] + s * (b[i] - a[i]);
        return p;
      };
      const model::ChainQ qa = tcp.joints_of(world(cuts[c - 1]), offsets), qb = tcp.joints_of(world(cuts[c]), offsets);
      for (int j = 1; j < 16; ++j) {
        const double f = j / 16.0;
        const FiveAxisWords joints = words_of(compensate::controlled_of_chain(qa + f * (qb - qa), offsets));
        const gcode::Axes line = world(cuts[c - 1] + f * (cuts[c] - cuts[c - 1]));
        const test::PartPose drawn = m.reference->nominal({line[0], line[1], line[2], 0, 0, 0}, kToolLength);
        worst = std::max(worst, (m.reference->nominal(joints, kToolLength).tip - drawn.tip).norm());
      }
    }
    EXPECT_LE(worst, kTolerance * 1.05) << m.name << " move " << k;
  }
  // Turning 3 degrees of tilt and 17 of C a move at some 100 mm from the lines, the axes'
  // straight lines leave the tip's by tenths of a millimetre: the moves are split.
  EXPECT_GT(pieces, 4 * (points.size() - 1)) << m.name;
}

TEST_P(TcpKinematicsTest, AMoveWithoutTurningIsOnePiece) {
  const Machine& m = GetParam();
  const model::ForwardModel model(model::parse_machine_model(m.model, m.name + ".yaml"));
  compensate::TcpKinematics tcp(model);
  FiveAxisWords a{-30, 10, 5, 0, 0, 40}, b{60, -25, 20, 0, 0, 40};
  (m.head ? a.b : a.a) = 25, (m.head ? b.b : b.a) = 25;
  EXPECT_EQ(compensate::tcp_split(tcp, axes_of(a), axes_of(b), tool_offsets(), 1e-4), (std::vector<double>{0.0, 1.0}));
}

// A move no machine makes (1e14 mm while the table tilts): refused (ccomp::Error, program)
// within the cap, not split without end.
TEST_P(TcpKinematicsTest, AMoveFarBeyondTheMachineIsRefusedNotSplitForever) {
  const Machine& m = GetParam();
  const model::ForwardModel model(model::parse_machine_model(m.model, m.name + ".yaml"));
  compensate::TcpKinematics tcp(model);
  FiveAxisWords a{0, 0, 20, 0, 0, 0}, b{1e14, 1e14, 20, 0, 0, 0};
  (m.head ? b.b : b.a) = 10;
  try {
    (void)compensate::tcp_split(tcp, axes_of(a), axes_of(b), tool_offsets(), 1e-4, 1000);
    FAIL() << "split";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::program) << e.message();
    EXPECT_NE(e.message().find("a tool-centre-point move"), std::string::npos) << e.message();
  }
}

// An arc under TCP (the tip half round a circle in the part while the tool tilts and C
// turns): its pieces cover the block in order, and both the axes' straight move along each
// and the control's straight line between the pieces' TCP points keep the reference's tip
// within the tolerance of the arc (the arc's part points, 4,000 of them).
TEST_P(TcpKinematicsTest, AnArcsPiecesKeepTheReferenceTipOnTheArc) {
  const Machine& m = GetParam();
  const model::ForwardModel model(model::parse_machine_model(m.model, m.name + ".yaml"));
  compensate::TcpKinematics tcp(model);
  const gcode::Offsets offsets = tool_offsets();
  constexpr double kTolerance = 0.5e-3, kRadius = 30.0;
  gcode::Motion arc;
  arc.kind = gcode::MotionKind::arc;
  arc.offsets = &offsets;
  FiveAxisWords from{kRadius, 0, 10, 0, 0, 0}, to{-kRadius, 0, 10, 0, 0, 90};
  (m.head ? from.b : from.a) = 15, (m.head ? to.b : to.a) = 30;
  arc.start = axes_of(from), arc.end = axes_of(to);
  arc.arc.plane = gcode::Plane::xy, arc.arc.center_first = 0, arc.arc.center_second = 0, arc.arc.turns = 1;
  std::vector<compensate::TcpPiece> pieces;
  compensate::tcp_pieces(tcp, arc, kTolerance, pieces);
  ASSERT_GT(pieces.size(), 50U);
  EXPECT_EQ(pieces.front().from, 0.0);
  EXPECT_EQ(pieces.back().to, 1.0);
  std::vector<Eigen::Vector3d> meant;  // the arc in the part: at rotary zero, where its X Y Z put the tip
  for (int k = 0; k <= 4000; ++k) {
    const double angle = std::numbers::pi * k / 4000.0;
    meant.push_back(m.reference->nominal({kRadius * std::cos(angle), kRadius * std::sin(angle), 10, 0, 0, 0}, kToolLength).tip);
  }
  auto off_arc = [&](const Eigen::Vector3d& p) {
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t k = 1; k < meant.size(); ++k) {
      const Eigen::Vector3d d = meant[k] - meant[k - 1];
      const double f = std::clamp((p - meant[k - 1]).dot(d) / d.squaredNorm(), 0.0, 1.0);
      nearest = std::min(nearest, (p - (meant[k - 1] + f * d)).norm());
    }
    return nearest;
  };
  double axes_off = 0.0, control_off = 0.0;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const compensate::TcpPiece& p = pieces[k];
    EXPECT_EQ(p.motion.kind, gcode::MotionKind::feed);
    EXPECT_FALSE(p.motion.tcp);
    if (k > 0) EXPECT_EQ(p.from, pieces[k - 1].to);
    EXPECT_LT(p.from, p.to);
    const gcode::Axes tcp_a = tcp.world_of(compensate::chain_of(p.motion.start, offsets), offsets);
    const gcode::Axes tcp_b = tcp.world_of(compensate::chain_of(p.motion.end, offsets), offsets);
    for (int j = 0; j <= 8; ++j) {
      const double f = j / 8.0;
      gcode::Axes joints, words;
      for (std::size_t i = 0; i < joints.size(); ++i) {
        joints[i] = p.motion.start[i] + f * (p.motion.end[i] - p.motion.start[i]);
        words[i] = tcp_a[i] + f * (tcp_b[i] - tcp_a[i]);
      }
      axes_off = std::max(axes_off, off_arc(m.reference->nominal(words_of(joints), kToolLength).tip));
      control_off = std::max(control_off, off_arc(m.reference->nominal({words[0], words[1], words[2], 0, 0, 0}, kToolLength).tip));
    }
  }
  EXPECT_LE(axes_off, kTolerance * 1.05) << m.name;
  EXPECT_LE(control_off, kTolerance * 1.05) << m.name;
  EXPECT_GT(axes_off, 0.1 * kTolerance) << m.name << ": pieces no finer than they need";
}

// The tool's direction as a program gives it (G43.5's I J K): along the reference's tool
// axis for the angles, (0, 0, 1) with the rotary axes at zero; and the angles for a
// direction, found from nearby ones, are the angles it came from (the branch nearest), at
// the singular pose without turning the last rotary axis.
TEST_P(TcpKinematicsTest, ADirectionGivesBackTheAnglesNearestTheOnesBefore) {
  const Machine& m = GetParam();
  const model::ForwardModel model(model::parse_machine_model(m.model, m.name + ".yaml"));
  compensate::TcpKinematics tcp(model);
  const gcode::Offsets offsets = tool_offsets();
  auto q_of = [&](double tilt, double c) {
    FiveAxisWords w{10, -5, 20, 0, 0, c};
    (m.head ? w.b : w.a) = tilt;
    return compensate::chain_of(axes_of(w), offsets);
  };
  EXPECT_LT((tcp.direction(q_of(0, 0)) - Eigen::Vector3d::UnitZ()).norm(), 1e-15) << m.name;
  const std::size_t tilt_place = m.head ? 4 : 3;
  for (const double tilt : {-40.0, -5.0, 0.5, 25.0})
    for (const double c : {-170.0, 0.0, 35.0, 200.0}) {
      const model::ChainQ q = q_of(tilt, c);
      FiveAxisWords angles{0, 0, 0, 0, 0, c};
      (m.head ? angles.b : angles.a) = tilt;
      const Eigen::Vector3d axis = m.reference->nominal(angles, kToolLength).axis;
      const Eigen::Vector3d d = tcp.direction(q);
      EXPECT_LT((d - axis).norm(), 1e-12) << m.name << " tilt " << tilt << " c " << c;
      model::ChainQ near = q;
      near[static_cast<Eigen::Index>(tilt_place)] += 0.04, near[5] -= 0.06;
      const std::optional<model::ChainQ> found = tcp.rotary_for(d, near);
      ASSERT_TRUE(found.has_value()) << m.name << " tilt " << tilt << " c " << c;
      EXPECT_NEAR((*found)[static_cast<Eigen::Index>(tilt_place)], q[static_cast<Eigen::Index>(tilt_place)], 1e-9);
      EXPECT_NEAR((*found)[5], q[5], 1e-9) << m.name << " tilt " << tilt << " c " << c;
      EXPECT_EQ((*found)[0], near[0]) << "the linear axes are left alone";
    }
  // Along the last rotary line (tilt 0) C turns the direction nowhere: it stays.
  model::ChainQ tilted = q_of(0.3, 57.0);
  const std::optional<model::ChainQ> upright = tcp.rotary_for(Eigen::Vector3d::UnitZ() * 3.0, tilted);
  ASSERT_TRUE(upright.has_value());
  EXPECT_NEAR((*upright)[static_cast<Eigen::Index>(tilt_place)], 0.0, 1e-9);
  EXPECT_NEAR((*upright)[5], tilted[5], 1e-6);
  EXPECT_FALSE(tcp.rotary_for(Eigen::Vector3d::Zero(), tilted).has_value());
}

// Under G43.5 a move's axes keep the tool within the angular tolerance of the great circle
// too; and a move that leaves the singular pose where its last rotary axis does not point is
// refused (the control would swing that axis at once).
TEST_P(TcpKinematicsTest, AGreatCircleMoveKeepsTheToolOnItAndLeavesNoPoleBySwinging) {
  const Machine& m = GetParam();
  const model::ForwardModel model(model::parse_machine_model(m.model, m.name + ".yaml"));
  compensate::TcpKinematics tcp(model);
  const gcode::Offsets offsets = tool_offsets();
  constexpr double kTolerance = 0.5e-3;
  FiveAxisWords from{-20, 10, 15, 0, 0, 10}, to{30, -5, 20, 0, 0, 80};
  (m.head ? from.b : from.a) = 15, (m.head ? to.b : to.a) = 35;
  const gcode::Axes a = axes_of(from), b = axes_of(to);
  const std::vector<double> cuts = compensate::tcp_split(tcp, a, b, offsets, kTolerance, 100000, nullptr, true);
  compensate::TcpLine line(tcp, a, b, offsets, true);
  double worst = 0.0;
  for (std::size_t c = 1; c < cuts.size(); ++c) {
    const model::ChainQ qa = tcp.joints_of(line.at(cuts[c - 1]), offsets), qb = tcp.joints_of(line.at(cuts[c]), offsets);
    for (int j = 1; j < 8; ++j) {
      const double f = j / 8.0;
      const FiveAxisWords joints = words_of(compensate::controlled_of_chain(qa + f * (qb - qa), offsets));
      const Eigen::Vector3d meant = line.direction_at(cuts[c - 1] + f * (cuts[c] - cuts[c - 1]));
      const Eigen::Vector3d axis = m.reference->nominal(joints, kToolLength).axis;
      worst = std::max(worst, std::atan2(axis.cross(meant).norm(), axis.dot(meant)));
    }
  }
  EXPECT_LT(worst, kTolerance / 10.0 * 1.05) << m.name;  // the angular tolerance: the tolerance over 10 mm
  EXPECT_GT(cuts.size(), 2U) << m.name;
  // From the pole (tilt 0, C at 10) towards a direction C 80 points to.
  FiveAxisWords pole = from;
  (m.head ? pole.b : pole.a) = 0;
  try {
    (void)compensate::tcp_split(tcp, axes_of(pole), b, offsets, kTolerance, 100000, nullptr, true);
    FAIL() << m.name << ": left the pole";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::unsupported) << e.message();
    EXPECT_NE(e.message().find("leaves the singular pose"), std::string::npos) << e.message();
  }
}

INSTANTIATE_TEST_SUITE_P(References, TcpKinematicsTest, ::testing::ValuesIn(machines()),
                         [](const ::testing::TestParamInfo<Machine>& p) { return p.param.name; });

// Without a rotary axis the tip in the part is where the axes put it: a TCP move is its own
// piece, arcs included, its points the axes'.
TEST(TcpKinematics, WithoutRotaryAxesAPointIsTheAxes) {
  const model::ForwardModel model(model::load_machine_model(CCOMP_SOURCE_DIR "/samples/machines/vmc-xyz.yaml"));
  compensate::TcpKinematics tcp(model);
  EXPECT_TRUE(tcp.identity());
  const gcode::Offsets offsets = tool_offsets();
  const gcode::Axes world{12.5, -40, 7, 0, 0, 0, 0, 0, 0};
  const model::ChainQ q = tcp.joints_of(world, offsets);
  EXPECT_EQ(q, compensate::chain_of(world, offsets));
  EXPECT_EQ(tcp.world_of(q, offsets), compensate::controlled_of_chain(q, offsets));
  EXPECT_FALSE(tcp.rotary_for(Eigen::Vector3d::UnitX(), q).has_value()) << "no rotary axis to turn";
  gcode::Motion arc;
  arc.kind = gcode::MotionKind::arc;
  arc.tcp = true;
  arc.start = world;
  arc.end = {30, -40, 7, 0, 0, 0, 0, 0, 0};
  arc.offsets = &offsets;
  std::vector<compensate::TcpPiece> pieces;
  compensate::tcp_pieces(tcp, arc, 1e-4, pieces);
  ASSERT_EQ(pieces.size(), 1U);
  EXPECT_FALSE(pieces[0].motion.tcp);
  EXPECT_EQ(pieces[0].motion.kind, gcode::MotionKind::arc);
  EXPECT_EQ(pieces[0].motion.end, arc.end);
}

}  // namespace
}  // namespace ccomp
