// Reading a machine model file: the document, its name, dialect, axes and sensors; the
// chains and the terms have their own readers (read_chain.hpp, read_terms.hpp).
#include <fmt/format.h>
#include <yaml-cpp/anchor.h>
#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>

#include "ccomp/axis.hpp"
#include "ccomp/constants.hpp"
#include "ccomp/error.hpp"
#include "ccomp/gcode/dialect.hpp"
#include "ccomp/model/model_file.hpp"
#include "ccomp/util/sha256.hpp"
#include "fit_information_io.hpp"
#include "model_schema.hpp"
#include "read_chain.hpp"
#include "read_terms.hpp"
#include "yaml_node.hpp"

namespace ccomp::model {
namespace {

using io::bad;

/// The model's name, description and dialect.
void read_identity(const std::string& file, const YAML::Node& root, MachineModel& m) {
  if (!root["name"]) bad(file, root, "the model needs a 'name' (what outputs and reports call the machine)");
  m.name = io::text(file, root["name"], "name");
  if (root["description"]) m.description = io::text(file, root["description"], "description");
  if (root["dialect"]) {
    m.dialect = io::text(file, root["dialect"], "dialect");
    if (!gcode::dialect_named(m.dialect))
      bad(file, root["dialect"],
          fmt::format("unknown dialect '{}' (known: linuxcnc, fanuc, mazak, wincnc)", m.dialect));
  }
}

/// An axis' type and limits, from its mapping (or nothing: a linear or rotary axis by its
/// letter, without limits).
void read_axis_spec(const std::string& file, const YAML::Node& spec, AxisSpec& a) {
  if (!spec || spec.IsNull()) return;
  io::check_keys(file, spec, io::Section{fmt::format("axis {}", a.letter), io::kAxis.keys});
  if (spec["type"]) {
    const std::string type = io::text(file, spec["type"], fmt::format("axis {} type", a.letter));
    if (type == "linear")
      a.type = AxisType::linear;
    else if (type == "rotary")
      a.type = AxisType::rotary;
    else
      bad(file, spec["type"], fmt::format("axis {}: type '{}' is neither linear nor rotary", a.letter, type));
    if (const std::optional<std::string> why = type_contradiction(a)) bad(file, spec["type"], *why);
  }
  if (spec["min"]) a.min = io::number(file, spec["min"], fmt::format("axis {} min", a.letter));
  if (spec["max"]) a.max = io::number(file, spec["max"], fmt::format("axis {} max", a.letter));
  if (!(a.min < a.max))
    bad(file, spec["max"] ? spec["max"] : spec["min"],
        fmt::format("axis {}: min {} is not below max {}", a.letter, a.min, a.max));
  if (const YAML::Node hold = spec["hold"]) {
    const std::string name = io::text(file, hold, fmt::format("axis {} hold", a.letter));
    const std::optional<AxisHold> h = axis_hold_named(name);
    if (!h) bad(file, hold, fmt::format("axis {}: hold '{}' is none of auto, clamped (or indexing), free", a.letter, name));
    if (a.type != AxisType::rotary)
      bad(file, hold, fmt::format("axis {}: hold is for a rotary axis (a linear axis is never held)", a.letter));
    a.hold = *h;
  }
}

void read_axes(const std::string& file, const YAML::Node& root, MachineModel& m) {
  const YAML::Node axes = root["axes"];
  if (!axes || !axes.IsMap()) bad(file, root, "the model needs 'axes': a map from axis letter to its type and limits");
  for (const auto& entry : axes) {
    AxisSpec a;
    const std::string letter = io::text(file, entry.first, "an axis letter");
    const char upper = letter.empty() ? '\0' : static_cast<char>(std::toupper(static_cast<unsigned char>(letter[0])));
    if (letter.size() != 1 || !axis_named(upper))
      bad(file, entry.first, fmt::format("axis '{}' is not one letter of XYZABCUVW", letter));
    a.letter = upper;
    if (m.axis(a.letter)) bad(file, entry.first, fmt::format("axis {} is declared twice", a.letter));
    a.type = angular_in_programs(a.axis()) ? AxisType::rotary : AxisType::linear;
    read_axis_spec(file, entry.second, a);
    m.axes.push_back(a);
  }
}

void read_sensors(const std::string& file, const YAML::Node& sensors, MachineModel& m) {
  if (!sensors) return;
  if (!sensors.IsSequence()) bad(file, sensors, "'sensors' must be a list of sensor names");
  for (const YAML::Node& n : sensors) {
    const std::string sensor = io::text(file, n, "a sensor's name");
    if (std::find(m.sensors.begin(), m.sensors.end(), sensor) != m.sensors.end())
      bad(file, n, fmt::format("sensor '{}' is listed twice", sensor));
    m.sensors.push_back(sensor);
  }
}

void read_max_correction(const std::string& file, const YAML::Node& node, MachineModel& m) {
  if (!node) return;
  m.max_correction = io::quantity(file, node, kLength, "mm", "max_correction");
  if (!(m.max_correction > 0) || !std::isfinite(m.max_correction))
    bad(file, node, fmt::format("max_correction must be positive, not {}", m.max_correction));
}

/// `work_offsets:`: a mapping from a coordinate system (G54 ... G59.3) to its origin in
/// machine coordinates, a mapping from the model's axis letters to mm or degrees (an axis
/// not written is 0).
void read_work_offsets(const std::string& file, const YAML::Node& node, MachineModel& m) {
  if (!node) return;
  if (!node.IsMap()) bad(file, node, "'work_offsets' is a mapping from G54 ... G59.3 to {X: ..., Y: ..., Z: ...}");
  std::vector<std::string_view> letters;
  for (const AxisSpec& a : m.axes) letters.push_back(kAxisLetters.substr(a.index(), 1));
  for (const auto& entry : node) {
    const std::string name = io::text(file, entry.first, "a coordinate system");
    const std::optional<std::size_t> system = coordinate_system_number(name);
    if (!system)
      bad(file, entry.first, fmt::format("work_offsets: '{}' is not a coordinate system (G54 ... G59, G59.1 ... G59.3)", name));
    if (m.work_offsets.of(*system)) bad(file, entry.first, fmt::format("work_offsets: {} is written twice", name));
    io::check_keys(file, entry.second, io::Section{fmt::format("work offset {}", name), letters});
    WorkOrigin origin{};
    for (const auto& axis : entry.second) {
      const char letter = axis.first.Scalar()[0];
      const std::size_t i = kAxisLetters.find(letter);
      const bool rotary = m.axis(letter)->type == AxisType::rotary;
      const std::string what = fmt::format("work offset {} {}", name, letter);
      const double v = rotary ? io::quantity(file, axis.second, kAngle, "deg", what) / kRadPerDeg
                              : io::quantity(file, axis.second, kLength, "mm", what);
      if (!std::isfinite(v) || std::abs(v) > 1e7) bad(file, axis.second, fmt::format("{}: {} is beyond any machine", what, v));
      origin[i] = v;
    }
    m.work_offsets.set(*system, origin);
  }
}

/// The model from its root mapping (parse_machine_model() loads and guards it).
MachineModel read_model(const YAML::Node& root, const std::string& name, const std::string& text) {
  io::check_keys(name, root, io::kTopLevel);
  MachineModel m;
  m.path = name;
  m.sha256 = util::sha256_hex(text);
  read_identity(name, root, m);
  read_axes(name, root, m);
  read_sensors(name, root["sensors"], m);
  io::read_chains(name, root["chain"], m);
  read_max_correction(name, root["max_correction"], m);
  read_work_offsets(name, root["work_offsets"], m);
  io::read_terms(name, root["terms"], m);
  (void)io::read_fit_information(name, root["fit_information"], m);  // checked here; read by those who need it
  validate(m);
  return m;
}

/// A one-line term spec as a YAML node; `name` stands for its file.
YAML::Node term_of_spec(const std::string& spec, const std::string& name) {
  YAML::Node term;
  try {
    term = YAML::Load(spec);
  } catch (const YAML::ParserException& e) {
    throw Error(ErrorKind::model, e.msg, SourceLocation{name, 1, static_cast<std::uint32_t>(e.mark.column + 1)});
  }
  if (!term.IsMap()) bad(name, term, fmt::format("'{}': a term is a mapping {{name: ..., form: ...}}", spec));
  return term;
}

/// Adds to the model the sensors a term names that it lacks.
void add_term_sensors(const YAML::Node& term, MachineModel& model) {
  for (const std::string& sensor : io::sensors_of_term(term))
    if (std::find(model.sensors.begin(), model.sensors.end(), sensor) == model.sensors.end())
      model.sensors.push_back(sensor);
}

/// What the documents after a file's first hold: a model is one YAML document, and a
/// trailing `---` (an empty document) is not a second one. Counted from the parser's events
/// rather than with YAML::LoadAll, which loops for ever on some malformed texts (",:" makes
/// a document that consumes nothing; found by fuzzing), so the count stops at the most
/// documents the text's `---` markers can start.
class LaterDocuments : public YAML::EventHandler {
 public:
  int documents = 0;
  std::optional<YAML::Mark> content;  ///< where a later document's first content is

