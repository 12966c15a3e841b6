#include "model_schema.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <set>

#include "ccomp/model/term_forms.hpp"
#include "ccomp/util/nearest_name.hpp"
#include "yaml_node.hpp"

namespace ccomp::model::io {

const Section kTopLevel{
    "the model", {"name", "description", "dialect", "axes", "chain", "sensors", "max_correction", "work_offsets", "terms", "fitted",
                  "fit_information"}};
const Section kAxis{"an axis", {"type", "min", "max", "hold"}};
const Section kChain{"chain", {"workpiece", "tool"}};
const Section kLink{"a link", {"link", "axis", "direction", "offset", "tool_length"}};
const std::vector<std::string_view> kTermKeys{"name", "link",     "component", "note",          "fit", "fit_period",
                                              "unit", "form",     "variable",  "variable_unit", "span"};

std::vector<std::string_view> form_keys(std::string_view form) {
  const TermFormInfo* info = term_form(form);
  return info ? info->keys : std::vector<std::string_view>{};
}

std::string nearest_key(std::string_view key, const std::vector<std::string_view>& keys) {
  return util::nearest_name(key, keys);
}

void check_keys(const std::string& file, const YAML::Node& node, const Section& section) {
  if (!node.IsMap()) bad(file, node, fmt::format("{} is a mapping of keys to values", section.what));
  std::set<std::string> seen;
  for (const auto& entry : node) {
    const YAML::Node& key = entry.first;
    if (!key.IsScalar()) bad(file, key, fmt::format("{}: a key is a plain word", section.what));
    const std::string& k = key.Scalar();
    if (!seen.insert(k).second) bad(file, key, fmt::format("{}: '{}' is written twice", section.what, k));
    if (std::find(section.keys.begin(), section.keys.end(), k) != section.keys.end()) continue;
    const std::string near = nearest_key(k, section.keys);
    std::string known;
    for (const std::string_view s : section.keys) known += (known.empty() ? "" : ", ") + std::string(s);
    bad(file, key,
        near.empty() ? fmt::format("{}: unknown key '{}' (known: {})", section.what, k, known)
                     : fmt::format("{}: unknown key '{}': did you mean '{}'?", section.what, k, near));
  }
}

}  // namespace ccomp::model::io
