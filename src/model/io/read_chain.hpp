#pragma once
// Private to src/model/io: reading the model file's `chain`, the links from the base to
// the workpiece and to the tool.
#include <yaml-cpp/yaml.h>

#include <string>

#include "ccomp/model/machine.hpp"

namespace ccomp::model::io {

/// Reads `chain` (nothing when it is absent) into m's chains; m's axes are read already.
void read_chains(const std::string& file, const YAML::Node& chain, MachineModel& m);

}  // namespace ccomp::model::io
