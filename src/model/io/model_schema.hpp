#pragma once
// Private to src/model/io: the keys each section of the machine model file may have. A
// key the schema lacks is refused where it is written, with the nearest known key (a
// misspelt `max_corection` would otherwise silently drop a safety bound).
#include <yaml-cpp/yaml.h>

#include <string>
#include <string_view>
#include <vector>

namespace ccomp::model::io {

/// A section of the file and the keys it may have.
struct Section {
  std::string_view what;  ///< "the model", "an axis", "a link", "term EXX (form periodic)"
  std::vector<std::string_view> keys;
};

extern const Section kTopLevel, kAxis, kChain, kLink;
/// The keys every term may have, whatever its form.
extern const std::vector<std::string_view> kTermKeys;
/// The keys of a form beyond kTermKeys; empty for a form the schema does not know.
[[nodiscard]] std::vector<std::string_view> form_keys(std::string_view form);

/// Refuses (ccomp::Error, model, at the key) a node that is not a mapping, a key that is
/// not a plain word, a key the section does not have (naming the nearest it does) and a
/// key written twice.
void check_keys(const std::string& file, const YAML::Node& node, const Section& section);

/// The known key nearest `key` (by edit distance), or empty when none is near.
[[nodiscard]] std::string nearest_key(std::string_view key, const std::vector<std::string_view>& keys);

}  // namespace ccomp::model::io
