#pragma once
// Private to src/model/io: reading one node of a machine model file. Every reader of the
// file (the model, its chains, its terms, the key schema) refuses a bad value through
// these, so every refusal names the file, the line and the column of the value.
#include <yaml-cpp/yaml.h>

#include <string>
#include <string_view>
#include <vector>

#include "ccomp/axis.hpp"
#include "ccomp/error.hpp"
#include "ccomp/model/units.hpp"

namespace ccomp::model::io {

/// The axis letters a model file may write, in the order of Variable::index.

/// The place of a YAML mark in `file` (lines and columns from 1; 0 when unknown).
[[nodiscard]] SourceLocation at(const std::string& file, const YAML::Mark& mark);

/// Throws ccomp::Error (model) with `message` at the node's place in `file`.
[[noreturn]] void bad(const std::string& file, const YAML::Node& node, const std::string& message);

/// A number, or a quantity with a unit ("350 mm"), as internal units.
[[nodiscard]] double quantity(const std::string& file, const YAML::Node& node, const Dimension& expected,
                              std::string_view default_unit, const std::string& what);
/// A plain number (an axis limit); NaN and text are refused naming `what`.
[[nodiscard]] double number(const std::string& file, const YAML::Node& node, const std::string& what);
/// A scalar's text; anything else (a list, a mapping, nothing) is refused naming `what`.
[[nodiscard]] std::string text(const std::string& file, const YAML::Node& node, const std::string& what);
/// true or false (YAML's yes/no/on/off too); anything else is refused naming `what`.
[[nodiscard]] bool flag(const std::string& file, const YAML::Node& node, const std::string& what);

/// The sensors a one-line term spec's T_<name> variables name (`variable`, `temperature`).
[[nodiscard]] std::vector<std::string> sensors_of_term(const YAML::Node& term);

}  // namespace ccomp::model::io