  void OnDocumentStart(const YAML::Mark&) override { ++documents; }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t) override { note(mark); }
  void OnScalar(const YAML::Mark& mark, const std::string&, YAML::anchor_t, const std::string&) override { note(mark); }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    note(mark);
  }
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    note(mark);
  }
  void OnMapEnd() override {}

 private:
  void note(const YAML::Mark& mark) {
    if (documents > 1 && !content) content = mark;
  }
};

/// Whether a second document can follow the one `root` was loaded from: only after a
/// '---', a '...' or a directive (a line starting with '%'), or after a root in flow style
/// ('{...}' ends its document). Else the text is not parsed again: that was half of
/// loading a model, which every run of every command does.
bool may_hold_more_documents(const std::string& text, const YAML::Node& root) {
  if (text.find("---") != std::string::npos || text.find("...") != std::string::npos) return true;
  if (text.starts_with('%') || text.find("\n%") != std::string::npos) return true;
  return root.Style() == YAML::EmitterStyle::Flow;
}

/// Refuses a text with a second document that has content.
void check_one_document(const std::string& text, const YAML::Node& root, const std::string& name) {
  if (!may_hold_more_documents(text, root)) return;
  std::size_t markers = 0;
  for (std::size_t at = text.find("---"); at != std::string::npos; at = text.find("---", at + 3)) ++markers;
  std::istringstream in(text);
  YAML::Parser parser(in);
  LaterDocuments later;
  while (later.documents <= static_cast<int>(markers) + 1 && !later.content && parser.HandleNextDocument(later)) {
  }
  if (later.content)
    throw Error(ErrorKind::model, "a machine model is one YAML document; another starts here",
                io::at(name, *later.content));
}

}  // namespace

