#include "ccomp/model/term_span.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "ccomp/axis.hpp"
#include "ccomp/constants.hpp"

namespace ccomp::model {
namespace {

/// Internal units per shown unit of a variable, and the unit's name.
std::pair<double, const char*> shown_unit(const Variable& v) {
  switch (v.kind) {
    case VariableKind::axis:
      return angular_at(v.index) ? std::pair{kRadPerDeg, "deg"} : std::pair{1.0, "mm"};
    case VariableKind::tool_length:
      return {1.0, "mm"};
    case VariableKind::temperature:
      return {1.0, "degC"};
    case VariableKind::time:
      return {1.0, "s"};
    default:
      return {1.0, ""};
  }
}

/// The range [low, high] of a term's variable over a use: an axis' travel or the tool
/// length from the chain values, a temperature or the time from the conditions.
std::pair<double, double> range_of(const Variable& v, const ChainQ& low, const ChainQ& high, const Conditions& c) {
  switch (v.kind) {
    case VariableKind::axis:
      return {low[static_cast<Eigen::Index>(v.index)], high[static_cast<Eigen::Index>(v.index)]};
    case VariableKind::tool_length:
      return {low[static_cast<Eigen::Index>(kToolLengthIndex)], high[static_cast<Eigen::Index>(kToolLengthIndex)]};
    case VariableKind::temperature: {
      const double t = v.index < c.temperatures.size() ? c.temperatures[v.index] : 20.0;
      return {t, t};
    }
    case VariableKind::time:
      return {c.time, c.time};
    default:
      return {0.0, 0.0};
  }
}

}  // namespace

std::string span_text(const ErrorTermSpec& term, const TermSpan& span) {
  const auto [unit, name] = shown_unit(term.primary);
  return fmt::format("{} [{:g}, {:g}] {}", term.primary.text, span.from / unit, span.to / unit, name);
}

SpanWatch::SpanWatch(const MachineModel& machine) : machine_(machine) {
  for (std::size_t t = 0; t < machine.terms.size(); ++t)
    if (machine.terms[t].span) watched_.push_back(t);
}

std::vector<std::string> SpanWatch::beyond(const ChainQ& low, const ChainQ& high, const Conditions& conditions) {
  std::vector<std::string> said;
  std::erase_if(watched_, [&](std::size_t t) {
    const ErrorTermSpec& term = machine_.terms[t];
    const TermSpan& span = *term.span;
    const auto [from, to] = range_of(term.primary, low, high, conditions);
    if (from >= span.from && to <= span.to) return false;
    const auto [unit, name] = shown_unit(term.primary);
    const bool below = from < span.from;
    said.push_back(fmt::format("term {} was fitted over {}; at {} {:g} {} it holds its value at {:g} {} (the model "
                               "is not measured there: measure the axis over its travel and fit again)",
                               term.name, span_text(term, span), term.primary.text, (below ? from : to) / unit, name,
                               (below ? span.from : span.to) / unit, name));
    return true;
  });
  return said;
}

}  // namespace ccomp::model
