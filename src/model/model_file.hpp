#pragma once
// Private: reading the parts of the machine model file (src/model/machine.cpp reads the
// file and its axes; model_terms.cpp the chain and the error terms).
#include <yaml-cpp/yaml.h>

#include <string>

#include "ccomp/model/machine.hpp"

namespace ccomp::model::file {

[[noreturn]] void bad(const std::string& file, const YAML::Node& node, const std::string& message);
/// A number, or a quantity with a unit ("350 mm"), as internal units.
double quantity(const std::string& file, const YAML::Node& node, const Dimension& expected,
                std::string_view default_unit, const std::string& what);

void read_chains(const std::string& file, const YAML::Node& chain, MachineModel& m);
void read_terms(const std::string& file, const YAML::Node& terms, MachineModel& m);

}  // namespace ccomp::model::file
