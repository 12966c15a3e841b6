#pragma once
// Private to src/model/io: reading the model file's error terms.
#include <yaml-cpp/yaml.h>

#include <string>

#include "ccomp/model/machine.hpp"

namespace ccomp::model::io {

/// Appends the terms of `terms` (nothing when it is absent) to m's; m's axes, sensors and
/// chains are read already.
void read_terms(const std::string& file, const YAML::Node& terms, MachineModel& m);

}  // namespace ccomp::model::io
