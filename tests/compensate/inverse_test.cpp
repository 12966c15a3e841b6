// The inverse: for a model with every kind of term, Newton lands the actual tool tip on the
// nominal point to below 1 nm, corrects the table's own rotation through B, and reports the
// orientation it cannot correct.
#include "ccomp/compensate/inverse.hpp"

#include <gtest/gtest.h>

#include <numbers>
#include <random>

#include "ccomp/model/model_file.hpp"
#include "sample_models.hpp"

namespace ccomp::compensate {
namespace {

const std::string kModel = std::string(test::kHmcChain) + R"(
terms:
  - {name: EXX, form: polynomial, coefficients: [3, 0.02, -3.0e-5]}
  - {name: EXX, form: periodic, period: 10 mm, harmonics: [[2, -1], [0.5, 0.3]]}
  - {name: ECX, form: polynomial, coefficients: [0, 0.05]}
  - {name: EBZ, form: table, interpolation: cubic, at: [-300, -100, 0, 200, 300], values: [10, -20, 0, 30, 10]}
  - {name: EYZ, form: cross_axis, other: x, coefficients: [[1.0e-2, 2.0e-5]]}
  - {name: EAY, value: 12}
  - {name: EZS, variable: T_spindle, form: thermal, coefficient: 1.5}
  - {name: EBB, form: periodic, period: 90 deg, harmonics: [[25, 13]]}
  - {name: EC0X, value: 15}
  - {name: EA0B, value: 8}
  - {name: EXB, form: polynomial, coefficients: [20, 0.01]}
)";

TEST(Inverse, LandsTheToolTipOnTheNominalPointBelowANanometre) {
  const model::MachineModel mm = model::parse_machine_model(kModel, "m.yaml");
  const model::ForwardModel m(mm);
  const InverseProblem problem(m);
  ASSERT_EQ(problem.unknowns.size(), 4U);
  model::ForwardData d(m);
  model::Conditions c;
  c.temperatures = {31.0};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 50; ++trial) {
    model::ChainQ q = model::ChainQ::Zero();
    q << 300 * u(rng), 250 * u(rng), 200 * u(rng), 0, 3.1 * u(rng), 0, 0, 0, 0, 80 + 60 * u(rng);
    const InverseResult r = solve_inverse(m, problem, d, q, c);
    ASSERT_TRUE(r.converged) << "trial " << trial << " after " << r.iterations << " iterations, residual "
                             << r.position_residual.transpose();
    EXPECT_LE(r.iterations, 6);
    // Check independently with a fresh evaluation.
    model::ForwardData check(m), nominal(m);
    model::forward(m, check, r.q, c);
    model::forward(m, nominal, q, c);
    EXPECT_LT((check.actual - nominal.nominal).norm(), 1e-6) << "trial " << trial;
    // The correction is of the size of the errors (tens of um), not of the axes.
    EXPECT_LT((r.q - q).head<3>().norm(), 0.5);
    EXPECT_GT((r.q - q).head<3>().norm(), 1e-4);
    EXPECT_NEAR(r.q[9], q[9], 0.0) << "the tool length is not an unknown";
    // Orientation about B is corrected; what is left is about the other axes.
    const Eigen::Vector3d b_axis_in_tool = check.R_nominal.transpose() * Eigen::Vector3d(0, -1, 0);
    EXPECT_LT(std::abs(b_axis_in_tool.dot(r.orientation_error)), 1e-8);
  }
}

TEST(Inverse, AStreamOfNeighboursReusesTheJacobianAndStillLandsBelowANanometre) {
  // A path in even steps (what a finishing program is), with a tool change, a table index
  // and a reversal along it: every point must land as a cold solve does, while the exact
  // Jacobian is evaluated for few of them. A stream told each point's nominal pose lands on
  // the same numbers to the last bit.
  const model::MachineModel mm = model::parse_machine_model(kModel + R"(
  - {name: EXX, variable: vx, form: reversal, reversal: -4 um}
)",
                                                            "m.yaml");
  const model::ForwardModel m(mm);
  const InverseProblem problem(m);
  model::ForwardData d(m), check(m), nominal(m), told(m);
  model::Conditions c;
  c.temperatures = {31.0};
  InverseWorkspace ws, ws_told;
  const int points = 2000;
  for (int k = 0; k < points; ++k) {
    const double s = k * 0.05;
    model::ChainQ q = model::ChainQ::Zero();
    q << -50 + (k < 1200 ? s : 120 - (s - 60)), 20 + 0.2 * std::sin(s / 7), -30 + 0.002 * s * s, 0,
        k < 1500 ? 0.0 : 0.5, 0, 0, 0, 0, k < 700 ? 100.0 : 130.0;
    c.directions[0] = k < 1200 ? 1.0 : -1.0;
    model::forward(m, nominal, q, c);
    const InverseResult r = solve_inverse(m, problem, d, q, c, {}, nullptr, &ws);
    ASSERT_TRUE(r.converged) << "point " << k << " after " << r.iterations << " iterations";
    const NominalPose pose{nominal.nominal, nominal.R_nominal};
    ASSERT_EQ(solve_inverse(m, problem, told, q, c, {}, nullptr, &ws_told, &pose).q, r.q) << "point " << k;
    model::forward(m, check, r.q, c);
    ASSERT_LT((check.actual - nominal.nominal).norm(), 1e-6) << "point " << k;
    ASSERT_EQ(r.q[9], q[9]) << "point " << k << ": the tool length is this point's";
  }
  EXPECT_LT(ws.jacobian_evaluations, static_cast<std::size_t>(points / 20));
}

