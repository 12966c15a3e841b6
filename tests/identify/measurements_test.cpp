// Reading the measurement CSV contract (error-model.md sect. 5): what it accepts, and errors
// that name the file, the row and the column.
#include "ccomp/identify/measurements.hpp"

#include <gtest/gtest.h>

#include "ccomp/error.hpp"
#include "ccomp/model/model_file.hpp"
#include "error_of.hpp"
#include "sample_models.hpp"

namespace ccomp::identify {
namespace {

const model::MachineModel& hmc() {
  static const model::MachineModel m = model::parse_machine_model(
      std::string(test::kHmcChain) + "terms:\n  - {name: EZS, variable: T_spindle, form: thermal, coefficient: 1.5}\n",
      "hmc.yaml");
  return m;
}

MeasurementSet parse(const std::string& text, double tool_length = 100.0) {
  MeasurementSet set;
  ReadOptions o;
  o.tool_length = tool_length;
  parse_measurements(text, "m.csv", hmc(), o, set);
  return set;
}

Error parse_error(const std::string& text) {
  return test::error_of([&] { (void)parse(text); }, text);
}

TEST(Measurements, ScalarAndFullRowsBecomeObservations) {
  const MeasurementSet s = parse(
      "# a laser line and a probed point\n"
      "x,y,z,b,T_spindle,vx,nx,ny,nz,d,dx,dy,dz,source,operator\n"
      "10,20,-30,90,25,1,0.6,0.8,0,0.004,,,,\"line, first\",ann\n"
      "1,2,3,,25,,,,,,0.001,-0.002,0.003,probe,ann\n");
  ASSERT_EQ(s.observations.size(), 4U);
  const Observation& a = s.observations[0];
  EXPECT_DOUBLE_EQ(a.q[0], 10);
  EXPECT_DOUBLE_EQ(a.q[2], -30 - 400 + 100) << "program z, G54 (the model's) and the tool length make the Z axis";
  EXPECT_DOUBLE_EQ(a.q[9], 100);
  EXPECT_NEAR(a.q[4], M_PI / 2, 1e-15);
  EXPECT_EQ(a.directions[0], 1.0);
  EXPECT_NEAR(a.direction.y(), 0.8, 1e-15);
  EXPECT_DOUBLE_EQ(a.value, 0.004);
  EXPECT_EQ(a.row, 3U);
  EXPECT_EQ(s.sources[a.source], "line, first");
  EXPECT_EQ(s.observations[3].direction, Eigen::Vector3d::UnitZ());
  EXPECT_DOUBLE_EQ(s.observations[2].value, -0.002);
  EXPECT_EQ(s.observations[1].temperatures, std::vector<double>({20.0, 25.0})) << "sensors the file lacks read 20";
  ASSERT_EQ(s.notices.size(), 1U);
  EXPECT_NE(s.notices[0].find("'operator'"), std::string::npos);
}

TEST(Measurements, SemicolonsAndTabsWithDecimalCommasReadAsCommas) {
  // What a spreadsheet set to a decimal comma writes ("header has no 'x' column" before).
  const MeasurementSet commas =
      parse("x,y,z,T_spindle,vx,nx,ny,nz,d,source\n10.5,-2,3,21.5,1,1,0,0,0.0042,\"a;b\"\n");
  for (const char* text :
       {"x;y;z;T_spindle;vx;nx;ny;nz;d;source\n10,5;-2;3;21,5;1;1;0;0;0,0042;\"a;b\"\n",
        "x\ty\tz\tT_spindle\tvx\tnx\tny\tnz\td\tsource\n10,5\t-2\t3\t21,5\t1\t1\t0\t0\t0,0042\ta;b\n"}) {
    const MeasurementSet s = parse(text);
    ASSERT_EQ(s.observations.size(), 1U) << text;
    EXPECT_EQ(s.observations[0].q, commas.observations[0].q) << text;
    EXPECT_EQ(s.observations[0].value, commas.observations[0].value) << text;
    EXPECT_EQ(s.observations[0].temperatures, commas.observations[0].temperatures) << text;
    EXPECT_EQ(s.sources, commas.sources) << text;
  }
}

TEST(Measurements, ErrorsNameRowColumnAndCause) {
  struct Case {
    const char* text;
    std::uint32_t row, column;
    const char* says;
  };
  const Case cases[] = {
      {"x,y,nx,ny,nz,d,T_spindle\n1,2,1,0,0,0.1,20\n", 1, 1, "no 'z' column"},
      {"x,y,z,nx,ny,nz,d\n1,2,3,1,0,0,0.1\n", 1, 1, "sensor 'spindle'"},
      {"x,y,z,T_spindle,nx,ny,nz,d\n1,2,3,20,1,0,0,0.1\n1,2,nan,20,1,0,0,0.1\n", 3, 5, "column 'z' is nan"},
      {"x,y,z,T_spindle,nx,ny,nz,d\n1,2,3,20,1,1,0,0.1\n", 2, 10, "not a unit vector"},
      {"x,y,z,T_spindle,nx,ny,nz,d\n1,2,3,20,1,0,0,1O\n", 2, 16, "'1O' is not a number"},
      // A position of 1e100 mm crashed fit and check (SIGSEGV in the eigen-solver).
      {"x,y,z,T_spindle,nx,ny,nz,d\n1e100,2,3,20,1,0,0,0.001\n", 2, 1, "beyond any machine's range"},
      {"x,y,z,T_spindle,nx,ny,nz,d\n1,2,3,-3e9,1,0,0,0.001\n", 2, 7, "beyond any machine's range"},
      {"x,y,z,T_spindle,nx,ny,nz,d\n1,2,3,20,1,0,0\n", 2, 1, "this row has 7 fields"},
      {"x,y,z,T_spindle,dx,dy\n", 1, 1, "needs dy and dz"},
      {"x,y,z,a,T_spindle,dx,dy,dz\n", 1, 7, "an axis machine 'test-hmc' does not have"},
      {"x,y,z,T_spindle,vx,dx,dy,dz\n1,2,3,20,2,0,0,0\n", 2, 10, "+1, -1 or 0"},
      {"x,y,z,T_spindle,nx,ny,nz,d\n", 1, 1, "no readings after the header"},
      {"# only a comment\nx,y,z,T_spindle,nx,ny,nz,d\n\n", 2, 1, "no readings after the header"},
      // um where mm is due: 2.5 and 4.1 "mm" of deviation, beyond the model's 0.5 mm bound.
      {"x,y,z,T_spindle,nx,ny,nz,d\n1,2,3,20,1,0,0,2.5\n4,5,6,20,1,0,0,-4.1\n7,8,9,20,1,0,0,0.3\n", 2, 26,
       "written in um?"},
      // Line ends of CR alone (a classic Mac file) read as one line: said so, at the first.
      {"x,y,z,T_spindle,nx,ny,nz,d\r1,2,3,20,1,0,0,0.001\r", 1, 27, "line ends of CR alone"},
      {"x,y,z,T_spindle,nx,ny,nz,d\r\n1,2,3,20,1,0,0,0.001\r4,5,6,20,1,0,0,0.001\r\n", 2, 21, "line ends of CR alone"},
  };
  for (const Case& c : cases) {
    const Error e = parse_error(c.text);
    EXPECT_EQ(e.kind(), ErrorKind::data) << c.text;
    EXPECT_EQ(e.where().file, "m.csv");
    EXPECT_EQ(e.where().line, c.row) << c.text << e.message();
    EXPECT_EQ(e.where().column, c.column) << c.text << e.message();
    EXPECT_NE(e.message().find(c.says), std::string::npos) << e.message();
  }
}

TEST(Measurements, AByteOrderMarkIsNotPartOfTheHeader) {
  // A spreadsheet's "CSV UTF-8" starts with one; CRLF line ends are read as LF ones.
  const MeasurementSet s = parse("\xEF\xBB\xBFx,y,z,T_spindle,nx,ny,nz,d\r\n1,2,3,20,1,0,0,0.001\r\n");
  ASSERT_EQ(s.observations.size(), 1U);
  EXPECT_DOUBLE_EQ(s.observations[0].q[0], 1.0);
  EXPECT_DOUBLE_EQ(s.observations[0].value, 0.001);
}

TEST(Measurements, ARepeatedRowIsKeptAndSaid) {
  // Repeated approaches read at 1 um resolution give the same row twice (ISO 230-2); a file
  // pasted in twice does too: kept, and the reader says where.
  const MeasurementSet s =
      parse("x,y,z,T_spindle,vx,nx,ny,nz,d\n1,2,3,20,1,1,0,0,0.001\n4,5,6,20,1,1,0,0,0.002\n1,2,3,20,1,1,0,0,0.001\n");
  EXPECT_EQ(s.observations.size(), 3U);
  ASSERT_EQ(s.notices.size(), 1U);
  EXPECT_NE(s.notices[0].find("m.csv:4: the row repeats row 2"), std::string::npos) << s.notices[0];
}

TEST(Measurements, SensorsTheModelLacksAreReadForTheDiagnosis) {
  MeasurementSet s;
  parse_measurements("x,y,z,T_spindle,T_column,nx,ny,nz,d\n1,2,3,20,21.5,1,0,0,0.001\n", "a.csv", hmc(), {}, s);
  parse_measurements("x,y,z,T_spindle,nx,ny,nz,d\n4,5,6,22,1,0,0,0.002\n", "b.csv", hmc(), {}, s);
  ASSERT_EQ(s.sensors.size(), 3U);
  EXPECT_EQ(s.sensors[0], "bed") << "the model's first";
  EXPECT_EQ(s.sensors[1], "spindle");
  EXPECT_EQ(s.sensors[2], "column");
  EXPECT_DOUBLE_EQ(s.observations[0].temperatures[2], 21.5);
  EXPECT_TRUE(std::isnan(s.observations[1].temperatures[2])) << "b.csv has no T_column";
  for (const std::string& notice : s.notices) EXPECT_EQ(notice.find("T_column"), std::string::npos) << notice;
}

TEST(Measurements, ASpikeIsNotTakenForAWrongUnit) {
  // One reading of 3 mm among small ones: a laser beam cut, not um written as mm.
  const MeasurementSet s =
      parse("x,y,z,T_spindle,nx,ny,nz,d\n1,2,3,20,1,0,0,0.002\n4,5,6,20,1,0,0,3.0\n7,8,9,20,1,0,0,-0.001\n");
  EXPECT_EQ(s.observations.size(), 3U);
}

TEST(Measurements, SummaryGivesRangesAndCsvRoundTrips) {
  MeasurementSet s =
      parse("x,y,z,b,L,T_spindle,vx,dx,dy,dz\n-5,0,1,0,50,21,-1,0,0,0.001\n7,3,1,45,150,24,1,0.002,0,0\n");
  summarize(s, hmc());
  auto range = [&](const std::string& name) {
    for (const VariableRange& r : s.ranges)
      if (r.name == name) return std::make_pair(r.min, r.max);
    return std::make_pair(-1.0, -1.0);
  };
  EXPECT_EQ(range("x"), std::make_pair(-5.0, 7.0));
  EXPECT_EQ(range("z"), std::make_pair(1.0, 1.0)) << "program z, not the Z axis";
  EXPECT_EQ(range("L"), std::make_pair(50.0, 150.0));
  EXPECT_EQ(range("b"), std::make_pair(0.0, 45.0));
  EXPECT_EQ(range("T_spindle"), std::make_pair(21.0, 24.0));
  const MeasurementSet again = parse(to_csv(s, hmc(), s.frames.at(0)));
  ASSERT_EQ(again.observations.size(), s.observations.size());
  for (std::size_t i = 0; i < s.observations.size(); ++i) {
    EXPECT_LT((again.observations[i].q - s.observations[i].q).norm(), 1e-9);
    EXPECT_NEAR(again.observations[i].value, s.observations[i].value, 1e-15);
    EXPECT_EQ(again.observations[i].direction, s.observations[i].direction);
    EXPECT_EQ(again.observations[i].directions, s.observations[i].directions);
  }
}

}  // namespace
}  // namespace ccomp::identify
