// The model file's `fit_information:`: written by `ccomp fit`, read with the model.
#include "fit_information_io.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "model_schema.hpp"
#include "yaml_node.hpp"

namespace ccomp::model::io {
namespace {

const Section kFitInformation{"fit_information",
                              {"observations", "noise_um", "excess_um", "parameters", "covariance_factor", "coverage"}};
const Section kCoverage{"fit_information coverage", {"axis", "from", "to", "rotary", "bins"}};
const Section kBin{"fit_information coverage bin", {"from", "to", "points", "readings"}};

std::string digits(double v) { return fmt::format("{:.10g}", v); }

YAML::Node flow_sequence() {
  YAML::Node n(YAML::NodeType::Sequence);
  n.SetStyle(YAML::EmitterStyle::Flow);
  return n;
}

double finite(const std::string& file, const YAML::Node& node, const std::string& what) {
  const double v = number(file, node, what);
  if (!std::isfinite(v)) bad(file, node, fmt::format("{}: {} is not a finite number", what, v));
  return v;
}

std::size_t count(const std::string& file, const YAML::Node& node, const std::string& what) {
  const double v = finite(file, node, what);
  if (v < 0 || v != std::floor(v) || v > 1e15) bad(file, node, fmt::format("{}: {} is not a count", what, v));
  return static_cast<std::size_t>(v);
}

FittedParameterRef read_parameter(const std::string& file, const YAML::Node& n, const MachineModel& m) {
  if (!n.IsSequence() || n.size() != 3)
    bad(file, n, "fit_information parameters: each is [term, parameter, label] (the term's place in 'terms', from 0)");
  FittedParameterRef p{count(file, n[0], "fit_information parameter's term"),
                       count(file, n[1], "fit_information parameter's index"),
                       text(file, n[2], "fit_information parameter's label")};
  if (p.term >= m.terms.size())
    bad(file, n[0], fmt::format("fit_information: parameter {} names term {}, and the model has {} terms: the file "
                                "was edited after its fit (fit it again)",
                                p.label, p.term, m.terms.size()));
  const ErrorTermSpec& t = m.terms[p.term];
  if (p.index >= static_cast<std::size_t>(t.parameters.size()) || (p.label != t.iso && !p.label.starts_with(t.iso + ".")))
    bad(file, n, fmt::format("fit_information: parameter {} is not parameter {} of term {} ({}): the file was edited "
                             "after its fit (fit it again)",
                             p.label, p.index, p.term, t.name));
  return p;
}

AxisCoverage read_coverage(const std::string& file, const YAML::Node& n, const MachineModel& m) {
  check_keys(file, n, kCoverage);
  AxisCoverage c;
  const std::string axis = text(file, n["axis"], "fit_information coverage axis");
  if (axis.size() != 1 || (axis != "L" && !m.axis(axis[0])))
    bad(file, n["axis"], fmt::format("fit_information coverage: '{}' is neither an axis of the model nor L", axis));
  c.axis = axis[0];
  c.from = finite(file, n["from"], "fit_information coverage from");
  c.to = finite(file, n["to"], "fit_information coverage to");
  if (n["rotary"]) c.rotary = flag(file, n["rotary"], "fit_information coverage rotary");
  if (n["bins"]) {
    if (!n["bins"].IsSequence()) bad(file, n["bins"], "fit_information coverage bins: a list");
    for (const YAML::Node& b : n["bins"]) {
      check_keys(file, b, kBin);
      CoverageBin bin{finite(file, b["from"], "a coverage bin's from"), finite(file, b["to"], "a coverage bin's to"), {}};
      if (!(bin.from < bin.to)) bad(file, b, "a coverage bin's from is below its to");
      if (b["points"]) bin.points = count(file, b["points"], "a coverage bin's points");
      if (b["readings"]) {
        if (!b["readings"].IsMap()) bad(file, b["readings"], "a coverage bin's readings: {source: count, ...}");
        for (const auto& e : b["readings"])
          bin.readings.emplace_back(text(file, e.first, "a source"), count(file, e.second, "a source's readings"));
      }
      c.bins.push_back(std::move(bin));
    }
  }
  return c;
}

}  // namespace

std::optional<FitInformation> read_fit_information(const std::string& file, const YAML::Node& node,
                                                   const MachineModel& m) {
  if (!node) return std::nullopt;
  check_keys(file, node, kFitInformation);
  FitInformation info;
  if (node["observations"]) info.observations = count(file, node["observations"], "fit_information observations");
  if (node["noise_um"]) info.noise = finite(file, node["noise_um"], "fit_information noise_um") * 1e-3;
  if (node["excess_um"]) info.excess = finite(file, node["excess_um"], "fit_information excess_um") * 1e-3;
  if (info.noise < 0 || info.excess < 0) bad(file, node, "fit_information: noise and excess are not negative");
  const YAML::Node params = node["parameters"];
  if (params) {
    if (!params.IsSequence()) bad(file, params, "fit_information parameters: a list of [term, parameter, label]");
    for (const YAML::Node& p : params) info.parameters.push_back(read_parameter(file, p, m));
  }
  const auto k = static_cast<Eigen::Index>(info.parameters.size());
  const YAML::Node factor = node["covariance_factor"];
  if (k > 0 && !factor) bad(file, node, "fit_information: its parameters need their covariance_factor");
  if (factor) {
    if (!factor.IsSequence()) bad(file, factor, "fit_information covariance_factor: a list of rows");
    info.covariance_factor.resize(static_cast<Eigen::Index>(factor.size()), k);
    Eigen::Index r = 0;
    for (const YAML::Node& row : factor) {
      if (!row.IsSequence() || static_cast<Eigen::Index>(row.size()) != k)
        bad(file, row, fmt::format("fit_information covariance_factor: each row has one number per parameter ({})", k));
      for (Eigen::Index c = 0; c < k; ++c)
        info.covariance_factor(r, c) = finite(file, row[static_cast<std::size_t>(c)], "a covariance_factor entry");
      ++r;
    }
  }
  if (const YAML::Node coverage = node["coverage"]) {
    if (!coverage.IsSequence()) bad(file, coverage, "fit_information coverage: a list, one entry per axis");
    for (const YAML::Node& c : coverage) info.coverage.push_back(read_coverage(file, c, m));
  }
  return info;
}

YAML::Node fit_information_node(const FitInformation& info) {
  YAML::Node root;
  root["observations"] = info.observations;
  root["noise_um"] = digits(info.noise * 1e3);
  root["excess_um"] = digits(info.excess * 1e3);
  YAML::Node params(YAML::NodeType::Sequence);
  for (const FittedParameterRef& p : info.parameters) {
    YAML::Node one = flow_sequence();
    one.push_back(p.term);
    one.push_back(p.index);
    one.push_back(p.label);
    params.push_back(one);
  }
  root["parameters"] = params;
  YAML::Node factor(YAML::NodeType::Sequence);
  for (Eigen::Index r = 0; r < info.covariance_factor.rows(); ++r) {
    YAML::Node row = flow_sequence();
    for (Eigen::Index c = 0; c < info.covariance_factor.cols(); ++c) row.push_back(digits(info.covariance_factor(r, c)));
    factor.push_back(row);
  }
  root["covariance_factor"] = factor;
  YAML::Node coverage(YAML::NodeType::Sequence);
  for (const AxisCoverage& a : info.coverage) {
    YAML::Node c;
    c["axis"] = std::string(1, a.axis);
    c["from"] = digits(a.from);
    c["to"] = digits(a.to);
    c["rotary"] = a.rotary;
    YAML::Node bins(YAML::NodeType::Sequence);
    for (const CoverageBin& b : a.bins) {
      YAML::Node bin;
      bin.SetStyle(YAML::EmitterStyle::Flow);
      bin["from"] = digits(b.from);
      bin["to"] = digits(b.to);
      bin["points"] = b.points;
      YAML::Node readings(YAML::NodeType::Map);
      for (const auto& [source, n] : b.readings) readings[source] = n;
      bin["readings"] = readings;
      bins.push_back(bin);
    }
    c["bins"] = bins;
    coverage.push_back(c);
  }
  root["coverage"] = coverage;
  return root;
}

}  // namespace ccomp::model::io

namespace ccomp::model {

std::optional<FitInformation> parse_fit_information(const std::string& text, const std::string& name,
                                                    const MachineModel& model) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw Error(ErrorKind::model, e.msg, io::at(name, e.mark));
  }
  if (!root.IsMap()) return std::nullopt;
  return io::read_fit_information(name, root["fit_information"], model);
}

std::optional<FitInformation> load_fit_information(const MachineModel& model) {
  std::ifstream in(model.path, std::ios::binary);
  if (!in) throw Error(ErrorKind::io, fmt::format("cannot read '{}'", model.path));
  std::ostringstream text;
  text << in.rdbuf();
  return parse_fit_information(text.str(), model.path, model);
}

std::string with_fit_information(const std::string& text, const FitInformation& info) {
  YAML::Node root = YAML::Load(text);
  root["fit_information"] = io::fit_information_node(info);
  YAML::Emitter out;
  out << root;
  if (!out.good()) throw Error(ErrorKind::internal, fmt::format("writing the fit's information: {}", out.GetLastError()));
  return std::string(out.c_str()) + "\n";
}

}  // namespace ccomp::model