TEST(Inverse, AStreamWhoseTableTurnsTurnsItsSolveMatrixWithIt) {
  // A 4-axis wrap: X creeps while B turns half a degree a point, three whole turns. The
  // solve matrix's position columns must follow the table's turn, or the Jacobian kept
  // from a few degrees back fails the tenfold test and is evaluated afresh every dozen
  // points. Every point still lands below a nanometre, in about one Newton step.
  const model::MachineModel mm = model::parse_machine_model(kModel, "m.yaml");
  const model::ForwardModel m(mm);
  const InverseProblem problem(m);
  model::ForwardData d(m), check(m);
  model::Conditions c;
  c.temperatures = {31.0};
  c.directions[4] = 1.0;
  InverseWorkspace ws;
  const int points = 2160;
  long iterations = 0;
  for (int k = 0; k < points; ++k) {
    model::ChainQ q = model::ChainQ::Zero();
    q << -50 + 0.005 * k, 20, -60, 0, k * 0.5 * std::numbers::pi / 180, 0, 0, 0, 0, 100;
    const InverseResult r = solve_inverse(m, problem, d, q, c, {}, nullptr, &ws);
    ASSERT_TRUE(r.converged) << "point " << k << " after " << r.iterations << " iterations";
    iterations += r.iterations;
    model::forward(m, check, r.q, c);
    ASSERT_LT((check.actual - r.target).norm(), 1e-6) << "point " << k;
  }
  EXPECT_LT(ws.jacobian_evaluations, static_cast<std::size_t>(points / 100));
  // Broyden's update within each solve follows the slopes as they turn: about one step a
  // point (a point and a half without it).
  EXPECT_LT(iterations, points * 5 / 4);
}

TEST(Inverse, APlayTakenUpPointByPointIsPredictedFromTheLastTakeUp) {
  // Along a finishing pass B's correction creeps by nanoradians a point, and with it the
  // table's play is taken up a little at every move: the compensator solves each point
  // again for the play its move left. How the solution moves per unit of B's approach is
  // learnt from one such solve and predicted for the next, so the solves again, and the
  // path's next points, land below a nanometre at their first evaluation.
  const model::MachineModel mm = model::parse_machine_model(kModel + R"(
  - {name: EBB, variable: vb, form: reversal, unit: urad, reversal: -10}
)",
                                                            "m.yaml");
  const model::ForwardModel m(mm);
  const InverseProblem problem(m);
  model::ForwardData d(m), check(m), nominal(m);
  model::Conditions c;
  c.temperatures = {31.0};
  c.directions[0] = 1.0;
  c.directions[4] = -1.0;
  InverseWorkspace ws;
  const int points = 400;
  int second_evaluations = 0;
  for (int k = 0; k < points; ++k) {
    model::ChainQ q = model::ChainQ::Zero();
    q << 150 + 0.05 * k, 20, -30 + 0.001 * k, 0, 0, 0, 0, 0, 0, 100;
    model::forward(m, nominal, q, c, false, model::Evaluate::nominal);
    for (const bool again : {false, true}) {
      if (again) c.directions[4] += 0.002;  // the play this move took up
      const InverseResult r = solve_inverse(m, problem, d, q, c, {}, nullptr, &ws);
      ASSERT_TRUE(r.converged) << "point " << k;
      second_evaluations += r.iterations > 0 ? 1 : 0;
      model::forward(m, check, r.q, c);
      ASSERT_LT((check.actual - nominal.nominal).norm(), 1e-6) << "point " << k << (again ? ", again" : "");
    }
  }
  EXPECT_LT(second_evaluations, points / 50);
}

