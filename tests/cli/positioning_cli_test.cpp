// ccomp positioning as the standard's report: a rotary calibrator's runs in arcsec (or
// urad), one run each way and one way only with the figures they cannot give "not stated"
// (null in JSON, which its schema allows), never a number.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <string>

#include "trace_capture.hpp"

namespace ccomp::test {
namespace {


CommandResult validate(const std::string& document) {
  return run_command("/usr/bin/python3 " + shell_quote(source_dir() + "/tools/validate-json.py") + " " +
                     shell_quote(source_dir() + "/docs/schemas/positioning.schema.json") + " " + shell_quote(document));
}

/// A figure of the JSON document: its number, or NaN when it is null.
double json_number(const std::string& json, const std::string& key) {
  std::smatch m;
  if (!std::regex_search(json, m, std::regex("\"" + key + "\": (null|[-+0-9.eE]+)"))) return -1e300;
  return m[1] == "null" ? std::nan("") : std::stod(m[1].str());
}

TEST(PositioningCli, ARotaryAxisInArcsecondsOrMicroradians) {
  const std::string dir = temp_dir("positioning_rotary");
  const std::string args = " positioning " + sample("measurements/b-rotary.txt") + " -m " +
                           sample("machines/hmc-xyzb-geometric.yaml") + " --axis b";
  const CommandResult text = run_command(ccomp() + args);
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("axis B (rotary): 8 targets from 0 to 315 deg; runs 1 up, 1 down"), std::string::npos)
      << text.out;
  EXPECT_NE(text.out.find("deviations in arcsec"), std::string::npos);
  // One run each way: no spread, so A and R are not stated; E, M and B are.
  EXPECT_TRUE(std::regex_search(text.out, std::regex(R"(repeatability +R +not stated +not stated +not stated)")))
      << text.out;
  // The sample's deviations: up -2.6 .. 3.4, down -1.5 .. 4.6 arcsec: E up 6.0, down 6.1, both 7.2.
  EXPECT_TRUE(std::regex_search(text.out, std::regex(R"(systematic deviation +E +6\.000 +6\.100 +7\.200)")))
      << text.out;
  EXPECT_NE(text.out.find("not stated: A and R up"), std::string::npos) << text.out;

  const CommandResult json = run_command(ccomp() + args + " --json");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  write_file(dir + "/arcsec.json", json.out);
  const CommandResult v = validate(dir + "/arcsec.json");
  EXPECT_EQ(v.exit_code, 0) << v.out << v.err << json.out;
  EXPECT_NE(json.out.find("\"deviation_unit\": \"arcsec\""), std::string::npos);
  EXPECT_TRUE(std::isnan(json_number(json.out, "A"))) << json.out;
  EXPECT_NEAR(json_number(json.out, "E"), 7.2, 1e-9);

  // check's page gives the same figures for the rotary axis, in arcseconds.
  const CommandResult page = run_command(ccomp() + " check " + sample("measurements/b-rotary.txt") + " -m " +
                                         sample("machines/hmc-xyzb-geometric.yaml") + " --report " +
                                         shell_quote(dir + "/b.html"));
  ASSERT_EQ(page.exit_code, 0) << page.err;
  const std::string html = read_file(dir + "/b.html");
  EXPECT_NE(html.find("ISO 230-2 positioning figures (rotary axes, in arcseconds)"), std::string::npos);
  EXPECT_TRUE(std::regex_search(
      html, std::regex(R"(<td>b-rotary</td><td>B</td><td class="num">8</td><td class="num">1 / 1</td>.*)"
                       R"(<td class="num">1\.300</td><td class="num">-1\.18[78]</td><td class="num">7\.200</td>)"
                       R"(<td class="num">6\.050</td>)")))
      << "B, mean B, E and M as positioning gives them (the mean reversal is -9.5 / 8 = -1.1875, a tie at "
         "three decimals: the last bit of the sum, which the optimiser may order otherwise, decides it)";
  EXPECT_TRUE(std::regex_search(html, std::regex(R"(<tr><td class="num">135</td><td class="num">1 / 1</td>)"
                                                 R"((<td class="num">[-0-9.]+</td>){3}<td class="num">-1\.300</td>)")))
      << "the per-target table: B_i -1.300 arcsec at 135 deg, as positioning says";

