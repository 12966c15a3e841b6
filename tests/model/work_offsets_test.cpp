// Work offsets as a user writes them (--work-offset, a measurement file's frame line, a
// compensated program's header) and as a model file gives them (work_offsets:); the
// interpreter starting in G54 with them; the header carrying them to verify.
#include <gtest/gtest.h>

#include "ccomp/compensate/machine_coordinates.hpp"
#include "ccomp/compensate/program_header.hpp"
#include "ccomp/identify/measurements.hpp"
#include "ccomp/model/model_file.hpp"
#include "ccomp/model/work_offsets.hpp"
#include "error_of.hpp"
#include "sample_models.hpp"
#include "trace_capture.hpp"

namespace ccomp::model {
namespace {

TEST(WorkOffsets, ParsedAsUsersWriteThem) {
  for (const char* text : {"G54=X-250,Y0,Z-300", "g54 X-250 Y0 Z-300", "G54=X-250mm, Z-0.3m", "G54=X-9.842519685in,Z-300"}) {
    const WorkOffsetEntry e = parse_work_offset(text, "--work-offset");
    EXPECT_EQ(e.system, 1U) << text;
    EXPECT_NEAR(e.origin[0], -250.0, 1e-6) << text;
    EXPECT_EQ(e.origin[1], 0.0) << text;
    EXPECT_NEAR(e.origin[2], -300.0, 1e-9) << text;
  }
  const WorkOffsetEntry b = parse_work_offset("G59.3=B30arcmin,Z5", "x");
  EXPECT_EQ(b.system, 9U);
  EXPECT_NEAR(b.origin[4], 0.5, 1e-12) << "an angle in degrees";
  EXPECT_EQ(describe_work_offset(b.system, b.origin), "G59.3 X0 Y0 Z5 B0.5");
}

TEST(WorkOffsets, RefusalsNameTheWord) {
  struct Case {
    const char *text, *says;
  };
  for (const Case& c : {Case{"G53=X1", "'G53' is not a coordinate system"}, Case{"G54=Q1", "'Q' is not an axis"},
                        Case{"G54=X1,X2", "axis X is given twice"}, Case{"G54=Xabc", "has no number after X"},
                        Case{"G54=X5deg", "'deg' measures angle, but length belongs here"},
                        Case{"G54=B5mm", "'mm' measures length, but angle belongs here"},
                        Case{"G54=Xnan", "not a finite number"}, Case{"G54=", "gives no axis"}, Case{"G55", "gives no axis"}, Case{"G54=X1e300", "beyond any machine"}}) {
    const Error e = test::error_of([&] { (void)parse_work_offset(c.text, "--work-offset"); }, c.text);
    EXPECT_EQ(e.kind(), ErrorKind::usage) << c.text;
    EXPECT_NE(e.message().find(c.says), std::string::npos) << c.text << ": " << e.message();
  }
}

TEST(WorkOffsets, AModelFileGivesThemPerSystem) {
  const MachineModel m = parse_machine_model(
      std::string(test::kHmcChain).replace(std::string(test::kHmcChain).find("work_offsets: {G54: {Z: -400 mm}}"),
                                           33, "work_offsets: {G54: {Z: -400 mm, B: 0.5 deg}, G55: {X: 0.1 m}}"),
      "m.yaml");
  ASSERT_TRUE(m.work_offsets.of(1).has_value());
  EXPECT_EQ((*m.work_offsets.of(1))[2], -400.0);
  EXPECT_NEAR((*m.work_offsets.of(1))[4], 0.5, 1e-12);
  EXPECT_EQ((*m.work_offsets.of(2))[0], 100.0);
  EXPECT_FALSE(m.work_offsets.of(3).has_value());
  struct Case {
    const char *offsets, *says;
  };
  for (const Case& c : {Case{"work_offsets: {G60: {X: 1}}", "'G60' is not a coordinate system"},
                        Case{"work_offsets: {G54: {A: 1}}", "unknown key 'A'"},
                        Case{"work_offsets: {G54: {X: 1 urad}}", "urad"},
                        Case{"work_offsets: [G54]", "'work_offsets' is a mapping"}}) {
    std::string text = test::kHmcChain;
    text.replace(text.find("work_offsets: {G54: {Z: -400 mm}}"), 33, c.offsets);
    const Error e = test::error_of([&] { (void)parse_machine_model(text, "m.yaml"); }, c.offsets);
    EXPECT_EQ(e.kind(), ErrorKind::model) << c.offsets;
    EXPECT_NE(e.message().find(c.says), std::string::npos) << c.offsets << ": " << e.message();
    EXPECT_GT(e.where().line, 0U) << "positioned";
  }
}

TEST(WorkOffsets, TheInterpreterStartsInG54AtTheGivenOriginAndParametersWin) {
  gcode::InterpreterOptions o;
  o.work_offsets[0] = gcode::Axes{10, 20, -400};
  test::RunResult r = test::run_program("G21 G90\nG0 X1 Y2 Z3\nM2\n", o);
  ASSERT_FALSE(r.error.has_value());
  ASSERT_EQ(r.motions.size(), 1U);
  EXPECT_EQ(r.motions[0].motion.end[0], 11.0);
  EXPECT_EQ(r.motions[0].motion.end[2], -397.0);
  EXPECT_EQ(compensate::starting_work_offsets(o).of(1)->at(2), -400.0);
  o.parameters = {{"5223", -300.0}};  // the control's own parameter, as --param gives it
  r = test::run_program("G21 G90\nG0 X1 Y2 Z3\nM2\n", o);
  EXPECT_EQ(r.motions[0].motion.end[2], -297.0);
  EXPECT_EQ(compensate::starting_work_offsets(o).of(1)->at(2), -300.0);
  EXPECT_EQ(compensate::starting_work_offsets(o).of(1)->at(0), 10.0);
}

TEST(WorkOffsets, ARotaryAxisTurningAboutAnOriginNobodyGaveIsSaidOnce) {
  const std::string turns = "G21 G90\nG0 X1 B10\nG0 B20\nG0 B30\nM2\n";
  test::RunResult r = test::run_program(turns);
  ASSERT_EQ(r.warnings.size(), 1U);
  EXPECT_NE(r.warnings[0].find("a rotary axis turns in G54, whose origin nobody gave"), std::string::npos)
      << r.warnings[0];
  EXPECT_TRUE(test::run_program("G21 G90\nG0 X1 Y2\nM2\n").warnings.empty()) << "no rotary axis turns";
  EXPECT_TRUE(test::run_program("G21 G90\nG10 L2 P1 Z-400\nG0 X1 B10\nM2\n").warnings.empty()) << "the program sets it";
  gcode::InterpreterOptions given;
  given.work_offsets[0] = gcode::Axes{};
  EXPECT_TRUE(test::run_program(turns, given).warnings.empty()) << "machine zero, given";
  EXPECT_EQ(test::run_program("G21 G90\nG55\nG0 X1 B10\nM2\n", given).warnings.size(), 1U) << "G55 is not G54";
}

TEST(WorkOffsets, TheHeaderCarriesThemToVerify) {
  MachineModel m;
  m.name = "m";
  m.sha256 = "ab12";
  WorkOffsets offsets;
  offsets.set(1, WorkOrigin{-35, 20, -330.25, 0, 0.5});
  offsets.set(7, WorkOrigin{1});
  const std::string line = compensate::header_line(m, 0.001, {offsets, {}, std::nullopt});
  EXPECT_NE(line.find("work offsets G54 X-35 Y20 Z-330.25 B0.5, G59.1 X1 Y0 Z0"), std::string::npos) << line;
  const auto facts = compensate::read_header(line);
  ASSERT_TRUE(facts.has_value());
  EXPECT_EQ(facts->tolerance, 0.001);
  ASSERT_TRUE(facts->work_offsets.has_value());
  EXPECT_EQ(*facts->work_offsets, offsets);
  const auto none = compensate::read_header(compensate::header_line(m, 0.002));
  ASSERT_TRUE(none && none->work_offsets);
  EXPECT_FALSE(none->work_offsets->any());
  const auto older = compensate::read_header("(ccomp 0.1.0 compensated for machine 'm' model sha256:ab12 at 1 um)");
  ASSERT_TRUE(older.has_value());
  EXPECT_EQ(older->tolerance, 0.001);
  EXPECT_FALSE(older->work_offsets.has_value()) << "a header older than them says nothing of them";
}

}  // namespace
}  // namespace ccomp::model

