// No writer puts a number that is not one, or a correction the main job would refuse, into
// a file with exit 0 (issue 45 point 3, issue 49 point 5): every control's table (LinuxCNC
// both types, Fanuc, Siemens, Heidenhain, Centroid, the volumetric ISG) of a model with a coefficient
// of 1e308, and of the cubic (fitted over +-20 mm, 15.9 m at X 1000, where export
// wrote rows '-1000.000000 -nan -nan' and exit 0), is refused with exit 7 naming where;
// simulate writes no NaN rows.
#include <gtest/gtest.h>

#include <filesystem>

#include "short_runs.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

struct Writer {
  const char* name;
  const char* arguments;
};

std::ostream& operator<<(std::ostream& os, const Writer& w) {
  return os << w.name;
}

class EveryWriter : public ::testing::TestWithParam<Writer> {};

/// The cubic of the issue: what a fit over +-20 mm of a few um gives, 15.9 m at 1000 mm.
constexpr const char* kRunawayCubic = "[0, 0.1, 0.001, 0.0159]";

TEST_P(EveryWriter, RefusesWhatTheMainJobRefuses) {
  const Writer& w = GetParam();
  const std::string dir = temp_dir(std::string("writer_bounds_") + w.name);
  for (const char* model : {"[0, 1e308]", kRunawayCubic}) {
    write_file(dir + "/m.yaml", one_axis_model(model));
    const std::string table = dir + "/table.txt";
    const CommandResult r = run_command(shell_quote(ccomp_binary()) + " export -m " + shell_quote(dir + "/m.yaml") +
                                        " " + w.arguments + " -o " + shell_quote(table));
    EXPECT_EQ(r.exit_code, 7) << model << ": " << r.out << r.err;
    EXPECT_NE(r.err.find("the correction of X at X -10"), std::string::npos) << "names where: " << r.err;
    // The size beyond the bound where it has one (15899.1000 mm for the cubic), else that it has none.
    EXPECT_TRUE(r.err.find("mm, beyond the model's bound of 1 mm (max_correction)") != std::string::npos ||
                r.err.find("is not a number") != std::string::npos)
        << r.err;
    EXPECT_EQ(r.err.find("nan") != std::string::npos, r.err.find("is not a number") != std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(table)) << "a refused export writes nothing";
  }
}

INSTANTIATE_TEST_SUITE_P(Controls, EveryWriter,
                         ::testing::Values(Writer{"linuxcnc_type0", "--control linuxcnc --axis X --comp-file-type 0"},
                                           Writer{"linuxcnc_type1", "--control linuxcnc --axis X --comp-file-type 1"},
                                           Writer{"fanuc", "--control fanuc --axis X"},
                                           Writer{"siemens", "--control siemens --axis X"},
                                           Writer{"heidenhain", "--control heidenhain --axis X"},
                                           Writer{"centroid", "--control centroid --axis X --to 0"},
                                           Writer{"isg", "--control isg --step 250"}),
                         [](const ::testing::TestParamInfo<Writer>& p) { return std::string(p.param.name); });

TEST(WriterBounds, SimulateWritesNoRowThatIsNotANumberOrBeyondTheBound) {
  const std::string dir = temp_dir("writer_bounds_simulate");
  for (const auto& [model, said] : {std::pair{"[0, 0, 1e308]", "is not a number"},
                                    std::pair{kRunawayCubic, "mm, beyond its bound of 1 mm (max_correction)"}}) {
    write_file(dir + "/m.yaml", one_axis_model(model));
    const std::string out = dir + "/sim.csv";
    const CommandResult r = run_command(shell_quote(ccomp_binary()) + " simulate -m " + shell_quote(dir + "/m.yaml") +
                                        " -o " + shell_quote(out));
    EXPECT_EQ(r.exit_code, 7) << r.err;
    EXPECT_NE(r.err.find(said), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("at X -1000"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(out));
  }
}

}  // namespace
}  // namespace ccomp::test

namespace ccomp::test {
namespace {

/// Readings of the cubic over +-20 mm, five runs each way, 0.2 um of noise.
std::string cubic_over_20mm() {
  std::string csv = "x,y,z,vx,nx,ny,nz,d\n";
  std::uint32_t state = 7;
  for (int run = 0; run < 5; ++run)
    for (const int v : {1, -1})
      for (int k = 0; k <= 20; ++k) {
        const double x = v > 0 ? -20.0 + 2.0 * k : 20.0 - 2.0 * k;
        state = state * 1664525U + 1013904223U;
        const double noise = 2e-4 * (2.0 * static_cast<double>(state >> 8) / static_cast<double>(1U << 24) - 1.0);
        const double e = (0.1 * x + 0.001 * x * x + 0.0159 * x * x * x) * 1e-3 + noise;
        csv += std::to_string(x) + ",0,0," + std::to_string(v) + ",1,0,0," + std::to_string(e) + "\n";
      }
  return csv;
}

TEST(WriterBounds, AFittedCubicIsHeldBeyondWhereItWasFittedAndSaidSo) {
  const std::string dir = temp_dir("writer_bounds_fitted");
  write_file(dir + "/m.yaml", one_axis_model("[0, 0, 0, 0]"));
  write_file(dir + "/pm20.csv", cubic_over_20mm());
  const std::string ccomp = shell_quote(ccomp_binary()), fitted = shell_quote(dir + "/fitted.yaml");
  CommandResult r = run_command(ccomp + " fit " + shell_quote(dir + "/pm20.csv") + " -m " +
                                shell_quote(dir + "/m.yaml") + " -o " + fitted);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("EXX x [-20, 20] mm"), std::string::npos) << r.out;
  EXPECT_NE(read_file(dir + "/fitted.yaml").find("span: [-20, 20]"), std::string::npos);
  const std::string said = "term EXX was fitted over x [-20, 20] mm; at x ";
  // Every writer: the held value (about 129 um at +-20 mm), not 15.9 m or NaN, and a warning.
  for (const char* control : {"linuxcnc --axis X", "linuxcnc --axis X --comp-file-type 1", "fanuc --axis X",
                              "siemens --axis X", "heidenhain --axis X", "centroid --axis X --to 0",
                              "isg --step 250"}) {
    const std::string table = dir + "/table.txt";
    r = run_command(ccomp + " export -m " + fitted + " --control " + control + " -o " + shell_quote(table));
    ASSERT_EQ(r.exit_code, 0) << control << ": " << r.err;
    EXPECT_NE(r.err.find(said), std::string::npos) << control << ": " << r.err;
    const std::string text = read_file(table);
    EXPECT_EQ(text.find("nan"), std::string::npos) << control;
    EXPECT_EQ(text.find("inf"), std::string::npos) << control;
  }
  // Once each, in predict and the main job, at the first line beyond.
  write_file(dir + "/p.ngc", "G21 G90\nG0 X0 Y0 Z0\nG1 X10 F100\nG1 X100\nG1 X-200\nM2\n");
  for (const std::string& command : {" predict " + shell_quote(dir + "/p.ngc") + " -m " + fitted,
                                    " " + shell_quote(dir + "/p.ngc") + " -m " + fitted + " -o " +
                                        shell_quote(dir + "/out.ngc")}) {
    r = run_command(ccomp + command);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const std::size_t first = r.err.find("p.ngc:4: warning: " + said + "100 mm it holds its value at 20 mm");
    EXPECT_NE(first, std::string::npos) << r.err;
    EXPECT_EQ(r.err.find(said, first + said.size()), std::string::npos) << "said once: " << r.err;
  }
}

}  // namespace
}  // namespace ccomp::test
