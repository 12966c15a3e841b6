// What makes an exported table worse than it looks is said, in the text and in --json: a
// periodic error the table's spacing cannot hold (Fanuc's pitch data every 8 mm against the
// sample HMC's 10 mm screw alias it into a 40 mm wave), a table that leaves more error than
// none (the HMC's B table, whose whole error along its line grows); and no writer prints a
// zero with a minus sign.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <string>

#include "ccomp/controller/table_checks.hpp"
#include "ccomp/model/model_file.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

const std::string kReadings = " --sensor bed=20 --sensor column=20 --sensor spindle=20";

std::string model_path(const std::string& name) {
  return source_dir() + "/samples/machines/" + name + ".yaml";
}

CommandResult export_to(const std::string& model, const std::string& options, const std::string& path, bool json) {
  return run_command(shell_quote(ccomp_binary()) + " export -m " + shell_quote(model_path(model)) + " " + options +
                     " -o " + shell_quote(path) + (json ? " --json" : ""));
}

/// The --json summary's "warnings" array, one string each (the writer escapes no quotes in them).
std::vector<std::string> json_warnings(const std::string& json) {
  std::vector<std::string> out;
  const std::size_t key = json.find("\"warnings\"");
  if (key == std::string::npos) return {"(no warnings key)"};
  const std::size_t open = json.find('[', key), close = json.find(']', open);
  const std::string list = json.substr(open + 1, close - open - 1);
  const std::regex item("\"([^\"]*)\"");
  for (auto it = std::sregex_iterator(list.begin(), list.end(), item); it != std::sregex_iterator(); ++it)
    out.push_back((*it)[1]);
  return out;
}

TEST(TableChecks, ShortPeriodsAndTheirAliases) {
  EXPECT_EQ(controller::first_short_harmonic(10, 1, 8), 1);     // 10 mm under 4 steps of 8
  EXPECT_EQ(controller::first_short_harmonic(10, 1, 2.5), std::nullopt);  // 4 steps exactly: held
  EXPECT_EQ(controller::first_short_harmonic(40, 3, 4), 3);     // 40/2 = 20 holds over 4 steps of 4; 40/3 does not
  EXPECT_NEAR(controller::alias_period(10, 8), 40, 1e-9);      // 0.1 - 0.125 cycles/mm
  EXPECT_NEAR(controller::alias_period(10, 6), 15, 1e-9);      // 0.1 - 0.1667: 1/0.0667
  EXPECT_TRUE(std::isinf(controller::alias_period(10, 10)));   // every sample at one phase

  const model::MachineModel hmc = model::load_machine_model(model_path("hmc-xyzb"));
  const auto fanuc = controller::short_periods(hmc, 0, 8.0);
  ASSERT_EQ(fanuc.size(), 1U);
  EXPECT_EQ(hmc.terms[fanuc[0].term].name, "EXX");
  EXPECT_TRUE(fanuc[0].aliased);
  EXPECT_NEAR(fanuc[0].alias, 40, 1e-9);
  EXPECT_TRUE(controller::short_periods(hmc, 0, 2.5).empty());
  // B's table every 1.5 deg: the worm wheel's 4 deg period over 2.7 points, held in part
  // (not aliased: over two steps); its once-a-turn errors are far above the step.
  const auto b = controller::short_periods(hmc, 4, 1.5);
  ASSERT_EQ(b.size(), 1U);
  EXPECT_NEAR(b[0].period, 4.0, 1e-9) << "in degrees, as the table";
  EXPECT_FALSE(b[0].aliased);
  EXPECT_TRUE(controller::short_periods(hmc, 4, 0.5).empty());
  std::size_t turn = 0;
  for (const controller::ShortPeriod& s : controller::short_periods(hmc, 4, 60.0)) turn += std::abs(s.period - 180.0) < 1e-9;
  EXPECT_EQ(turn, 1U) << "EBB's second harmonic, 180 deg, under four steps of 60";
}

TEST(TableChecks, WorseThanNoneIsSaidByItsLargestOrItsRms) {
  controller::Residual r;
  r.max_before_um = 25.9, r.max_after_um = 29.3, r.rms_before_um = 10, r.rms_after_um = 9;
  ASSERT_EQ(controller::worse_than_none(r, "along the line").size(), 1U);
  EXPECT_NE(controller::worse_than_none(r, "along the line")[0].find("25.900 -> 29.300 um"), std::string::npos);
  r.max_after_um = 20;
  EXPECT_TRUE(controller::worse_than_none(r, "along the line").empty());
  r.rms_after_um = 11;
  EXPECT_EQ(controller::worse_than_none(r, "along the line").size(), 1U);
}

struct AliasCase {
  std::string control, step;
  bool aliased;
};

class ExportAliasing : public ::testing::TestWithParam<AliasCase> {};

