// verify() and predict() are the instruments every closed-loop test reads: here they are
// checked against answers known without them, on paths where a careless distance or a
// careless sampling goes wrong (arcs meeting at corners, helices of several turns, arcs
// whose ends are at different radii, full circles).
#include "ccomp/compensate/verify.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "ccomp/compensate/program_job.hpp"
#include "ccomp/error.hpp"
#include "ccomp/gcode/dialect.hpp"
#include "ccomp/model/chain_values.hpp"
#include "ccomp/model/forward.hpp"
#include "ccomp/model/machine.hpp"
#include "ccomp/model/model_file.hpp"
#include "ccomp/model/variation_bound.hpp"
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

/// A polygon of `sides` around (0, 0), radius 20, from (20, dy) and back, as G1 lines.
std::string polygon(int sides, double dy) {
  std::string out = "G1 X20 Y" + std::to_string(dy) + "\n";
  for (int k = 1; k <= sides; ++k) {
    const double a = 2 * 3.14159265358979323846 * k / sides;
    out += "G1 X" + std::to_string(20 * std::cos(a)) + " Y" + std::to_string(20 * std::sin(a) + dy) + "\n";
  }
  return out;
}

TEST(Verify, ASpringPassDoesNotPullTheSearchAhead) {
  // The contour runs twice, the second time 0.2 um lower, with a move out to (50, 50)
  // between. The executed path, 0.3 um low, is nearer the second pass all through the
  // first: the search must still follow the first, or it finds the move out left behind.
  const std::string program =
      "G21 G90 G17 F500\nG0 X20 Y0 Z0\n" + polygon(120, 0) + "G1 X50 Y50\n" + polygon(120, -0.0002) + "M2\n";
  const std::string shifted = "G10 L2 P1 Y-0.0003\n" + program;
  const compensate::PathError e = verify_text(program, shifted, model::ForwardModel(exact_machine()));
  EXPECT_LE(e.max, 0.0003 + 1e-9) << "at line " << e.worst_line;
  EXPECT_GT(e.max, 0.0002);
}

TEST(Verify, AnErrorInEitherProgramIsReportedWithItsPlace) {
  // The original is read on a thread of its own, ahead of the compensated one: its error
  // must reach the caller, and an error in the compensated program must stop that thread
  // even while it waits for room (a long original) rather than hang.
  std::string long_program = "G21 G90 G17 F500\nG0 X0 Y0 Z0\n";
  for (int k = 0; k < 20000; ++k) long_program += "G1 X" + std::to_string(k % 2) + " Y" + std::to_string(k) + "\n";
  const model::ForwardModel m(exact_machine());
  auto error_of = [&](const std::string& original, const std::string& compensated) {
    try {
      (void)verify_text(original, compensated, m);
    } catch (const Error& e) {
      return e;
    }
    return Error(ErrorKind::internal, "no error");
  };
  const Error in_original = error_of("G21 G90\nG1 X1 Y1 Z1 F100\nG1 X2 Q?\n", long_program);
  EXPECT_EQ(in_original.where().file, "in.ngc") << in_original.what();
  EXPECT_EQ(in_original.where().line, 3U) << in_original.what();
  const Error in_output = error_of(long_program, "G21 G90\nG1 X1 Y1 Z1 F100\nG1 X2 Q?\n");
  EXPECT_EQ(in_output.where().file, "out.ngc") << in_output.what();
  EXPECT_EQ(in_output.where().line, 3U) << in_output.what();
  // The compensated program is read on a thread of its own too, many batches ahead of the
  // search: its error comes after every point before it was measured, at its own line.
  const Error late_in_output = error_of(long_program, long_program + "G1 X2 Q?\n");
  EXPECT_EQ(late_in_output.where().file, "out.ngc") << late_in_output.what();
  EXPECT_EQ(late_in_output.where().line, 20003U) << late_in_output.what();
}

