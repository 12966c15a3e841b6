// Reading the kinematic chains of a machine model file.
#include "read_chain.hpp"

#include <Eigen/Geometry>
#include <fmt/format.h>

#include <cctype>
#include <string_view>
#include <utility>
#include <vector>

#include "model_schema.hpp"
#include "yaml_node.hpp"

namespace ccomp::model::io {
namespace {

Eigen::Vector3d vector3(const std::string& file, const YAML::Node& node, const std::string& what, bool unit_length,
                        bool lengths) {
  if (!node.IsSequence() || node.size() != 3) bad(file, node, what + " must be a list of three numbers");
  Eigen::Vector3d v;
  for (std::size_t i = 0; i < 3; ++i)
    v[static_cast<Eigen::Index>(i)] =
        lengths ? quantity(file, node[i], kLength, "mm", what) : quantity(file, node[i], kDimensionless, "1", what);
  if (unit_length) {
    if (v.norm() < 1e-12) bad(file, node, what + " must not be zero");
    v.normalize();
  }
  return v;
}

LinkSpec read_link(const std::string& file, const YAML::Node& n, const std::string& side) {
  LinkSpec l;
  check_keys(file, n, kLink);
  if (!n["link"]) bad(file, n, fmt::format("every link of chain.{} needs a 'link' name", side));
  l.name = text(file, n["link"], fmt::format("chain.{} link", side));
  const std::string what = fmt::format("chain.{} link {}", side, l.name);
  if (n["axis"]) {
    const std::string a = text(file, n["axis"], what + " axis");
    if (a.size() != 1 || kAxisLetters.find(static_cast<char>(std::toupper(a[0]))) == std::string_view::npos)
      bad(file, n["axis"], fmt::format("{}: axis '{}' is not one of X Y Z A B C U V W", what, a));
    l.axis = static_cast<char>(std::toupper(a[0]));
  }
  if (n["direction"]) l.direction = vector3(file, n["direction"], what + " direction", true, false);
  if (n["offset"]) l.offset = vector3(file, n["offset"], what + " offset", false, true);
  if (n["tool_length"]) {
    l.tool = true;
    l.direction = vector3(file, n["tool_length"], what + " tool_length direction", true, false);
  }
  return l;
}

std::vector<LinkSpec> read_chain(const std::string& file, const YAML::Node& list, const std::string& side) {
  if (!list || !list.IsSequence()) bad(file, list, fmt::format("chain.{} must be a list of links", side));
  std::vector<LinkSpec> links;
  for (const YAML::Node& n : list) links.push_back(read_link(file, n, side));
  return links;
}

void check_linear_lines(const std::string& file, const YAML::Node& chain, const MachineModel& m);

/// What validate() checks, here where the file's lines are known: every moving link names
/// an axis of the machine, once; every axis moves a link; at most one tool link.
void check_chains(const std::string& file, const YAML::Node& chain, const MachineModel& m) {
  std::string seen;
  int tools = 0;
  for (const char* side : {"workpiece", "tool"}) {
    const YAML::Node list = chain[side];
    const auto& links = std::string_view(side) == "tool" ? m.tool_chain : m.workpiece_chain;
    for (std::size_t i = 0; i < links.size(); ++i) {
      const LinkSpec& l = links[i];
      if (l.tool && ++tools > 1) bad(file, list[i], "the chains have more than one tool link");
      if (!l.axis) continue;
      if (!m.axis(*l.axis))
        bad(file, list[i]["axis"], fmt::format("link {} moves axis {}, which is not in 'axes'", l.name, *l.axis));
      if (seen.find(*l.axis) != std::string::npos)
        bad(file, list[i]["axis"], fmt::format("axis {} moves two links", *l.axis));
      seen.push_back(*l.axis);
    }
  }
  for (const AxisSpec& a : m.axes)
    if (seen.find(a.letter) == std::string::npos)
      bad(file, chain, fmt::format("axis {} moves no link of the chains", a.letter));
  check_linear_lines(file, chain, m);
}

/// X, Y and Z must move the tool along three independent lines, or some points are out of
/// reach and the compensation's solve has no answer (U V W may run parallel to them: a
/// quill). At the chain's zero the links are placed by translations alone, so each axis
/// moves the tool along its direction (the workpiece side's against it).
void check_linear_lines(const std::string& file, const YAML::Node& chain, const MachineModel& m) {
  std::vector<std::pair<char, Eigen::Vector3d>> lines;
  std::vector<YAML::Node> nodes;
  for (const char* side : {"workpiece", "tool"}) {
    const auto& links = std::string_view(side) == "tool" ? m.tool_chain : m.workpiece_chain;
    for (std::size_t i = 0; i < links.size(); ++i) {
      const LinkSpec& l = links[i];
      if (!l.axis || std::string_view("XYZ").find(*l.axis) == std::string_view::npos) continue;
      const AxisSpec* a = m.axis(*l.axis);
      if (!a || a->type != AxisType::linear) continue;
      lines.emplace_back(*l.axis, std::string_view(side) == "tool" ? l.direction : Eigen::Vector3d(-l.direction));
      nodes.push_back(chain[side][i]);
    }
  }
  for (std::size_t j = 1; j < lines.size(); ++j)
    for (std::size_t i = 0; i < j; ++i)
      if (lines[i].second.cross(lines[j].second).norm() < 1e-6)
        bad(file, nodes[j], fmt::format("axis {} moves the tool along the same line as axis {}: the chain's linear "
                                        "axes must move it along independent directions",
                                        lines[j].first, lines[i].first));
  if (lines.size() == 3 &&
      std::abs(lines[0].second.dot(lines[1].second.cross(lines[2].second))) < 1e-6)
    bad(file, nodes[2], fmt::format("axes {}, {} and {} move the tool in one plane: the chain's linear axes must move "
                                    "it along independent directions",
                                    lines[0].first, lines[1].first, lines[2].first));
}

}  // namespace

void read_chains(const std::string& file, const YAML::Node& chain, MachineModel& m) {
  if (!chain) return;
  check_keys(file, chain, kChain);
  for (const char* side : {"workpiece", "tool"})
    if (!chain[side]) bad(file, chain, fmt::format("the chain needs '{}': the links from the base to that side", side));
  m.workpiece_chain = read_chain(file, chain["workpiece"], "workpiece");
  m.tool_chain = read_chain(file, chain["tool"], "tool");
  check_chains(file, chain, m);
}

}  // namespace ccomp::model::io
