#pragma once
// Placing the machine on a point fixed to the table: the linear axes that take the nominal
// tool tip there as the rotary axes turn it (a probed sphere's poses, for simulate's sphere
// plan and for the spheres `plan` offers).
#include <Eigen/Core>

#include "ccomp/model/forward.hpp"

namespace ccomp::identify {

/// Moves X, Y and Z of `q` so that the nominal tool tip is on `target` (table frame), every
/// other value as given. The nominal tip is affine in the linear axes at fixed rotary
/// angles: two Newton steps on finite differences solve it to rounding.
void reach_table_point(const model::ForwardModel& model, model::ForwardData& d, model::ChainQ& q,
                       const Eigen::Vector3d& target, const model::Conditions& conditions = {});

/// Whether every axis of the model is within its limits at q (Z with the tool length in it,
/// as the axis stands; rotary limits in degrees).
[[nodiscard]] bool within_limits(const model::MachineModel& m, const model::ChainQ& q);

}  // namespace ccomp::identify