TEST(Predict, ReadsOnAThreadOfItsOwnAndStillSaysWhereTheProgramIsWrong) {
  // The program is read on another thread while its moves are evaluated: an error many
  // batches in comes at its own line, after the moves before it; progress is reported on
  // the caller's thread.
  std::string program = "G21 G90 G17 F500\nG0 X0 Y0 Z0\n";
  for (int k = 0; k < 20000; ++k) program += "G1 X" + std::to_string(k % 2) + " Y" + std::to_string(k) + "\n";
  const model::ForwardModel m(exact_machine());
  compensate::CheckOptions options;
  const auto caller = std::this_thread::get_id();
  bool elsewhere = false;
  double last_share = -1.0;
  options.progress = [&](double share) {
    elsewhere = elsewhere || std::this_thread::get_id() != caller;
    last_share = share;
  };
  gcode::LineSource good = gcode::LineSource::from_string(program, "in.ngc");
  EXPECT_EQ(compensate::predict(good, m, options).moves, 20000U);
  EXPECT_FALSE(elsewhere);
  EXPECT_EQ(last_share, 1.0);
  gcode::LineSource bad = gcode::LineSource::from_string(program + "G1 X2 Q?\n", "bad.ngc");
  try {
    (void)compensate::predict(bad, m, {});
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.where().file, "bad.ngc") << e.what();
    EXPECT_EQ(e.where().line, 20003U) << e.what();
  }
}

TEST(Verify, ProgressRisesToTheEndOnTheCallersThread) {
  // The compensated program is read on another thread; the caller's callback is still
  // called on the caller's thread, with the share read rising to 1.
  std::string program = "G21 G90 G17 F500\nG0 X0 Y0 Z0\n";
  for (int k = 0; k < 20000; ++k) program += "G1 X" + std::to_string(k % 2) + " Y" + std::to_string(k) + "\n";
  gcode::LineSource a = gcode::LineSource::from_string(program, "in.ngc");
  gcode::LineSource b = gcode::LineSource::from_string(program, "out.ngc");
  compensate::CheckOptions options;
  std::vector<double> shares;
  const auto caller = std::this_thread::get_id();
  bool elsewhere = false;
  options.progress = [&](double share) {
    shares.push_back(share);
    elsewhere = elsewhere || std::this_thread::get_id() != caller;
  };
  const compensate::PathError e = compensate::verify(a, b, model::ForwardModel(exact_machine()), options);
  EXPECT_EQ(e.moves, 20000U);
  EXPECT_FALSE(elsewhere);
  ASSERT_GT(shares.size(), 20000U);
  EXPECT_TRUE(std::is_sorted(shares.begin(), shares.end()));
  EXPECT_EQ(shares.back(), 1.0);
  EXPECT_LT(shares.front(), 0.01);
}

TEST(Verify, AnOutputThatStopsShortLeavesTheRestUncut) {
  // The whole output covers the whole path; without its last two lines (a 10 mm line and
  // a half circle of radius 5), those are what is left uncut, from the original's line 5.
  const std::string program = "G21 G90 G17 F500\nG0 X0 Y0 Z0\nG1 X30\nG1 Y20\nG1 X20\nG2 X10 Y20 I-5 J0\nM2\n";
  const model::ForwardModel m(exact_machine());
  const compensate::PathError whole = verify_text(program, program, m);
  EXPECT_EQ(whole.uncut_line, 0U);
  EXPECT_LT(whole.uncut_length, 1e-9);
  const std::string cut_short = program.substr(0, program.find("G1 X20"));
  const compensate::PathError part = verify_text(program, cut_short, m);
  EXPECT_EQ(part.uncut_line, 5U);
  EXPECT_NEAR(part.uncut_length, 10.0 + 5.0 * 3.14159265358979323846, 1e-9);
  EXPECT_LT(part.max, 1e-9);  // what it does cut is right

  // A closed contour ends where it starts: its last piece is near the first point cut, and
  // still uncut when the output stops after the first side.
  const std::string square = "G21 G90 G17 F500\nG0 X0 Y0 Z0\nG1 X10\nG1 Y10\nG1 X0\nG1 Y0\nM2\n";
  const compensate::PathError first_side = verify_text(square, square.substr(0, square.find("G1 Y10")), m);
  EXPECT_NEAR(first_side.uncut_length, 30.0, 1e-9);
  EXPECT_EQ(first_side.uncut_line, 4U);
}

