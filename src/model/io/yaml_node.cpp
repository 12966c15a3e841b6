#include "yaml_node.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdint>

namespace ccomp::model::io {

SourceLocation at(const std::string& file, const YAML::Mark& mark) {
  return SourceLocation{file, mark.line >= 0 ? static_cast<std::uint32_t>(mark.line + 1) : 0,
                        mark.column >= 0 ? static_cast<std::uint32_t>(mark.column + 1) : 0};
}

void bad(const std::string& file, const YAML::Node& node, const std::string& message) {
  // A key that is not there has no place in the file: the message alone, with the file.
  throw Error(ErrorKind::model, message, at(file, node.IsDefined() ? node.Mark() : YAML::Mark::null_mark()));
}

double quantity(const std::string& file, const YAML::Node& node, const Dimension& expected,
                std::string_view default_unit, const std::string& what) {
  if (!node || !node.IsScalar()) bad(file, node, what + " must be a number, with a unit or not");
  try {
    return parse_quantity(node.as<std::string>(), expected, default_unit, what);
  } catch (const Error& e) {
    bad(file, node, e.message());
  }
}

double number(const std::string& file, const YAML::Node& node, const std::string& what) {
  try {
    const std::string s = node.as<std::string>();
    if (s == ".nan" || s == "nan" || s == "NaN") bad(file, node, what + " is NaN");
    const double v = node.as<double>();
    if (std::isnan(v)) bad(file, node, what + " is NaN");
    return v;
  } catch (const YAML::Exception&) {
    bad(file, node, fmt::format("{} must be a number, not '{}'", what, YAML::Dump(node)));
  }
}

std::string text(const std::string& file, const YAML::Node& node, const std::string& what) {
  if (!node || !node.IsScalar()) bad(file, node, fmt::format("{} must be a single value, not a list or mapping", what));
  return node.Scalar();
}

bool flag(const std::string& file, const YAML::Node& node, const std::string& what) {
  bool value = false;
  if (!node.IsScalar() || !YAML::convert<bool>::decode(node, value))
    bad(file, node, fmt::format("{} is true or false, not '{}'", what, node.IsScalar() ? node.Scalar() : "a list"));
  return value;
}

std::vector<std::string> sensors_of_term(const YAML::Node& term) {
  std::vector<std::string> sensors;
  for (const char* key : {"variable", "temperature"})
    if (const YAML::Node v = term[key]; v && v.IsScalar() && v.Scalar().starts_with("T_"))
      sensors.push_back(v.Scalar().substr(2));
  return sensors;
}

}  // namespace ccomp::model::io
