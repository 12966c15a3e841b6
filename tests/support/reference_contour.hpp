#pragma once
// Test support: a program judged on the reference machine (reference_hmc.hpp): the path it
// means on the reference's table, and how far what the reference cuts running a program
// (the original, or a compensated one) strays from it.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "reference_hmc.hpp"

namespace ccomp::test {

struct ContourSegment {
  Eigen::Vector3d a, b;
};

/// The feed moves of `program` (tool 1 as kTool1) as the perfect machine cuts them on the table.
[[nodiscard]] std::vector<ContourSegment> nominal_contour(const ReferenceHmc& machine, const std::string& program);

/// The largest distance from `path` of what the reference cuts running `program`, sampled
/// every millimetre or so along each feed move.
[[nodiscard]] double contour_error(const ReferenceHmc& machine, const std::vector<ContourSegment>& path,
                                   const std::string& program);

}  // namespace ccomp::test