MachineModel parse_machine_model(const std::string& text, const std::string& name) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
    check_one_document(text, root, name);
  } catch (const YAML::ParserException& e) {
    throw Error(ErrorKind::model, e.msg, io::at(name, e.mark));
  }
  if (!root.IsMap()) {  // at the document's start where it has no place of its own (an empty file)
    const YAML::Mark mark = root.Mark();
    throw Error(ErrorKind::model, "a machine model is a YAML mapping",
                mark.line >= 0 ? io::at(name, mark) : SourceLocation{name, 1, 1});
  }
  try {
    return read_model(root, name, text);
  } catch (const YAML::Exception& e) {
    // A conversion the readers above did not guard: still the file's fault, at its place.
    throw Error(ErrorKind::model, fmt::format("a value of the wrong kind: {}", e.msg), io::at(name, e.mark));
  }
}

MachineModel with_terms(MachineModel model, const std::vector<std::string>& specs, const std::string& name) {
  YAML::Node terms(YAML::NodeType::Sequence);
  for (const std::string& spec : specs) {
    const YAML::Node term = term_of_spec(spec, name);
    add_term_sensors(term, model);
    terms.push_back(term);
  }
  try {
    io::read_terms(name, terms, model);
  } catch (const YAML::Exception& e) {
    throw Error(ErrorKind::model, fmt::format("a value of the wrong kind: {}", e.msg), io::at(name, e.mark));
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

}  // namespace ccomp::model
