// The metrology loop from the command line: simulate measurements, check a model against
// them, fit it, check again; and the exit code of a bad measurement file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <regex>
#include <sstream>
#include <utility>

#include "short_runs.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {


double rms_of(const std::string& check_output) {
  std::smatch m;
  const std::regex rms("rms ([0-9.]+) um");
  return std::regex_search(check_output, m, rms) ? std::stod(m[1]) : -1.0;
}

TEST(IdentifyCli, SimulateCheckFitCheck) {
  const std::string dir = temp_dir("identify_cli");
  const std::string meas = shell_quote(dir + "/meas.csv"), fitted = shell_quote(dir + "/fitted.yaml");
  CommandResult r = run_command(ccomp() + " simulate -m " + sample("machines/hmc-xyzb-geometric.yaml") +
                                " --plan nine_lines --plan grid --noise 0.2 --seed 7 -o " + meas);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // The zero model misses the machine's errors; the fit brings it to the noise.
  r = run_command(ccomp() + " check " + meas + " -m " + sample("machines/zero.yaml"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_GT(rms_of(r.out), 5.0) << r.out;
  // Fitting starts from the geometric model's layout with its values scaled away.
  std::string start = read_file(source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml");
  for (std::size_t at = start.find("coefficients: ["); at != std::string::npos;
       at = start.find("coefficients: [", at + 1)) {
    const std::size_t open = at + 15, close = start.find(']', open);
    start.replace(open, close - open,
                  std::regex_replace(start.substr(open, close - open), std::regex("[-0-9.e]+"), "0"));
  }
  write_file(dir + "/start.yaml", start);
  r = run_command(ccomp() + " check " + meas + " -m " + shell_quote(dir + "/start.yaml"));
  const double before = rms_of(r.out);
  r = run_command(ccomp() + " fit " + meas + " -m " + shell_quote(dir + "/start.yaml") + " -o " + fitted);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("singular values"), std::string::npos);
  {
    // Every parameter in the model file's unit, its uncertainty in that unit to the digits it
    // has: no bare numbers, no "+- 1.5e-14".
    const std::regex line(
        R"(^  (E\S+)\s+(\S+) -> +(\S+) (\S+)\s+\+- (\S+|0 \(to rounding\))\s*(\(not separable: see below\))?$)");
    const std::regex unit(R"(^(um|urad|mm|deg|s|um/mm|urad/mm|um/mm\^\d|urad/mm\^\d|um/degC|urad/degC)$)");
    const std::regex uncertainty(R"(^(n/a|0 \(to rounding\)|\d+(\.\d+)?|\d(\.\d)?e[-+]\d\d)$)");
    std::istringstream out(r.out);
    std::size_t parameters = 0;
    for (std::string text; std::getline(out, text);) {
      if (!text.starts_with("  E")) continue;
      std::smatch p;
      ASSERT_TRUE(std::regex_match(text, p, line)) << text;
      ++parameters;
      EXPECT_TRUE(std::regex_match(p[4].str(), unit)) << text;
      EXPECT_TRUE(std::regex_match(p[5].str(), uncertainty)) << text;
      // Two significant digits at most: "0.059", "0.00016", "2.1e-07".
      if (std::isdigit(static_cast<unsigned char>(p[5].str()[0])) && p[5] != "0 (to rounding)") {
        std::string digits = p[5].str().substr(0, p[5].str().find('e'));
        const bool whole = digits.find('.') == std::string::npos;  // "150": its zeros only place
        digits.erase(std::remove(digits.begin(), digits.end(), '.'), digits.end());
        digits.erase(0, digits.find_first_not_of('0'));
        if (whole) digits.erase(digits.find_last_not_of('0') + 1);
        EXPECT_LE(digits.size(), 2U) << text;
      }
      if (p[1] == "EXX.a1") EXPECT_EQ(p[4], "um/mm") << text;
      if (p[1] == "EC0X") EXPECT_EQ(p[4], "urad") << text;
    }
    EXPECT_GE(parameters, 10U) << r.out;
  }
  EXPECT_NE(read_file(dir + "/fitted.yaml").find("fitted:"), std::string::npos) << "the file records the fit";
  r = run_command(ccomp() + " check " + meas + " -m " + fitted + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex("\"rms_um\": ([0-9.]+)"))) << r.out;
  const double after = std::stod(m[1]);
  EXPECT_GT(before, 5 * after) << "fitting must lower the residual";
  EXPECT_LT(after, 1.3 * 0.2 + 0.05) << "a quadratic start cannot follow every term, but comes near the noise";
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex("\"noise_floor_um\": ([0-9.]+)")));
  EXPECT_NEAR(std::stod(m[1]), 0.2, 0.06);
}

