// Where program zero lies, on every sample machine: a constant angular error of its rotary
// axis alone moves the tool by the angle times the point's arm from the rotary line, and
// the samples put program zero on that line (their comments say so, their work_offsets
// make it so). Read as a measurement file in program coordinates with zero deviations, as
// `ccomp check` reads one, the model's prediction is the closed form d = e x p at program
// zero and 150 mm from it along each axis.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "ccomp/identify/measurements.hpp"
#include "ccomp/model/model_file.hpp"
#include "trace_capture.hpp"

namespace ccomp::identify {
namespace {

struct Sample {
  const char* file;
  char rotary;  ///< its rotary axis
};

class ProgramOrigin : public ::testing::TestWithParam<Sample> {};

TEST_P(ProgramOrigin, ARotaryErrorsLeverIsTheArmFromProgramZero) {
  const Sample& sample = GetParam();
  std::string text = test::read_file(test::source_dir() + "/samples/machines/" + sample.file);
  text = text.substr(0, text.find("\nterms:")) + "\nterms:\n";
  constexpr double kAngle = 8e-6;  // rad
  const std::string column = std::string(1, static_cast<char>(std::tolower(sample.rotary)));
  const std::vector<Eigen::Vector3d> points = {{0, 0, 0},   {150, 0, 0}, {-150, 0, 0}, {0, 150, 0},
                                               {0, -150, 0}, {0, 0, 150}, {0, 0, -150}};
  std::string csv = "x,y,z," + column + ",L,dx,dy,dz\n";
  for (const Eigen::Vector3d& p : points) csv += fmt::format("{},{},{},0,100,0,0,0\n", p.x(), p.y(), p.z());
  for (int component = 0; component < 3; ++component) {
    const std::string term = fmt::format("{}{}", "ABC"[component], sample.rotary);
    const model::MachineModel m = model::parse_machine_model(
        text + fmt::format("  - {{name: E{}, value: {}, unit: urad}}\n", term, kAngle * 1e6), "origin.yaml");
    const model::ForwardModel forward(m);
    model::ForwardData data(forward);
    MeasurementSet set;
    parse_measurements(csv, "zero.csv", m, {}, set);  // program coordinates, the model's G54
    ASSERT_EQ(set.observations.size(), 3 * points.size());
    for (std::size_t k = 0; k < points.size(); ++k) {
      const Eigen::Vector3d expected = kAngle * Eigen::Vector3d::Unit(component).cross(points[k]);
      Eigen::Vector3d predicted;
      for (int c = 0; c < 3; ++c) predicted[c] = predict(forward, data, set.observations[3 * k + c]);
      // First order: the exact turn differs by the angle squared times the arm.
      EXPECT_LT((predicted - expected).norm(), kAngle * kAngle * points[k].norm() + 1e-12)
          << sample.file << " E" << term << " at program point " << points[k].transpose() << ": predicted "
          << predicted.transpose() * 1e3 << " um, the arm from program zero gives " << expected.transpose() * 1e3;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Samples, ProgramOrigin,
                         ::testing::Values(Sample{"hmc-xyzb.yaml", 'B'}, Sample{"hmc-xyzb-geometric.yaml", 'B'},
                                           Sample{"vmc-xyza-trunnion.yaml", 'A'}),
                         [](const ::testing::TestParamInfo<Sample>& sample) {
                           std::string name = sample.param.file;
                           name = name.substr(0, name.find('.'));
                           for (char& c : name)
                             if (c == '-') c = '_';
                           return name;
                         });

}  // namespace
}  // namespace ccomp::identify
