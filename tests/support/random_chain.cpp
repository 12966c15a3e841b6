#include "random_chain.hpp"

#include <random>

namespace ccomp::test {

using namespace kinematics;

namespace {
std::mt19937& rng() {
  static std::mt19937 g(20261122);
  return g;
}
}  // namespace

double uniform(double a, double b) {
  return std::uniform_real_distribution<double>(a, b)(rng());
}
Vec3 random_vec(double scale) {
  return Vec3(uniform(-scale, scale), uniform(-scale, scale), uniform(-scale, scale));
}
Pose random_pose() {
  return Pose{so3_exp(random_vec(2.0)), random_vec(300.0)};
}

/// A machine-like chain: W -> X -> Z -> offset d -> B on the workpiece side, W -> Y ->
/// spindle offset -> tool length on the tool side, with random placements and errors.
ChainModel sample_chain() {
  ChainModel m;
  auto joint = [](const char* name, JointType type, std::size_t axis, Vec3 dir, Pose placement) {
    return Joint{name, type, axis, dir.normalized(), placement};
  };
  m.workpiece.joints = {joint("X", JointType::linear, 0, Vec3(-1, 0, 0), Pose{}),
                        joint("Z", JointType::linear, 2, Vec3(0, 0, -1), Pose{so3_exp(random_vec(1e-3)), Vec3::Zero()}),
                        joint("B", JointType::rotary, 4, Vec3(0, -1, 0), Pose::translation(Vec3(0, 0, 350))),
                        joint("p", JointType::fixed, 0, Vec3::UnitX(), Pose{})};
  m.tool.joints = {joint("Y", JointType::linear, 1, Vec3(0, 1, 0), Pose{}),
                   joint("S", JointType::fixed, 0, Vec3::UnitX(), Pose::translation(Vec3(0, 0, 600))),
                   joint("tool", JointType::fixed, 0, Vec3::UnitX(), Pose::translation(Vec3(0, 0, -100)))};
  return m;
}

void randomise(ChainData& d, VecQ& q) {
  for (Pose& e : d.work_error) e = error_pose(random_vec(0.05), random_vec(1e-4));
  for (Pose& e : d.tool_error) e = error_pose(random_vec(0.05), random_vec(1e-4));
  for (Pose& e : d.work_location) e = error_pose(random_vec(0.05), random_vec(1e-4));
  for (Pose& e : d.tool_location) e = error_pose(random_vec(0.05), random_vec(1e-4));
  q = VecQ::Zero(9);
  q << uniform(-400, 400), uniform(-300, 300), uniform(-200, 200), 0, uniform(-3, 3), 0, 0, 0, 0;
}

}  // namespace ccomp::test