TEST(Verify, ACutMissingBetweenRapidsIsFound) {
  // Three 10 mm squares, rapids between; the output lost the second (a transfer that
  // dropped a block of lines): 40 mm of the original's cuts, from its line 9, are not cut.
  auto square = [](int x) {
    const std::string at = std::to_string(x);
    return "G0 X" + at + " Y0\nG1 X" + std::to_string(x + 10) + "\nG1 Y10\nG1 X" + at + "\nG1 Y0\n";
  };
  const std::string head = "G21 G90 G17 F100\nG0 X0 Y0 Z0\n";
  const std::string program = head + square(0) + square(20) + square(40) + "M2\n";
  const std::string lost = head + square(0) + "G0 X20 Y0\n" + square(40) + "M2\n";
  const model::ForwardModel m(exact_machine());
  EXPECT_LT(verify_text(program, program, m).uncut_length, 1e-9);
  const compensate::PathError e = verify_text(program, lost, m);
  EXPECT_NEAR(e.uncut_length, 40.0, 1e-9);
  EXPECT_EQ(e.uncut_line, 9U);
  EXPECT_LT(e.max, 1e-9) << "what is cut is right";
}

TEST(Verify, ATableTurningBackWhileTheToolMovesOnIsCutToItsEnd) {
  // B turns to 10 degrees, then back while X moves 10 mm: in the table frame the way back
  // starts on the way out, 300 mm from B's axis (program zero on it). The output takes the way back in steps
  // (as take-ups and splits write it), its first points as near the way out as the way back;
  // the search follows the program's order, and nothing is uncut.
  const std::string program = "G21 G90 G17 F500\nG0 X0 Y0 Z300 B0\nG1 B10\nG1 X10 B0\nM2\n";
  const std::string stepped =
      "G21 G90 G17 F500\nG0 X0 Y0 Z300 B0\nG1 B10\nG1 X0.01 B9.99\nG1 X0.05 B9.95\nG1 X10 B0\nM2\n";
  const model::ForwardModel m(sample_machine("hmc-xyzb-geometric"));
  for (const std::string& output : {program, stepped}) {
    const compensate::PathError e = verify_text(program, output, m);
    EXPECT_EQ(e.uncut_length, 0.0) << "from line " << e.uncut_line;
    EXPECT_GT(e.points, 30U);
  }
}

TEST(Verify, ACutLeftOutIsFoundWhereThePathMeetsItselfAgain) {
  // Outputs that leave a whole cut out, where what is cut touches it only at an end or runs
  // over the same line: a cut written as a rapid (the rapid lands where it ends), a spring
  // pass left out, a path's way back left out. Each is the length of the cut left out, from
  // its line; the original against itself leaves nothing.
  const std::string head = "G21 G90 G94 F1000\nG0 X0 Y0 Z0\nG1 X100\n";
  struct Case {
    std::string original, output;
    double uncut;
    std::uint32_t line;
  };
  const Case cases[] = {
      {head + "G1 Y50\nG1 X0\nM2\n", head + "G0 Y50\nG1 X0\nM2\n", 50.0, 4},
      {head + "G0 X0\nG1 X100\nG0 Y50\nG1 X0\nM2\n", head + "G0 X0\nG0 X100 Y50\nG1 X0\nM2\n", 100.0, 5},
      {head + "G1 X0\nG1 Y50\nM2\n", head + "G0 X0\nG1 Y50\nM2\n", 100.0, 4},
  };
  const model::ForwardModel m(exact_machine());
  for (const Case& c : cases) {
    EXPECT_LT(verify_text(c.original, c.original, m).uncut_length, 1e-9) << c.original;
    const compensate::PathError e = verify_text(c.original, c.output, m);
    EXPECT_NEAR(e.uncut_length, c.uncut, 1e-9) << c.output;
    EXPECT_EQ(e.uncut_line, c.line) << c.output;
  }
  // Out and back along one line, the corner written 0.5 um short of the nominal one along
  // it: the way back is cut, not left out.
  const std::string out_and_back = "G21 G90 G94 F1000\nG0 X0 Y0 Z0\nG1 X10 Y10 Z-10\nG1 X0 Y0 Z0\nG1 Y5\nM2\n";
  std::string short_corner = out_and_back;
  short_corner.replace(short_corner.find("X10 Y10 Z-10"), 12, "X9.9997 Y9.9997 Z-9.9997");
  const compensate::PathError back = verify_text(out_and_back, short_corner, m);
  EXPECT_EQ(back.uncut_length, 0.0) << "from line " << back.uncut_line;
  EXPECT_LT(back.max, 1e-9);
}

