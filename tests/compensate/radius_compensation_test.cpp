// Under cutter radius compensation (G41/G42) the control offsets the path by the tool's
// radius, so the axes run the tool centre's path: the job compensates that path, and writes
// each point as the programmed point the control offsets to it. It splits moves only within
// the stretch the control settles between its corners (so no piece is one the control
// refuses), keeps arcs as arcs, writes no take-ups (a jog that turns back is an inside corner
// the control refuses), and LinuxCNC's own interpreter accepts what it writes.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "ccomp/compensate/program_job.hpp"
#include "ccomp/compensate/verify.hpp"
#include "ccomp/model/conditions.hpp"
#include "ccomp/model/forward.hpp"
#include "ccomp/model/model_file.hpp"
#include "job_runner.hpp"
#include "rs274_oracle.hpp"
#include "sample_models.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

/// A zig-zag finish with inside corners on the left (G41), and the same without G41/G40.
std::string zigzag(bool offset_by_control) {
  const std::string on = offset_by_control ? "G41.1 D10\n" : "";
  const std::string off = offset_by_control ? "G40\n" : "";
  return "G21 G90 G94 G54\nT1 M6\nG43 H1\nG0 X-60 Y-40 Z-90 B0\nG1 F800\n" + on +
         "G1 X-50 Y-40\nG1 X50\nG1 Y-30\nG1 X-50\nG1 Y-20\nG1 X50\nG1 Y20\n" + off + "G0 Z-60\nM30\n";
}

/// LinuxCNC's interpreter runs `output` with tool 1 (10 mm; rs274 alone reads its table in
/// inches) to its end.
void expect_rs274_accepts(const std::string& output) {
  CCOMP_REQUIRE_RS274();
  const std::string dir = temp_dir("radius_compensation");
  write_file(dir + "/tools.tbl", "T1 P1 Z3.937008 D0.393701 ;\n");
  write_file(dir + "/out.ngc", output);
  const TraceResult theirs = rs274_trace(dir + "/out.ngc", dir + "/tools.tbl");
  EXPECT_FALSE(theirs.error) << theirs.error->what() << "\n" << output;
}

compensate::JobOptions warm_machine(std::vector<std::string>* warnings) {
  compensate::JobOptions o;
  o.sensors = {{"bed", 24}, {"column", 23}, {"spindle", 31}};
  o.time = 3600;
  o.warning = [warnings](const std::string& text, std::uint32_t) { warnings->push_back(text); };
  return o;
}

/// The test VMC with one error term (a YAML mapping), without its spindle sensor: no term
/// reads it, and tool_centre_error() reads the sensors a model has.
model::MachineModel vmc_with(const std::string& term) {
  std::string chain = kVmcChain;
  const std::string sensor = "sensors: [spindle]\n";
  chain.erase(chain.find(sensor), sensor.size());
  return model::parse_machine_model(chain + "terms:\n  - " + term + "\n", "vmc.yaml");
}

/// The lines of `text` between the line holding `from` and the one holding `to`.
std::vector<std::string> lines_between(const std::string& text, const std::string& from, const std::string& to) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  bool inside = false;
  for (std::string line; std::getline(in, line);) {
    if (inside && line.find(to) != std::string::npos) break;
    if (inside) lines.push_back(line);
    if (line.find(from) != std::string::npos) inside = true;
  }
  return lines;
}

/// The value of `letter` in the last of `lines` that has it.
double last_word(const std::vector<std::string>& lines, char letter) {
  for (auto line = lines.rbegin(); line != lines.rend(); ++line)
    if (const auto at = line->find(letter); at != std::string::npos) return std::stod(line->substr(at + 1));
  ADD_FAILURE() << "no " << letter << " word";
  return 0.0;
}

