// Differential tests against LinuxCNC's own interpreter, rs274, unpacked from Debian's
// package by tools/rs274/fetch.sh: on the corpus programs in the LinuxCNC dialect and on
// generated programs, ccomp's motions must equal rs274's (to 1e-4, rs274's print precision).
#include "rs274_differential.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <random>
#include <sstream>

#include "ccomp/gcode/tool_table.hpp"
#include "rs274_oracle.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

namespace fs = std::filesystem;

/// Runs both interpreters on `path` and compares their motions.
void expect_same_as_rs274(const std::string& path, const std::string& tool_table, const std::string& label) {
  const TraceResult theirs = rs274_trace(path, tool_table);
  ASSERT_FALSE(theirs.error) << label << ": " << theirs.error->what();
  gcode::InterpreterOptions o;
  o.machine_units = gcode::Units::inch;
  o.tools = gcode::read_tool_table_file(tool_table);
  const TraceResult ours = trace_file(path, o);
  ASSERT_FALSE(ours.error) << label << ": " << format_error(*ours.error);
  const auto expected = geometry(theirs.lines);
  const auto actual = geometry(ours.lines);
  EXPECT_GT(expected.size(), 0U) << label;
  if (auto diff = compare_calls(actual, expected)) ADD_FAILURE() << label << ": " << *diff;
}

std::string tool_table_file() {
  const std::string path = temp_dir("rs274_tools") + "/tools.tbl";
  write_file(path, "T1 P1 Z0.5 D0.25\nT2 P2 Z1.25 D0.5\n");
  return path;
}

// ----------------------------------------------------------------------------------------
// Corpus programs in the LinuxCNC dialect. boat-xyzbc's M428 is a remap of its machine and
// metric_pipe reads a HAL pin: rs274 alone knows neither, so those lines are stubbed in a
// copy. HAAS, Mazak, WinCNC and the Fanuc bolt circle are other dialects rs274 does not read.

struct CorpusCase {
  const char* file;
  std::vector<std::pair<std::string, std::string>> stubs;  ///< text to replace in the copy
};

TEST(Rs274Differential, CorpusProgramsInTheLinuxcncDialect) {
  CCOMP_REQUIRE_RS274();
  const std::string tools = tool_table_file();
  const CorpusCase cases[] = {
      {"linuxcnc_sample.ngc", {}},
      {"stellabee1.ngc", {}},
      {"boat-xyzbc.ngc", {{"M428 ;", "(M428 removed) ;"}, {"M429 ;", "(M429 removed) ;"}}},
      {"metric_pipe.ngc", {{"#<_hal[plasmac.float-switch-travel]>", "1.5"}}},
  };
  for (const CorpusCase& c : cases) {
    std::string text = read_file(corpus_dir() + "/programs/" + c.file);
    for (const auto& [from, to] : c.stubs)
      for (std::size_t at; (at = text.find(from)) != std::string::npos;) text.replace(at, from.size(), to);
    const std::string path = temp_dir(std::string("rs274_") + c.file) + "/" + c.file;
    write_file(path, text);
    expect_same_as_rs274(path, tools, c.file);
  }
}

// ----------------------------------------------------------------------------------------
// Programs ccomp once read otherwise than rs274 (each found by a held-out test or by the
// fuzzer), kept as they are.