TEST(IdentifyCli, ABadMeasurementFileExitsWithItsCode) {
  const std::string dir = temp_dir("identify_cli_bad");
  write_file(dir + "/bad.csv", "x,y,z,nx,ny,nz,d\n1,2,3,1,0,0,0.001\n1,2,3,0,0,1,abc\n");
  const CommandResult r =
      run_command(ccomp() + " check " + shell_quote(dir + "/bad.csv") + " -m " + sample("machines/zero.yaml"));
  EXPECT_EQ(r.exit_code, 8);
  EXPECT_NE(r.err.find("bad.csv:3:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("'abc' is not a number"), std::string::npos) << r.err;
}

TEST(IdentifyCli, AFitBeyondWhatAMachineCanHaveIsNotWritten) {
  // Readings 30 mm off in X (a file in um read as mm, past the magnitude check because the
  // model's bound is lifted): EXX.a0 would move by 3000 physical scales. Nothing is written,
  // and a file already there stays as it was.
  const std::string dir = temp_dir("identify_cli_refused");
  std::string model = read_file(source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml");
  model.replace(model.find("max_correction: 0.5 mm"), 22, "max_correction: 100 mm");
  write_file(dir + "/m.yaml", model);
  std::string rows = "x,y,z,nx,ny,nz,d\n";
  for (int k = 0; k < 80; ++k)
    rows += std::to_string(-400 + 10 * k) + ",0,0,1,0,0," + std::to_string(30.0 + 1e-4 * k) + "\n";
  write_file(dir + "/far.csv", rows);
  write_file(dir + "/out.yaml", "kept\n");
  const CommandResult r = run_command(ccomp() + " fit " + shell_quote(dir + "/far.csv") + " -m " +
                                      shell_quote(dir + "/m.yaml") + " -o " + shell_quote(dir + "/out.yaml"));
  EXPECT_EQ(r.exit_code, 8) << r.out << r.err;
  EXPECT_NE(r.err.find("is not written"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("EXX.a0"), std::string::npos) << r.err;
  EXPECT_EQ(read_file(dir + "/out.yaml"), "kept\n");
}

TEST(IdentifyCli, AWrongTermToAddIsShownAtItsPlaceInItsArgument) {
  // Not at a line of the model file with the term joined to it, which no file has.
  const std::string dir = temp_dir("identify_cli_add");
  const std::string fitted = dir + "/fitted.yaml";
  const std::string meas = shell_quote(source_dir() + "/samples/measurements/hmc-laser-grid-sphere.csv");
  for (const auto& [spec, place] : {std::pair{"{name: EXX, vlaue: 1}", ":1:13: "},
                                    std::pair{"{name: EXX, variable: vc, form: reversal, reversal: 1}", ":1:23: "}}) {
    const CommandResult r = run_command(ccomp() + " fit " + meas + " -m " + sample("machines/hmc-xyzb-geometric.yaml") +
                                        " --add '" + spec + "' -o " + shell_quote(fitted));
    EXPECT_EQ(r.exit_code, 5) << r.err;
    EXPECT_EQ(r.err.rfind(std::string("--add '") + spec + "'" + place, 0), 0U) << r.err;
    EXPECT_FALSE(std::filesystem::exists(fitted));
  }
}

TEST(IdentifyCli, AHeaderWithoutRowsOrTooFewRowsExitWithTheirCode) {
  const std::string dir = temp_dir("identify_cli_few");
  const std::string header = "x,y,z,nx,ny,nz,d\n";
  write_file(dir + "/none.csv", header);
  write_file(dir + "/few.csv", header + "1,2,3,1,0,0,0.001\n4,5,6,1,0,0,0.002\n");
  for (const char* command : {"check", "fit"})
    for (const char* file : {"none.csv", "few.csv"}) {
      const std::string output = command == std::string("fit") ? " -o " + shell_quote(dir + "/fitted.yaml") : "";
      const CommandResult r = run_command(ccomp() + " " + command + " " + shell_quote(dir + "/" + file) + " -m " +
                                          sample("machines/hmc-xyzb-geometric.yaml") + output);
      // check still shows the model against two readings, and says why it cannot refit.
      const bool shown = command == std::string("check") && file == std::string("few.csv");
      EXPECT_EQ(r.exit_code, shown ? 0 : 8) << command << " " << file << ": " << r.err;
      const std::string said =
          file == std::string("none.csv") ? "no readings after the header" : "2 readings cannot determine";
      EXPECT_NE((shown ? r.out : r.err).find(said), std::string::npos) << r.out << r.err;
    }
}

TEST(IdentifyCli, AThermalEffectOnASensorTheModelLacksIsFoundAndTheSensorAdded) {
  // The temperature columns were dropped unless the model had the sensor: a thermal effect
  // could never be found. The geometric model has no sensors; the machine drifts 2.5 um/degC
  // along Z with its spindle's temperature.
  const std::string dir = temp_dir("identify_cli_thermal");
  const std::string base = read_file(source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml");
  std::string truth = base + "sensors: [spindle]\n";
  truth.replace(truth.find("terms:\n"), 7,
                "terms:\n  - {name: EZS, variable: T_spindle, form: thermal, unit: um, coefficient: 2.5}\n");
  write_file(dir + "/truth.yaml", truth);
  write_file(dir + "/base.yaml", base);
  const std::string meas = shell_quote(dir + "/meas.csv");
  CommandResult r = run_command(ccomp() + " simulate -m " + shell_quote(dir + "/truth.yaml") +
                                " --plan thermal --plan nine_lines --noise 0.2 --seed 3 -o " + meas);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_command(ccomp() + " check " + meas + " -m " + shell_quote(dir + "/base.yaml") + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex("\"spec\": \"([^\"]*)\""))) << r.out;
  const std::string spec = m[1];
  EXPECT_NE(spec.find("variable: T_spindle"), std::string::npos) << spec;
  r = run_command(ccomp() + " fit " + meas + " -m " + shell_quote(dir + "/base.yaml") + " --add '" + spec + "' -o " +
                  shell_quote(dir + "/fitted.yaml"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string fitted = read_file(dir + "/fitted.yaml");
  EXPECT_NE(fitted.find("sensors:\n  - spindle"), std::string::npos) << fitted;
  r = run_command(ccomp() + " check " + meas + " -m " + shell_quote(dir + "/fitted.yaml"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_LT(rms_of(r.out), 1.3 * 0.2) << r.out;
  EXPECT_NE(r.out.find("missing effects: none"), std::string::npos) << r.out;
}

TEST(IdentifyCli, InstrumentFilesAreImportedOrReadDirectly) {
  const std::string dir = temp_dir("identify_cli_import");
  const std::string laser = shell_quote(source_dir() + "/samples/measurements/x-laser.rtl");
  const std::string csv = shell_quote(dir + "/x.csv");
  const std::string place = " --at y=-360,z=-400 ";
  CommandResult r = run_command(ccomp() + " import " + laser + place + "-o " + csv);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("renishaw-rtl file, 24 observations"), std::string::npos) << r.err;
  const std::string converted_text = read_file(dir + "/x.csv");
  EXPECT_EQ(std::count(converted_text.begin(), converted_text.end(), '\n'), 30)
      << "its frame, what it states (title, machine, two temperatures), the header, 24 rows";
  EXPECT_TRUE(converted_text.starts_with("# frame:")) << converted_text.substr(0, 80);
  EXPECT_NE(converted_text.find("\n# Air temperature: 20.9\n"), std::string::npos) << converted_text.substr(0, 400);
  // The native file and its conversion give the same figures.
  const std::string model = " -m " + sample("machines/hmc-xyzb-geometric.yaml");
  const CommandResult native = run_command(ccomp() + " positioning " + laser + model + " --axis x" + place);
  const CommandResult converted = run_command(ccomp() + " positioning " + csv + model + " --axis x");
  ASSERT_EQ(native.exit_code, 0) << native.err;
  EXPECT_EQ(native.out, converted.out);
  r = run_command(ccomp() + " check " + laser + model + place);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("x-laser (24)"), std::string::npos) << r.out;
  // What a one-axis file lacks is said with its code: its axis (usage), its unit (data).
  write_file(dir + "/stage.txt", "target;deviation\n0;0,01\n12,5;0,0888\n25;0,03\n");
  r = run_command(ccomp() + " import " + shell_quote(dir + "/stage.txt") + " -o " + csv);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  r = run_command(ccomp() + " import " + shell_quote(dir + "/stage.txt") + " --axis x -o " + csv);
  EXPECT_EQ(r.exit_code, 8) << r.err;
  EXPECT_NE(r.err.find("stage.txt:3:1: error: no unit stated"), std::string::npos) << r.err;
  r = run_command(ccomp() + " import " + shell_quote(dir + "/stage.txt") + " --axis x --unit um --json -o " + csv);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"format\": \"axis-table\""), std::string::npos) << r.out;
}

}  // namespace
}  // namespace ccomp::test

namespace ccomp::test {
namespace {

/// A quadratic error of X (10 um at 100 mm) over +-`reach` mm, three runs each way.
std::string quadratic_runs(int reach) {
  std::string csv = "x,y,z,vx,nx,ny,nz,d\n";
  for (int run = 0; run < 3; ++run)
    for (const int v : {1, -1})
      for (int k = 0; k <= 10; ++k) {
        const double x = v * (-reach + reach * k / 5.0);
        const double noise = 1e-4 * ((k * 7 + run * 3 + (v > 0 ? 0 : 5)) % 5 - 2) / 2.0;
        csv += std::to_string(x) + ",0,0," + std::to_string(v) + ",1,0,0," + std::to_string(1e-6 * x * x + noise) +
               "\n";
      }
  return csv;
}

TEST(IdentifyCli, CheckRefitsATermBeyondWhereItWasFitted) {
  // Fitted over +-20 mm, the cubic holds its value beyond; checked against +-100 mm, the
  // model as it is misses by 10 um there, and its refit (as fit would) follows the new data
  // instead of staying held.
  const std::string dir = temp_dir("identify_cli_span_refit");
  write_file(dir + "/m.yaml", one_axis_model("[0, 0, 0, 0]"));
  write_file(dir + "/near.csv", quadratic_runs(20));
  write_file(dir + "/far.csv", quadratic_runs(100));
  const std::string fitted = shell_quote(dir + "/fitted.yaml");
  CommandResult r = run_command(ccomp() + " fit " + shell_quote(dir + "/near.csv") + " -m " +
                                shell_quote(dir + "/m.yaml") + " -o " + fitted);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_command(ccomp() + " check " + shell_quote(dir + "/far.csv") + " -m " + fitted);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex("max ([0-9.]+) um"))) << r.out;
  EXPECT_GT(std::stod(m[1]), 5.0) << "held beyond +-20 mm: " << r.out;
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex("refitted as it is \\(its free parameters\\): rms ([0-9.]+) um")));
  EXPECT_LT(std::stod(m[1]), 0.2) << r.out;
}

}  // namespace
}  // namespace ccomp::test