TEST(RadiusCompensation, ArcsStayArcsInPiecesWithTheirCentreWords) {
  // An arc entering the offset (as LinuxCNC's mill-g90g91g92 test does) and a fillet at an
  // inside corner: as chords, the control would offset each chord on its own. They stay
  // arcs: the entry arc whole (the control computes its path from where the tool stands),
  // the fillet in as many arcs as the machine's error needs, each with its centre words.
  const std::string program =
      "G21 G90 G94 G54\nT1 M6\nG43 H1\nG0 X-30 Y-20 Z-90 B0\nG1 F800\nG41.1 D10\n"
      "G3 X-20 Y-30 R10\nG1 X20\nG3 X30 Y-20 I0 J10\nG1 Y20\nG1 X-30\nG40\nG0 Z-60\nM30\n";
  const model::MachineModel mm = sample_machine("hmc-xyzb");
  std::vector<std::string> warnings;
  compensate::JobReport report;
  const std::string output = compensate(program, mm, warm_machine(&warnings), &report);
  const std::vector<std::string> offset = lines_between(output, "G41.1 D10", "G40");
  ASSERT_GE(offset.size(), 5U) << output;
  EXPECT_EQ(offset.front().rfind("G3 X-20.0", 0), 0U) << output;
  EXPECT_NE(offset.front().find(" R10"), std::string::npos) << "the entry arc is whole\n" << output;
  std::size_t arcs = 0;
  for (const std::string& line : offset) {
    if (line.rfind("G3", 0) != 0) continue;
    ++arcs;
    EXPECT_TRUE(line.find(" R10") != std::string::npos ||
                (line.find(" I") != std::string::npos && line.find(" J") != std::string::npos))
        << line;
  }
  EXPECT_GT(arcs, 2U) << "the fillet in pieces\n" << output;
  for (const std::string& line : offset)
    EXPECT_EQ(line.rfind("G1", 0) == 0 && line.find(" I") != std::string::npos, false);
  // What the arcs do between their compensated ends is measured, not assumed.
  EXPECT_GT(report.max_error_after, 0.0);
  expect_rs274_accepts(output);
}

/// How far the tool centre strays from the original's (its offset path, as the control
/// runs both programs), on `mm` warm.
compensate::PathError tool_centre_error(const std::string& original, const std::string& output,
                                        const model::MachineModel& mm) {
  const model::ForwardModel fm(mm);
  compensate::CheckOptions o;
  o.interpreter.tools.tools[1] = kTool1;
  o.conditions = model::conditions_for(
      mm,
      mm.sensors.empty() ? std::vector<model::SensorReading>{}
                         : std::vector<model::SensorReading>{{"bed", 24}, {"column", 23}, {"spindle", 31}},
      mm.sensors.empty() ? 0.0 : 3600.0);
  gcode::LineSource a = gcode::LineSource::from_string(original, "original.ngc");
  gcode::LineSource b = gcode::LineSource::from_string(output, "output.ngc");
  return compensate::verify(a, b, fm, o);
}

TEST(RadiusCompensation, StraightMovesAreSplitAndNothingIsTakenUp) {
  const model::MachineModel mm = sample_machine("hmc-xyzb");
  std::vector<std::string> warnings;
  compensate::JobReport offset;
  const std::string output = compensate(zigzag(true), mm, warm_machine(&warnings), &offset);
  EXPECT_GT(offset.added_lines, 0U) << "the long moves are split\n" << output;
  EXPECT_EQ(offset.take_up_moves, 0U) << output;
  ASSERT_FALSE(warnings.empty());
  EXPECT_NE(warnings.front().find("cutter radius compensation (G41/G42) is on"), std::string::npos) << warnings.front();
  EXPECT_GT(offset.max_error_after, 0.001) << "the turns' backlash is left, and said";
  expect_rs274_accepts(output);
  // A ramp down and back up under the offset: Z turns at each, and as its play runs out
  // along the cut the tool strays; what it leaves is in the job's figure (it took only
  // where each move starts: 2.5 um where verify finds 6.7).
  const std::string ramps =
      "G21 G90 G94 G54\nT1 M6\nG43 H1\nG0 X-60 Y-10 Z-90 B0\nG1 F800 Z-89\nG41 D1\nG1 X-50 Y0\n"
      "G1 X50 Z-95\nG1 X0 Z-89\nG40\nG1 X60 Y-10\nM30\n";
  compensate::JobReport ramped;
  const std::string ramp_output = compensate(ramps, mm, warm_machine(&warnings), &ramped);
  const double left = tool_centre_error(ramps, ramp_output, mm).max;
  EXPECT_GT(left, 0.003);
  EXPECT_GE(ramped.max_error_after, 0.9 * left) << "verify finds " << left * 1e3 << " um";
}

