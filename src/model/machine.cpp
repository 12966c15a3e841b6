#include "ccomp/model/machine.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "ccomp/error.hpp"
#include "ccomp/gcode/dialect.hpp"
#include "ccomp/util/sha256.hpp"
#include "model_file.hpp"

namespace ccomp::model {

namespace file {

void bad(const std::string& file, const YAML::Node& node, const std::string& message) {
  const auto mark = node.Mark();
  throw Error(ErrorKind::model, message,
              SourceLocation{file, mark.line >= 0 ? static_cast<std::uint32_t>(mark.line + 1) : 0,
                             mark.column >= 0 ? static_cast<std::uint32_t>(mark.column + 1) : 0});
}

double quantity(const std::string& file, const YAML::Node& node, const Dimension& expected,
                std::string_view default_unit, const std::string& what) {
  if (!node || !node.IsScalar()) bad(file, node, what + " must be a number, with a unit or not");
  try {
    return parse_quantity(node.as<std::string>(), expected, default_unit, what);
  } catch (const Error& e) {
    bad(file, node, e.message());
  }
}

}  // namespace file

namespace {

using file::bad;

double number(const std::string& file, const YAML::Node& node, const std::string& what) {
  try {
    const std::string s = node.as<std::string>();
    if (s == ".nan" || s == "nan" || s == "NaN") bad(file, node, what + " is NaN");
    return node.as<double>();
  } catch (const YAML::Exception&) {
    bad(file, node, fmt::format("{} must be a number, not '{}'", what, YAML::Dump(node)));
  }
}

/// A yaml-cpp exception the reader let through (a value of the wrong type: a mapping where
/// a name is due), as the model error at its mark.
[[noreturn]] void wrong_value(const std::string& file, const YAML::Exception& e) {
  throw Error(ErrorKind::model, fmt::format("a value of the wrong type ({})", e.msg),
              SourceLocation{file, e.mark.line >= 0 ? static_cast<std::uint32_t>(e.mark.line + 1) : 0,
                             e.mark.column >= 0 ? static_cast<std::uint32_t>(e.mark.column + 1) : 0});
}

MachineModel read_machine_model(const std::string& text, const std::string& name) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw Error(ErrorKind::model, e.msg,
                SourceLocation{name, static_cast<std::uint32_t>(e.mark.line + 1),
                               static_cast<std::uint32_t>(e.mark.column + 1)});
  }
  if (!root.IsMap()) throw Error(ErrorKind::model, "a machine model is a YAML mapping", SourceLocation{name});
  MachineModel m;
  m.path = name;
  m.sha256 = util::sha256_hex(text);
  if (root["name"]) m.name = root["name"].as<std::string>();
  if (root["description"]) m.description = root["description"].as<std::string>();
  if (root["dialect"]) m.dialect = root["dialect"].as<std::string>();
  const YAML::Node axes = root["axes"];
  if (!axes || !axes.IsMap()) bad(name, root, "the model needs 'axes': a map from axis letter to its type and limits");
  for (const auto& entry : axes) {
    AxisSpec a;
    const std::string letter = entry.first.as<std::string>();
    if (letter.size() != 1) bad(name, entry.first, fmt::format("axis '{}' is not one letter of XYZABCUVW", letter));
    a.letter = static_cast<char>(std::toupper(static_cast<unsigned char>(letter[0])));
    a.type = (a.letter >= 'A' && a.letter <= 'C') ? AxisType::rotary : AxisType::linear;
    const YAML::Node spec = entry.second;
    if (spec && spec.IsMap()) {
      if (spec["type"]) {
        const std::string type = spec["type"].as<std::string>();
        if (type == "linear")
          a.type = AxisType::linear;
        else if (type == "rotary")
          a.type = AxisType::rotary;
        else
          bad(name, spec["type"], fmt::format("axis {}: type '{}' is neither linear nor rotary", a.letter, type));
      }
      if (spec["min"]) a.min = number(name, spec["min"], fmt::format("axis {} min", a.letter));
      if (spec["max"]) a.max = number(name, spec["max"], fmt::format("axis {} max", a.letter));
    }
    m.axes.push_back(a);
  }
  file::read_chains(name, root["chain"], m);
  if (const YAML::Node s = root["sensors"]) {
    if (!s.IsSequence()) bad(name, s, "'sensors' must be a list of sensor names");
    for (const YAML::Node& n : s) m.sensors.push_back(n.as<std::string>());
  }
  if (root["max_correction"])
    m.max_correction = file::quantity(name, root["max_correction"], kLength, "mm", "max_correction");
  file::read_terms(name, root["terms"], m);
  validate(m);
  return m;
}

}  // namespace

