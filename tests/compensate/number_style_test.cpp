// How compensated coordinates are written: in the program's style unless told otherwise
// (--decimals, --rotary-decimals), and what the written digits' rounding costs.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <regex>
#include <sstream>
#include <vector>

#include "ccomp/compensate/program_job.hpp"
#include "ccomp/compensate/verify.hpp"
#include "ccomp/error.hpp"
#include "error_of.hpp"
#include "job_runner.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

// Line 5 wrote five decimals, line 6 one, line 7 a bare ".5"; line 8 turns B (and is split).
const std::string kProgram =
    "G21 G90 G94 G54\n"
    "T1 M6\n"
    "G43 H1\n"
    "G0 X-60.5 Y-40.25 Z-100 B0\n"
    "G1 X60.12345 Y-40.25 Z-100 F800\n"
    "G1 X60.1 Y40.2 Z-90.5\n"
    "G1 X-.5 Y40.2 Z-90.5\n"
    "G1 X-.4 Y40.123456 B90.\n"
    "M30\n";

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

/// The value texts of `letter`'s words in `line` (after the letter, sign included).
std::vector<std::string> values_of(const std::string& line, char letter) {
  std::vector<std::string> values;
  const std::regex word(std::string(1, letter) + "(-?[0-9]*\\.?[0-9]*)");
  for (auto it = std::sregex_iterator(line.begin(), line.end(), word); it != std::sregex_iterator(); ++it)
    values.push_back((*it)[1]);
  return values;
}

int decimals_of(const std::string& value) {
  const auto dot = value.find('.');
  return dot == std::string::npos ? 0 : static_cast<int>(value.size() - dot - 1);
}

struct JobRun {
  std::vector<std::string> lines;  ///< the output, header first
  std::vector<std::string> warnings;
  compensate::JobReport report;
};

JobRun run(const std::string& program, compensate::JobOptions o) {
  JobRun r;
  o.warning = [&r](const std::string& message, std::uint32_t) { r.warnings.push_back(message); };
  r.lines = lines_of(compensate(program, sample_machine("hmc-xyzb-geometric"), o, &r.report));
  return r;
}

TEST(NumberStyle, CompensatedWordsKeepTheProgramsDecimalsAndAtLeastTheToleranceNeeds) {
  const JobRun r = run(kProgram, {});
  ASSERT_EQ(r.lines.size(), lines_of(kProgram).size() + 1 + r.report.added_lines);
  const std::vector<std::string> in = lines_of(kProgram);
  EXPECT_EQ(r.lines[2], in[1]) << "a line without motion stays as it was";
  // Line 5 wrote five decimals: kept. Line 6 wrote one: 4, enough for 1 um in mm.
  EXPECT_EQ(decimals_of(values_of(r.lines[5], 'X').at(0)), 5) << r.lines[5];
  EXPECT_EQ(decimals_of(values_of(r.lines[6], 'X').at(0)), 4) << r.lines[6];
  EXPECT_EQ(decimals_of(values_of(r.lines[6], 'Z').at(0)), 4) << r.lines[6];
  // ".5" has no leading zero, and the compensated value keeps that look.
  EXPECT_TRUE(values_of(r.lines[7], 'X').at(0).starts_with("-.")) << r.lines[7];
  // The lines a split adds are written in the style of the block's own words.
  ASSERT_GE(r.report.added_lines, 1U) << "turning B by 90 degrees splits the move";
  for (std::size_t k = 8; k + 1 < r.lines.size(); ++k) {
    EXPECT_EQ(decimals_of(values_of(r.lines[k], 'Y').at(0)), 6) << r.lines[k];
    EXPECT_EQ(decimals_of(values_of(r.lines[k], 'B').at(0)), 5) << r.lines[k];
    const std::string x = values_of(r.lines[k], 'X').at(0);
    EXPECT_TRUE(x.starts_with("-.") || x.starts_with(".")) << r.lines[k];
  }
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
}

TEST(NumberStyle, DecimalsAsToldForEveryCompensatedWordAndNoOtherLine) {
  compensate::JobOptions o;
  o.decimals = 3;
  o.rotary_decimals = 6;
  const JobRun r = run(kProgram, o);
  const JobRun plain = run(kProgram, {});
  ASSERT_EQ(r.lines.size(), plain.lines.size());
  // Every axis word of this program is on a line the job compensates (the header, line 0,
  // names the work offsets in axis words of its own).
  int words = 0;
  for (std::size_t k = 1; k < r.lines.size(); ++k) {
    for (char letter : {'X', 'Y', 'Z'})
      for (const std::string& v : values_of(r.lines[k], letter)) {
        EXPECT_EQ(decimals_of(v), 3) << "line " << k << ": " << r.lines[k];
        ++words;
      }
    for (const std::string& v : values_of(r.lines[k], 'B')) EXPECT_EQ(decimals_of(v), 6) << r.lines[k];
  }
  EXPECT_GE(words, 12);
  EXPECT_EQ(r.lines[2], plain.lines[2]);
  EXPECT_EQ(r.lines.back(), plain.lines.back());
  // 3 decimals in mm round each of X Y Z by up to 0.5 um, the tool by up to 0.87 um: more
  // than a quarter of 1 um, so the user hears of it.
  ASSERT_EQ(r.warnings.size(), 1U);
  EXPECT_NE(r.warnings[0].find("3 decimals in mm"), std::string::npos) << r.warnings[0];
  EXPECT_NE(r.warnings[0].find("0.866 um"), std::string::npos) << r.warnings[0];
}