TEST(Verify, ACannedCyclesPecksNeedNotMeetTheOriginalsPieceForPiece) {
  // The corpus' Haas sample (github.com/dillonhuff/gpr), its first two tools: a G83 whose
  // compensated R and Z move its pecks, so its first, 0.05 mm peck is not the output's.
  // The holes are drilled as deep as the original's: nothing is uncut.
  const std::string program =
      "%\nO4004(BLOCK #4 .5 DRILL)\nT0 M06 (.50 INCH SPOT DRILL)\nG90 G80 G40 G55\nS1504 M03\nG43 H0\n/\n"
      "G00 X-1. Y-0.5 Z1.\nG99 G82 R0.1 Z-0.1227 P F15.04\nX-4.501\nG80\nG00 Z1.\nM01\n"
      "T2 M06 ( 1/2 DRILL FOR 14 X 1.25MM TAP)\nG90 G80 G40 G55\nS763 M03\nG43 H2\n/M08\n"
      "G00 X-1. Y-0.5 Z1.\nZ1.\nG99 G83 R0.1 Z-2.15 Q0.05 F15.26\nX-4.501\nG80\nG00 Z1.\nM30\n%\n";
  const model::MachineModel mm = sample_machine("vmc-xyz");
  compensate::JobOptions o;
  o.interpreter.dialect = *gcode::dialect_named("fanuc");
  o.interpreter.tools.tools[0] = gcode::ToolEntry{0, 0, {0, 0, 0}, 0, ""};
  o.interpreter.tools.tools[2] = gcode::ToolEntry{2, 2, {0, 0, 110.0}, 0, ""};
  const std::string output = compensate(program, mm, o);
  compensate::CheckOptions check;
  check.interpreter = o.interpreter;
  check.interpreter.tools.tools[1] = kTool1;
  gcode::LineSource a = gcode::LineSource::from_string(program, "in.ngc");
  gcode::LineSource b = gcode::LineSource::from_string(output, "out.ngc");
  const compensate::PathError e = compensate::verify(a, b, model::ForwardModel(mm), check);
  EXPECT_LT(e.max, 0.001);
  EXPECT_EQ(e.uncut_length, 0.0) << "from line " << e.uncut_line;
}

TEST(Verify, APathThatTurnsBackOverItselfIsCutToItsEnd) {
  // The last move runs back over the one before it (LinuxCNC's ccomp-gouging test): its
  // points are as near the piece before as its own, and it is still cut.
  const std::string program = "G21 G90 G17 F100\nG0 X0 Y0 Z0\nG1 X1\nG1 X2\nG1 Y0.1\nG1 X1\nG1 X2\nM2\n";
  const compensate::PathError e = verify_text(program, program, model::ForwardModel(exact_machine()));
  EXPECT_LT(e.max, 1e-9);
  EXPECT_LT(e.uncut_length, 1e-9) << "from line " << e.uncut_line;
}

TEST(Verify, TheHeaderSaysTheModelAndTheTolerance) {
  const model::MachineModel& mm = exact_machine();
  const std::string line = compensate::header_line(mm, 0.0025);
  const std::optional<compensate::HeaderFacts> facts = compensate::read_header(line);
  ASSERT_TRUE(facts) << line;
  EXPECT_EQ(facts->model_sha256, mm.sha256);
  EXPECT_DOUBLE_EQ(facts->tolerance, 0.0025);
  // A header from before the tolerance was in it still names the model.
  const std::optional<compensate::HeaderFacts> old =
      compensate::read_header("(ccomp 0.1.0 compensated for machine 'm' model sha256:00ff)");
  ASSERT_TRUE(old);
  EXPECT_EQ(old->model_sha256, "00ff");
  EXPECT_TRUE(std::isnan(old->tolerance));
  EXPECT_FALSE(compensate::read_header("(a comment)"));
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
    model::forward(m, d, model::chain_of({x, 0, 0}, gcode::Offsets{}), {});
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

/// The distance from p to the segment [a, b].
double segment_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - p).norm();
}

