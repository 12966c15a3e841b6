#pragma once
// What a test's files and its command line state about how it was made, beyond the readings:
// the instrument, the temperatures, the uncertainty of measurement, and any other setting a
// file carries (title, machine, date, serial number). ISO 230-2's report states them beside
// the figures; a report that lacks one says so rather than leaving it out.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ccomp::identify {

/// One setting as a file or an option states it.
struct StatedField {
  std::string key;     ///< as written: "Air temperature", "Instrument"
  std::string value;   ///< as written: "20.9", "Renishaw XL-80"
  std::string source;  ///< the file it is from, or the option ("--instrument")
};

/// What a report needs of them, sorted out of the fields.
struct StatedConditions {
  struct Temperature {
    std::string name;  ///< the key as written
    double degc = 0.0;
    std::string source;
  };
  std::optional<StatedField> instrument, uncertainty;
  std::vector<Temperature> temperatures;
  std::vector<StatedField> others;  ///< every other field, in order
};

/// Sorts `fields` (files' first, then the options', which take precedence for the instrument
/// and the uncertainty): a key naming an instrument, laser, interferometer or calibrator is
/// the instrument; one naming uncertainty the uncertainty statement; one naming a temperature
/// (or "temp"), with a number, a temperature in degC (a value ending in F is converted).
[[nodiscard]] StatedConditions sort_stated(const std::vector<StatedField>& fields);

/// A `--temperature` option's NAME=DEGC (degC), as a field; throws ccomp::Error (usage)
/// naming the option and the bad value.
[[nodiscard]] StatedField temperature_option(std::string_view text);

}  // namespace ccomp::identify
