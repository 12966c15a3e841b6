// Under cutter radius compensation (G41/G42) the control offsets every line by the tool's
// radius as a piece of its own: it refuses an entry move shorter than the radius, and a
// piece shorter than the radius next to an inside corner ("cannot be reached by the tool
// without gouging"). So there the job neither splits straight moves nor writes take-ups,
// and LinuxCNC's own interpreter accepts what it writes.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "ccomp/compensate/program_job.hpp"
#include "job_runner.hpp"
#include "rs274_oracle.hpp"
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

/// LinuxCNC's interpreter runs `output` with tool 1 (10 mm) to its end.
void expect_rs274_accepts(const std::string& output) {
  const std::string dir = temp_dir("radius_compensation");
  write_file(dir + "/tools.tbl", "T1 P1 Z100 D10 ;\n");
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

TEST(RadiusCompensation, ArcsStayArcsTheirEndsCompensated) {
  // An arc entering the offset (as LinuxCNC's mill-g90g91g92 test does) and a fillet at an
  // inside corner: as chords, the first chord would be a too short entry move and the last
  // a piece too short next to the corner. They stay arcs with their centre words.
  const std::string program =
      "G21 G90 G94 G54\nT1 M6\nG43 H1\nG0 X-30 Y-20 Z-90 B0\nG1 F800\nG41.1 D10\n"
      "G3 X-20 Y-30 R10\nG1 X20\nG3 X30 Y-20 I0 J10\nG1 Y20\nG1 X-30\nG40\nG0 Z-60\nM30\n";
  const model::MachineModel mm = sample_machine("hmc-xyzb");
  std::vector<std::string> warnings;
  compensate::JobReport report;
  const std::string output = compensate(program, mm, warm_machine(&warnings), &report);
  const auto on = output.find("G41.1 D10\n") + 10, off = output.find("G40\n");
  ASSERT_LT(on, off) << output;
  const std::string offset = output.substr(on, off - on);
  EXPECT_EQ(std::count(offset.begin(), offset.end(), '\n'), 5) << "five moves, five lines\n" << output;
  EXPECT_EQ(offset.rfind("G3 X-20.0", 0), 0U) << output;
  EXPECT_NE(offset.find(" R10\n"), std::string::npos) << output;
  EXPECT_NE(offset.find("\nG3 X29.9"), std::string::npos) << "its end compensated\n" << output;
  EXPECT_NE(offset.find(" I0 J10\n"), std::string::npos) << output;
  // What the arcs do between their compensated ends is measured, not assumed.
  EXPECT_GT(report.max_error_after, 0.0);
  if (!have_rs274()) GTEST_SKIP() << "rs274 not found at " << rs274() << ": run tools/rs274/fetch.sh build/rs274";
  expect_rs274_accepts(output);
}

TEST(RadiusCompensation, StraightMovesStayOneLineAndNothingIsTakenUp) {
  const model::MachineModel mm = sample_machine("hmc-xyzb");
  std::vector<std::string> warnings;
  compensate::JobReport free, offset;
  (void)compensate(zigzag(false), mm, warm_machine(&warnings), &free);
  ASSERT_GT(free.added_lines, 0U) << "without G41 the long moves are split";
  ASSERT_GT(free.take_up_moves, 0U) << "and the turns taken up";
  warnings.clear();
  const std::string output = compensate(zigzag(true), mm, warm_machine(&warnings), &offset);
  // Between G41.1 and G40 the seven moves stay seven lines (after G40 the last rapid's
  // re-approach is written as ever).
  const auto on = output.find("G41.1 D10\n") + 10, off = output.find("G40\n");
  ASSERT_LT(on, off) << output;
  EXPECT_EQ(std::count(output.begin() + static_cast<std::ptrdiff_t>(on),
                       output.begin() + static_cast<std::ptrdiff_t>(off), '\n'),
            7)
      << output;
  ASSERT_FALSE(warnings.empty());
  EXPECT_NE(warnings.front().find("cutter radius compensation (G41/G42) is on"), std::string::npos) << warnings.front();
  EXPECT_GT(offset.max_error_after, 0.001) << "the turns' backlash is left, and said";

  if (!have_rs274()) GTEST_SKIP() << "rs274 not found at " << rs274() << ": run tools/rs274/fetch.sh build/rs274";
  expect_rs274_accepts(output);
}

}  // namespace
}  // namespace ccomp::test
