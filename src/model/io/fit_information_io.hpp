#pragma once
// Private to src/model/io: the model file's `fit_information:` section (model/fit_information.hpp).
#include <yaml-cpp/yaml.h>

#include <string>

#include "ccomp/model/fit_information.hpp"
#include "ccomp/model/machine.hpp"

namespace ccomp::model::io {

/// Reads `fit_information:` (none when the file has none) of the model `m`, whose terms are
/// read: each parameter must name a term and a parameter it has, under its own label; the
/// covariance factor has one number per parameter in each row, finite; coverage names the
/// model's axes or L. Throws Error (model) at the bad value.
[[nodiscard]] std::optional<FitInformation> read_fit_information(const std::string& file, const YAML::Node& node,
                                                                 const MachineModel& m);

/// The section as a YAML node (numbers to round-trip; lists in flow style).
[[nodiscard]] YAML::Node fit_information_node(const FitInformation& info);

}  // namespace ccomp::model::io
