// Conditions travel: the readings, the time and the work offsets a run used go into the
// output's header, and verify and predict take them from it unless told otherwise (with a
// warning where told otherwise); readings the model needs and lacks are all named in one
// refusal, exit 2, as README's table says.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>

#include "ccomp/compensate/program_header.hpp"
#include "ccomp/model/model_file.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {


const std::string kHmc = " -m " + sample("machines/hmc-xyzb.yaml") + " --tool-table " + sample("tools.tbl");
const std::string kPocket = sample("programs/pocket-xy.ngc");

model::MachineModel three_sensors() {
  model::MachineModel m;
  m.name = "m";
  m.sha256 = "ab12";
  m.sensors = {"bed", "column", "spindle"};
  return m;
}

TEST(RunConditions, TheHeaderCarriesTheReadingsAndTheTime) {
  compensate::RunConditions run;
  run.work_offsets.set(1, model::WorkOrigin{0, 0, -400});
  run.sensors = {{"spindle", 31.25}, {"bed", 24}, {"column", -3e-7}};
  run.time = 3600.5;
  const std::string line = compensate::header_line(three_sensors(), 0.001, run);
  // In the model's sensor order, whatever the command line's, numbers as given.
  EXPECT_NE(line.find("; work offsets G54 X0 Y0 Z-400; sensors bed=24, column=-3e-07, spindle=31.25; time 3600.5 s)"),
            std::string::npos)
      << line;
  const auto facts = compensate::read_header(line);
  ASSERT_TRUE(facts && facts->sensors && facts->time && facts->work_offsets);
  EXPECT_EQ(*facts->sensors,
            (std::vector<model::SensorReading>{{"bed", 24}, {"column", -3e-7}, {"spindle", 31.25}}));
  EXPECT_EQ(*facts->time, 3600.5);
  EXPECT_EQ(*facts->work_offsets, run.work_offsets);
  EXPECT_EQ(facts->tolerance, 0.001);
}

TEST(RunConditions, AHeaderWithoutThemSaysNothingOfThem) {
  const auto none = compensate::read_header(compensate::header_line(three_sensors(), 0.002));
  ASSERT_TRUE(none && none->work_offsets);
  EXPECT_FALSE(none->sensors.has_value());
  EXPECT_FALSE(none->time.has_value());
  // A name the header could not give back is left out (a check then needs --sensor).
  compensate::RunConditions odd;
  odd.sensors = {{"bed, left", 20}};
  const std::string line = compensate::header_line(three_sensors(), 0.001, odd);
  EXPECT_EQ(line.find("sensors"), std::string::npos) << line;
  EXPECT_FALSE(compensate::read_header(line)->sensors.has_value());
}

/// The max of a predict or verify line.
double max_of(const std::string& out) {
  std::smatch m;
  if (!std::regex_search(out, m, std::regex(R"(max ([0-9.]+) um)"))) {
    ADD_FAILURE() << out;
    return -1;
  }
  return std::stod(m[1]);
}

TEST(RunConditions, VerifyAndPredictTakeThemFromTheHeader) {
  const std::string dir = temp_dir("conditions_travel");
  const std::string out = dir + "/p.ngc";
  const std::string warm = " --sensor spindle=31 --sensor bed=24 --sensor column=23 --time 3600";
  const CommandResult job = run_command(ccomp() + " " + kPocket + kHmc + warm + " -o " + out);
  ASSERT_EQ(job.exit_code, 0) << job.err;
  EXPECT_NE(read_file(out).find("; sensors bed=24, column=23, spindle=31; time 3600 s)"), std::string::npos);
  const std::string verify = ccomp() + " verify " + kPocket + " " + out + kHmc;
  const CommandResult told = run_command(verify + warm);
  const CommandResult from_header = run_command(verify);
  ASSERT_EQ(told.exit_code, 0) << told.err;
  ASSERT_EQ(from_header.exit_code, 0) << from_header.err;
  EXPECT_EQ(from_header.out, told.out);
  EXPECT_EQ(from_header.err.find("warning"), std::string::npos) << from_header.err;
  // Told another reading: measured at it, and said.
  const CommandResult hotter = run_command(verify + " --sensor spindle=35");
  EXPECT_NE(hotter.err.find("compensated with --sensor spindle=31, measured with --sensor spindle=35"),
            std::string::npos)
      << hotter.err;
  EXPECT_GT(max_of(hotter.out), max_of(told.out) + 1.0) << hotter.out;
  // predict of the output: the header's conditions, no readings needed; another time is said.
  const std::string predict = ccomp() + " predict " + out + kHmc;
  const CommandResult predicted = run_command(predict);
  ASSERT_EQ(predicted.exit_code, 0) << predicted.err;
  EXPECT_EQ(predicted.out, run_command(predict + warm).out);
  const CommandResult later = run_command(predict + " --time 7200");
  ASSERT_EQ(later.exit_code, 0) << later.err;
  EXPECT_NE(later.err.find("compensated with --time 3600, measured with --time 7200"), std::string::npos)
      << later.err;
}

/// Each command that evaluates the model, without any reading of the full HMC.
class MissingReadings : public ::testing::TestWithParam<std::string> {};

// All of them named in one refusal, in the model's sensor order, the same every run; exit 2.
TEST_P(MissingReadings, AreAllNamedInOneRefusalWithExitTwo) {
  const std::string dir = temp_dir("conditions_missing");
  std::string command = ccomp() + " " + GetParam() + kHmc;
  for (const auto& [key, value] : {std::pair<std::string, std::string>{"{p}", kPocket}, {"{out}", dir}})
    for (auto at = command.find(key); at != std::string::npos; at = command.find(key))
      command.replace(at, key.size(), value);
  const CommandResult first = run_command(command);
  EXPECT_EQ(first.exit_code, 2) << first.err;
  std::size_t at = 0;
  for (const char* sensor : {"--sensor bed=VALUE", "--sensor column=VALUE", "--sensor spindle=VALUE"}) {
    const auto found = first.err.find(sensor, at);
    EXPECT_NE(found, std::string::npos) << sensor << " in order, in:\n" << first.err;
    at = found == std::string::npos ? at : found;
  }
  EXPECT_NE(first.err.find("3 readings the model needs were not given"), std::string::npos) << first.err;
  EXPECT_EQ(run_command(command).err, first.err);
  EXPECT_FALSE(std::filesystem::exists(dir + "/out.ngc"));
}

INSTANTIATE_TEST_SUITE_P(Commands, MissingReadings,
                         ::testing::Values("{p} -o {out}/out.ngc", "predict {p}", "verify {p} {p}"),
                         [](const ::testing::TestParamInfo<std::string>& p) {
                           return std::string(p.index == 0 ? "main_job" : p.index == 1 ? "predict" : "verify");
                         });

}  // namespace
}  // namespace ccomp::test
