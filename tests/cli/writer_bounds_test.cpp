// No writer puts a number that is not one, or a correction the main job would refuse, into
// a file with exit 0 (issue 45 point 3, issue 49 point 5): every control's table (LinuxCNC
// both types, Fanuc, Siemens, Heidenhain, the volumetric ISG) of a model with a coefficient
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
                                           Writer{"isg", "--control isg --step 250"}),
                         [](const ::testing::TestParamInfo<Writer>& p) { return std::string(p.param.name); });

TEST(WriterBounds, SimulateWritesNoRowThatIsNotANumber) {
  const std::string dir = temp_dir("writer_bounds_simulate");
  write_file(dir + "/m.yaml", one_axis_model("[0, 0, 1e308]"));
  const std::string out = dir + "/sim.csv";
  const CommandResult r = run_command(shell_quote(ccomp_binary()) + " simulate -m " + shell_quote(dir + "/m.yaml") +
                                      " -o " + shell_quote(out));
  EXPECT_EQ(r.exit_code, 7) << r.err;
  EXPECT_NE(r.err.find("is not a number"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("at X -1000"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace ccomp::test
