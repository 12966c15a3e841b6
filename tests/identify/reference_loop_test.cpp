// The promise users buy, end to end on a machine written apart from ccomp's model code
// (tests/support/reference_hmc): measure it (nine laser lines, a grid at two tool lengths,
// two spheres probed as B turns), follow the loop from the geometric sample model as a script
// would (check's first suggestion added, refit, again until nothing is missing), compensate
// a program cut across the workspace at several table angles with the model it ends with,
// and judge the compensated program on the reference machine itself.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numbers>

#include "ccomp/compensate/verify.hpp"
#include "ccomp/identify/diagnose.hpp"
#include "ccomp/identify/fit.hpp"
#include "ccomp/model/model_file.hpp"
#include "job_runner.hpp"
#include "metrology_loop.hpp"
#include "reference_contour.hpp"
#include "reference_hmc.hpp"
#include "reference_measurements.hpp"
#include "trace_capture.hpp"

namespace ccomp::identify {
namespace {

constexpr double kNoise = 0.0002;  // mm

/// The reference: a machine of the sample HMC's kind with a 10 mm lead-screw error on X
/// that the geometric model lacks.
test::ReferenceHmc reference() {
  test::ReferenceHmc m = test::geometric_reference();
  const auto polynomial = m.EXX;
  m.EXX = [polynomial](double x) {
    return polynomial(x) + 0.0018 * std::cos(2 * std::numbers::pi * x / 10.0) -
           0.0009 * std::sin(2 * std::numbers::pi * x / 10.0);
  };
  return m;
}

/// A slanted rectangle cut at each table angle, across the workspace the reference was
/// measured over, in its program coordinates (its own zero, reference_hmc.hpp).
std::string contour_program(const test::ReferenceHmc& machine) {
  const Eigen::Vector3d o = -machine.work_origin;  // machine zero in program coordinates
  std::string p = "G21 G17 G90 G94 G54\nT1 M6\nG43 H1\n";
  for (const char* b : {"0", "30", "135", "220", "300"})
    p += fmt::format(
        "G0 B{}\nG0 X{} Y{} Z{}\nG1 X{} F800\nG1 Y{} Z{}\nG1 X{}\nG1 Y{} Z{}\nG0 Z{}\n", b, o.x() - 300,
        o.y() - 200, o.z() - 380, o.x() + 310, o.y() + 180, o.z() - 220, o.x() - 300, o.y() - 200, o.z() - 380,
        o.z() - 480);
  return p + "M30\n";
}

/// The program compensated with the model `text`, told where the reference's program zero
/// is in each documented way: the model's work_offsets, --work-offset, the program's own
/// G10 L2, and the control's parameters (--param 5221...). Each output, judged on the
/// reference, by way.
std::vector<std::pair<std::string, double>> compensated_each_way(const test::ReferenceHmc& machine,
                                                                 const std::vector<test::ContourSegment>& path,
                                                                 const std::string& text, const std::string& program) {
  const Eigen::Vector3d o = machine.work_origin;
  std::vector<std::pair<std::string, double>> judged;
  {
    std::string with_offsets = text;
    const std::string g54 = "G54: {X: 0 mm, Y: 0 mm, Z: -400 mm}";
    const auto at = with_offsets.find(g54);
    EXPECT_NE(at, std::string::npos) << "the sample's work offset, to replace";
    if (at != std::string::npos) with_offsets.replace(at, g54.size(), fmt::format("G54: {{X: {}, Y: {}, Z: {}}}", o.x(), o.y(), o.z()));
    const model::MachineModel m = model::parse_machine_model(with_offsets, "fitted.yaml");
    judged.emplace_back("model", test::contour_error(machine, path, test::compensate(program, m, 0.001)));
  }
  const model::MachineModel m = model::parse_machine_model(text, "fitted.yaml");
  compensate::JobOptions option;
  option.interpreter.work_offsets[0] = gcode::Axes{o.x(), o.y(), o.z()};
  judged.emplace_back("--work-offset", test::contour_error(machine, path, test::compensate(program, m, option)));
  std::string set_by_program = program;
  set_by_program.insert(set_by_program.find('\n') + 1, fmt::format("G10 L2 P1 X{} Y{} Z{}\n", o.x(), o.y(), o.z()));
  judged.emplace_back("G10 L2", test::contour_error(machine, path, test::compensate(set_by_program, m, 0.001)));
  compensate::JobOptions params;
  params.interpreter.parameters = {{"5221", o.x()}, {"5222", o.y()}, {"5223", o.z()}};
  judged.emplace_back("--param", test::contour_error(machine, path, test::compensate(program, m, params)));
  return judged;
}

TEST(ReferenceLoop, FollowingTheSuggestionsThenCompensatingLeavesUnderFivePercentOfTheError) {
  const test::ReferenceHmc machine = reference();
  test::ReferencePlans plans;
  plans.noise = kNoise, plans.seed = 11, plans.line_step = 2.5;  // four readings per screw pitch, as the samples
  const MeasurementSet data = test::reference_measurements(machine, test::measure_reference(machine, plans));
  // The loop, as a script follows check --json: add the first suggestion, refit, again.
  const test::LoopResult loop =
      test::follow_the_loop(test::read_file(test::source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml"), data);
  ASSERT_TRUE(loop.refusals.empty()) << loop.refusals.front();
  const std::vector<std::string>& added = loop.added;
  ASSERT_FALSE(added.empty()) << "the lead screw is missing from the geometric model";
  EXPECT_NE(added.front().find("name: EXX, form: periodic, period: "), std::string::npos) << added.front();
  const double period = std::stod(added.front().substr(added.front().find("period: ") + 8));
  EXPECT_NEAR(period, 10.0, 0.01) << added.front();
  EXPECT_TRUE(loop.ended) << "the loop ends: nothing is missing";
  EXPECT_LE(loop.last.rms_after, 1.3 * kNoise);
  // Compensate with the model the loop ended with; judge on the reference machine.
  const std::string program = contour_program(machine);
  const std::vector<test::ContourSegment> path = test::nominal_contour(machine, program);
  const double before = test::contour_error(machine, path, program);
  EXPECT_GT(before, 0.015) << "the machine as it is misses the contour by tens of um";
  const auto judged = compensated_each_way(machine, path, loop.text, program);
  for (const auto& [way, after] : judged) {
    EXPECT_LE(after, 0.05 * before) << way << ": before " << before * 1e3 << " um, after " << after * 1e3 << " um";
    EXPECT_NEAR(after, judged.front().second, 1e-6) << "told by " << way << " as by the model's work_offsets";
  }
  std::cout << "[ reference ] loop added " << added.size() << " term(s); contour error before " << before * 1e3
            << " um, after " << judged.front().second * 1e3 << " um\n";
}

// Where the reference's program zero is told the reader in each documented way, the
// readings land on the same axis positions: the loop above is the same whichever way.
TEST(ReferenceLoop, TheMeasurementsFrameGivenAnyWayPlacesTheSameReadings) {
  const test::ReferenceHmc machine = reference();
  test::ReferencePlans plans;
  plans.noise = kNoise, plans.seed = 11, plans.line_step = 20.0;
  const std::vector<test::ReferenceReading> readings = test::measure_reference(machine, plans);
  const MeasurementSet in_file = test::reference_measurements(machine, readings, test::FrameGiven::in_file);
  for (const test::FrameGiven how : {test::FrameGiven::by_option, test::FrameGiven::by_model}) {
    const MeasurementSet other = test::reference_measurements(machine, readings, how);
    ASSERT_EQ(other.observations.size(), in_file.observations.size());
    double off = 0.0;
    for (std::size_t i = 0; i < other.observations.size(); ++i)
      off = std::max(off, (other.observations[i].q - in_file.observations[i].q).cwiseAbs().maxCoeff());
    EXPECT_LT(off, 1e-9) << "frame given way " << static_cast<int>(how);
  }
  // And they are the reference's own axis positions.
  for (std::size_t i = 0; i < readings.size(); i += 97) {
    const model::ChainQ& q = in_file.observations[i].q;
    EXPECT_NEAR(q[0], readings[i].x, 1e-8);
    EXPECT_NEAR(q[2], readings[i].z, 1e-8);
  }
}

}  // namespace
}  // namespace ccomp::identify

namespace ccomp::identify {
namespace {

// The reference's readings read with the sample's own G54 (the B centre) instead of the
// reference's program zero: check says the frame is wrong, with the shift, rather than let
// the table's harmonics absorb it; read right, it says nothing of the kind.
TEST(ReferenceLoop, AWrongWorkOffsetIsNamedAsSuch) {
  // The table's angular positioning with a second harmonic (an encoder's or a worm's): what
  // it moves a point by grows with the point's distance from the B line, so a wrong origin
  // leaves a twice-a-turn error that B's own translations (one harmonic in the model)
  // cannot take. (Errors the model's free terms can take whatever the origin, the data
  // cannot place: then nothing is said, and nothing is lost in compensation either.)
  test::ReferenceHmc machine = test::geometric_reference();
  machine.EBB = [](double b) {
    const double r = b * std::numbers::pi / 180.0;
    return 12e-6 * std::cos(r) + 20e-6 * std::sin(2 * r);
  };
  test::ReferencePlans plans;
  plans.noise = kNoise, plans.seed = 5, plans.line_step = 20.0;
  const std::vector<test::ReferenceReading> readings = test::measure_reference(machine, plans);
  const std::string sample = test::source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml";
  const model::MachineModel geometric = model::load_machine_model(sample);
  MeasurementSet wrong;  // no frame line: the model's G54, Z-400 where the reference's is Z-330
  parse_measurements(test::reference_csv(machine, readings, test::FrameGiven::by_model), "wrong.csv", geometric, {},
                     wrong);
  const Diagnosis d = diagnose(model::ForwardModel(geometric), wrong);
  ASSERT_TRUE(d.origin_misfit.has_value()) << "the readings sit 70 mm off along Z and 35 along X; " << d.skipped
                                            << " rms " << d.rms_refit << " noise " << d.noise << " readings "
                                            << wrong.observations.size();
  const Eigen::Vector3d truth = machine.work_origin - Eigen::Vector3d(0, 0, -400);
  // Weighed at the refit of the wrongly placed readings: near the truth, not at it.
  EXPECT_NEAR(d.origin_misfit->shift.x(), truth.x(), 0.3 * truth.norm()) << d.origin_misfit->shift.transpose();
  EXPECT_NEAR(d.origin_misfit->shift.z(), truth.z(), 0.3 * truth.norm()) << d.origin_misfit->shift.transpose();
  EXPECT_LT(std::abs(d.origin_misfit->shift.y()), 0.3 * truth.norm()) << "Y moves no lever of B's: not said";
  EXPECT_LT(d.origin_misfit->rms_after, 0.8 * d.origin_misfit->rms_before);
  const MeasurementSet right = test::reference_measurements(machine, readings);
  EXPECT_FALSE(diagnose(model::ForwardModel(geometric), right).origin_misfit.has_value());
}

}  // namespace
}  // namespace ccomp::identify