  const CommandResult urad = run_command(ccomp() + args + " --json --angle-unit urad");
  ASSERT_EQ(urad.exit_code, 0) << urad.err;
  EXPECT_NE(urad.out.find("\"deviation_unit\": \"urad\""), std::string::npos);
  EXPECT_NEAR(json_number(urad.out, "E"), 7.2 * 4.84813681109536, 1e-9);
}

TEST(PositioningCli, OneWayRunsGiveTheUnidirectionalFigures) {
  const std::string dir = temp_dir("positioning_one_way");
  write_file(dir + "/up.csv",
             "# one way, two runs; um\ntarget,run,direction,deviation [um]\n"
             "0,1,+,0\n50,1,+,2\n100,1,+,3\n0,2,+,0.4\n50,2,+,2.2\n100,2,+,3.6\n");
  const std::string args = " positioning " + shell_quote(dir + "/up.csv") + " -m " +
                           sample("machines/hmc-xyzb-geometric.yaml") + " --axis x --at y=0,z=0";
  const CommandResult text = run_command(ccomp() + args);
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_TRUE(std::regex_search(text.out, std::regex(R"(systematic deviation +E +3\.100 +not stated +not stated)")))
      << text.out;
  EXPECT_NE(text.out.find("not stated: E, A and R down: no target is approached down"), std::string::npos);
  EXPECT_NE(text.out.find("not stated: E, M, A, R and B bidirectional"), std::string::npos);

  const CommandResult json = run_command(ccomp() + args + " --json");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  write_file(dir + "/up.json", json.out);
  EXPECT_EQ(validate(dir + "/up.json").exit_code, 0) << json.out;
  EXPECT_NEAR(json_number(json.out, "E_up"), 3.1, 1e-9);  // means 0.2 2.1 3.3
  EXPECT_TRUE(std::isnan(json_number(json.out, "E_down")));
  EXPECT_TRUE(std::isnan(json_number(json.out, "B")));
  EXPECT_TRUE(std::isnan(json_number(json.out, "M")));
}

TEST(PositioningCli, TheReportStatesTheInstrumentTemperaturesAndUncertaintyOrSaysTheyAreNot) {
  const std::string dir = temp_dir("positioning_stated");
  const std::string args = " positioning " + sample("measurements/x-laser.rtl") + " -m " +
                           sample("machines/hmc-xyzb-geometric.yaml") + " --axis x --at y=-360,z=-400";
  // The laser file states two temperatures and its machine; nothing states the instrument
  // or the uncertainty, and the report says so.
  const CommandResult text = run_command(ccomp() + args);
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("temperature    Material temperature: 20.40 degC"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("temperature    Air temperature: 20.90 degC"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("instrument     not stated (--instrument)"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("uncertainty    not stated"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("  Machine: HMC sample"), std::string::npos) << text.out;

  const CommandResult json = run_command(ccomp() + args +
                                         " --json --instrument 'Renishaw XL-80' --temperature machine=20.6"
                                         " --uncertainty 'U = 1.2 um, k = 2'");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  write_file(dir + "/stated.json", json.out);
  const CommandResult v = validate(dir + "/stated.json");
  EXPECT_EQ(v.exit_code, 0) << v.out << v.err << json.out;
  EXPECT_NE(json.out.find("\"instrument\": \"Renishaw XL-80\""), std::string::npos) << json.out;
  EXPECT_NE(json.out.find("\"uncertainty\": \"U = 1.2 um, k = 2\""), std::string::npos) << json.out;
  EXPECT_NE(json.out.find("\"name\": \"machine temperature\""), std::string::npos) << json.out;
  EXPECT_NEAR(json_number(json.out, "degC"), 20.4, 1e-12) << "the file's first temperature, as it states it";

  // A contract CSV states them in '# key: value' lines before its header.
  std::string csv = read_file(source_dir() + "/samples/measurements/x-axis-contract.csv");
  csv = "# instrument: XL-80\n# air temperature: 20,7\n" + csv;
  write_file(dir + "/x.csv", csv);
  const CommandResult from_csv = run_command(ccomp() + " positioning " + shell_quote(dir + "/x.csv") + " -m " +
                                             sample("machines/hmc-xyzb-geometric.yaml") + " --axis x");
  ASSERT_EQ(from_csv.exit_code, 0) << from_csv.err;
  EXPECT_NE(from_csv.out.find("instrument     XL-80"), std::string::npos) << from_csv.out;
  EXPECT_NE(from_csv.out.find("air temperature: 20.70 degC"), std::string::npos) << from_csv.out;

  // check's page gives them under its ISO 230-2 table.
  const CommandResult page = run_command(ccomp() + " check " + sample("measurements/x-laser.rtl") + " -m " +
                                         sample("machines/hmc-xyzb-geometric.yaml") + " --at y=-360,z=-400 --report " +
                                         shell_quote(dir + "/check.html"));
  ASSERT_EQ(page.exit_code, 0) << page.err;
  const std::string html = read_file(dir + "/check.html");
  EXPECT_NE(html.find("instrument <em>not stated</em>; temperatures Material temperature 20.40 &deg;C, Air "
                      "temperature 20.90 &deg;C; uncertainty of measurement <em>not stated</em>"),
            std::string::npos);

  const CommandResult bad = run_command(ccomp() + args + " --temperature air");
  EXPECT_EQ(bad.exit_code, 2) << bad.err;
  EXPECT_NE(bad.err.find("--temperature air: give NAME=DEGC"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace ccomp::test