TEST(Inverse, AHeadOverATableSolvesTheToolsDirectionAndKeepsItsBranchAtTheSingularPose) {
  // A B head over a C table (one rotary axis on each side), with both lines' location
  // errors: the tip lands below a nanometre and the tool's direction in the part below the
  // angle tolerance, the tool's turn about its own axis left alone; at B 0 (the tool along
  // C's line) C stays within a milliradian of the program's value and what is left is
  // reported.
  const model::MachineModel mm = model::parse_machine_model(R"(
name: head-b-table-c
axes: {X: {}, Y: {}, Z: {}, B: {type: rotary}, C: {type: rotary}}
chain:
  workpiece:
    - {link: X, axis: X, direction: [-1, 0, 0]}
    - {link: C, axis: C, direction: [0, 0, -1], offset: [20 mm, -10 mm, 0 mm]}
    - {link: part, offset: [-20 mm, 10 mm, 250 mm]}
  tool:
    - {link: Y, axis: Y, direction: [0, 1, 0]}
    - {link: Z, axis: Z, direction: [0, 0, 1], offset: [0 mm, 0 mm, 400 mm]}
    - {link: B, axis: B, direction: [0, 1, 0]}
    - {link: tool, tool_length: [0, 0, -1], offset: [0 mm, 0 mm, -150 mm]}
terms:
  - {name: EX0B, value: 8}
  - {name: EA0B, value: 14}
  - {name: EC0B, value: -9}
  - {name: EX0C, value: -6}
  - {name: EA0C, value: 11}
  - {name: EB0C, value: 13}
  - {name: EBB, form: periodic, period: 360 deg, harmonics: [[0, 12]]}
)",
                                                            "m.yaml");
  const model::ForwardModel m(mm);
  const InverseProblem problem(m);
  ASSERT_EQ(problem.orientation, OrientationEquations::tool_direction);
  model::ForwardData d(m), check(m), nominal(m);
  for (const double b_deg : {30.0, -25.0, 0.0}) {
    for (const double c_deg : {0.0, 100.0, -170.0}) {
      model::ChainQ q = model::ChainQ::Zero();
      q << 35, -20, 60 + 90, 0, b_deg * std::numbers::pi / 180, c_deg * std::numbers::pi / 180, 0, 0, 0, 90;
      const InverseResult r = solve_inverse(m, problem, d, q, {});
      ASSERT_TRUE(r.converged) << "B" << b_deg << " C" << c_deg;
      model::forward(m, check, r.q, {});
      model::forward(m, nominal, q, {});
      EXPECT_LT((check.actual - nominal.nominal).norm(), 1e-6) << "B" << b_deg << " C" << c_deg;
      const Eigen::Vector3d meant = nominal.R_nominal * problem.tool_axis, got = check.R_actual * problem.tool_axis;
      const double direction = meant.cross(got).norm();
      EXPECT_NEAR(direction, r.orientation_error.norm(), 1e-9) << "what is left is what is reported";
      EXPECT_LT(std::abs(r.q[5] - q[5]), 1e-3) << "C keeps the program's branch";
      if (b_deg != 0.0) {
        EXPECT_LT(direction, 1e-7) << "B" << b_deg << " C" << c_deg;
      }
    }
  }
}

TEST(Inverse, ThreeAxisMachineHasNoOrientationEquation) {
  const model::MachineModel mm = model::parse_machine_model(std::string(test::kVmcChain) + R"(
terms:
  - {name: EXX, form: polynomial, coefficients: [0, 0.015]}
  - {name: EBX, value: 25}
  - {name: EC0X, value: 10}
)",
                                                            "vmc.yaml");
  const model::ForwardModel m(mm);
  const InverseProblem problem(m);
  EXPECT_EQ(problem.unknowns.size(), 3U);
  EXPECT_TRUE(problem.rotary_unknowns.empty());
  model::ForwardData d(m);
  model::ChainQ q = model::ChainQ::Zero();
  q << 250, -120, -80, 0, 0, 0, 0, 0, 0, 100;
  const InverseResult r = solve_inverse(m, problem, d, q, {});
  ASSERT_TRUE(r.converged);
  EXPECT_LT(r.position_residual.norm(), 1e-6);
  EXPECT_GT(r.orientation_error.norm(), 1e-5) << "EBX tilts the tool; a 3-axis machine cannot correct that";
}

}  // namespace
}  // namespace ccomp::compensate
