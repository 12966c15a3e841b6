#include "ccomp/identify/next_measurement.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

namespace ccomp::identify {
namespace {

std::set<std::string> variables_of(const std::string& text) {
  std::set<std::string> out;
  std::stringstream in(text);
  for (std::string v; std::getline(in, v, ',');)
    if (!v.empty()) out.insert(v);
  return out;
}

bool is_temperature(const std::string& v) {
  return v.starts_with("T_");
}

/// The one variable of `a` that `b` lacks, or "".
std::string only_in(const std::set<std::string>& a, const std::set<std::string>& b) {
  for (const std::string& v : a)
    if (!b.count(v)) return v;
  return {};
}

}  // namespace

std::string separating_measurement(const std::string& a, const std::string& b) {
  const std::set<std::string> va = variables_of(a), vb = variables_of(b);
  const std::string extra_a = only_in(va, vb), extra_b = only_in(vb, va);
  if (va == vb)
    return fmt::format(
        "both vary with {}: readings over more of its range, or closer together, show which shape "
        "it has",
        a);
  if (!extra_a.empty() && !extra_b.empty()) {
    const std::string &p = extra_a, &q = extra_b;
    if ((is_temperature(p) && q == "t") || (p == "t" && is_temperature(q))) {
      const std::string& sensor = is_temperature(p) ? p : q;
      return fmt::format(
          "{} and the time since the start rose together in every run: a run where they do not (a "
          "cool-down after the warm-up, or a warm-up at another spindle speed) tells a drift that "
          "follows the temperature from one that follows the time",
          sensor);
    }
    if (is_temperature(p) && is_temperature(q))
      return fmt::format(
          "{} and {} moved together: a run where one warms and the other does not (heat one source "
          "alone) separates them",
          p, q);
    return fmt::format("{} and {} varied together in these readings: readings along {} at several {} separate them", p,
                       q, p, q);
  }
  // One candidate depends on a variable more than the other (a cross-axis term against a
  // higher order of the same axis): that variable must vary where the other stands still.
  const std::string& more = extra_a.empty() ? extra_b : extra_a;
  const std::set<std::string>& fewer = extra_a.empty() ? va : vb;
  return fmt::format(
      "readings along {} at several {} separate an effect that changes with {} from one that does "
      "not",
      *fewer.begin(), more, more);
}

namespace {

/// A term's variables as the candidates name them ("x", "x,z", "T_spindle"); "" for a constant.
std::string variables_text(const model::ErrorTermSpec& t) {
  std::string out;
  for (const model::Variable* v : {&t.primary, &t.secondary})
    if (v->kind != model::VariableKind::none && !v->text.empty()) out += (out.empty() ? "" : ",") + v->text;
  return out;
}

/// Whether parameter k of t moves the tool by the same everywhere: a constant term, or a
/// polynomial's constant coefficient.
bool constant(const model::ErrorTermSpec& t, std::size_t k) {
  return t.primary.kind == model::VariableKind::none || t.shape.form == model::TermForm::constant ||
         (t.shape.form == model::TermForm::polynomial && k == 0);
}

}  // namespace

std::string separating_parameters(const model::MachineModel& model, TermParameter a, TermParameter b) {
  const model::ErrorTermSpec &ta = model.terms.at(a.term), &tb = model.terms.at(b.term);
  const bool angle_a = ta.component >= 3, angle_b = tb.component >= 3;
  const std::string va = constant(ta, a.k) ? "" : variables_text(ta), vb = constant(tb, b.k) ? "" : variables_text(tb);
  if (va.empty() && vb.empty()) {
    if (!angle_a && !angle_b)
      return fmt::format(
          "nothing: {} and {} are constant offsets of the tool's position, which no reading tells apart; "
          "a work offset probed on the part takes their sum",
          ta.name, tb.name);
    if (angle_a != angle_b)
      return fmt::format(
          "readings at two or more tool lengths L (a short and a long tool, or the optics further out) "
          "separate the angle {} (its effect grows with the arm) from the offset {} (it does not)",
          angle_a ? ta.name : tb.name, angle_a ? tb.name : ta.name);
    return fmt::format(
        "readings with the tool tip at other places around the rotations (other tool lengths L, other "
        "positions along the lines, the rotary axes turned) separate the angles {} and {}",
        ta.name, tb.name);
  }
  if (va.empty() || vb.empty()) {
    const std::string& v = va.empty() ? vb : va;
    return fmt::format(
        "readings at several {0} (over more of its range, where these did not vary it enough) separate {1}, which "
        "changes with {0}, from the constant {2}",
        v, va.empty() ? tb.name : ta.name, va.empty() ? ta.name : tb.name);
  }
  if (va == vb && ta.component != tb.component)
    // The same variable, errors in other directions: what the data lack is not the shape
    // along the variable but places where the two move the tool differently.
    return fmt::format(
        "readings with the tool tip at other places (other tool lengths L, other points on the table, other "
        "directions read) as {} varies, where {} and {} move it differently",
        va, ta.name, tb.name);
  return separating_measurement(va, vb);
}

std::vector<Tie> find_ties(const std::vector<Suggestion>& suggestions, const Eigen::VectorXd& residual) {
  std::vector<Tie> out;
  if (suggestions.size() < 2) return out;
  const Suggestion& first = suggestions.front();
  if (first.residual.size() != residual.size()) return out;
  const Eigen::VectorXd explained_first = residual - first.residual;
  const double gain = first.rms_before - first.rms_after;
  for (std::size_t k = 1; k < suggestions.size(); ++k) {
    const Suggestion& s = suggestions[k];
    // (A reversal and the same reversal varying along its axis are one effect, the second
    // a shape of the first: what tells them apart is the data's own spread along the axis.)
    const bool one_reversal = s.term == first.term && s.form == "reversal" && first.form == "reversal";
    if (s.residual.size() != residual.size() || (s.term == first.term && s.variable == first.variable) || one_reversal)
      continue;
    const Eigen::VectorXd explained = residual - s.residual;
    const double norms = explained.norm() * explained_first.norm();
    const double correlation = norms > 0 ? explained.dot(explained_first) / norms : 0.0;
    if (correlation < 0.9 || s.rms_after - first.rms_after > 0.1 * gain) continue;
    out.push_back({0, k, correlation, separating_measurement(first.variable, s.variable)});
  }
  return out;
}

}  // namespace ccomp::identify