MachineModel parse_machine_model(const std::string& text, const std::string& name) {
  try {
    return read_machine_model(text, name);
  } catch (const YAML::Exception& e) {
    wrong_value(name, e);
  }
}

MachineModel with_terms(MachineModel model, const std::vector<std::string>& specs, const std::string& name) {
  YAML::Node terms(YAML::NodeType::Sequence);
  for (const std::string& spec : specs) {
    YAML::Node term;
    try {
      term = YAML::Load(spec);
    } catch (const YAML::ParserException& e) {
      throw Error(ErrorKind::model, e.msg, SourceLocation{name, 1, static_cast<std::uint32_t>(e.mark.column + 1)});
    }
    if (!term.IsMap()) file::bad(name, term, fmt::format("'{}': a term is a mapping {{name: ..., form: ...}}", spec));
    for (const char* key : {"variable", "temperature"})
      if (const YAML::Node v = term[key]; v && v.IsScalar() && v.Scalar().starts_with("T_")) {
        const std::string sensor = v.Scalar().substr(2);
        if (std::find(model.sensors.begin(), model.sensors.end(), sensor) == model.sensors.end())
          model.sensors.push_back(sensor);
      }
    terms.push_back(term);
  }
  try {
    file::read_terms(name, terms, model);
  } catch (const YAML::Exception& e) {
    wrong_value(name, e);
  }
  validate(model);
  return model;
}

MachineModel load_machine_model(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorKind::io, "cannot open machine model '" + path + "'");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_machine_model(text.str(), path);
}

void validate(const MachineModel& model) {
  auto fail = [&](const std::string& message) { throw Error(ErrorKind::model, message, SourceLocation{model.path}); };
  if (model.axes.empty()) fail("the model has no axes");
  for (std::size_t i = 0; i < model.axes.size(); ++i) {
    const AxisSpec& a = model.axes[i];
    if (std::string_view("XYZABCUVW").find(a.letter) == std::string_view::npos)
      fail(fmt::format("axis '{}' is not one of X Y Z A B C U V W", a.letter));
    for (std::size_t j = 0; j < i; ++j)
      if (model.axes[j].letter == a.letter) fail(fmt::format("axis {} is declared twice", a.letter));
    if (std::isnan(a.min) || std::isnan(a.max)) fail(fmt::format("axis {}: a limit is NaN", a.letter));
    if (!(a.min < a.max)) fail(fmt::format("axis {}: min {} is not below max {}", a.letter, a.min, a.max));
  }
  // The chains: every moving link names an axis of the machine, once; every axis moves a
  // link; at most one tool link. Every term's link is a link of a chain.
  if (!model.workpiece_chain.empty() || !model.tool_chain.empty()) {
    std::string seen;
    int tools = 0;
    for (const auto* chain : {&model.workpiece_chain, &model.tool_chain}) {
      for (const LinkSpec& l : *chain) {
        tools += l.tool;
        if (!l.axis) continue;
        if (!model.axis(*l.axis)) fail(fmt::format("link {} moves axis {}, which is not in 'axes'", l.name, *l.axis));
        if (seen.find(*l.axis) != std::string::npos) fail(fmt::format("axis {} moves two links", *l.axis));
        seen.push_back(*l.axis);
      }
    }
    for (const AxisSpec& a : model.axes)
      if (seen.find(a.letter) == std::string::npos) fail(fmt::format("axis {} moves no link of the chains", a.letter));
    if (tools > 1) fail("the chains have more than one tool link");
  }
  for (const ErrorTermSpec& t : model.terms) {
    bool found = false;
    for (const auto* chain : {&model.workpiece_chain, &model.tool_chain})
      for (const LinkSpec& l : *chain) found = found || l.name == t.link;
    if (!found) fail(fmt::format("term {} belongs to link {}, which no chain has", t.name, t.link));
    for (Eigen::Index k = 0; k < t.parameters.size(); ++k)
      if (!std::isfinite(t.parameters[k])) fail(fmt::format("term {}: parameter {} is not finite", t.name, k));
  }
  if (!(model.max_correction > 0)) fail(fmt::format("max_correction must be positive, not {}", model.max_correction));
  if (!gcode::dialect_named(model.dialect))
    fail(fmt::format("unknown dialect '{}' (known: linuxcnc, fanuc, mazak, wincnc)", model.dialect));
}

}  // namespace ccomp::model
