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
#include "model_schema.hpp"

namespace ccomp::model {

namespace file {

void bad(const std::string& file, const YAML::Node& node, const std::string& message) {
  // A key that is not there has no place in the file: the message alone, with the file.
  const auto mark = node.IsDefined() ? node.Mark() : YAML::Mark::null_mark();
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
    const double v = node.as<double>();
    if (std::isnan(v)) bad(file, node, what + " is NaN");
    return v;
  } catch (const YAML::Exception&) {
    bad(file, node, fmt::format("{} must be a number, not '{}'", what, YAML::Dump(node)));
  }
}

}  // namespace

namespace {

/// The model from its root mapping (parse_machine_model() loads and guards it).
MachineModel read_model(const YAML::Node& root, const std::string& name, const std::string& text) {
  file::check_keys(name, root, file::kTopLevel);
  MachineModel m;
  m.path = name;
  m.sha256 = util::sha256_hex(text);
  if (!root["name"]) bad(name, root, "the model needs a 'name' (what outputs and reports call the machine)");
  m.name = file::text(name, root["name"], "name");
  if (root["description"]) m.description = file::text(name, root["description"], "description");
  if (root["dialect"]) {
    m.dialect = file::text(name, root["dialect"], "dialect");
    if (!gcode::dialect_named(m.dialect))
      bad(name, root["dialect"],
          fmt::format("unknown dialect '{}' (known: linuxcnc, fanuc, mazak, wincnc)", m.dialect));
  }
  const YAML::Node axes = root["axes"];
  if (!axes || !axes.IsMap()) bad(name, root, "the model needs 'axes': a map from axis letter to its type and limits");
  for (const auto& entry : axes) {
    AxisSpec a;
    const std::string letter = file::text(name, entry.first, "an axis letter");
    if (letter.size() != 1 || std::string_view("XYZABCUVWxyzabcuvw").find(letter[0]) == std::string_view::npos)
      bad(name, entry.first, fmt::format("axis '{}' is not one letter of XYZABCUVW", letter));
    a.letter = static_cast<char>(std::toupper(static_cast<unsigned char>(letter[0])));
    if (m.axis(a.letter)) bad(name, entry.first, fmt::format("axis {} is declared twice", a.letter));
    a.type = (a.letter >= 'A' && a.letter <= 'C') ? AxisType::rotary : AxisType::linear;
    const YAML::Node spec = entry.second;
    if (spec && !spec.IsNull()) {
      file::check_keys(name, spec, file::Section{fmt::format("axis {}", a.letter), file::kAxis.keys});
      if (spec["type"]) {
        const std::string type = file::text(name, spec["type"], fmt::format("axis {} type", a.letter));
        if (type == "linear")
          a.type = AxisType::linear;
        else if (type == "rotary")
          a.type = AxisType::rotary;
        else
          bad(name, spec["type"], fmt::format("axis {}: type '{}' is neither linear nor rotary", a.letter, type));
      }
      if (spec["min"]) a.min = number(name, spec["min"], fmt::format("axis {} min", a.letter));
      if (spec["max"]) a.max = number(name, spec["max"], fmt::format("axis {} max", a.letter));
      if (!(a.min < a.max))
        bad(name, spec["max"] ? spec["max"] : spec["min"],
            fmt::format("axis {}: min {} is not below max {}", a.letter, a.min, a.max));
    }
    m.axes.push_back(a);
  }
  if (const YAML::Node s = root["sensors"]) {
    if (!s.IsSequence()) bad(name, s, "'sensors' must be a list of sensor names");
    for (const YAML::Node& n : s) {
      const std::string sensor = file::text(name, n, "a sensor's name");
      if (std::find(m.sensors.begin(), m.sensors.end(), sensor) != m.sensors.end())
        bad(name, n, fmt::format("sensor '{}' is listed twice", sensor));
      m.sensors.push_back(sensor);
    }
  }
  file::read_chains(name, root["chain"], m);
  if (root["max_correction"]) {
    m.max_correction = file::quantity(name, root["max_correction"], kLength, "mm", "max_correction");
    if (!(m.max_correction > 0) || !std::isfinite(m.max_correction))
      bad(name, root["max_correction"], fmt::format("max_correction must be positive, not {}", m.max_correction));
  }
  file::read_terms(name, root["terms"], m);
  validate(m);
  return m;
}

SourceLocation at(const std::string& name, const YAML::Mark& mark) {
  return SourceLocation{name, mark.line >= 0 ? static_cast<std::uint32_t>(mark.line + 1) : 0,
                        mark.column >= 0 ? static_cast<std::uint32_t>(mark.column + 1) : 0};
}

}  // namespace

MachineModel parse_machine_model(const std::string& text, const std::string& name) {
  std::vector<YAML::Node> documents;
  try {
    documents = YAML::LoadAll(text);
  } catch (const YAML::ParserException& e) {
    throw Error(ErrorKind::model, e.msg, at(name, e.mark));
  }
  if (documents.empty() || !documents.front().IsMap())
    throw Error(ErrorKind::model, "a machine model is a YAML mapping", SourceLocation{name});
  // A trailing `---` makes an empty document: only one with content is a second model.
  for (std::size_t k = 1; k < documents.size(); ++k)
    if (!documents[k].IsNull())
      bad(name, documents[k], "a machine model is one YAML document; this file holds more ('---' starts another)");
  try {
    return read_model(documents.front(), name, text);
  } catch (const YAML::Exception& e) {
    // A conversion the readers above did not guard: still the file's fault, at its place.
    throw Error(ErrorKind::model, fmt::format("a value of the wrong kind: {}", e.msg), at(name, e.mark));
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
    throw Error(ErrorKind::model, fmt::format("a value of the wrong kind: {}", e.msg), at(name, e.mark));
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
