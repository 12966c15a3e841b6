// Instruments' files read natively (identify/measurement_formats, identify/axis_runs): each
// format and each spelling of a one-axis table reads to the rows of the hand-written contract
// CSV; the approach worked out from the run order; units converted, and a file without one
// refused when its values cannot be mm; a rotary calibrator's turn placed through the
// kinematics; a line's length capped while it is read.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "ccomp/constants.hpp"
#include "ccomp/error.hpp"
#include "ccomp/identify/axis_runs.hpp"
#include "ccomp/identify/measurements.hpp"
#include "ccomp/model/forward.hpp"
#include "ccomp/model/model_file.hpp"
#include "error_of.hpp"

namespace ccomp::identify {
namespace {

const std::string kSamples = CCOMP_SOURCE_DIR "/samples/measurements/";

const model::MachineModel& hmc() {
  static const model::MachineModel m =
      model::load_machine_model(CCOMP_SOURCE_DIR "/samples/machines/hmc-xyzb-geometric.yaml");
  return m;
}

ReadOptions placed() {
  ReadOptions o;
  o.tool_length = 100.0;
  o.at = {{'Y', -360.0}, {'Z', -400.0}};
  return o;
}

MeasurementSet read_file(const std::string& path, const ReadOptions& o = placed()) {
  MeasurementSet set;
  read_measurements(path, hmc(), o, set);
  return set;
}

MeasurementSet parse(const std::string& text, const ReadOptions& o = placed()) {
  MeasurementSet set;
  parse_measurements(text, "table.txt", hmc(), o, set);
  return set;
}

/// The sample's runs: run, approach, target, deviation (um), as x-axis-contract.csv has them.
struct Row {
  int run, approach;
  double target, um;
};
std::vector<Row> sample_rows() {
  const double t[] = {0, 20, 40, 60, 80, 100};
  const double up[2][6] = {{0.0, 1.2, 2.1, 2.9, 3.3, 4.1}, {0.2, 1.3, 2.0, 3.0, 3.5, 4.0}};
  const double down[2][6] = {{6.0, 5.1, 4.8, 3.9, 3.0, 2.2}, {6.1, 5.3, 4.7, 4.0, 3.1, 2.0}};
  std::vector<Row> rows;
  for (int run = 0; run < 2; ++run) {
    for (int k = 0; k < 6; ++k) rows.push_back({run + 1, 1, t[k], up[run][k]});
    for (int k = 0; k < 6; ++k) rows.push_back({run + 1, -1, t[5 - k], down[run][k]});
  }
  return rows;
}

void expect_same_rows(const MeasurementSet& got, const MeasurementSet& want, const std::string& what) {
  ASSERT_EQ(got.observations.size(), want.observations.size()) << what;
  for (std::size_t i = 0; i < got.observations.size(); ++i) {
    const Observation &g = got.observations[i], &w = want.observations[i];
    EXPECT_TRUE(g.q.isApprox(w.q, 1e-12)) << what << " row " << i << ": " << g.q.transpose() << " / " << w.q.transpose();
    EXPECT_EQ(g.directions, w.directions) << what << " row " << i;
    EXPECT_TRUE(g.direction.isApprox(w.direction)) << what << " row " << i;
    EXPECT_NEAR(g.value, w.value, 1e-12) << what << " row " << i;
  }
}

TEST(InstrumentFormats, EachSampleFormatReadsToTheHandWrittenRows) {
  const MeasurementSet contract = read_file(kSamples + "x-axis-contract.csv");
  ASSERT_EQ(contract.observations.size(), 24U);
  for (const char* file : {"x-laser.rtl", "x-axis-table.csv"}) {
    const MeasurementSet native = read_file(kSamples + file);
    expect_same_rows(native, contract, file);
    EXPECT_EQ(native.files, std::vector<std::string>{kSamples + file});
    EXPECT_GT(native.observations.back().row, 10U) << "rows point at the file's own lines";
  }
}

TEST(InstrumentFormats, TheAngularLaserFileAndTheCalibratorsTableReadAlike) {
  // The same B runs as a laser's "Run Target Data" block and as a tab-separated table.
  const MeasurementSet table = read_file(kSamples + "b-rotary.txt", ReadOptions{});
  const MeasurementSet laser = read_file(kSamples + "b-laser.rtl", ReadOptions{});
  expect_same_rows(laser, table, "b-laser.rtl");
  EXPECT_EQ(laser.observations.front().row, 10U) << "the line of the reading";
}

TEST(InstrumentFormats, AOneAxisTableStatesItsFrameAsTheContractDoes) {
  const std::string rows = "axis: X\nunit: um\ntarget,deviation\n0,1\n10,2\n";
  const MeasurementSet plain = parse(rows), offset = parse("# frame: program G54 X-250 Y10 Z-300\n" + rows);
  ASSERT_EQ(offset.observations.size(), 2U);
  EXPECT_NEAR(offset.observations[1].q[0] - plain.observations[1].q[0], -250.0 - plain.frames[0].origin[0], 1e-9);
  EXPECT_NEAR(offset.observations[1].q[1] - plain.observations[1].q[1], 10.0 - plain.frames[0].origin[1], 1e-9);
  EXPECT_EQ(offset.frames.size(), 1U);
}

TEST(InstrumentFormats, AContractFileWithColumnsNamedLikeATablesIsTheContract) {
  const MeasurementSet set = parse("x,y,z,nx,ny,nz,d,target,error\n1,2,3,1,0,0,0.001,a,b\n");
  ASSERT_EQ(set.observations.size(), 1U);
  EXPECT_DOUBLE_EQ(set.observations[0].q[1], 2.0);
}

TEST(InstrumentFormats, ASpreadsheetOrABinaryFileIsSaidToBeOne) {
  const std::string xlsx("PK\x03\x04\x14\x00\x06\x00", 8), binary("x,y,z\n\x00\x01", 8);
  EXPECT_NE(test::error_of([&] { (void)parse(xlsx); }, "xlsx").message().find("save the sheet as CSV"),
            std::string::npos);
  EXPECT_NE(test::error_of([&] { (void)parse(binary); }, "binary").message().find("a binary file"), std::string::npos);
}

TEST(InstrumentFormats, RecognisedByContentNotByName) {
  std::ifstream f(kSamples + "x-laser.rtl");
  std::stringstream text;
  text << f.rdbuf();
  MeasurementSet set;
  parse_measurements(text.str(), "laser-export.csv", hmc(), placed(), set);
  EXPECT_EQ(set.observations.size(), 24U);
}

/// One spelling of a one-axis table of the sample's rows.
struct Spelling {
  const char* name;
  char delimiter;
  bool decimal_comma;
  bool um;          // else mm
  bool direction;   // a direction column
  bool run;         // a run column
  int only_run;     // 0: both
  int only_approach;  // 0: both ways
};

class OneAxisTables : public ::testing::TestWithParam<Spelling> {};

TEST_P(OneAxisTables, ReadToTheContractsRows) {
  const Spelling& s = GetParam();
  const std::string d(1, s.delimiter);
  std::string table = "axis: X\n";
  table += std::string("target") + (s.run ? d + "run" : "") + (s.direction ? d + "direction" : "") + d +
           (s.um ? "deviation [um]" : "deviation [mm]") + "\n";
  std::string contract = "x,y,z,vx,nx,ny,nz,d\n";
  for (const Row& r : sample_rows()) {
    if ((s.only_run && r.run != s.only_run) || (s.only_approach && r.approach != s.only_approach)) continue;
    std::string value = s.um ? fmt::format("{:g}", r.um) : fmt::format("{:.4f}", r.um * 1e-3);
    if (s.decimal_comma)
      for (char& c : value)
        if (c == '.') c = ',';
    table += fmt::format("{:g}", r.target) + (s.run ? d + std::to_string(r.run) : "") +
             (s.direction ? d + (r.approach > 0 ? "+" : "-") : "") + d + value + "\n";
    contract += fmt::format("{:g},-360,-400,{},1,0,0,{:.4f}\n", r.target, r.approach, r.um * 1e-3);
  }
  expect_same_rows(parse(table), parse(contract), s.name);
}

INSTANTIATE_TEST_SUITE_P(
    Spellings, OneAxisTables,
    ::testing::Values(Spelling{"commas_mm_direction", ',', false, false, true, true, 0, 0},
                      Spelling{"semicolons_decimal_comma_um", ';', true, true, false, true, 0, 0},
                      Spelling{"tabs_decimal_comma_um", '\t', true, true, true, false, 0, 0},
                      Spelling{"one_direction", ';', true, true, false, true, 0, 1},
                      Spelling{"one_direction_down", ',', false, true, false, true, 0, -1},
                      Spelling{"one_run", '\t', false, true, false, false, 1, 0},
                      Spelling{"one_run_one_direction", ';', true, true, false, false, 2, 1}),
    [](const ::testing::TestParamInfo<Spelling>& spelling) { return std::string(spelling.param.name); });

TEST(InstrumentFormats, ApproachFromTheRunOrder) {
  struct Case {
    const char* what;
    std::vector<double> targets;
    std::vector<int> runs, expected;
  };
  const std::vector<Case> cases{
      {"there and back, the end read twice", {0, 10, 20, 20, 10, 0}, {}, {1, 1, 1, -1, -1, -1}},
      {"there and back, the end read once", {0, 10, 20, 10, 0}, {}, {1, 1, 1, -1, -1}},
      {"one way twice, returning over the targets", {0, 10, 20, 0, 10, 20}, {}, {1, 1, 1, 1, 1, 1}},
      {"down only", {20, 10, 0, 20, 10, 0}, {}, {-1, -1, -1, -1, -1, -1}},
      {"runs apart", {0, 10, 20, 0, 10, 20}, {1, 1, 1, 2, 2, 2}, {1, 1, 1, 1, 1, 1}},
      {"irregular targets (ISO 230-2)", {0, 9.2, 21.4, 29.7, 21.4, 9.2, 0}, {}, {1, 1, 1, 1, -1, -1, -1}},
  };
  for (const Case& c : cases) {
    std::vector<AxisReading> readings;
    for (std::size_t i = 0; i < c.targets.size(); ++i)
      readings.push_back({c.targets[i], 0.0, c.runs.empty() ? 0 : c.runs[i], 0, 0});
    approach_from_run_order(readings);
    std::vector<int> got;
    for (const AxisReading& r : readings) got.push_back(r.approach);
    EXPECT_EQ(got, c.expected) << c.what;
  }
}

TEST(InstrumentFormats, AFileWithoutAUnitIsRefusedWhenItsValuesCannotBeMm) {
  // A stage with 0.1 um errors over 25 mm written in um: read as mm, 89 um (3.6 mm/m), which
  // positioning used to report as A = 88.8 um; a 20 um machine written in um reads as 20 mm.
  std::string small = "target,deviation\n", large = "target,deviation\n", fine = "target,deviation\n";
  for (int k = 0; k <= 10; ++k) {
    const double x = 2.5 * k;
    small += fmt::format("{},{:.4f}\n", x, 0.0888 * std::sin(0.3 * x));
    large += fmt::format("{},{:.2f}\n", 100.0 * k, 20.0 * std::sin(0.03 * 100.0 * k));
    fine += fmt::format("{},{:.5f}\n", 100.0 * k, 0.012 * std::sin(0.03 * 100.0 * k));  // 12 um over 1 m, in mm
  }
  ReadOptions o = placed();
  o.axis = 'X';
  for (const std::string& text : {small, large}) {
    const Error e = test::error_of([&] { (void)parse(text, o); }, text);
    EXPECT_EQ(e.kind(), ErrorKind::data);
    EXPECT_NE(e.message().find("no unit stated"), std::string::npos) << e.message();
    EXPECT_NE(e.message().find("unit: um"), std::string::npos) << "says how to state it: " << e.message();
    EXPECT_GT(e.where().line, 1U);
  }
  EXPECT_NEAR(parse(fine, o).observations[3].value, 0.012 * std::sin(9.0), 1e-5) << "plausible in mm: read as mm";
  o.unit = "um";
  EXPECT_NEAR(parse(small, o).observations[1].value, 1e-3 * 0.0888 * std::sin(0.75), 1e-7) << "--unit states it";
  o.unit.clear();
  EXPECT_NEAR(parse("unit: um\n" + small, o).observations[1].value, 1e-3 * 0.0888 * std::sin(0.75), 1e-7)
      << "a unit line states it";
  o.unit = "mm";
  EXPECT_EQ(test::error_of([&] { (void)parse("unit: um\n" + small, o); }, "--unit mm on a file in um").kind(),
            ErrorKind::usage)
      << "an option that contradicts the file";
}

TEST(InstrumentFormats, ARotaryCalibratorsTurnIsTheTablesTurnAtTheReadingsPoint) {
  const MeasurementSet set = read_file(kSamples + "b-rotary.txt", ReadOptions{});
  ASSERT_EQ(set.observations.size(), 16U);
  // The table turned e beyond its target moves the tool, relative to the table, as the
  // perfect machine at b + e would: its reading along n is that, to first order.
  const model::ForwardModel forward(hmc());
  model::ForwardData data(forward);
  const double arcsec = kRadPerDeg / 3600.0;
  const double expected_arcsec[] = {0.0, 2.1, 3.4, 2.8, 0.9, -1.2, -2.6, -1.9};
  for (std::size_t i = 0; i < 8; ++i) {
    const Observation& o = set.observations[i];
    EXPECT_EQ(o.directions[4], 1.0);
    EXPECT_EQ(set.observations[15 - i].directions[4], -1.0);
    model::forward(forward, data, o.q, MeasurementSet::conditions(o));
    const Eigen::Vector3d at_target = data.nominal;
    const Eigen::Matrix3d R = data.nominal_chain.oMp.R;
    model::ChainQ turned = o.q;
    turned[4] += expected_arcsec[i] * arcsec;
    model::forward(forward, data, turned, MeasurementSet::conditions(o));
    const double moved = o.direction.dot(R * (data.nominal - at_target));
    // The conversion takes the turn's lever from the modelled machine, the test from the
    // perfect one: they differ by the model's errors (its B line tens of um off), some 1e-4
    // of the lever.
    EXPECT_NEAR(o.value, moved, 1e-3 * std::abs(moved) + 1e-12) << "target " << i;
    EXPECT_NEAR(o.direction.norm(), 1.0, 1e-12);
  }
  MeasurementSet linear_units;
  EXPECT_EQ(test::error_of([&] { parse_measurements("axis: B\ntarget,deviation [um]\n0,1\n90,2\n", "b.txt", hmc(), {},
                                                    linear_units); }, "um on B")
                .kind(),
            ErrorKind::data)
      << "um on a rotary axis";
}

TEST(InstrumentFormats, RtlErrorsNameTheirLine) {
  const std::string head =
      "Renishaw Laser10\nAxis: X\nError units: um\nTarget-Count: 3  Run-count: 1\nTargets:\n 0 10 20\n";
  struct Case {
    std::string text, says;
    std::uint32_t line;
  };
  const std::vector<Case> cases{
      {head + "Run: 1 Dir: Fwd\n 0.1 0.2\n", "2 errors for 3 targets", 7},
      {head + "Run: 1 Dir: Fwd\n 0.1 0.2 0.3\nRun: 2 Dir: Bwd\n 0.1 0.2 0.3\n", "Run-count says 1", 10},
      {head + "Run: 1 Dir: Sideways\n 0.1 0.2 0.3\n", "Fwd or Bwd", 7},
      {head + "Run: 1 Dir: Fwd\n 0.1 x 0.3\n", "not a number", 8},
      {"Renishaw Laser10\nAxis: Q\nTargets: 0 10\n", "not an axis", 2},
      {"Renishaw\nAxis: X\nTargets :  0  10  20  Flags : 0 0 0\nRun Target Data:\n1 1 0.1\n1 2 0.2\n1 3 0.3\n1 3 0.3\n"
       "EQUIPMENT::\n",
       "4 readings for 3 targets", 4},
      {"Renishaw\nAxis: X\nTargets :  0  10  x20\n", "'x20' is not a number", 3},
  };
  for (const Case& c : cases) {
    const Error e = test::error_of([&] { (void)parse(c.text); }, c.text);
    EXPECT_EQ(e.kind(), ErrorKind::data) << c.text;
    EXPECT_NE(e.message().find(c.says), std::string::npos) << e.message();
    EXPECT_EQ(e.where().line, c.line) << c.text;
  }
}

TEST(InstrumentFormats, ALineIsCappedWhileItIsRead) {
  const std::string text = "x,y,z,nx,ny,nz,d\n" + std::string(200000, '1') + ",0,0,1,0,0,0\n";
  const Error e = test::error_of([&] { (void)parse(text); }, "a line of 200,000 characters");
  EXPECT_EQ(e.kind(), ErrorKind::data);
  EXPECT_EQ(e.where().line, 2U);
  EXPECT_EQ(e.where().column, 65537U);
  EXPECT_LE(e.source_line().size(), 200U) << "the message carries a piece of the line, not the line";
}

}  // namespace
}  // namespace ccomp::identify
