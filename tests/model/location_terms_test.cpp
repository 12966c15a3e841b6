// Location errors in closed form, one term at a time on the seed's HMC: a squareness is a
// shear of its size and sign that turns nothing; the B axis' position is, over a turn, a
// constant deviation equal to it; its tilt turns a point of the table about the tilted line
// (a point on the axis describes the cone the tilt predicts). And the location terms the
// reference frame fixes at zero, or that mean nothing, are refused with the reason.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "ccomp/error.hpp"
#include "ccomp/model/forward.hpp"
#include "ccomp/model/model_file.hpp"
#include "error_of.hpp"
#include "sample_models.hpp"

namespace ccomp::model {
namespace {

constexpr double kRadPerDeg = std::numbers::pi / 180.0;

ForwardModel hmc_with(const std::string& term) {
  return ForwardModel(parse_machine_model(std::string(test::kHmcChain) + "terms:\n  - " + term + "\n", "m.yaml"));
}

struct Point {
  Eigen::Vector3d deviation;  ///< machine-axis directions, mm
  Eigen::Vector3d table;      ///< the nominal tool tip in the table frame, mm
  Eigen::Matrix3d table_to_machine;
  double orientation = 0.0;  ///< the tool's orientation error, rad
};

Point at(const ForwardModel& m, double x, double y, double z, double b_deg, double L = 100.0) {
  ForwardData d(m);
  ChainQ q = ChainQ::Zero();
  q << x, y, z, 0, b_deg * kRadPerDeg, 0, 0, 0, 0, L;
  forward(m, d, q, {});
  const Eigen::AngleAxisd turn(d.R_nominal.transpose() * d.R_actual);
  return {deviation(d), d.nominal, d.nominal_chain.oMp.R, turn.angle()};
}

TEST(LocationTerms, SquarenessIsAShearOfItsSizeAndSignThatTurnsNothing) {
  // ISO: X's line runs along (1, EC0X, -EB0X), Y's along (0, 1, EA0Y), Z's along z.
  struct Case {
    const char* term;
    int moving;      // the axis whose travel the deviation grows with
    int deviating;   // the component it deviates in
    double per_rad;  // deviation per mm of travel, per rad of the term
  };
  for (const Case& c :
       {Case{"{name: EC0X, value: 40, unit: urad}", 0, 1, 1.0}, Case{"{name: EB0X, value: 40, unit: urad}", 0, 2, -1.0},
        Case{"{name: EA0Y, value: 40, unit: urad}", 1, 2, 1.0}, Case{"{name: S_xy, value: 40, unit: urad}", 0, 1, -1.0},
        Case{"{name: S_xz, value: 40, unit: urad}", 0, 2, -1.0},
        Case{"{name: S_yz, value: 40, unit: urad}", 1, 2, -1.0}}) {
    const ForwardModel m = hmc_with(c.term);
    for (const Eigen::Vector3d& p : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(300, -200, 150),
                                     Eigen::Vector3d(-250, 180, -300), Eigen::Vector3d(120, 90, 40)})
      for (double L : {0.0, 250.0}) {
        const Point r = at(m, p.x(), p.y(), p.z(), 0.0, L);
        Eigen::Vector3d expected = Eigen::Vector3d::Zero();
        expected[c.deviating] = c.per_rad * 40e-6 * p[c.moving];
        // The line is turned exactly: it shortens along itself by (1 - cos) of the angle,
        // below 0.3 nm here.
        EXPECT_LT((r.deviation - expected).norm(), 1e-6) << c.term << " at " << p.transpose() << " L " << L;
        EXPECT_LT(r.orientation, 1e-15) << c.term << ": a tilted line of motion turns nothing it carries";
      }
  }
}

TEST(LocationTerms, TheSeedsSquarenessIsPositiveWhenTheAxesOpenBeyondARightAngle) {
  // docs/error-model.md Ref 1: S_xy > 0 when the angle between +X and +Y exceeds 90 deg.
  const ForwardModel m = hmc_with("{name: S_xy, value: 50, unit: urad}");
  const Eigen::Vector3d origin = at(m, 0, 0, 0, 0).deviation;
  const Eigen::Vector3d x_line = Eigen::Vector3d(100, 0, 0) + at(m, 100, 0, 0, 0).deviation - origin;
  const Eigen::Vector3d y_line = Eigen::Vector3d(0, 100, 0) + at(m, 0, 100, 0, 0).deviation - origin;
  const double angle = std::acos(x_line.normalized().dot(y_line.normalized()));
  EXPECT_NEAR(angle - std::numbers::pi / 2, 50e-6, 1e-9);
}

TEST(LocationTerms, TheRotaryAxisPositionIsOverATurnAConstantDeviationEqualToIt) {
  for (const char* term : {"{name: EX0B, value: 12, unit: um}", "{name: EZ0B, value: -8, unit: um}"}) {
    const ForwardModel m = hmc_with(term);
    const Eigen::Index along = term[8] == 'X' ? 0 : 2;
    const double size = term[8] == 'X' ? 0.012 : -0.008;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    const int steps = 360;
    for (int k = 0; k < steps; ++k) {
      const double b = 360.0 * k / steps;
      const Point r = at(m, 35, -20, 60, b);
      // The table turns about the line displaced by -size (tool relative to the work: the
      // deviation's constant part is +size): the point fixed on the table is off by
      // size * (I - Rot(b)) e.
      Eigen::Vector3d e = Eigen::Vector3d::Zero();
      e[along] = size;
      const Eigen::Vector3d expected = e - r.table_to_machine * e;
      EXPECT_LT((r.deviation - expected).norm(), 1e-12) << term << " at B" << b;
      mean += r.deviation / steps;
    }
    Eigen::Vector3d constant = Eigen::Vector3d::Zero();
    constant[along] = size;
    EXPECT_LT((mean - constant).norm(), 1e-12) << term << ": mean " << mean.transpose();
    EXPECT_LT(at(m, 35, -20, 60, 0).deviation.norm(), 1e-15) << term << ": at B0 the line's place shows nowhere";
  }
}

TEST(LocationTerms, TheRotaryAxisTiltTurnsTheTableAboutTheTiltedLine) {
  for (const char* term : {"{name: EA0B, value: 50, unit: urad}", "{name: EC0B, value: -30, unit: urad}"}) {
    const ForwardModel m = hmc_with(term);
    Eigen::Vector3d theta = Eigen::Vector3d::Zero();
    theta[term[8] == 'A' ? 0 : 2] = (term[8] == 'A' ? 50e-6 : -30e-6);
    for (double b : {0.0, 30.0, 90.0, 200.0}) {
      const Point r = at(m, 80, 150, -40, b);
      // The table point n, turned by Rot(b) about the line tilted by theta instead of about
      // -Y: the table moves by theta x (Rot n) - Rot (theta x n); the tool, relative to it,
      // by the opposite (first order; the second, tilt^2 x radius, is below 2 nm here).
      const Eigen::Matrix3d R = r.table_to_machine;
      const Eigen::Vector3d n = r.table;
      const Eigen::Vector3d expected = -(theta.cross(R * n) - R * theta.cross(n));
      EXPECT_LT((r.deviation - expected).norm(), 2e-6) << term << " at B" << b << ": " << r.deviation.transpose();
    }
  }
  // The cone: a point on B's line, h above the table centre, circles with radius tilt * h.
  const ForwardModel m = hmc_with("{name: EA0B, value: 50, unit: urad}");
  const double h = 200.0;
  // The tool at program (0, h, -300) with L 100 stands on the table's axis (table x = z = 0).
  for (double b = 0; b < 360; b += 15) {
    const Point r = at(m, 0, h, -300, b);
    ASSERT_LT(std::hypot(r.table.x(), r.table.z()), 1e-9);
    const Eigen::Vector3d centre(0, 0, -50e-6 * h);  // the circle's centre, where B0 puts it
    EXPECT_NEAR((r.deviation - centre).norm(), 50e-6 * h, 1e-9) << "B" << b;
    EXPECT_NEAR(r.deviation.y(), 0.0, 1e-6);  // the cone's height changes at second order only
  }
}

TEST(LocationTerms, WhatTheReferenceFrameFixesOrWhatMeansNothingIsRefusedWithTheReason) {
  struct Case {
    const char* term;
    const char* reason;
  };
  for (const Case& c : {Case{"{name: EA0Z, value: 5}", "primary axis"}, Case{"{name: EB0Z, value: 5}", "primary axis"},
                        Case{"{name: EC0Y, value: 5}", "Z-Y plane"}, Case{"{name: EA0X, value: 5}", "no roll"},
                        Case{"{name: EY0B, value: 5}", "along itself"}, Case{"{name: EB0B, value: 5}", "EBB"}}) {
    const Error e = test::error_of([&] { (void)hmc_with(c.term); }, c.term, " was accepted");
    EXPECT_EQ(e.kind(), ErrorKind::model) << c.term;
    EXPECT_NE(e.message().find(c.reason), std::string::npos) << c.term << ": " << e.message();
  }
  // A thermal drift of a frame's origin is an error motion, not a location: accepted.
  EXPECT_NO_THROW((void)hmc_with("{name: EA0Z, variable: T_bed, form: thermal, coefficient: 1, unit: urad}"));
}

}  // namespace
}  // namespace ccomp::model