TEST(RadiusCompensation, TheErrorIsTakenWhereTheToolCentreRuns) {
  // A line at Y0 under G41 with a 10 mm tool: the tool centre runs at Y5, where the machine's
  // X is 2.5 um off (Y's straightness in X grows 0.5 um a millimetre). Written out, the
  // line's end must carry the correction the same path gets programmed at Y5 without G41
  // (the corner's arc written as the control makes it); not the one at Y0.
  const model::MachineModel mm = vmc_with("{name: EXY, form: polynomial, unit: um, coefficients: [0, 0.5]}");
  const std::string with_offset =
      "G21 G90 G94 G54\nG0 X-60 Y-10 Z-90\nG1 F800\nG41.1 D10\nG1 X-50 Y0\n"
      "(the line)\nG1 X50\n(the line's end)\nG40\nG1 X60 Y-10\nM30\n";
  auto tool_path = [](double y) {
    const double ay = y - 5.0 + 3.535534;
    return fmt::format(
        "G21 G90 G94 G54\nG0 X-60 Y-10 Z-90\nG1 F800\nG1 X-53.535534 Y{}\nG2 X-50 Y{} I3.535534 J-3.535534\n"
        "(the line)\nG1 X50\n(the line's end)\nG1 X60 Y-10\nM30\n",
        ay, y);
  };
  const std::string a = compensate(with_offset, mm, 0.001), at_tool = compensate(tool_path(5.0), mm, 0.001),
                    at_program = compensate(tool_path(0.0), mm, 0.001);
  auto end_of_line = [](const std::string& output, char letter) {
    return last_word(lines_between(output, "(the line)", "(the line's end)"), letter);
  };
  EXPECT_NEAR(end_of_line(a, 'X'), end_of_line(at_tool, 'X'), 1.5e-4) << a << "\n" << at_tool;
  EXPECT_GT(std::abs(end_of_line(a, 'X') - end_of_line(at_program, 'X')), 0.002) << a << "\n" << at_program;
}

TEST(RadiusCompensation, TheSampleProfilePassesVerifyOnTheToolCentresPath) {
  // samples/programs/profile-g41.ngc, a finishing pass under G41: kept for the control on
  // the geometric HMC, resolved (the offset path written) on the full HMC, whose backlash
  // needs take-ups the control's offset cannot have. Checked on the tool centre's path.
  const std::string program = read_file(source_dir() + "/samples/programs/profile-g41.ngc");
  for (const auto& [machine, resolve] :
       {std::pair{"hmc-xyzb-geometric", false}, std::pair{"hmc-xyzb", true}, std::pair{"hmc-xyzb-geometric", true}}) {
    const model::MachineModel mm = sample_machine(machine);
    std::vector<std::string> warnings;
    compensate::JobOptions o = warm_machine(&warnings);
    if (mm.sensors.empty()) o.sensors.clear(), o.time = 0;
    o.resolve_cutter_comp = resolve;
    const std::string output = compensate(program, mm, o);
    const compensate::PathError e = tool_centre_error(program, output, mm);
    EXPECT_LE(e.max, 0.001) << machine << (resolve ? " resolved" : "") << " line " << e.worst_line << "\n" << output;
    EXPECT_EQ(e.uncut_length, 0.0) << machine;
    EXPECT_EQ(output.find("G41"), resolve ? std::string::npos : output.find("G41 D1")) << output;
    expect_rs274_accepts(output);
  }
  // Kept for the control on the full HMC, its turns' backlash stays: said, and measured.
  const model::MachineModel mm = sample_machine("hmc-xyzb");
  std::vector<std::string> warnings;
  const std::string kept = compensate(program, mm, warm_machine(&warnings));
  EXPECT_GT(tool_centre_error(program, kept, mm).max, 0.001);
  EXPECT_TRUE(std::any_of(warnings.begin(), warnings.end(),
                          [](const std::string& w) { return w.find("no take-up moves") != std::string::npos; }));
}

