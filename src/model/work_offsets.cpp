#include "ccomp/model/work_offsets.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>

#include "ccomp/axis.hpp"
#include "ccomp/constants.hpp"
#include "ccomp/error.hpp"
#include "ccomp/model/quantity_reader.hpp"
#include "ccomp/model/units.hpp"

namespace ccomp::model {
namespace {

constexpr std::array<std::string_view, kCoordinateSystems> kSystemNames = {"G54", "G55", "G56",   "G57",  "G58",
                                                                           "G59", "G59.1", "G59.2", "G59.3"};

bool is_rotary_letter(char letter) {
  const std::optional<Axis> axis = axis_named(letter);
  return axis && angular_in_programs(*axis);
}

std::string upper(std::string_view s) {
  std::string out;
  for (char c : s) out.push_back(static_cast<char>(std::toupper(static_cast<unsigned char>(c))));
  return out;
}

/// "-250", "-300mm", "0.5 deg": the value in mm (linear) or degrees (rotary).
double axis_value(std::string_view text, char letter, const std::string& what) {
  const std::string_view number = text.starts_with('+') ? text.substr(1) : text;
  if (number.empty() || !(std::isdigit(static_cast<unsigned char>(number.front())) || number.front() == '-' ||
                          number.front() == '.' || number.starts_with("nan") || number.starts_with("inf")))
    throw Error(ErrorKind::usage, fmt::format("{}: '{}{}' has no number after {}", what, letter, text, letter));
  return read_quantity(text, is_rotary_letter(letter) ? rules::angle() : rules::position(),
                       fmt::format("{}: {}{}", what, letter, text));
}

}  // namespace

void check_on_machine(const WorkOrigin& origin, std::size_t system, const std::vector<char>& axes, ErrorKind kind,
                      const std::string& what) {
  for (std::size_t i = 0; i < origin.size(); ++i)
    if (origin[i] != 0.0 && std::find(axes.begin(), axes.end(), kAxisLetters[i]) == axes.end())
      throw Error(kind, fmt::format("{}: {} puts {} at {:g}, and the machine has no {} axis", what,
                                    coordinate_system_name(system), kAxisLetters[i], origin[i], kAxisLetters[i]));
}

bool WorkOffsets::any() const {
  for (const auto& s : systems)
    if (s) return true;
  return false;
}

void WorkOffsets::override_with(const WorkOffsets& other) {
  for (std::size_t i = 0; i < kCoordinateSystems; ++i)
    if (other.systems[i]) systems[i] = other.systems[i];
}

std::optional<std::size_t> coordinate_system_number(std::string_view name) {
  const std::string n = upper(name);
  for (std::size_t i = 0; i < kCoordinateSystems; ++i)
    if (n == kSystemNames[i]) return i + 1;
  return std::nullopt;
}

std::string coordinate_system_name(std::size_t number) {
  return std::string(kSystemNames.at(number - 1));
}

std::string describe_work_offset(std::size_t number, const WorkOrigin& origin) {
  std::string out = coordinate_system_name(number);
  for (std::size_t i = 0; i < origin.size(); ++i) {
    if (i > index(Axis::Z) && origin[i] == 0.0) continue;  // X Y Z always, the others where set
    std::string v = fmt::format("{:.6f}", origin[i]);
    while (v.back() == '0') v.pop_back();
    if (v.back() == '.') v.pop_back();
    if (v == "-0") v = "0";
    out += fmt::format(" {}{}", kAxisLetters[i], v);
  }
  return out;
}

std::string describe_work_offsets(const WorkOffsets& offsets) {
  std::string out;
  for (std::size_t i = 0; i < kCoordinateSystems; ++i)
    if (offsets.systems[i]) out += (out.empty() ? "" : ", ") + describe_work_offset(i + 1, *offsets.systems[i]);
  return out.empty() ? "none" : out;
}

WorkOffsetEntry parse_work_offset(std::string_view text, const std::string& what) {
  // The system's name, then '=' or blanks, then the axis words.
  std::size_t at = 0;
  while (at < text.size() && text[at] == ' ') ++at;
  std::size_t name_end = at;
  while (name_end < text.size() && text[name_end] != '=' && text[name_end] != ' ' && text[name_end] != ',') ++name_end;
  const std::string_view name = text.substr(at, name_end - at);
  const std::optional<std::size_t> system = coordinate_system_number(name);
  if (!system)
    throw Error(ErrorKind::usage,
                fmt::format("{}: '{}' is not a coordinate system (G54 ... G59, G59.1 ... G59.3); write e.g. "
                            "G54=X-250,Y0,Z-300",
                            what, name));
  WorkOffsetEntry entry;
  entry.system = *system;
  std::array<bool, 9> seen{};
  std::size_t i = name_end;
  if (i < text.size() && text[i] == '=') ++i;
  while (i < text.size()) {
    if (text[i] == ' ' || text[i] == ',') {
      ++i;
      continue;
    }
    const char letter = static_cast<char>(std::toupper(static_cast<unsigned char>(text[i])));
    const std::size_t axis = kAxisLetters.find(letter);
    if (axis == std::string_view::npos)
      throw Error(ErrorKind::usage, fmt::format("{}: '{}' is not an axis letter (X Y Z A B C U V W)", what, text[i]));
    if (seen[axis]) throw Error(ErrorKind::usage, fmt::format("{}: axis {} is given twice", what, letter));
    seen[axis] = true;
    std::size_t end = i + 1;
    while (end < text.size() && text[end] != ',' &&
           !(text[end] == ' ' && end + 1 < text.size() && kAxisLetters.find(static_cast<char>(std::toupper(
                                                              static_cast<unsigned char>(text[end + 1])))) !=
                                                              std::string_view::npos))
      ++end;
    std::string_view value = text.substr(i + 1, end - i - 1);
    while (!value.empty() && value.back() == ' ') value.remove_suffix(1);
    entry.origin[axis] = axis_value(value, letter, what);
    i = end;
  }
  // A system named without a word is no origin at all: machine zero must be said.
  if (std::none_of(seen.begin(), seen.end(), [](bool s) { return s; }))
    throw Error(ErrorKind::usage, fmt::format("{}: {} gives no axis; write {}=X0,Y0,Z0 to mean machine zero", what,
                                              coordinate_system_name(entry.system), coordinate_system_name(entry.system)));
  return entry;
}

}  // namespace ccomp::model
