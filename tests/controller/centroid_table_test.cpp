// Centroid's ballscrew table (cnc-x.tab, version 3) as the file itself says it: its header
// names the version, the axis, the unit (mm), the interval and the count; its rows run from
// machine home (0) outwards, and each row's two values, read back per the format, are the
// model's correction at that point travelling forward (up) and in reverse: commanded there,
// the model's tool lands on the row's position (less the reference point's offset, which a
// work offset takes), checked on the model itself, not on the writer's numbers.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <sstream>

#include "ccomp/model/forward.hpp"
#include "job_runner.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

const std::string kReadings = " --sensor bed=20 --sensor column=20 --sensor spindle=20";

struct Written {
  std::vector<std::string> header;  ///< the five lines before the rows
  struct Row {
    double at, forward, reverse;
  };
  std::vector<Row> rows;
};

Written export_centroid(const std::string& model, const std::string& options) {
  const std::string path = temp_dir("centroid_table") + "/cnc-x.tab";
  const CommandResult r = run_command(shell_quote(ccomp_binary()) + " export -m " +
                                      shell_quote(source_dir() + "/samples/machines/" + model + ".yaml") +
                                      " --control centroid " + options + " -o " + shell_quote(path));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  Written w;
  std::istringstream in(read_file(path));
  std::string line;
  for (int k = 0; k < 5 && std::getline(in, line); ++k) w.header.push_back(line);
  const std::regex row(R"((-?\d+)\t(-?\d+\.\d{5})\t(-?\d+\.\d{5}))");
  std::smatch m;
  while (std::getline(in, line)) {
    EXPECT_TRUE(std::regex_match(line, m, row)) << "a row: position, forward, reverse, tab-separated: " << line;
    w.rows.push_back({std::stod(m[1]), std::stod(m[2]), std::stod(m[3])});
  }
  return w;
}

TEST(CentroidTable, TheHeaderStatesVersionAxisUnitIntervalAndCount) {
  const Written w = export_centroid("hmc-xyzb", "--axis X --to 0" + kReadings);
  ASSERT_EQ(w.header.size(), 5U);
  EXPECT_EQ(w.header[0], "CNC10 TAB FILE VERSION 3");
  EXPECT_EQ(w.header[1], "AXIS X");
  EXPECT_EQ(w.header[2], "UNITS MM") << "positions, interval and corrections in mm";
  // X from -500 to 0: 256 points at most, whole mm, so every 2 mm.
  EXPECT_EQ(w.header[3], "INTERVAL 2");
  EXPECT_EQ(w.header[4], "ENTRIES 251");
  ASSERT_EQ(w.rows.size(), 251U);
  for (std::size_t k = 0; k < w.rows.size(); ++k) EXPECT_EQ(w.rows[k].at, -2.0 * static_cast<double>(k));
  // The other way when the travel lies above home.
  const Written up = export_centroid("hmc-xyzb-geometric", "--axis Y --from 0 --step 5");
  EXPECT_EQ(up.header[3], "INTERVAL 5");
  EXPECT_EQ(up.header[4], "ENTRIES 91");
  ASSERT_EQ(up.rows.size(), 91U);
  EXPECT_EQ(up.rows.back().at, 450.0);
}

/// The tool tip's deviation along machine axis `axis` (mm) with `axis` commanded to `at`
/// (mm) travelling `direction`, the others at 0 and a 100 mm tool, the sensors at 20 degC.
double miss_along(const model::ForwardModel& f, std::size_t axis, double nominal, double commanded, int direction) {
  model::ForwardData d(f);
  model::Conditions conditions;
  conditions.temperatures.assign(f.machine().sensors.size(), 20.0);
  model::ChainQ q = model::ChainQ::Zero();
  q[9] = 100;
  q[static_cast<Eigen::Index>(axis)] = nominal;
  model::forward(f, d, q, conditions, false, model::Evaluate::nominal);
  const Eigen::Vector3d wanted = d.nominal;
  conditions.directions[axis] = direction;
  q[static_cast<Eigen::Index>(axis)] = commanded;
  model::forward(f, d, q, conditions);
  return (d.nominal_chain.oMp.R * (d.actual - wanted))[static_cast<Eigen::Index>(axis)];
}

struct ReadBack {
  std::string model;
  char axis;
  std::string options;
};

class CentroidReadBack : public ::testing::TestWithParam<ReadBack> {};

TEST_P(CentroidReadBack, EachRowIsTheModelsCorrectionThereInBothDirections) {
  const ReadBack& c = GetParam();
  const Written w = export_centroid(c.model, std::string("--axis ") + c.axis + " " + c.options);
  ASSERT_GT(w.rows.size(), 10U);
  const model::MachineModel machine = sample_machine(c.model);
  const model::ForwardModel f(machine);
  const std::size_t axis = std::string("XYZ").find(c.axis);
  ASSERT_EQ(w.rows.front().at, 0.0);
  EXPECT_EQ(w.rows.front().forward, 0.0) << "0 at the reference point, machine home";
  const double offset = miss_along(f, axis, 0.0, 0.0, +1);  // what a work offset probed there takes
  double largest = 0.0, reversal = 0.0;
  for (const Written::Row& r : w.rows) {
    // Within 5 nm of rounding, and the reference's offset times the change of the error's
    // slope between there and here (the corrections are relative to the reference's): on
    // the full HMC 10.5 um times the lead screw's 2e-3, 21 nm. A column swapped (4 um of
    // backlash) or a unit wrong is far beyond.
    EXPECT_NEAR(miss_along(f, axis, r.at, r.at + r.forward, +1), offset, 5e-5) << "forward at " << r.at;
    EXPECT_NEAR(miss_along(f, axis, r.at, r.at + r.reverse, -1), offset, 5e-5) << "reverse at " << r.at;
    largest = std::max(largest, std::abs(r.forward));
    reversal = std::max(reversal, std::abs(r.forward - r.reverse));
  }
  EXPECT_GT(largest, 0.001) << "a table that corrects something (in mm: 1 um and more)";
  if (c.model == "hmc-xyzb") {
    EXPECT_GT(reversal, 0.003) << "X's 4 um backlash in the reverse column";
  }
}

INSTANTIATE_TEST_SUITE_P(Centroid, CentroidReadBack,
                         ::testing::Values(ReadBack{"hmc-xyzb", 'X', "--to 0" + kReadings},
                                           ReadBack{"hmc-xyzb-geometric", 'Z', "--from 0"},
                                           ReadBack{"vmc-xyz", 'Y', "--to 0 --step 10"}),
                         [](const ::testing::TestParamInfo<ReadBack>& p) {
                           std::string name = p.param.model + "_" + std::string(1, p.param.axis);
                           for (char& ch : name)
                             if (ch == '-') ch = '_';
                           return name;
                         });

TEST(CentroidTable, NoValueIsAMinusZeroOrNotANumber) {
  for (const char* axis : {"X", "Y", "Z"}) {
    const std::string path = temp_dir("centroid_zero") + "/t.tab";
    const CommandResult r = run_command(shell_quote(ccomp_binary()) + " export -m " +
                                        shell_quote(source_dir() + "/samples/machines/vmc-xyza-trunnion.yaml") +
                                        " --control centroid --to 0 --axis " + axis + " -o " + shell_quote(path));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string text = read_file(path);
    EXPECT_EQ(text.find("-0.00000"), std::string::npos) << axis;
    EXPECT_EQ(text.find("nan"), std::string::npos) << axis;
  }
}

}  // namespace
}  // namespace ccomp::test