TEST(Verify, ShortMovesMeasuredOnTheirChordsAgreeWithEveryPointEvaluatedAsPredictsDo) {
  // Y's straightness along X (a slope and a slight bow), Z's, and X's lead screw: a 0.05 mm
  // move bends far less than a nanometre, so verify takes its points on the chord between
  // its ends; a 40 mm move it evaluates point by point. Measured here at every point the
  // model gives (its own samples: twice its check points), against the nominal polyline,
  // the figures agree within the nanometre a chord may cost, verify's and predict's (which
  // takes the nominal tip on the chord too).
  const model::MachineModel mm = model::parse_machine_model(with_limits(kVmcChain, 500) + R"(
terms:
  - {name: EYX, form: polynomial, coefficients: [0, 0.2, 1e-4]}
  - {name: EZX, form: polynomial, coefficients: [1, -0.05]}
  - {name: EXX, form: periodic, period: 20 mm, harmonics: [[0.5, 0.2]]}
)",
                                                            "vmc.yaml");
  const model::ForwardModel m(mm);
  std::vector<Eigen::Vector3d> points{{0, 0, 0}};
  for (int k = 1; k <= 400; ++k) points.emplace_back(0.05 * k, 0.0, 0.01 * std::sin(0.3 * k));
  points.emplace_back(60, 0, 0);
  points.emplace_back(100, 0.5, 0);
  std::string program = "G21 G90 G17 F500\nG0 X0 Y0 Z0\n";
  for (std::size_t k = 1; k < points.size(); ++k)
    program += "G1 X" + std::to_string(points[k].x()) + " Y" + std::to_string(points[k].y()) + " Z" +
               std::to_string(points[k].z()) + "\n";
  program += "M2\n";
  // The program's points as the interpreter reads them (six decimals).
  for (Eigen::Vector3d& p : points)
    for (Eigen::Index i = 0; i < 3; ++i) p[i] = std::stod(std::to_string(p[i]));
  auto chain = [](const Eigen::Vector3d& p) {
    model::ChainQ q = model::ChainQ::Zero();
    q.head<3>() = p;
    return q;
  };
  const model::VariationBound bound(m, {});
  ASSERT_LE(bound.chord_deviation(chain(points[1]), chain(points[2])), 1e-6) << "the short moves are on chords";
  ASSERT_GT(bound.chord_deviation(chain(points[400]), chain(points[401])), 1e-6) << "the long one is not";

  model::ForwardData d(m);
  std::vector<Eigen::Vector3d> nominal;
  for (const Eigen::Vector3d& p : points) {
    model::forward(m, d, chain(p), {}, false, model::Evaluate::nominal);
    nominal.push_back(d.nominal);
  }
  double max = 0.0, sum2 = 0.0, error_max = 0.0, error_sum2 = 0.0;
  std::uint64_t count = 0;
  for (std::size_t k = 1; k < points.size(); ++k) {
    const model::ChainQ a = chain(points[k - 1]), b = chain(points[k]);
    const int steps = 2 * m.check_points(a, b, 8);
    for (int j = 0; j <= steps; ++j) {
      model::forward(m, d, a + (b - a) * (static_cast<double>(j) / steps), {});
      double off = std::numeric_limits<double>::infinity();
      for (std::size_t i = 1; i < nominal.size(); ++i)
        off = std::min(off, segment_distance(d.actual, nominal[i - 1], nominal[i]));
      max = std::max(max, off), sum2 += off * off, ++count;
      const double error = (d.actual - d.nominal).norm();  // what predict measures
      error_max = std::max(error_max, error), error_sum2 += error * error;
    }
  }
  const compensate::PathError e = verify_text(program, program, m);
  EXPECT_EQ(e.points, count);
  EXPECT_GT(max, 5e-3) << "the errors are large enough to tell";
  EXPECT_NEAR(e.max, max, 1e-6);
  EXPECT_NEAR(e.rms, std::sqrt(sum2 / static_cast<double>(count)), 1e-6);
  gcode::LineSource source = gcode::LineSource::from_string(program, "in.ngc");
  const compensate::PathError p = compensate::predict(source, m, {});
  EXPECT_EQ(p.points, count);
  EXPECT_NEAR(p.max, error_max, 1e-6);
  EXPECT_NEAR(p.rms, std::sqrt(error_sum2 / static_cast<double>(count)), 1e-6);
}

}  // namespace
}  // namespace ccomp::test
