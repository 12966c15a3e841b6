#include "ccomp/identify/stated_conditions.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>

#include "ccomp/error.hpp"
#include "ccomp/util/ascii.hpp"

namespace ccomp::identify {
namespace {

bool names_any(std::string_view key, std::initializer_list<std::string_view> words) {
  const std::string k = util::lower_ascii(key);
  return std::any_of(words.begin(), words.end(), [&](std::string_view w) { return k.find(w) != std::string::npos; });
}

/// The leading number of a temperature as written ("20.4", "20.4 C", "68.7 F", "20,4"), in
/// degC; nullopt where it has none or it is not a plausible workshop temperature.
std::optional<double> degc_of(std::string_view value) {
  std::string text(value);
  std::replace(text.begin(), text.end(), ',', '.');
  const char* begin = text.c_str();
  char* end = nullptr;
  const double v = std::strtod(begin, &end);
  if (end == begin || !std::isfinite(v)) return std::nullopt;
  std::string unit = util::lower_ascii(std::string_view(end));
  unit.erase(std::remove_if(unit.begin(), unit.end(), [](unsigned char c) { return !std::isalpha(c); }), unit.end());
  const double c = unit == "f" || unit == "degf" ? (v - 32.0) * 5.0 / 9.0 : v;
  if (c < -50.0 || c > 150.0) return std::nullopt;
  return c;
}

}  // namespace

StatedConditions sort_stated(const std::vector<StatedField>& fields) {
  StatedConditions out;
  for (const StatedField& f : fields) {
    if (names_any(f.key, {"instrument", "laser", "interferometer", "calibrator", "equipment"})) {
      out.instrument = f;
    } else if (names_any(f.key, {"uncertainty"})) {
      out.uncertainty = f;
    } else if (const std::optional<double> c = names_any(f.key, {"temperature", "temp"}) ? degc_of(f.value) : std::nullopt) {
      std::erase_if(out.temperatures, [&](const StatedConditions::Temperature& t) {
        return util::lower_ascii(t.name) == util::lower_ascii(f.key);
      });
      out.temperatures.push_back({f.key, *c, f.source});
    } else {
      out.others.push_back(f);
    }
  }
  return out;
}

StatedField temperature_option(std::string_view text) {
  const std::size_t eq = text.find('=');
  const std::string_view name = eq == std::string_view::npos ? std::string_view() : text.substr(0, eq);
  const std::string_view value = eq == std::string_view::npos ? std::string_view() : text.substr(eq + 1);
  char* end = nullptr;
  const std::string number(value);
  const double v = std::strtod(number.c_str(), &end);
  if (name.empty() || number.empty() || end != number.c_str() + number.size() || !std::isfinite(v) || v < -50.0 ||
      v > 150.0)
    throw Error(ErrorKind::usage,
                fmt::format("--temperature {}: give NAME=DEGC, a name and a temperature in degC from -50 to 150 "
                            "(--temperature air=20.3)",
                            text));
  std::string key(name);
  if (!names_any(key, {"temperature", "temp"})) key += " temperature";
  return {key, number, "--temperature"};
}

}  // namespace ccomp::identify
