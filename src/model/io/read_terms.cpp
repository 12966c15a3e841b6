// Reading the error terms of a machine model file.
#include "read_terms.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <string_view>
#include <tuple>

#include "ccomp/constants.hpp"
#include "model_schema.hpp"
#include "yaml_node.hpp"

namespace ccomp::model::io {
namespace {

/// An ISO 230-1 name, and the sign a value written under the file's name takes in it.
struct IsoName {
  std::string name;
  double sign = 1.0;
};

/// The seed's symbols, accepted as aliases of ISO 230-1 names. The seed's squareness S and
/// parallelism P are positive when the angle between the positive directions (of the two
/// lines, or of the reference plane's normal and the axis) exceeds 90 deg: with X's line
/// along (1, EC0X, -EB0X), Y's along (0, 1, EA0Y) and B's along (-EC0B, 1, EA0B),
/// S_xy = -EC0X, S_xz = EB0X, S_yz = -EA0Y, P_yzb = EC0B and P_xyb = -EA0B (B's tilt
/// out of the reference frame's X-Y plane; docs/machine-model.md).
IsoName iso_name(const std::string& name) {
  static const std::tuple<const char*, const char*, double> kAliases[] = {{"S_xy", "EC0X", -1.0},
                                                                          {"S_xz", "EB0X", 1.0},
                                                                          {"S_yz", "EA0Y", -1.0},
                                                                          {"P_xyb", "EA0B", -1.0},
                                                                          {"P_yzb", "EC0B", 1.0}};
  for (const auto& [alias, iso, sign] : kAliases)
    if (name == alias) return {iso, sign};
  // delta_<dir><axis> -> E<DIR><AXIS>, eps_<dir><axis> -> E<ROT><AXIS> (x->A, y->B, z->C)
  auto rot = [](char c) { return c == 'x' ? 'A' : c == 'y' ? 'B' : c == 'z' ? 'C' : '?'; };
  if (name.size() == 8 && name.starts_with("delta_"))
    return {{'E', static_cast<char>(std::toupper(name[6])), static_cast<char>(std::toupper(name[7]))}};
  if (name.size() == 6 && name.starts_with("eps_"))
    return {{'E', rot(name[4]), static_cast<char>(std::toupper(name[5]))}};
  return {name};
}

/// The link spec a term names, or null.
const LinkSpec* find_link(const MachineModel& m, const std::string& name) {
  for (const auto* chain : {&m.workpiece_chain, &m.tool_chain})
    for (const LinkSpec& l : *chain)
      if (l.name == name) return &l;
  return nullptr;
}

/// Where a term acts: a constant E<c>0<axis> on a moving link is a location error; every
/// other term (a thermal drift of a frame's origin included) an error motion. Location
/// errors that mean nothing, or that the reference frame fixes at zero, are refused.
ErrorPlacement placement_of(const std::string& file, const YAML::Node& node, const ErrorTermSpec& t, bool location_name,
                            const MachineModel& m) {
  if (!location_name || t.shape.form != TermForm::constant) return ErrorPlacement::motion;
  const LinkSpec* link = find_link(m, t.link);
  if (!link || !link->axis || link->tool) return ErrorPlacement::motion;  // a fixed link has no line
  const char axis = *link->axis;
  const AxisSpec* spec = m.axis(axis);
  const bool rotary = spec && spec->type == AxisType::rotary;
  // The axis' own direction as a component index (0 x, 1 y, 2 z), from its name: X Y Z and
  // A B C name their directions; U V W travel along X Y Z.
  const int own = static_cast<int>(std::string_view("XYZ"
                                                    "XYZ"
                                                    "XYZ")
                                       .at(kAxisLetters.find(axis)) -
                                   'X');
  const std::string what = "term " + t.name;
  const char angle = "ABC"[own];
  if (rotary && t.component == own)
    bad(file, node,
        fmt::format("{}: moving {}'s line along itself changes nothing; a shift of what it carries along it is "
                    "the error motion E{}{}",
                    what, axis, "XYZ"[own], axis));
  if (rotary && t.component == own + 3)
    bad(file, node, fmt::format("{}: {}'s zero is its angular positioning error E{}{}", what, axis, angle, axis));
  if (!rotary && t.component == own + 3)
    bad(file, node,
        fmt::format("{}: a line has no roll; a constant roll of the {} carriage is the error motion E{}{}", what, axis,
                    angle, axis));
  if (!rotary && axis == 'Z' && frame_fixes_line_turn(axis, t.component))
    bad(file, node,
        fmt::format("{}: Z's line is the reference frame's primary axis (its squareness to X and Y is carried by "
                    "EB0X and EA0Y), so {} is zero by definition",
                    what, t.iso));
  if (!rotary && axis == 'Y' && frame_fixes_line_turn(axis, t.component))
    bad(file, node,
        fmt::format("{}: Y's line lies in the reference frame's Z-Y plane (its squareness to X is carried by EC0X), "
                    "so EC0Y is zero by definition",
                    what));
  return ErrorPlacement::location;
}

/// Component and link from an ISO name: E<c><axis> (error motion of <axis>, varying with it)
/// or E<c>0<axis> (location error of <axis>, constant). <c>: X Y Z translation, A B C rotation.
bool decode_iso(const std::string& iso, int& component, std::string& link, bool& location) {
  if (iso.size() < 3 || iso[0] != 'E') return false;
  const std::string_view comps = "XYZABC";
  const auto c = comps.find(iso[1]);
  if (c == std::string_view::npos) return false;
  component = static_cast<int>(c);
  location = iso[2] == '0';
  link = iso.substr(location ? 3 : 2);
  return !link.empty();
}

Variable read_variable(const std::string& file, const YAML::Node& node, const std::string& text, const MachineModel& m,
                       const std::string& what) {
  Variable v;
  v.text = text;
  if (text == "L") {
    v.kind = VariableKind::tool_length;
  } else if (text == "t") {
    v.kind = VariableKind::time;
  } else if (text.starts_with("T_")) {
    v.kind = VariableKind::temperature;
    const std::string sensor = text.substr(2);
    const auto it = std::find(m.sensors.begin(), m.sensors.end(), sensor);
    if (it == m.sensors.end()) bad(file, node, fmt::format("{}: sensor '{}' is not in 'sensors'", what, sensor));
    v.index = static_cast<std::size_t>(it - m.sensors.begin());
  } else if (text.size() == 2 && text[0] == 'v' &&
             kAxisLetters.find(static_cast<char>(std::toupper(text[1]))) != std::string_view::npos) {
    v.kind = VariableKind::direction;
    v.index = kAxisLetters.find(static_cast<char>(std::toupper(text[1])));
  } else if (text.size() == 1 &&
             kAxisLetters.find(static_cast<char>(std::toupper(text[0]))) != std::string_view::npos) {
    v.kind = VariableKind::axis;
    v.index = kAxisLetters.find(static_cast<char>(std::toupper(text[0])));
    if (!m.axis(kAxisLetters[v.index]))
      bad(file, node, fmt::format("{}: the machine has no axis {}", what, kAxisLetters[v.index]));
  } else {
    bad(file, node, fmt::format("{}: unknown variable '{}' (an axis x..w, L, t, T_<sensor>, vx..vw)", what, text));
  }
  return v;
}

/// The dimension of a variable and the unit a file writes it in by default.
std::pair<Dimension, std::string_view> variable_unit(const Variable& v, const MachineModel& m) {
  switch (v.kind) {
    case VariableKind::axis: {
      const AxisSpec* a = m.axis(kAxisLetters[v.index]);
      return a && a->type == AxisType::rotary ? std::pair{kAngle, std::string_view("deg")}
                                              : std::pair{kLength, std::string_view("mm")};
    }
    case VariableKind::tool_length:
      return {kLength, "mm"};
    case VariableKind::time:
      return {kTime, "s"};
    case VariableKind::temperature:
      return {kTemperature, "degC"};
    default:
      return {kDimensionless, "1"};
  }
}

}  // namespace

void read_terms(const std::string& file, const YAML::Node& terms, MachineModel& m) {
  if (!terms) return;
  if (!terms.IsSequence()) bad(file, terms, "'terms' must be a list");
  for (const YAML::Node& n : terms) {
    ErrorTermSpec t;
    if (!n.IsMap()) bad(file, n, "a term is a mapping {name: ..., form: ..., ...}");
    if (!n["name"]) bad(file, n, "every term needs a 'name' (its ISO 230-1 name, e.g. EXX)");
    t.name = text(file, n["name"], "a term's name");
    {
      const std::string form = n["form"] ? text(file, n["form"], "term " + t.name + " form") : "constant";
      std::vector<std::string_view> keys = kTermKeys;
      const std::vector<std::string_view> own = form_keys(form);
      keys.insert(keys.end(), own.begin(), own.end());
      const std::string section = fmt::format("term {} (form {})", t.name, form);
      if (!own.empty()) check_keys(file, n, Section{section, keys});
    }
    const IsoName iso = iso_name(t.name);
    t.iso = iso.name;
    const std::string what = "term " + t.name;
    bool location = false;
    if (!decode_iso(t.iso, t.component, t.link, location) && !n["link"])
      bad(file, n["name"],
          fmt::format("{}: not an ISO 230-1 name (E<X Y Z A B C><axis> or E<..>0<axis>); give "
                      "'link' and 'component'",
                      what));
    if (n["link"]) t.link = text(file, n["link"], what + " link");
    if (n["component"]) {
      const std::string c = text(file, n["component"], what + " component");
      const auto k = std::string_view("xyzabc").find(c.size() == 1 ? c[0] : '?');
      if (k == std::string_view::npos) bad(file, n["component"], what + ": component is one of x y z a b c");
      t.component = static_cast<int>(k);
    }
    if (n["note"]) t.note = text(file, n["note"], what + " note");
    t.free = n["fit"] && flag(file, n["fit"], what + " fit");
    t.free_period = n["fit_period"] && flag(file, n["fit_period"], what + " fit_period");
    const bool rotation = t.component >= 3;
    const Dimension out_dim = rotation ? kAngle : kLength;
    const std::string out_text = n["unit"] ? text(file, n["unit"], what + " unit") : (rotation ? "urad" : "um");
    const auto out_unit = parse_unit(out_text);
    if (!out_unit) bad(file, n["unit"], fmt::format("{}: unknown unit '{}'", what, out_text));
    if (!(out_unit->dimension == out_dim))
      bad(file, n["unit"],
          fmt::format("{}: '{}' measures {}, but the {} of {} is a {}", what, out_text, out_unit->dimension.describe(),
                      rotation ? "rotation" : "translation", t.iso, out_dim.describe()));
    const double out = out_unit->scale;

    const std::string form = n["form"] ? text(file, n["form"], what + " form") : "constant";
    // The variable: given, or the link's own axis for an error motion.
    std::string var_text;
    if (n["variable"]) {
      var_text = text(file, n["variable"], what + " variable");
    } else if (!location && form != "constant" && t.link.size() == 1) {
      var_text = std::string(1, static_cast<char>(std::tolower(t.link[0])));
    }
    if (!var_text.empty()) t.primary = read_variable(file, n["variable"] ? n["variable"] : n, var_text, m, what);
    const auto [vdim, vdefault] = variable_unit(t.primary, m);
    const std::string vunit_text =
        n["variable_unit"] ? text(file, n["variable_unit"], what + " variable_unit") : std::string(vdefault);
    const auto vunit = parse_unit(vunit_text);
    if (!vunit || !(vunit->dimension == vdim))
      bad(file, n,
          fmt::format("{}: variable_unit '{}' does not fit variable '{}' ({})", what, vunit_text, var_text,
                      vdim.describe()));
    const double var = vunit->scale;
    auto number = [&](const YAML::Node& v, const std::string& field) {
      const double x = quantity(file, v, kDimensionless, "1", what + " " + field);
      if (!std::isfinite(x)) bad(file, v, fmt::format("{} {}: {} is not finite", what, field, x));
      return x;
    };
    // An amount of the term's value: a bare number in `unit`, or a quantity with its own.
    auto amount = [&](const YAML::Node& v, const std::string& field) {
      const std::string written = v.IsScalar() ? v.Scalar() : std::string();
      if (written.find_first_of("abcdefghijklmnopqrstuvwxyzµ") != std::string::npos &&
          written.find("e-") == std::string::npos && written.find("e+") == std::string::npos)
        return quantity(file, v, out_dim, out_text, what + " " + field);
      return number(v, field) * out;
    };
    auto require = [&](const char* key) {
      if (!n[key]) bad(file, n, fmt::format("{}: form {} needs '{}'", what, form, key));
      return n[key];
    };
    auto need_variable = [&] {
      if (t.primary.kind == VariableKind::none) bad(file, n, fmt::format("{}: form {} needs a 'variable'", what, form));
    };
    std::vector<double> p, scale;
    if (form == "constant") {
      t.shape.form = TermForm::constant;
      p = {amount(require("value"), "value")};
      scale = {out};
    } else if (form == "polynomial") {
      need_variable();
      t.shape.form = TermForm::polynomial;
      const YAML::Node c = require("coefficients");
      if (!c.IsSequence() || c.size() == 0) bad(file, c, what + ": coefficients must be a list (a0, a1, ...)");
      t.shape.order = static_cast<int>(c.size()) - 1;
      for (std::size_t k = 0; k < c.size(); ++k) {
        const double s = out / std::pow(var, static_cast<double>(k));
        p.push_back(number(c[k], fmt::format("coefficient {}", k)) * s);
        scale.push_back(s);
      }
    } else if (form == "table") {
      need_variable();
      t.shape.form = TermForm::table;
      const YAML::Node at = require("at"), values = require("values");
      if (!at.IsSequence() || !values.IsSequence() || at.size() != values.size() || at.size() < 2)
        bad(file, n, what + ": 'at' and 'values' must be lists of the same length (at least 2)");
      for (std::size_t k = 0; k < at.size(); ++k) {
        t.shape.knots.push_back(number(at[k], fmt::format("at[{}]", k)) * var);
        if (k > 0 && !(t.shape.knots[k] > t.shape.knots[k - 1]))
          bad(file, at[k],
              fmt::format("{}: table positions must increase; at[{}] = {} follows {}", what, k, t.shape.knots[k] / var,
                          t.shape.knots[k - 1] / var));
        p.push_back(amount(values[k], fmt::format("values[{}]", k)));
        scale.push_back(out);
      }
      const std::string interp =
          n["interpolation"] ? text(file, n["interpolation"], what + " interpolation") : "linear";
      if (interp != "linear" && interp != "cubic")
        bad(file, n["interpolation"], what + ": interpolation is linear or cubic");
      t.shape.interpolation = interp == "cubic" ? Interpolation::cubic : Interpolation::linear;
    } else if (form == "periodic") {
      need_variable();
      t.shape.form = TermForm::periodic;
      const double period = quantity(file, require("period"), vdim, vunit_text, what + " period");
      if (!(period > 0)) bad(file, n["period"], fmt::format("{}: period must be positive", what));
      p.push_back(period);
      scale.push_back(var);
      const YAML::Node h = require("harmonics");
      if (!h.IsSequence() || h.size() == 0) bad(file, h, what + ": harmonics is a list of [cos, sin] pairs");
      t.shape.order = static_cast<int>(h.size());
      for (std::size_t k = 0; k < h.size(); ++k) {
        if (!h[k].IsSequence() || h[k].size() != 2) bad(file, h[k], what + ": each harmonic is [cos, sin]");
        p.push_back(amount(h[k][0], fmt::format("harmonic {} cos", k + 1)));
        p.push_back(amount(h[k][1], fmt::format("harmonic {} sin", k + 1)));
        scale.insert(scale.end(), {out, out});
      }
    } else if (form == "reversal") {
      t.shape.form = TermForm::reversal;
      if (t.primary.kind == VariableKind::axis) {  // the approach direction of that axis
        t.primary.kind = VariableKind::direction;
        t.primary.text = "v" + t.primary.text;
      }
      if (t.primary.kind != VariableKind::direction)
        bad(file, n, what + ": a reversal depends on a direction (vx..vw)");
      p = {amount(require("reversal"), "reversal")};
      scale = {out};
    } else if (form == "thermal" || form == "thermal_linear") {
      t.shape.form = TermForm::thermal_linear;
      if (t.primary.kind != VariableKind::temperature) bad(file, n, what + ": a thermal term depends on T_<sensor>");
      if (n["reference"]) t.shape.reference = quantity(file, n["reference"], kTemperature, "degC", what + " reference");
      p = {number(require("coefficient"), "coefficient") * out};
      scale = {out};
    } else if (form == "warmup") {
      t.shape.form = TermForm::thermal_warmup;
      if (t.primary.kind != VariableKind::time) bad(file, n, what + ": a warm-up depends on the time t");
      p = {amount(require("amplitude"), "amplitude"),
           quantity(file, require("time_constant"), kTime, "s", what + " time_constant")};
      scale = {out, 1.0};
      if (!(p[1] > 0)) bad(file, n["time_constant"], what + ": time_constant must be positive");
    } else if (form == "scale_expansion") {
      need_variable();
      t.shape.form = TermForm::scale_expansion;
      if (rotation || vdim != kLength) bad(file, n, what + ": scale expansion is a translation along a linear axis");
      t.secondary = read_variable(file, require("temperature"),
                                  text(file, require("temperature"), what + " temperature"), m, what);
      if (t.secondary.kind != VariableKind::temperature)
        bad(file, n["temperature"], what + ": temperature is T_<sensor>");
      if (n["reference"]) t.shape.reference = quantity(file, n["reference"], kTemperature, "degC", what + " reference");
      p = {quantity(file, require("coefficient"), kTemperature.pow(-1), "1/degC", what + " coefficient")};
      scale = {1.0};
    } else if (form == "bump") {
      need_variable();
      t.shape.form = TermForm::bump;
      const double width = quantity(file, require("width"), vdim, vunit_text, what + " width");
      if (!(width > 0) || !std::isfinite(width)) bad(file, n["width"], fmt::format("{}: width must be positive", what));
      p = {amount(require("amplitude"), "amplitude"), quantity(file, require("at"), vdim, vunit_text, what + " at"),
           width};
      scale = {out, var, var};
    } else if (form == "cross_axis") {
      need_variable();
      t.shape.form = TermForm::cross_axis;
      const YAML::Node other = require("other");
      t.secondary = read_variable(file, other, text(file, other, what + " other"), m, what);
      if (t.secondary.kind != VariableKind::axis) bad(file, other, what + ": 'other' is another axis");
      const double other_unit = variable_unit(t.secondary, m).first == kAngle ? kRadPerDeg : 1.0;
      const YAML::Node c = require("coefficients");
      if (!c.IsSequence() || c.size() == 0 || !c[0].IsSequence() || c[0].size() == 0)
        bad(file, c, what + ": coefficients is a list of rows [c_i1, c_i2, ...], row i for the power of the own axis");
      t.shape.order_primary = static_cast<int>(c.size()) - 1;
      t.shape.order = static_cast<int>(c[0].size());
      for (std::size_t i = 0; i < c.size(); ++i) {
        if (!c[i].IsSequence() || static_cast<int>(c[i].size()) != t.shape.order)
          bad(file, c[i], what + ": every row of coefficients has the same length");
        for (std::size_t j = 0; j < c[i].size(); ++j) {
          const double s =
              out / (std::pow(var, static_cast<double>(i)) * std::pow(other_unit, static_cast<double>(j + 1)));
          p.push_back(number(c[i][j], fmt::format("coefficient [{}][{}]", i, j)) * s);
          scale.push_back(s);
        }
      }
    } else {
      bad(file, n["form"],
          fmt::format("{}: unknown form '{}' (constant, polynomial, table, periodic, reversal, "
                      "thermal, warmup, scale_expansion, cross_axis, bump)",
                      what, form));
    }
    // A seed symbol of the opposite sign flips the term's amounts, not its shape (a period,
    // a time constant, a bump's place and width).
    for (std::size_t k = 0; k < p.size(); ++k) {
      const bool shape = (t.shape.form == TermForm::periodic && k == 0) ||
                         (t.shape.form == TermForm::thermal_warmup && k == 1) ||
                         (t.shape.form == TermForm::bump && k >= 1);
      if (shape) continue;
      p[k] *= iso.sign;
      scale[k] *= iso.sign;
    }
    t.parameters = Eigen::Map<Eigen::VectorXd>(p.data(), static_cast<Eigen::Index>(p.size()));
    t.parameter_unit = scale;
    t.placement = placement_of(file, n["name"], t, location, m);
    if (!find_link(m, t.link))
      bad(file, n["name"], fmt::format("{} belongs to link {}, which no chain has", what, t.link));
    m.terms.push_back(std::move(t));
  }
}

}  // namespace ccomp::model::io