TEST_P(ExportAliasing, ASpacingThatCannotHoldTheScrewIsSaidInTextAndJson) {
  const AliasCase& c = GetParam();
  const std::string dir = temp_dir("export_alias");
  const std::string options = "--control " + c.control + " --axis X" + c.step + kReadings;
  const CommandResult text = export_to("hmc-xyzb", options, dir + "/x.tbl", false);
  ASSERT_EQ(text.exit_code, 0) << text.err;
  const CommandResult json = export_to("hmc-xyzb", options, dir + "/x.tbl", true);
  ASSERT_EQ(json.exit_code, 0) << json.err;
  const std::vector<std::string> warnings = json_warnings(json.out);
  std::size_t alias = 0;
  for (const std::string& w : warnings)
    if (w.starts_with("term EXX: its periodic error of period 10 mm")) {
      ++alias;
      EXPECT_NE(text.err.find("warning: " + w + "\n"), std::string::npos) << "the same words in the text";
      EXPECT_EQ(w.find("a 40 mm wave") != std::string::npos, c.control == "fanuc") << w;
    }
  EXPECT_EQ(alias, c.aliased ? 1U : 0U) << json.out;
}

INSTANTIATE_TEST_SUITE_P(Controls, ExportAliasing,
                         ::testing::Values(AliasCase{"fanuc", "", true},             // every 8 mm: aliased
                                           AliasCase{"linuxcnc", "", true},          // every 4 mm: in part
                                           AliasCase{"siemens", " --step 2.5", false},
                                           AliasCase{"heidenhain", " --step 2 --from -200 --to 200", false},
                                           AliasCase{"centroid", " --to 0 --step 4", true},  // in part
                                           AliasCase{"centroid", " --to 0", false}));        // every 2 mm

TEST(ExportWarnings, ATableWorseThanNoneIsSaidInTextAndJson) {
  // The sample HMC's B table corrects B's turn, but at the tool the turn had cancelled part of
  // the table's other errors: the whole error along the line grows.
  const std::string dir = temp_dir("export_worse");
  const std::string options = "--control heidenhain --axis B" + kReadings;
  const CommandResult json = export_to("hmc-xyzb", options, dir + "/B.COM", true);
  ASSERT_EQ(json.exit_code, 0) << json.err;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      json.out, m,
      std::regex(R"re("line": \{"points": \d+, "max_before_um": ([0-9.]+), "rms_before_um": [0-9.]+, "max_after_um": ([0-9.]+))re")))
      << json.out;
  ASSERT_GT(std::stod(m[2]), std::stod(m[1])) << "the case this checks: worse along the line";
  bool said = false;
  for (const std::string& w : json_warnings(json.out))
    said = said || w.starts_with("the table makes the error worse than no table along the line, for the whole error");
  EXPECT_TRUE(said) << json.out;
  const CommandResult text = export_to("hmc-xyzb", options, dir + "/B.COM", false);
  EXPECT_NE(text.err.find("warning: the table makes the error worse than no table along the line, for the whole "
                          "error: max "),
            std::string::npos)
      << text.err;
  // A table that helps says nothing of the kind.
  const CommandResult good = export_to("hmc-xyzb", "--control siemens --axis X --step 2" + std::string(kReadings),
                                       dir + "/x.spf", true);
  ASSERT_EQ(good.exit_code, 0) << good.err;
  for (const std::string& w : json_warnings(good.out))
    EXPECT_EQ(w.find("along the line, for X's own error"), std::string::npos) << w;
}

TEST(ExportWarnings, NoWriterPrintsAZeroWithAMinusSign) {
  // A correction of -0.000001 mm written "-0.00000" (Heidenhain) or "-0.000000" reads as a
  // sign error. Before, the five-axis trunnion's Y table had five such rows.
  const std::string dir = temp_dir("export_zero");
  const std::regex negative_zero(R"((^|[\s=])-0\.0+(\s|$))");
  std::size_t tables = 0;
  for (const std::string model : {"vmc-xyza-trunnion", "vmc-xyz", "hmc-xyzb"})
    for (const char* axis : {"X", "Y", "Z"})
      for (const char* control : {"heidenhain", "linuxcnc", "siemens"}) {
        SCOPED_TRACE(model + " " + axis + " " + control);
        const std::string path = dir + "/" + model + axis + control;
        const CommandResult r = export_to(model, std::string("--control ") + control + " --axis " + axis +
                                                     (model == "hmc-xyzb" ? kReadings : ""),
                                          path, false);
        ASSERT_EQ(r.exit_code, 0) << r.err;
        const std::string text = read_file(path);
        std::smatch m;
        EXPECT_FALSE(std::regex_search(text, m, negative_zero)) << m.str();
        ++tables;
      }
  EXPECT_EQ(tables, 27U);
}

}  // namespace
}  // namespace ccomp::test
