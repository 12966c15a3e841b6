// verify() and predict() are the instruments every closed-loop test reads: here they are
// checked against answers known without them, on paths where a careless distance or a
// careless sampling goes wrong (arcs meeting at corners, helices of several turns, arcs
// whose ends are at different radii, full circles).
#include "ccomp/compensate/verify.hpp"

#include <gtest/gtest.h>

#include <string>

#include "ccomp/model/forward.hpp"
#include "ccomp/model/machine.hpp"
#include "job_runner.hpp"
#include "sample_models.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

/// Arcs in all three planes, meeting each other at corners, a helix of three turns, a full
/// circle, an arc whose end radius differs from its start's (within LinuxCNC's tolerance).
constexpr const char* kArcs = R"(G21 G90 G94 F500
G0 X0 Y0 Z0
G18 G1 X10
G3 X20 Z-2 R6
G3 X30 Z0 R6
G2 X34 Z4 I4 K0
G17 G2 X44 Y0 I5 J0
G2 X44 Y0 Z-3 I-5 J0 P3
G3 X44.0 Y0.0 I-12 J0
G1 Z0
G19 G2 Y8 Z0 J4 K0
G3 Y16 Z0 J4.0002 K0
G17 G1 X0 Y16
M2
)";

compensate::PathError verify_text(const std::string& original, const std::string& compensated,
                                  const model::ForwardModel& m) {
  gcode::LineSource a = gcode::LineSource::from_string(original, "in.ngc");
  gcode::LineSource b = gcode::LineSource::from_string(compensated, "out.ngc");
  return compensate::verify(a, b, m, {});
}

/// A 3-axis machine without error terms: the executed path is the commanded one.
const model::MachineModel& exact_machine() {
  static const model::MachineModel mm = model::parse_machine_model(kVmcChain, "exact.yaml");
  return mm;
}

TEST(Verify, AProgramAgainstItselfOnAnExactMachineLeavesNothing) {
  const model::ForwardModel m(exact_machine());
  const compensate::PathError e = verify_text(kArcs, kArcs, m);
  EXPECT_GT(e.points, 200U);
  EXPECT_LT(e.max, 1e-9) << "at line " << e.worst_line;
}

TEST(Verify, AShiftedProgramIsNoFurtherFromThePathThanItsShift) {
  // The work offset moves the executed path by (0.4, -0.3, 0.2) um, 0.54 um: no point is
  // further from the nominal path than that, and where the path runs across the shift
  // (the lines along X, the arcs) some point is nearly that far.
  const std::string shifted = std::string("G10 L2 P1 X0.0004 Y-0.0003 Z0.0002\n") + kArcs;
  const model::ForwardModel m(exact_machine());
  const compensate::PathError e = verify_text(kArcs, shifted, m);
  const double shift = std::sqrt(0.16 + 0.09 + 0.04) * 1e-3;
  // On a helix the distance is taken at the point's own angle: an upper bound, above the
  // true one by a fraction of the order of the helix' slope squared (here 1e-3).
  EXPECT_LE(e.max, shift * (1 + 1e-3)) << "at line " << e.worst_line;
  EXPECT_GT(e.max, 0.9 * shift);
}

TEST(Predict, AFullCircleIsSampledAllRound) {
  // A machine whose X scale is off: the error is largest where the circle reaches
  // furthest along X, half a turn from where it starts and ends.
  const model::MachineModel mm = model::parse_machine_model(std::string(kVmcChain) + R"(
terms:
  - {name: EXX, form: polynomial, coefficients: [0, 0.2]}
)",
                                                            "vmc.yaml");
  const model::ForwardModel m(mm);
  model::ForwardData d(m);
  double expected = 0;
  for (double x : {-50.0, 50.0}) {
    model::forward(m, d, compensate::chain_of({x, 0, 0}, gcode::Offsets{}), {});
    expected = std::max(expected, (d.actual - d.nominal).norm());
  }
  ASSERT_GT(expected, 1e-3);
  gcode::LineSource program =
      gcode::LineSource::from_string("G21 G90 G17 F500\nG0 X0 Y50 Z0\nG2 X0 Y50 I0 J-50\nM2\n", "circle.ngc");
  const compensate::PathError e = compensate::predict(program, m, {});
  EXPECT_NEAR(e.max, expected, 1e-3 * expected);
}

TEST(Verify, TheJobsFigureForArcsCountsTheirChords) {
  // Large circles become chords whose sagitta approaches half the tolerance: the job's
  // "after" must say so, and verify, which measures from the arcs, agrees within the
  // rounding of the written digits (0.5e-4 mm on each of three axes).
  const model::MachineModel mm = model::parse_machine_model(std::string(kVmcChain) + R"(
terms:
  - {name: EXX, form: polynomial, coefficients: [0, 0.2]}
  - {name: EYY, form: polynomial, coefficients: [0, -0.1]}
)",
                                                            "vmc.yaml");
  const std::string program = "G21 G90 G17 F500\nG0 X0 Y80 Z0\nG2 X0 Y80 I0 J-80\nG3 X-80 Y0 I0 J-80\nM2\n";
  compensate::JobReport report;
  const std::string output = compensate(program, mm, 0.001, &report);
  const compensate::PathError left = verify_text(program, output, model::ForwardModel(mm));
  EXPECT_GT(report.max_error_after, 0.4 * 0.001);
  EXPECT_LE(report.max_error_after, 0.001);
  EXPECT_LE(left.max, report.max_error_after + 0.5e-4 * std::sqrt(3.0));
}

}  // namespace
}  // namespace ccomp::test
