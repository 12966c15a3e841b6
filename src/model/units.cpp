#include "ccomp/model/units.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <numbers>

#include "ccomp/constants.hpp"
#include "ccomp/error.hpp"

namespace ccomp::model {
namespace {

struct Named {
  std::string_view name;
  Unit unit;
};

// Internal units: mm, rad, s, degC.
const Named kUnits[] = {
    {"nm", {1e-6, kLength}},
    {"um", {1e-3, kLength}},
    {"µm", {1e-3, kLength}},
    {"mm", {1.0, kLength}},
    {"cm", {10.0, kLength}},
    {"m", {1000.0, kLength}},
    {"in", {kMmPerInch, kLength}},
    {"inch", {kMmPerInch, kLength}},
    {"nrad", {1e-9, kAngle}},
    {"urad", {1e-6, kAngle}},
    {"µrad", {1e-6, kAngle}},
    {"mrad", {1e-3, kAngle}},
    {"rad", {1.0, kAngle}},
    {"arcsec", {std::numbers::pi / 648000.0, kAngle}},
    {"arcmin", {std::numbers::pi / 10800.0, kAngle}},
    {"deg", {std::numbers::pi / 180.0, kAngle}},
    {"s", {1.0, kTime}},
    {"min", {60.0, kTime}},
    {"h", {3600.0, kTime}},
    {"degC", {1.0, kTemperature}},
    {"K", {1.0, kTemperature}},
    {"1", {1.0, kDimensionless}},
};

std::optional<Unit> one_unit(std::string_view text) {
  int power = 1;
  if (const auto caret = text.find('^'); caret != std::string_view::npos) {
    const std::string_view p = text.substr(caret + 1);
    if (std::from_chars(p.data(), p.data() + p.size(), power).ec != std::errc()) return std::nullopt;
    text = text.substr(0, caret);
  }
  for (const Named& n : kUnits)
    if (n.name == text) return Unit{std::pow(n.unit.scale, power), n.unit.dimension.pow(power)};
  return std::nullopt;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

}  // namespace

Dimension Dimension::operator*(const Dimension& o) const {
  Dimension d;
  for (std::size_t i = 0; i < 4; ++i) d.powers[i] = powers[i] + o.powers[i];
  return d;
}
Dimension Dimension::operator/(const Dimension& o) const {
  Dimension d;
  for (std::size_t i = 0; i < 4; ++i) d.powers[i] = powers[i] - o.powers[i];
  return d;
}
Dimension Dimension::pow(int k) const {
  Dimension d;
  for (std::size_t i = 0; i < 4; ++i) d.powers[i] = powers[i] * k;
  return d;
}

std::string Dimension::describe() const {
  static constexpr const char* kNames[] = {"length", "angle", "time", "temperature"};
  std::string up, down;
  for (std::size_t i = 0; i < 4; ++i) {
    const int p = powers[i];
    if (p == 0) continue;
    std::string& side = p > 0 ? up : down;
    if (!side.empty()) side += " x ";
    side += kNames[i];
    if (std::abs(p) > 1) side += fmt::format("^{}", std::abs(p));
  }
  if (up.empty() && down.empty()) return "a plain number";
  if (down.empty()) return up;
  return (up.empty() ? "1" : up) + " / " + down;
}

std::optional<Unit> parse_unit(std::string_view text) {
  text = trim(text);
  Unit result{1.0, kDimensionless};
  bool divide = false;
  while (!text.empty()) {
    const auto cut = text.find_first_of("/*");
    const std::string_view piece = trim(text.substr(0, cut));
    if (!piece.empty()) {
      const auto u = one_unit(piece);
      if (!u) return std::nullopt;
      result.scale = divide ? result.scale / u->scale : result.scale * u->scale;
      result.dimension = divide ? result.dimension / u->dimension : result.dimension * u->dimension;
    }
    if (cut == std::string_view::npos) break;
    divide = text[cut] == '/';
    text = text.substr(cut + 1);
  }
  return result;
}

double parse_quantity(std::string_view text, const Dimension& expected, std::string_view default_unit,
                      const std::string& what) {
  text = trim(text);
  double number = 0.0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), number);
  if (ec != std::errc() || std::isnan(number))
    throw Error(ErrorKind::model, fmt::format("{}: '{}' is not a number with a unit", what, text));
  std::string_view unit_text = trim(std::string_view(ptr, static_cast<std::size_t>(text.data() + text.size() - ptr)));
  if (unit_text.empty()) unit_text = default_unit;
  const auto unit = parse_unit(unit_text);
  if (!unit) throw Error(ErrorKind::model, fmt::format("{}: unknown unit '{}'", what, unit_text));
  if (!(unit->dimension == expected))
    throw Error(ErrorKind::model, fmt::format("{}: '{}' measures {}, but {} belongs here", what, unit_text,
                                              unit->dimension.describe(), expected.describe()));
  return number * unit->scale;
}

}  // namespace ccomp::model
