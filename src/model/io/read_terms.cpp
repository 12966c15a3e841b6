// Reading the error terms of a machine model file: each term's name, link, units and
// variable, then its form's parameters (one reader per form).
#include "read_terms.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <string_view>
#include <tuple>
#include <utility>

#include "ccomp/constants.hpp"
#include "ccomp/model/term_forms.hpp"
#include "model_schema.hpp"
#include "yaml_node.hpp"

namespace ccomp::model::io {
namespace {

/// An ISO 230-1 name, and the sign a value written under the file's name takes in it.
struct IsoName {
  std::string name;
  double sign = 1.0;
};

/// The symbols of docs/error-model.md Ref 1, accepted as aliases of ISO 230-1 names. Its squareness S and
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
    if (!m.axis(kAxisLetters[v.index]))
      bad(file, node, fmt::format("{}: the machine has no axis {} to approach", what, kAxisLetters[v.index]));
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

/// What the reader of a form's parameters needs of its term: where it is, what to call
/// it, and the units its amounts and its variable are written in.
struct TermReading {
  const std::string& file;
  const YAML::Node& node;
  const MachineModel& model;
  std::string what;  ///< "term EXX": how messages start
  std::string form{};
  Dimension out_dim{};          ///< what the term's value measures: a length or an angle
  std::string out_text{};       ///< the term's unit as written ("um", "urad")
  double out = 1.0;             ///< internal units per unit of the term
  Dimension var_dim{};          ///< what the primary variable measures
  std::string var_unit_text{};  ///< the variable's unit as written ("mm", "deg")
  double var = 1.0;             ///< internal units per unit of the variable
};

/// A form's parameters in internal units, and the internal units per file unit of each.
struct Parameters {
  std::vector<double> values, scale;
};

double finite_number(const TermReading& r, const YAML::Node& v, const std::string& field) {
  const double x = quantity(r.file, v, kDimensionless, "1", r.what + " " + field);
  if (!std::isfinite(x)) bad(r.file, v, fmt::format("{} {}: {} is not finite", r.what, field, x));
  return x;
}

/// An amount of the term's value: a bare number in `unit`, or a quantity with its own.
double amount(const TermReading& r, const YAML::Node& v, const std::string& field) {
  const std::string written = v.IsScalar() ? v.Scalar() : std::string();
  if (written.find_first_of("abcdefghijklmnopqrstuvwxyzµ") != std::string::npos &&
      written.find("e-") == std::string::npos && written.find("e+") == std::string::npos)
    return quantity(r.file, v, r.out_dim, r.out_text, r.what + " " + field);
  return finite_number(r, v, field) * r.out;
}

YAML::Node require(const TermReading& r, const char* key) {
  if (!r.node[key]) bad(r.file, r.node, fmt::format("{}: form {} needs '{}'", r.what, r.form, key));
  return r.node[key];
}

void need_variable(const TermReading& r, const ErrorTermSpec& t) {
  if (t.primary.kind == VariableKind::none)
    bad(r.file, r.node, fmt::format("{}: form {} needs a 'variable'", r.what, r.form));
}

Parameters read_constant(const TermReading& r, ErrorTermSpec& t) {
  t.shape.form = TermForm::constant;
  return {{amount(r, require(r, "value"), "value")}, {r.out}};
}

Parameters read_polynomial(const TermReading& r, ErrorTermSpec& t) {
  need_variable(r, t);
  t.shape.form = TermForm::polynomial;
  const YAML::Node c = require(r, "coefficients");
  if (!c.IsSequence() || c.size() == 0) bad(r.file, c, r.what + ": coefficients must be a list (a0, a1, ...)");
  t.shape.order = static_cast<int>(c.size()) - 1;
  Parameters p;
  for (std::size_t k = 0; k < c.size(); ++k) {
    const double s = r.out / std::pow(r.var, static_cast<double>(k));
    p.values.push_back(finite_number(r, c[k], fmt::format("coefficient {}", k)) * s);
    p.scale.push_back(s);
  }
  return p;
}

Parameters read_table(const TermReading& r, ErrorTermSpec& t) {
  need_variable(r, t);
  t.shape.form = TermForm::table;
  const YAML::Node at = require(r, "at"), values = require(r, "values");
  if (!at.IsSequence() || !values.IsSequence() || at.size() != values.size() || at.size() < 2)
    bad(r.file, r.node, r.what + ": 'at' and 'values' must be lists of the same length (at least 2)");
  Parameters p;
  for (std::size_t k = 0; k < at.size(); ++k) {
    t.shape.knots.push_back(finite_number(r, at[k], fmt::format("at[{}]", k)) * r.var);
    if (k > 0 && !(t.shape.knots[k] > t.shape.knots[k - 1]))
      bad(r.file, at[k],
          fmt::format("{}: table positions must increase; at[{}] = {} follows {}", r.what, k, t.shape.knots[k] / r.var,
                      t.shape.knots[k - 1] / r.var));
    p.values.push_back(amount(r, values[k], fmt::format("values[{}]", k)));
    p.scale.push_back(r.out);
  }
  const YAML::Node interpolation = r.node["interpolation"];
  const std::string interp = interpolation ? text(r.file, interpolation, r.what + " interpolation") : "linear";
  if (interp != "linear" && interp != "cubic")
    bad(r.file, interpolation, r.what + ": interpolation is linear or cubic");
  t.shape.interpolation = interp == "cubic" ? Interpolation::cubic : Interpolation::linear;
  return p;
}

Parameters read_periodic(const TermReading& r, ErrorTermSpec& t) {
  need_variable(r, t);
  t.shape.form = TermForm::periodic;
  const double period = quantity(r.file, require(r, "period"), r.var_dim, r.var_unit_text, r.what + " period");
  if (!(period > 0)) bad(r.file, r.node["period"], fmt::format("{}: period must be positive", r.what));
  Parameters p{{period}, {r.var}};
  const YAML::Node h = require(r, "harmonics");
  if (!h.IsSequence() || h.size() == 0) bad(r.file, h, r.what + ": harmonics is a list of [cos, sin] pairs");
  t.shape.order = static_cast<int>(h.size());
  for (std::size_t k = 0; k < h.size(); ++k) {
    if (!h[k].IsSequence() || h[k].size() != 2) bad(r.file, h[k], r.what + ": each harmonic is [cos, sin]");
    p.values.push_back(amount(r, h[k][0], fmt::format("harmonic {} cos", k + 1)));
    p.values.push_back(amount(r, h[k][1], fmt::format("harmonic {} sin", k + 1)));
    p.scale.insert(p.scale.end(), {r.out, r.out});
  }
  return p;
}

Parameters read_reversal(const TermReading& r, ErrorTermSpec& t) {
  t.shape.form = TermForm::reversal;
  if (t.primary.kind == VariableKind::axis) {  // the approach direction of that axis
    t.primary.kind = VariableKind::direction;
    t.primary.text = "v" + t.primary.text;
  }
  if (t.primary.kind != VariableKind::direction)
    bad(r.file, r.node, r.what + ": a reversal depends on a direction (vx..vw)");
  const YAML::Node value = require(r, "reversal");
  if (!r.node["along"]) {
    if (!value.IsScalar()) bad(r.file, value, r.what + ": reversal is one amount (a list needs 'along: <axis>')");
    return {{amount(r, value, "reversal")}, {r.out}};
  }
  // A reversal varying along an axis (a screw worn more at one end): r(w) = r_0 + r_1 w + ...
  const YAML::Node along = r.node["along"];
  t.secondary = read_variable(r.file, along, text(r.file, along, r.what + " along"), r.model, r.what);
  if (t.secondary.kind != VariableKind::axis) bad(r.file, along, r.what + ": 'along' is an axis (x..w)");
  if (!value.IsSequence() || value.size() == 0 || value.size() > 4)
    bad(r.file, value, r.what + ": with 'along', reversal is a list [r0, r1, ...] (1 to 4 coefficients)");
  const double along_unit = variable_unit(t.secondary, r.model).first == kAngle ? kRadPerDeg : 1.0;
  t.shape.order_primary = static_cast<int>(value.size()) - 1;
  Parameters p;
  for (std::size_t k = 0; k < value.size(); ++k) {
    const double s = r.out / std::pow(along_unit, static_cast<double>(k));
    p.values.push_back(finite_number(r, value[k], fmt::format("reversal[{}]", k)) * s);
    p.scale.push_back(s);
  }
  return p;
}

/// The term's reference temperature, when the file gives one.
void read_reference(const TermReading& r, ErrorTermSpec& t) {
  if (r.node["reference"])
    t.shape.reference = quantity(r.file, r.node["reference"], kTemperature, "degC", r.what + " reference");
}

Parameters read_thermal(const TermReading& r, ErrorTermSpec& t) {
  t.shape.form = TermForm::thermal_linear;
  if (t.primary.kind != VariableKind::temperature)
    bad(r.file, r.node, r.what + ": a thermal term depends on T_<sensor>");
  read_reference(r, t);
  return {{finite_number(r, require(r, "coefficient"), "coefficient") * r.out}, {r.out}};
}

Parameters read_warmup(const TermReading& r, ErrorTermSpec& t) {
  t.shape.form = TermForm::thermal_warmup;
  if (t.primary.kind != VariableKind::time) bad(r.file, r.node, r.what + ": a warm-up depends on the time t");
  Parameters p{{amount(r, require(r, "amplitude"), "amplitude"),
                quantity(r.file, require(r, "time_constant"), kTime, "s", r.what + " time_constant")},
               {r.out, 1.0}};
  if (!(p.values[1] > 0)) bad(r.file, r.node["time_constant"], r.what + ": time_constant must be positive");
  return p;
}

Parameters read_scale_expansion(const TermReading& r, ErrorTermSpec& t) {
  need_variable(r, t);
  t.shape.form = TermForm::scale_expansion;
  if (t.component >= 3 || r.var_dim != kLength)
    bad(r.file, r.node, r.what + ": scale expansion is a translation along a linear axis");
  const YAML::Node temperature = require(r, "temperature");
  t.secondary = read_variable(r.file, temperature, text(r.file, temperature, r.what + " temperature"), r.model, r.what);
  if (t.secondary.kind != VariableKind::temperature) bad(r.file, temperature, r.what + ": temperature is T_<sensor>");
  read_reference(r, t);
  return {{quantity(r.file, require(r, "coefficient"), kTemperature.pow(-1), "1/degC", r.what + " coefficient")},
          {1.0}};
}

Parameters read_bump(const TermReading& r, ErrorTermSpec& t) {
  need_variable(r, t);
  t.shape.form = TermForm::bump;
  const double width = quantity(r.file, require(r, "width"), r.var_dim, r.var_unit_text, r.what + " width");
  if (!(width > 0) || !std::isfinite(width))
    bad(r.file, r.node["width"], fmt::format("{}: width must be positive", r.what));
  return {{amount(r, require(r, "amplitude"), "amplitude"),
           quantity(r.file, require(r, "at"), r.var_dim, r.var_unit_text, r.what + " at"), width},
          {r.out, r.var, r.var}};
}

Parameters read_cross_axis(const TermReading& r, ErrorTermSpec& t) {
  need_variable(r, t);
  t.shape.form = TermForm::cross_axis;
  if (t.primary.kind != VariableKind::axis) bad(r.file, r.node, r.what + ": a cross-axis term's variable is an axis");
  const YAML::Node other = require(r, "other");
  t.secondary = read_variable(r.file, other, text(r.file, other, r.what + " other"), r.model, r.what);
  if (t.secondary.kind != VariableKind::axis) bad(r.file, other, r.what + ": 'other' is another axis");
  const double other_unit = variable_unit(t.secondary, r.model).first == kAngle ? kRadPerDeg : 1.0;
  const YAML::Node c = require(r, "coefficients");
  if (!c.IsSequence() || c.size() == 0 || !c[0].IsSequence() || c[0].size() == 0)
    bad(r.file, c, r.what + ": coefficients is a list of rows [c_i1, c_i2, ...], row i for the power of the own axis");
  t.shape.order_primary = static_cast<int>(c.size()) - 1;
  t.shape.order = static_cast<int>(c[0].size());
  Parameters p;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (!c[i].IsSequence() || static_cast<int>(c[i].size()) != t.shape.order)
      bad(r.file, c[i], r.what + ": every row of coefficients has the same length");
    for (std::size_t j = 0; j < c[i].size(); ++j) {
      const double s =
          r.out / (std::pow(r.var, static_cast<double>(i)) * std::pow(other_unit, static_cast<double>(j + 1)));
      p.values.push_back(finite_number(r, c[i][j], fmt::format("coefficient [{}][{}]", i, j)) * s);
      p.scale.push_back(s);
    }
  }
  return p;
}

/// The term's shape and parameters, by the reader of its form.
Parameters read_form(const TermReading& r, ErrorTermSpec& t) {
  using Reader = Parameters (*)(const TermReading&, ErrorTermSpec&);
  static const std::pair<std::string_view, Reader> kReaders[] = {{"constant", read_constant},
                                                                 {"polynomial", read_polynomial},
                                                                 {"table", read_table},
                                                                 {"periodic", read_periodic},
                                                                 {"reversal", read_reversal},
                                                                 {"thermal", read_thermal},
                                                                 {"thermal_linear", read_thermal},
                                                                 {"warmup", read_warmup},
                                                                 {"scale_expansion", read_scale_expansion},
                                                                 {"bump", read_bump},
                                                                 {"cross_axis", read_cross_axis}};
  for (const auto& [form, reader] : kReaders)
    if (r.form == form) return reader(r, t);
  std::string known;
  for (const TermFormInfo& f : term_forms()) known += (known.empty() ? "" : ", ") + std::string(f.names.front());
  bad(r.file, r.node["form"], fmt::format("{}: unknown form '{}' ({})", r.what, r.form, known));
}

/// A symbol of Ref 1 of the opposite sign flips the term's amounts, not its shape (a period,
/// a time constant, a bump's place and width).
void apply_sign(const ErrorTermSpec& t, double sign, Parameters& p) {
  const TermFormInfo& form = term_form(t.shape.form);
  for (std::size_t k = 0; k < p.values.size(); ++k) {
    if (form.shapes_only(k)) continue;
    p.values[k] *= sign;
    p.scale[k] *= sign;
  }
}

/// Refuses a key the term's form does not have. (A form the schema does not know is
/// refused by read_form(), naming the forms it knows.)
void check_term_keys(const std::string& file, const YAML::Node& n, const std::string& name) {
  const std::string form = n["form"] ? text(file, n["form"], "term " + name + " form") : "constant";
  std::vector<std::string_view> keys = kTermKeys;
  const std::vector<std::string_view> own = form_keys(form);
  keys.insert(keys.end(), own.begin(), own.end());
  if (!own.empty()) check_keys(file, n, Section{fmt::format("term {} (form {})", name, form), keys});
}

/// The term's ISO name, link and component (from its name, or given), note and fit flags.
/// True for a location error's name (E<c>0<axis>).
bool read_identity(const std::string& file, const YAML::Node& n, const IsoName& iso, ErrorTermSpec& t) {
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
  return location;
}

/// The unit of the term's value (`unit`, or um / urad): a length for a translation, an
/// angle for a rotation.
void read_term_unit(TermReading& r, const ErrorTermSpec& t) {
  const bool rotation = t.component >= 3;
  r.out_dim = rotation ? kAngle : kLength;
  const YAML::Node unit = r.node["unit"];
  r.out_text = unit ? text(r.file, unit, r.what + " unit") : (rotation ? "urad" : "um");
  const auto out_unit = parse_unit(r.out_text);
  if (!out_unit) bad(r.file, unit, fmt::format("{}: unknown unit '{}'", r.what, r.out_text));
  if (!(out_unit->dimension == r.out_dim))
    bad(r.file, unit,
        fmt::format("{}: '{}' measures {}, but the {} of {} is a {}", r.what, r.out_text,
                    out_unit->dimension.describe(), rotation ? "rotation" : "translation", t.iso,
                    r.out_dim.describe()));
  r.out = out_unit->scale;
}

/// The term's variable (given, or the link's own axis for an error motion) and its unit.
void read_primary_variable(TermReading& r, bool location, ErrorTermSpec& t) {
  const YAML::Node& n = r.node;
  std::string var_text;
  if (n["variable"]) {
    var_text = text(r.file, n["variable"], r.what + " variable");
  } else if (!location && r.form != "constant" && t.link.size() == 1) {
    var_text = std::string(1, static_cast<char>(std::tolower(t.link[0])));
  }
  if (!var_text.empty())
    t.primary = read_variable(r.file, n["variable"] ? n["variable"] : n, var_text, r.model, r.what);
  const auto [dimension, default_unit] = variable_unit(t.primary, r.model);
  r.var_dim = dimension;
  r.var_unit_text =
      n["variable_unit"] ? text(r.file, n["variable_unit"], r.what + " variable_unit") : std::string(default_unit);
  const auto unit = parse_unit(r.var_unit_text);
  if (!unit || !(unit->dimension == dimension))
    bad(r.file, n,
        fmt::format("{}: variable_unit '{}' does not fit variable '{}' ({})", r.what, r.var_unit_text, var_text,
                    dimension.describe()));
  r.var = unit->scale;
}

/// An approach state runs from -1 to +1 as an axis takes up its play: a term of it is
/// linear in it (the take-ups follow it in a straight line; what a turn switches is its
/// value at +1 less its value at -1).
void check_linear_in_approach(const TermReading& r, const ErrorTermSpec& t) {
  if (t.primary.kind != VariableKind::direction) return;
  const auto& knots = t.shape.knots;
  const bool linear =
      t.shape.form == TermForm::reversal || (t.shape.form == TermForm::polynomial && t.shape.order <= 1) ||
      (t.shape.form == TermForm::table && t.shape.interpolation == Interpolation::linear && knots.size() == 2 &&
       knots[0] == -1.0 && knots[1] == 1.0);
  if (!linear)
    bad(r.file, r.node,
        fmt::format("{}: a term of an approach ({}) is linear in it: a reversal, a polynomial of order 1, or a "
                    "linear table at -1 and 1",
                    r.what, t.primary.text));
}

/// `span: [from, to]`, in the variable's unit: where the term was fitted (`ccomp fit`
/// writes it), its value held at the ends beyond. Only of a variable that has a range (an
/// axis, the tool length, a temperature, the time), ordered and finite.
void read_span(const TermReading& r, ErrorTermSpec& t) {
  t.variable_unit = r.var;
  const YAML::Node n = r.node["span"];
  if (!n) return;
  const VariableKind kind = t.primary.kind;
  if (kind == VariableKind::none || kind == VariableKind::direction)
    bad(r.file, n,
        fmt::format("{}: span is the range of the term's variable where it was fitted; {} has none", r.what,
                    kind == VariableKind::none ? "a term without a variable" : "an approach (" + t.primary.text + ")"));
  if (!n.IsSequence() || n.size() != 2)
    bad(r.file, n, fmt::format("{}: span is [from, to] in the variable's unit ({})", r.what, r.var_unit_text));
  const double from = finite_number(r, n[0], "span from"), to = finite_number(r, n[1], "span to");
  if (!(from < to))
    bad(r.file, n, fmt::format("{}: span [{}, {}] of {} is empty: from must be below to", r.what, from, to,
                               t.primary.text));
  t.span = TermSpan{from * r.var, to * r.var};
}

ErrorTermSpec read_term(const std::string& file, const YAML::Node& n, const MachineModel& m) {
  ErrorTermSpec t;
  if (!n.IsMap()) bad(file, n, "a term is a mapping {name: ..., form: ..., ...}");
  if (!n["name"]) bad(file, n, "every term needs a 'name' (its ISO 230-1 name, e.g. EXX)");
  t.name = text(file, n["name"], "a term's name");
  check_term_keys(file, n, t.name);
  const IsoName iso = iso_name(t.name);
  const bool location = read_identity(file, n, iso, t);
  TermReading r{.file = file, .node = n, .model = m, .what = "term " + t.name};
  read_term_unit(r, t);
  r.form = n["form"] ? text(file, n["form"], r.what + " form") : "constant";
  read_primary_variable(r, location, t);
  Parameters p = read_form(r, t);
  check_linear_in_approach(r, t);
  read_span(r, t);
  apply_sign(t, iso.sign, p);
  t.parameters = Eigen::Map<Eigen::VectorXd>(p.values.data(), static_cast<Eigen::Index>(p.values.size()));
  t.parameter_unit = p.scale;
  t.placement = placement_of(file, n["name"], t, location, m);
  if (!find_link(m, t.link))
    bad(file, n["name"], fmt::format("{} belongs to link {}, which no chain has", r.what, t.link));
  return t;
}

}  // namespace

void read_terms(const std::string& file, const YAML::Node& terms, MachineModel& m) {
  if (!terms) return;
  if (!terms.IsSequence()) bad(file, terms, "'terms' must be a list");
  for (const YAML::Node& n : terms) m.terms.push_back(read_term(file, n, m));
}

}  // namespace ccomp::model::io
