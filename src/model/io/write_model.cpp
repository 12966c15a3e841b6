// Writing fitted parameters back into a model file, in the file's own units and keys.
#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <cstdlib>

#include "ccomp/error.hpp"
#include "ccomp/model/model_file.hpp"
#include "ccomp/model/term_forms.hpp"
#include "yaml_node.hpp"

namespace ccomp::model {
namespace {

/// A number as the file would write it: enough digits to round-trip.
std::string number(double v) {
  return fmt::format("{:.10g}", v);
}

/// Replaces a scalar's number. A unit written after it ("-4 um") stays, the number scaled
/// by what the file's number meant (`before`, internal); without one, or when the file's
/// number was 0, the value is written in the term's units (`value` / `unit`).
void set(YAML::Node node, double after, double before, double unit) {
  const std::string text = node.IsScalar() ? node.as<std::string>() : "";
  const auto space = text.find(' ');
  if (space != std::string::npos) {
    const double written = std::strtod(text.c_str(), nullptr);
    if (written != 0.0 && before != 0.0) {
      node = number(after * written / before) + text.substr(space);
      return;
    }
  }
  node = number(after / unit);
}

/// The node of a term's node `n` that holds a parameter at `place`. (Returned, never
/// assigned: assigning a yaml-cpp node to another rebinds what it refers to in the document.)
YAML::Node node_at(YAML::Node n, const ParameterPlace& place) {
  YAML::Node key = n[std::string(place.key)];
  if (place.index < 0) return key.IsSequence() ? key[0] : key;  // a scalar as a sequence of one: `reversal: [r]`
  YAML::Node item = key[static_cast<std::size_t>(place.index)];
  return place.sub < 0 ? item : item[static_cast<std::size_t>(place.sub)];
}

/// Writes a term's parameters `p` into its node `n`, each where its form places it.
void write_parameters(YAML::Node n, const ErrorTermSpec& t, const Eigen::VectorXd& p) {
  const TermFormInfo& form = term_form(t.shape.form);
  for (Eigen::Index k = 0; k < p.size(); ++k)
    set(node_at(n, form.place(t.shape, static_cast<std::size_t>(k))), p[k], t.parameters[k],
        t.parameter_unit[static_cast<std::size_t>(k)]);
}

/// A term on a sensor the model lacks (found in the measurements' T_<name> columns)
/// brings the sensor with it into the file's `sensors`.
void add_term_sensors(const YAML::Node& term, YAML::Node& root) {
  for (const std::string& sensor : io::sensors_of_term(term)) {
    YAML::Node sensors = root["sensors"];
    bool known = false;
    if (sensors && sensors.IsSequence())
      for (const YAML::Node& s : sensors) known = known || (s.IsScalar() && s.Scalar() == sensor);
    if (!known) {
      sensors.push_back(sensor);
      root["sensors"] = sensors;
    }
  }
}

/// The node's YAML text, ending in a newline.
std::string emit(const YAML::Node& root, const std::string& what) {
  YAML::Emitter out;
  out << root;
  if (!out.good()) throw Error(ErrorKind::internal, fmt::format("{}: {}", what, out.GetLastError()));
  return std::string(out.c_str()) + "\n";
}

}  // namespace

std::string rewrite_parameters(const std::string& text, const MachineModel& model,
                               const std::vector<Eigen::VectorXd>& parameters, const std::string& record,
                               const std::vector<std::optional<TermSpan>>& spans) {
  YAML::Node root = YAML::Load(text);
  YAML::Node terms = root["terms"];
  for (std::size_t i = 0; i < model.terms.size() && i < parameters.size(); ++i)
    write_parameters(terms[i], model.terms[i], parameters[i]);
  for (std::size_t i = 0; i < model.terms.size() && i < spans.size(); ++i) {
    if (!spans[i]) continue;
    const double unit = model.terms[i].variable_unit;
    YAML::Node span = YAML::Load(fmt::format("[{}, {}]", number(spans[i]->from / unit), number(spans[i]->to / unit)));
    span.SetStyle(YAML::EmitterStyle::Flow);
    terms[i]["span"] = span;
  }
  if (!record.empty()) root["fitted"] = YAML::Load(record);
  // New values: what an earlier fit knew of the old ones no longer describes them.
  root.remove("fit_information");
  return emit(root, "writing the model");
}

std::string add_terms(const std::string& text, const std::vector<std::string>& specs, const std::string& name) {
  YAML::Node root = YAML::Load(text);
  YAML::Node terms = root["terms"];
  for (const std::string& spec : specs) {
    YAML::Node term;
    try {
      term = YAML::Load(spec);
    } catch (const YAML::Exception& e) {
      throw Error(ErrorKind::usage, fmt::format("--add '{}': not YAML: {}", spec, e.msg));
    }
    if (!term.IsMap())
      throw Error(ErrorKind::usage, fmt::format("--add '{}': a term is a mapping {{name: ..., form: ...}}", spec));
    add_term_sensors(term, root);
    terms.push_back(term);
  }
  root["terms"] = terms;
  return emit(root, "adding terms to " + name);
}

}  // namespace ccomp::model
