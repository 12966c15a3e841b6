// Issue 49: no arithmetic drops or changes a move. A chord count that overflows is refused
// at its block (a circle became `G1 X0 Y0`), an inverse-time F keeps the digits its duration
// needs (F0.00004 was written F0.0000), and the default digits are never by themselves what
// makes verify reject an output (at 0.01 um the 4 decimals did).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <regex>
#include <string>
#include <vector>

#include "ccomp/compensate/verify.hpp"
#include "ccomp/error.hpp"
#include "ccomp/model/forward.hpp"
#include "ccomp/model/model_file.hpp"
#include "compensate/move_solver.hpp"
#include "job_runner.hpp"
#include "sample_models.hpp"

namespace ccomp::test {
namespace {

gcode::ArcGeometry full_circle(double r) {
  gcode::ArcGeometry g;
  g.r_start = g.r_end = r;
  g.sweep = 2 * std::numbers::pi;
  return g;
}

TEST(ArithmeticGuards, AChordCountBeyondTheCapIsRefusedNotConvertedToNothing) {
  // (radius mm, tolerance mm): the issue's three, where 1 - tolerance / r rounded to 1.
  struct Case {
    double radius, tolerance;
  };
  for (const Case c : {Case{50.0, 1e-320}, Case{1e13, 0.0005}, Case{1e4, 0.5e-12}}) {
    try {
      (void)compensate::arc_chord_count(full_circle(c.radius), c.tolerance);
      ADD_FAILURE() << "no refusal for r " << c.radius << " at " << c.tolerance;
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::program);
      EXPECT_NE(e.message().find("chords"), std::string::npos) << e.message();
    }
  }
  // Where the cosine's form cancelled but the count is within the cap, the count is right:
  // a 1e6 mm circle at 0.5 um, the sagitta of its chords within the tolerance, one fewer not.
  const double r = 1e6, tolerance = 0.0005;
  const std::size_t n = compensate::arc_chord_count(full_circle(r), tolerance);
  auto sagitta = [&](double chords) { return 2 * r * std::pow(std::sin(std::numbers::pi / chords / 2), 2); };
  EXPECT_LE(sagitta(static_cast<double>(n)), tolerance * (1 + 1e-9));
  EXPECT_GT(sagitta(static_cast<double>(n - 1)), tolerance);
}

TEST(ArithmeticGuards, AHugeCircleInAProgramIsRefusedAtItsLine) {
  // (A model with an error term, without limits: a model without terms rewrites nothing.)
  const model::MachineModel mm = model::parse_machine_model(std::string(kVmcChain) + R"(
terms:
  - {name: EXX, form: polynomial, coefficients: [0, 0.2]}
)",
                                                            "vmc.yaml");
  const std::string program = "G21 G90 G17 F500\nG0 X0 Y0 Z0\nG2 X0 Y0 I10000000000000 J0\nM2\n";
  try {
    const std::string out = compensate(program, mm, 0.001);
    ADD_FAILURE() << "written:\n" << out.substr(0, 500);
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::program) << e.what();
    EXPECT_EQ(e.where().line, 3U) << e.what();
  }
}

/// The F values of each line of `text` that has one.
std::vector<double> feeds(const std::string& text) {
  std::vector<double> out;
  static const std::regex f(R"(F([0-9.]+))");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), f); it != std::sregex_iterator(); ++it)
    out.push_back(std::stod((*it)[1].str()));
  return out;
}

TEST(ArithmeticGuards, InverseTimeFeedsKeepTheMovesDuration) {
  // A long X move with B turning under G93, split by the sample HMC's error field: each
  // piece takes 1/F of a minute, and together they take the block's 1/F0.00004 = 25,000 min.
  const model::MachineModel mm = sample_machine("hmc-xyzb-geometric");
  const std::string program = "G21 G90 G17 G93\nG0 X-200 Y0 Z100 B0\nG1 X200 B40 F0.00004\nM2\n";
  const std::string out = compensate(program, mm, 0.001);
  const std::string moves = out.substr(out.find("G1 X"));
  const std::vector<double> f = feeds(moves);
  ASSERT_GE(f.size(), 2U) << "the move is split:\n" << moves;
  double minutes = 0.0;
  for (const double v : f) {
    ASSERT_GT(v, 0.0) << moves;
    minutes += 1.0 / v;
  }
  // Take-ups, if any, add a thousandth each; the digits may cost a few parts per million.
  EXPECT_NEAR(minutes, 25000.0, 25000.0 * (1e-5 + 1e-3 * 4)) << moves;
  EXPECT_GE(minutes, 25000.0 * (1 - 1e-5)) << moves;
}

TEST(ArithmeticGuards, TheDefaultDigitsFollowAFineTolerance) {
  // At 0.01 um the program's 4 decimals would round the tool by up to 87 nm: the job writes
  // enough for a quarter of the tolerance, and verify finds the output within it.
  const model::MachineModel mm = model::parse_machine_model(std::string(kVmcChain) + R"(
terms:
  - {name: EXX, form: polynomial, coefficients: [0, 0.2]}
  - {name: EYX, form: polynomial, coefficients: [0, 0.1, 1e-4]}
)",
                                                            "vmc.yaml");
  const std::string program = "G21 G90 G17 F500\nG0 X0 Y0 Z0\nG1 X33.3333 Y11.1111\nG1 X70 Y-20\nM2\n";
  compensate::JobOptions o;
  o.tolerance = 0.00001;
  const std::string out = compensate(program, mm, o);
  static const std::regex x(R"(X-?[0-9]+\.([0-9]+))");
  std::smatch match;
  const std::string first_move = out.substr(out.find("G1 X"));
  ASSERT_TRUE(std::regex_search(first_move, match, x)) << out;
  EXPECT_GE(match[1].length(), 6) << out;
  gcode::LineSource original = gcode::LineSource::from_string(program, "in.ngc");
  gcode::LineSource written = gcode::LineSource::from_string(out, "out.ngc");
  const compensate::PathError e = compensate::verify(original, written, model::ForwardModel(mm), {});
  EXPECT_LE(e.max, o.tolerance) << "at line " << e.worst_line << "\n" << out;
  EXPECT_EQ(e.uncut_length, 0.0);

  // Finer than 9 decimals can serve: refused as a usage error, as --decimals is.
  o.tolerance = 1e-320;
  try {
    (void)compensate(program, mm, o);
    ADD_FAILURE() << "a tolerance of 1e-320 mm was taken";
  } catch (const Error& refusal) {
    EXPECT_EQ(refusal.kind(), ErrorKind::usage) << refusal.what();
  }
}

}  // namespace
}  // namespace ccomp::test