TEST(RadiusCompensation, AMoveAlongTheNormalKeepsThePlaneStill) {
  // A plunge and a retract under G41: the control offsets a step in the plane across the
  // step's own direction, so the correction's few micrometres of X and Y there would be a
  // move of their own, a radius off, and one that turns back a gouging corner LinuxCNC
  // refuses. X and Y stay where the last move left them; what that leaves is reported. Z
  // is 0.2 um a millimetre off in X here, so the plunge's 15 mm leave 3 um at its bottom:
  // along a feed, and where the cut after a rapid starts.
  const model::MachineModel mm = vmc_with("{name: EXZ, form: polynomial, unit: um, coefficients: [0, 0.2]}");
  for (const std::string plunge : {"G1 Z-95", "G0 Z-95"}) {
    const std::string program =
        "G21 G90 G94 G54\nG0 X-60 Y-40 Z-80\nG1 F800\nG41.1 D10\nG1 X-50 Y-30\nG1 X50\n(plunge)\n" + plunge +
        "\n(plunged)\nG1 Y30\nG1 X-50\n(retract)\nG0 Z-80\n(retracted)\nG40\nG0 X-60 Y40\nM30\n";
    compensate::JobReport report;
    const std::string output = compensate(program, mm, 0.001, &report);
    for (const auto& [from, to] : {std::pair{"(plunge)", "(plunged)"}, std::pair{"(retract)", "(retracted)"}}) {
      const std::vector<std::string> lines = lines_between(output, from, to);
      ASSERT_FALSE(lines.empty()) << output;
      for (const std::string& line : lines) {
        EXPECT_EQ(line.find('X'), std::string::npos) << line << "\n" << output;
        EXPECT_EQ(line.find('Y'), std::string::npos) << line << "\n" << output;
      }
    }
    expect_rs274_accepts(output);
    const double left = tool_centre_error(program, output, mm).max;
    EXPECT_NEAR(left, 0.003, 0.0005) << plunge << "\n" << output;
    // (verify finds 2.75 um: the next move's correction turns it by 50 urad, and the
    // control's corner, offset across it, slides a quarter of a micrometre; see
    // docs/compensation.md)
    EXPECT_GE(report.max_error_after, 0.95 * left) << plunge << ": verify finds " << left * 1e3 << " um";
    EXPECT_LE(report.max_error_after, 1.15 * left) << plunge << ": verify finds " << left * 1e3 << " um";
  }
}

TEST(RadiusCompensation, ARetractAfterTheLastCutLeavesNothingInTheFigure) {
  // X held up a 30 mm retract under G41 ends 6 um off its correction, but nothing is cut
  // from there: the figure is the cut's (it said 6 um where verify finds none while a rapid's
  // end counted whatever followed it).
  const model::MachineModel mm = vmc_with("{name: EXZ, form: polynomial, unit: um, coefficients: [0, 0.2]}");
  const std::string program =
      "G21 G90 G94 G54\nG0 X-70 Y-40 Z-80\nG0 X-60\nG1 F800\nG41.1 D10\nG1 X-50 Y-30\nG1 X50\nG0 Z-50\nG40\n"
      "G0 X70 Y40\nM30\n";
  compensate::JobReport report;
  const std::string output = compensate(program, mm, 0.001, &report);
  EXPECT_LE(tool_centre_error(program, output, mm).max, 1e-4);
  EXPECT_LE(report.max_error_after, 1e-4) << output;
}

TEST(RadiusCompensation, AReversalOnTheControlsCornerIsReported) {
  // Under G41 the entry move takes the tool centre to X-5 and the control's corner arc turns
  // X round to +X: the 4 um of X backlash is taken up on the control's arc, where no take-up
  // can be written. The job reported 0 there (verify finds 3.98 um).
  const model::MachineModel mm = vmc_with("{name: EXX, variable: vx, form: reversal, reversal: -4 um}");
  const std::string program =
      "G21 G90 G94 G54\nG0 X0 Y-40 Z-80\nG1 F800\nG41.1 D10\nG1 X0 Y-30\nG1 X50\nG1 Y30\nG40\nG0 X0 Y40\nM30\n";
  compensate::JobReport report;
  const std::string output = compensate(program, mm, 0.001, &report);
  const double left = tool_centre_error(program, output, mm).max;
  EXPECT_GT(left, 0.003);
  EXPECT_GE(report.max_error_after, 0.95 * left) << "verify finds " << left * 1e3 << " um";
  EXPECT_LE(report.max_error_after, 1.15 * left) << "verify finds " << left * 1e3 << " um";
}