TEST(Rs274Differential, ProgramsThatOnceDiffered) {
  CCOMP_REQUIRE_RS274();
  const std::string tools = tool_table_file();
  const std::string dir = temp_dir("rs274_once");
  const std::pair<const char*, const char*> cases[] = {
      {"g91-cycle-in-repeated-sub",
       "G20 G17 G40 G80 G90 G94\nG0 X0 Y0 Z1\nF10\nM98 P1 L3\nG80 G90\nM30\nO1\nG91 G99 G81 X1 Z-0.5 "
       "R-0.25\nM99\n%\n"},
      {"cycle-holes-at-the-clearance-level",
       "G21 G17 G90 G94\nG0 X0 Y0 Z10\nF100\nG99 G81 X1 Y1 Z-2 R2\nX5\nG98 X10 R3\nG91 X2 Z-1 R-1 L2\nG90 "
       "G80\nG0 Z12\nG98 G83 X1 Y1 Z-4 R1 Q1\nY3\nG99 Y5\nG80\nG0 Z0\nG91 G98 G81 X1 Z-1 R2\nX1\nG80\nM2\n"},
      {"cutter-comp-corners-and-queued-calls",
       "G20 F60\nG0 X0 Y0 Z0\nG41 D1\nG1 X1 Y0\nM3 S100\nG1 X1 Y1\n(msg, hi)\nM8\nG1 X0 Y1\nG1 X0.5 "
       "Y0.5\nG3 X1 Y0 R0.5\nG40\nG1 X2 Y2\nM2\n"},
      {"cutter-comp-arc-allowance-in-mm",
       "G21 G17 G90 G94 F500\nT1 M6\nG0 X76.3838 Y-20.7814 Z-4.9431\nG41\nG1 X59.5137 Y-22.4172\nG1 X42.6436 "
       "Y-24.0530\nG3 X31.0430 Y-30.1714 I0.9600 J-15.8768\nG1 X20.7320 Y-28.6021\nG40\nG1 X0 Y0\nM2\n"},
      {"cutter-comp-stops-issue-what-waits",
       "G20 F60\nG0 X0 Y0\nG41 D1\nG1 X1\nM0\nG1 Y1\nG1 X0\nM1\nG3 X-1 Y0 R1\nM1\nG1 X-1 Y-1\nG40\nG1 X-2 "
       "Y-2\nM2\n"},
      {"cutter-comp-units-change-while-a-move-waits",
       "G20 F60\nG0 X0 Y0 Z0\nG41 D1\nG1 X1\nG21\nG1 Y25\nG40\nG1 X50\nM2\n"},
      {"cutter-comp-after-a-stop-the-corner-rule-reads-the-last-front",
       "G21 F500\nG0 X40 Y-95\nG41 D2\nG1 X42.6717 Y-90.7385\nG3 X65.2495 Y-89.4423 I11.0654 J4.5404\nM1\nG1 "
       "X39.8476 Y-89.7561\nG40\nG1 X30 Y-100\nM2\n"},
      {"cutter-comp-in-g18",
       "G21 G18 F100\nG0 X0 Y0 Z0\nG42 D2\nG1 Z20 X0\nG1 X20\nG2 Z40 X40 K20 I0\nG1 Z60\nG40\nG1 X80\nM2\n"},
  };
  for (const auto& [name, program] : cases) {
    const std::string path = dir + "/" + name + ".ngc";
    write_file(path, program);
    // (some are refused by both: then after the same motions)
    if (auto divergence = rs274_divergence(path, tools)) ADD_FAILURE() << name << ": " << *divergence;
  }
  // Whole generated programs the fuzzer's run of 2026-11-24 found diverging (stops inside
  // a profile under cutter compensation), now agreeing.
  for (unsigned seed : {1401U, 2020U, 8114U}) {
    const std::string path = dir + "/seed-" + std::to_string(seed) + ".ngc";
    write_file(path, generated_program(seed, 120));
    if (auto divergence = rs274_divergence(path, tools)) ADD_FAILURE() << "seed " << seed << ": " << *divergence;
  }
}

// ----------------------------------------------------------------------------------------
// Generated programs: random blocks of every kind the milling dialect has
// (tests/support/rs274_differential.cpp; tools/rs274-diff.sh runs thousands).

TEST(Rs274Differential, GeneratedPrograms) {
  CCOMP_REQUIRE_RS274();
  const std::string tools = tool_table_file();
  const std::string dir = temp_dir("rs274_generated");
  // Some profiles under cutter compensation gouge: then both must refuse, after the same
  // motions. Most programs must run to their end, or little would be compared.
  int whole = 0;
  constexpr unsigned kPrograms = 300;
  for (unsigned seed = 1; seed <= kPrograms; ++seed) {
    const std::string path = dir + "/gen" + std::to_string(seed) + ".ngc";
    write_file(path, generated_program(seed, 60));
    bool refused = false;
    if (auto divergence = rs274_divergence(path, tools, &refused)) {
      ADD_FAILURE() << "seed " << seed << " (" << path << "): " << *divergence;
      break;  // one diverging program is enough to read
    }
    if (!refused) ++whole;
  }
  EXPECT_GE(whole, static_cast<int>(kPrograms) / 2) << "programs run to their end by both";
}

// The fuzzer's minimiser (tools/rs274-diff.sh), on a difference ccomp keeps: what is left of
// a program around it must still differ, and be little more than the lines that make it.
TEST(Rs274Differential, ADivergentProgramIsCutDownToWhatMakesItDiverge) {
  CCOMP_REQUIRE_RS274();
  const std::string tools = tool_table_file();
  const std::string dir = temp_dir("rs274_smallest");
  std::string program = generated_program(7, 40);
  // A difference ccomp keeps on purpose (tests/support/linuxcnc_suite.cpp): LinuxCNC
  // permutes G84's feed coordinates outside G17.
  const std::string tap = "M3 S100\nG18 G90 G0 X5 Y5 Z5\nG84 X1 Y2 Z-3 R4 F100\nG80 G17\n";
  program.insert(program.find("G0 X0 Y0 Z10\n"), tap);  // before any block both may refuse
  write_file(dir + "/whole.ngc", program);
  ASSERT_TRUE(rs274_divergence(dir + "/whole.ngc", tools)) << "G84 in G18 no longer diverges: pick another difference";
  const std::string smallest = smallest_divergent(program, tools, dir + "/cut.ngc");
  EXPECT_TRUE(rs274_divergence(dir + "/cut.ngc", tools)) << smallest;
  EXPECT_EQ(read_file(dir + "/cut.ngc"), smallest);
  EXPECT_NE(smallest.find("G84"), std::string::npos) << smallest << "\n---\n" << program;
  EXPECT_LE(std::count(smallest.begin(), smallest.end(), '\n'), 8) << smallest;
  EXPECT_GT(std::count(program.begin(), program.end(), '\n'), 60);
}

}  // namespace
}  // namespace ccomp::test
