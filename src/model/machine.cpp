#include "ccomp/model/machine.hpp"

#include <fmt/format.h>

#include <cmath>
#include <string_view>

#include "ccomp/error.hpp"
#include "ccomp/gcode/dialect.hpp"

namespace ccomp::model {

void validate(const MachineModel& model) {
  auto fail = [&](const std::string& message) { throw Error(ErrorKind::model, message, SourceLocation{model.path}); };
  if (model.axes.empty()) fail("the model has no axes");
  for (std::size_t i = 0; i < model.axes.size(); ++i) {
    const AxisSpec& a = model.axes[i];
    if (!axis_named(a.letter)) fail(fmt::format("axis '{}' is not one of X Y Z A B C U V W", a.letter));
    if (const std::optional<std::string> why = type_contradiction(a)) fail(*why);
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

std::optional<std::string> type_contradiction(const AxisSpec& a) {
  if (a.rotary() == angular_in_programs(a.axis())) return std::nullopt;
  return fmt::format("axis {}: type {}, but programs give {} in {} (RS-274's rotary axes are A, B and C)", a.letter,
                     a.rotary() ? "rotary" : "linear", a.letter, a.rotary() ? "lengths" : "degrees");
}

std::optional<AxisHold> axis_hold_named(std::string_view name) {
  if (name == "auto") return AxisHold::automatic;
  if (name == "clamped" || name == "indexing") return AxisHold::clamped;
  if (name == "free") return AxisHold::free;
  return std::nullopt;
}

std::string_view axis_hold_name(AxisHold hold) {
  switch (hold) {
    case AxisHold::automatic: return "auto";
    case AxisHold::clamped: return "clamped";
    case AxisHold::free: return "free";
  }
  return "auto";
}

}  // namespace ccomp::model