TEST(NumberStyle, DecimalsTooCoarseForTheToleranceAreRefusedNamingBoth) {
  compensate::JobOptions o;
  o.decimals = 2;  // 5 um a place: 8.7 um on the tool, beyond 1 um
  const Error e = test::error_of([&] { (void)run(kProgram, o); }, "accepted 2 decimals at 1 um");
  EXPECT_EQ(e.kind(), ErrorKind::usage);
  EXPECT_NE(e.message().find("--decimals 2"), std::string::npos) << e.message();
  EXPECT_NE(e.message().find("8.66 um"), std::string::npos) << e.message();
  EXPECT_NE(e.message().find("tolerance of 1 um"), std::string::npos) << e.message();
  o.tolerance = 0.010;  // the same digits are fine at 10 um
  EXPECT_NO_THROW((void)run(kProgram, o));
}

TEST(NumberStyle, InchProgramsAreCheckedInInches) {
  // 4 decimals of an inch round each axis by 1.27 um: too coarse for 1 um, fine for 5 um.
  const std::string inch = "G20 G90 G94 G54\nT1 M6\nG43 H1\nG0 X-2 Y-1.5 Z-4 B0\nG1 X2.0001 F30\nM30\n";
  compensate::JobOptions o;
  o.decimals = 4;
  EXPECT_THROW((void)run(inch, o), Error);
  o.tolerance = 0.005;
  const JobRun r = run(inch, o);
  ASSERT_EQ(r.warnings.size(), 1U);
  EXPECT_NE(r.warnings[0].find("4 decimals in inch"), std::string::npos) << r.warnings[0];
  EXPECT_EQ(decimals_of(values_of(r.lines[5], 'X').at(0)), 4) << r.lines[5];
}

TEST(NumberStyle, TheWarnedRoundingIsWhatVerifyFinds) {
  // What the digits cost shows in the executed path, within what the warning said.
  const model::MachineModel mm = sample_machine("hmc-xyzb-geometric");
  const model::ForwardModel m(mm);
  const std::string program = random_program(4);
  auto left = [&](int decimals) {
    compensate::JobOptions o;
    o.decimals = decimals;
    const std::string output = compensate(program, sample_machine("hmc-xyzb-geometric"), o);
    compensate::CheckOptions check;
    check.interpreter.tools.tools[1] = kTool1;
    gcode::LineSource a = gcode::LineSource::from_string(program, "in.ngc");
    gcode::LineSource b = gcode::LineSource::from_string(output, "out.ngc");
    return compensate::verify(a, b, m, check).max;
  };
  const double fine = left(-1), coarse = left(3);
  EXPECT_LE(fine, 0.001 + 1e-4);
  EXPECT_GT(coarse, fine + 1e-4) << "3 decimals must cost something";
  EXPECT_LE(coarse, 0.001 + 0.5e-3 * std::sqrt(3.0)) << "no more than the tolerance and the rounding";
}

TEST(NumberStyle, CoarseRotaryDecimalsAreWarnedOfAtTheFarthestLimit) {
  compensate::JobOptions o;
  o.rotary_decimals = 3;
  const JobRun r = run(kProgram, o);
  EXPECT_EQ(decimals_of(values_of(r.lines[8], 'B').at(0)), 3) << r.lines[8];
  ASSERT_EQ(r.warnings.size(), 1U);
  EXPECT_NE(r.warnings[0].find("rotary coordinates written to 3 decimals"), std::string::npos) << r.warnings[0];
  o.rotary_decimals = 6;
  EXPECT_TRUE(run(kProgram, o).warnings.empty());
}

TEST(NumberStyle, ValidateNamesTheOptionAndItsValue) {
  auto message = [](const compensate::JobOptions& o) {
    try {
      compensate::validate(o);
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::usage);
      return e.message();
    }
    return std::string("valid");
  };
  EXPECT_EQ(message({}), "valid");
  // Each bad setting, and what its message must say.
  const std::vector<std::pair<std::function<void(compensate::JobOptions&)>, std::vector<std::string>>> cases = {
      {[](auto& o) { o.tolerance = std::nan(""); }, {"tolerance", "nan"}},
      {[](auto& o) { o.tolerance = -0.001; }, {"-0.001"}},
      {[](auto& o) { o.decimals = 10; }, {"decimals must be 0 to 9", "10"}},
      {[](auto& o) { o.rotary_decimals = -2; }, {"rotary_decimals"}},
      {[](auto& o) { o.threads = 3; }, {"threads must be 1 or 2, not 3"}},
      {[](auto& o) {
         o.sensors = {{"bed", std::numeric_limits<double>::infinity()}};
       },
       {"sensor 'bed'"}},
  };
  for (const auto& [set, said] : cases) {
    compensate::JobOptions o;
    set(o);
    const std::string m = message(o);
    for (const std::string& text : said) EXPECT_NE(m.find(text), std::string::npos) << text << " in: " << m;
  }
}

}  // namespace
}  // namespace ccomp::test
