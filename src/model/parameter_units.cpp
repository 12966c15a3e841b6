#include "ccomp/model/parameter_units.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "ccomp/axis.hpp"
#include "ccomp/model/term_forms.hpp"

namespace ccomp::model {
namespace {

/// A unit's name from its scale in internal units (mm, rad); empty when not a common one.
std::string unit_name(double scale, bool angle, MicroSign micro) {
  const double s = std::abs(scale);
  const auto is = [&](double v) { return std::abs(s / v - 1.0) < 1e-9; };
  const std::string u = micro == MicroSign::micro ? "µ" : "u";
  if (angle) {
    if (is(1.0)) return "rad";
    if (is(1e-3)) return "mrad";
    if (is(1e-6)) return u + "rad";
    if (is(std::numbers::pi / 180)) return "deg";
    if (is(std::numbers::pi / 180 / 3600)) return "arcsec";
    return "";
  }
  if (is(1.0)) return "mm";
  if (is(1e-3)) return u + "m";
  if (is(1e-6)) return "nm";
  return "";
}

/// The unit of a variable as model files write it by default (mm, deg, s, degC) and its
/// scale in internal units.
std::pair<std::string, double> variable_unit(const Variable& v, MicroSign micro) {
  switch (v.kind) {
    case VariableKind::axis:
      return angular_at(v.index) ? std::pair<std::string, double>{"deg", std::numbers::pi / 180}
                                          : std::pair<std::string, double>{"mm", 1.0};
    case VariableKind::tool_length:
      return {"mm", 1.0};
    case VariableKind::time:
      return {"s", 1.0};
    case VariableKind::temperature:
      return {micro == MicroSign::micro ? "°C" : "degC", 1.0};
    default:
      return {"", 1.0};
  }
}

}  // namespace

std::string UnitNames::value(double scale) const { return unit_name(scale, angle, micro); }

std::pair<std::string, double> UnitNames::variable(const Variable& v) const { return variable_unit(v, micro); }

std::string parameter_unit_name(const ErrorTermSpec& t, std::size_t k, MicroSign micro) {
  if (k >= t.parameter_unit.size()) return "";
  return term_form(t.shape.form).unit_name(t, k, UnitNames{t.component >= 3, micro});
}

bool within_rounding(double uncertainty, double magnitude) {
  return !(std::abs(uncertainty) > 1e-9 * std::abs(magnitude));
}

std::string uncertainty_text(double uncertainty, double magnitude) {
  const double u = std::abs(uncertainty);
  if (!std::isfinite(u)) return "unknown";
  if (within_rounding(u, magnitude)) return "0 (to rounding)";
  if (u < 1e-4 || u >= 1e6) return fmt::format("{:.2g}", u);
  const int digits = std::max(0, 1 - static_cast<int>(std::floor(std::log10(u))));
  return fmt::format("{:.{}f}", u, digits);
}

}  // namespace ccomp::model
