#include "model_schema.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <set>

#include "ccomp/model/term_forms.hpp"
#include "yaml_node.hpp"

namespace ccomp::model::io {

const Section kTopLevel{
    "the model", {"name", "description", "dialect", "axes", "chain", "sensors", "max_correction", "work_offsets", "terms", "fitted",
                  "fit_information"}};
const Section kAxis{"an axis", {"type", "min", "max"}};
const Section kChain{"chain", {"workpiece", "tool"}};
const Section kLink{"a link", {"link", "axis", "direction", "offset", "tool_length"}};
const std::vector<std::string_view> kTermKeys{"name", "link",     "component", "note",          "fit", "fit_period",
                                              "unit", "form",     "variable",  "variable_unit", "span"};

std::vector<std::string_view> form_keys(std::string_view form) {
  const TermFormInfo* info = term_form(form);
  return info ? info->keys : std::vector<std::string_view>{};
}

namespace {

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

}  // namespace

std::string nearest_key(std::string_view key, const std::vector<std::string_view>& keys) {
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(2, key.size() / 3) + 1;
  for (const std::string_view k : keys)
    if (const std::size_t d = edit_distance(key, k); d < best_distance) best_distance = d, best = std::string(k);
  return best;
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
