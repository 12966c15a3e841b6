#pragma once
// Test support: random poses and a machine-like kinematic chain with random placements and
// errors, for the chain's tests and the Jacobian suite. One seeded generator: the same
// draws every run.
#include "ccomp/kinematics/chain.hpp"
#include "ccomp/kinematics/pose.hpp"

namespace ccomp::test {

using kinematics::Pose;
using kinematics::Vec3;

/// Uniform in [a, b), from the suite's one seeded generator.
double uniform(double a, double b);
Vec3 random_vec(double scale);
Pose random_pose();

/// A machine-like chain: W -> X -> Z -> offset d -> B on the workpiece side, W -> Y ->
/// spindle offset -> tool length on the tool side, with random placements.
kinematics::ChainModel sample_chain();
/// Random error motions and locations on every link, and a random point of the workspace.
void randomise(kinematics::ChainData& d, kinematics::VecQ& q);

}  // namespace ccomp::test