TEST(RadiusCompensation, AHeldAxisNeitherTurnsNorReportsATurn) {
  // X held through a plunge under G41 on a machine with 4 um of X backlash: the correction's
  // travel in X (3 um along the plunge, against X's last travel) would turn X round, but X
  // does not move.
  // Neither its reversal nor the play it would leave is in the figure: it is what verify
  // finds (it said 7 um where verify finds 3 before X's approach was kept).
  const model::MachineModel mm = vmc_with(
      "{name: EXZ, form: polynomial, unit: um, coefficients: [0, 0.2]}\n  - {name: EXX, variable: vx, "
      "form: reversal, reversal: -4 um}");
  const std::string program =
      "G21 G90 G94 G54\nG0 X0 Y-40 Z-80\nG1 F800\nG41.1 D10\nG1 X0 Y-30\nG1 X-50\nG1 Z-95\nG1 Y30\nG0 Z-80\n"
      "G40\nG0 X0 Y40\nM30\n";
  compensate::JobReport report;
  const std::string output = compensate(program, mm, 0.001, &report);
  const double left = tool_centre_error(program, output, mm).max;
  EXPECT_GE(report.max_error_after, 0.95 * left) << "verify finds " << left * 1e3 << " um";
  EXPECT_LE(report.max_error_after, 1.15 * left) << "verify finds " << left * 1e3 << " um\n" << output;
  expect_rs274_accepts(output);
  // A rapid retract between two cuts: X, held, has no play to take up, so no take-up is
  // withheld (the warning, said once a job, was spent on it before).
  std::vector<std::string> warnings;
  compensate::JobOptions o;
  o.warning = [&warnings](const std::string& text, std::uint32_t) { warnings.push_back(text); };
  (void)compensate(
      "G21 G90 G94 G54\nG0 X-70 Y-40 Z-80\nG0 X-60\nG1 F800\nG41.1 D10\nG1 X-50 Y-30\nG1 X50\nG1 Z-95\n"
      "G1 Y30\nG0 Z-80\nG1 X60\nG40\nG0 X70 Y40\nM30\n",
      mm, o);
  for (const std::string& w : warnings) EXPECT_EQ(w.find("no take-up moves"), std::string::npos) << w;
}

TEST(RadiusCompensation, TheCorpusRetractUnderG41IsNoGougingCorner) {
  // What the job fuzzer found (fuzz/job_fuzz.cpp): the corpus' mill-g90g91g92 on the full
  // HMC, whose retract under G41 was written "G0Z0.99836 X0.99933 Y-0.00118", a step back
  // in the plane that LinuxCNC refuses as a concave corner it cannot reach without gouging.
  CCOMP_REQUIRE_RS274();
  const std::string dir = source_dir() + "/tests/data/corpus/linuxcnc/ccomp/mill-g90g91g92";
  std::vector<std::string> warnings;
  compensate::JobOptions o = warm_machine(&warnings);
  o.interpreter.tools = gcode::read_tool_table_file(dir + "/test.tbl");
  const std::string program = read_file(dir + "/test.ngc");
  const std::string output = compensate(program, sample_machine("hmc-xyzb"), o);
  const std::string out_dir = temp_dir("radius_compensation_corpus");
  write_file(out_dir + "/out.ngc", output);
  const TraceResult theirs = rs274_trace(out_dir + "/out.ngc", dir + "/test.tbl");
  EXPECT_FALSE(theirs.error) << theirs.error->what() << "\n" << output;
}

TEST(RadiusCompensation, OutsideCornersAndRadiusArcsBothWays) {
  // Round a boss clockwise with the tool on the left (outside): every corner is convex, so
  // the control adds an arc before the move; the arcs are R-format, one the long way round.
  const std::string program =
      "G21 G90 G94 G54\nT1 M6\nG43 H1\nG0 X-70 Y-50 Z-90 B0\nG1 F800\nG41 D1\nG1 X-50 Y-30\nG1 Y20\n"
      "G2 X-30 Y40 R20\nG1 X30\nG1 X40 Y0\nG2 X-10 Y-30 R-45\nG1 X-50\nG40\nG1 X-70 Y-50\nM30\n";
  const model::MachineModel mm = sample_machine("hmc-xyzb");
  for (const bool resolve : {false, true}) {
    std::vector<std::string> warnings;
    compensate::JobOptions o = warm_machine(&warnings);
    o.resolve_cutter_comp = resolve;
    const std::string output = compensate(program, mm, o);
    if (!resolve) {
      // The arcs in pieces, each with its centre words: a radius word, the long way round,
      // would be wrong for a piece.
      std::size_t arcs = 0;
      for (const std::string& line : lines_between(output, "G41 D1", "G40")) {
        if (line.rfind("G2", 0) != 0) continue;
        ++arcs;
        EXPECT_EQ(line.find(" R"), std::string::npos) << line;
        EXPECT_NE(line.find(" I"), std::string::npos) << line;
      }
      EXPECT_GT(arcs, 2U) << output;
    } else {
      EXPECT_EQ(output.find("G41"), std::string::npos) << output;
      const compensate::PathError e = tool_centre_error(program, output, mm);
      EXPECT_LE(e.max, 0.001) << "line " << e.worst_line << "\n" << output;
      EXPECT_EQ(e.uncut_length, 0.0);
    }
    expect_rs274_accepts(output);
  }
}

}  // namespace
}  // namespace ccomp::test