namespace ccomp::identify {
namespace {

TEST(MeasurementFrame, AFileSaysItsFrameAndTheUsersWordMustAgree) {
  const model::MachineModel m = model::parse_machine_model(test::kHmcChain, "m.yaml");
  MeasurementFrame named = parse_frame_line("# frame: program G55", "f.csv", 1);
  EXPECT_EQ(named.system, 2U);
  EXPECT_FALSE(named.origin.has_value());
  EXPECT_EQ(parse_frame_line("#Frame: MACHINE", "f.csv", 1).kind, FrameKind::machine);
  const MeasurementFrame stated = parse_frame_line("# frame: program G54 X-35 Y20 Z-330", "f.csv", 1);
  ASSERT_TRUE(stated.origin.has_value());
  EXPECT_EQ((*stated.origin)[2], -330.0);
  EXPECT_FALSE(is_frame_line("# a frame of mind"));
  // A frame among the rows would be a comment, the rows read in another frame: refused there.
  MeasurementSet late;
  const Error after = test::error_of(
      [&] { parse_measurements("x,y,z,dx,dy,dz\n1,2,3,0,0,0\n# frame: machine\n", "late.csv", m, {}, late); },
      "a frame line after the header");
  EXPECT_EQ(after.kind(), ErrorKind::data);
  EXPECT_EQ(after.where().line, 3U);
  // An origin on an axis the machine lacks is a mistake, in the file or given.
  MeasurementSet on_a;
  const Error no_a = test::error_of(
      [&] { parse_measurements("# frame: program G54 A10\nx,y,z,dx,dy,dz\n1,2,3,0,0,0\n", "a.csv", m, {}, on_a); },
      "an A offset on a machine without A");
  EXPECT_EQ(no_a.kind(), ErrorKind::data);
  EXPECT_NE(no_a.message().find("has no A axis"), std::string::npos) << no_a.message();
  // The file's own numbers first; the model's where nobody says; unknown past that.
  EXPECT_EQ(resolve_frame(stated, std::nullopt, m, "f.csv").origin[0], -35.0);
  EXPECT_EQ(resolve_frame(std::nullopt, std::nullopt, m, "f.csv").origin[2], -400.0) << "the model's G54";
  EXPECT_TRUE(resolve_frame(named, std::nullopt, m, "f.csv").unknown) << "G55 nobody gave";
  MeasurementFrame user;
  user.origin = model::WorkOrigin{-35, 20, -300};
  const Error clash = test::error_of([&] { (void)resolve_frame(stated, user, m, "f.csv"); }, "a contradiction");
  EXPECT_EQ(clash.kind(), ErrorKind::data);
  EXPECT_NE(clash.message().find("which is it?"), std::string::npos) << clash.message();
  for (const char* bad : {"# frame: table", "# frame: program", "# frame: machine G54", "# frame: program G54 Q1"}) {
    const Error e = test::error_of([&] { (void)parse_frame_line(bad, "f.csv", 3); }, bad);
    EXPECT_EQ(e.kind(), ErrorKind::data) << bad;
    EXPECT_EQ(e.where().line, 3U) << bad;
  }
}

TEST(MeasurementFrame, MachineCoordinatesAreTheAxesThemselves) {
  const model::MachineModel m = model::parse_machine_model(test::kHmcChain, "m.yaml");
  MeasurementSet set;
  parse_measurements("# frame: machine\nx,y,z,L,dx,dy,dz\n1,2,-250,100,0,0,0\n", "m.csv", m, {}, set);
  EXPECT_EQ(set.observations[0].q[2], -250.0) << "the Z axis as the control shows it (G53): no tool taken off";
  MeasurementSet program;
  parse_measurements("x,y,z,L,dx,dy,dz\n1,2,-250,100,0,0,0\n", "p.csv", m, {}, program);
  EXPECT_EQ(program.observations[0].q[2], -250.0 - 400.0 + 100.0) << "program z, G54 and the tool";
}

}  // namespace
}  // namespace ccomp::identify
