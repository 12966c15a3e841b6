// What the model lacks (the diagnosis' missing effects, where the residual concentrates) and
// what its parameters are: as the file gives them and refitted, in the units `fit` prints
// (the model file's), with their uncertainty and identifiability.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "ccomp/model/parameter_units.hpp"
#include "report/figures.hpp"

namespace ccomp::report {

Section effects_section(const CheckReportInput& in, FigureIds& ids) {
  Section s{"effects", "Missing effects", "", {}, ""};
  const identify::Diagnosis& d = in.diagnosis;
  if (!d.skipped.empty()) {
    s.html = "<p>" + html_escape(d.skipped) + "</p>\n";
    return s;
  }
  s.html = fmt::format(
      "<p>{} candidate effects (a screw's periodic error, a reversal, squareness, thermal drifts...) were tried "
      "against the refitted residual; {} significant where fitted but not on readings left out, {} only with "
      "implausible values. Those below predict readings they were not fitted to, best first.</p>\n",
      d.candidates_tried, d.unproven, d.implausible);
  if (d.suggestions.empty()) {
    s.html += "<p><b>None of the candidates is significant against the noise floor.</b></p>\n";
  } else {
    s.html +=
        "<table><tr><th>rank</th><th>effect</th><th>term</th><th>variable</th><th>form</th><th>period, time "
        "constant or place</th><th>rms before &rarr; after (&micro;m)</th><th>BIC</th><th>held out</th><th>add with "
        "<code>ccomp fit --add</code></th></tr>\n";
    for (const identify::Suggestion& g : d.suggestions)
      s.html += fmt::format(
          "<tr><td class=\"num\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td class=\"num\">{}</td><td "
          "class=\"num\">{:.3f} &rarr; {:.3f}</td><td class=\"num\">{:+.1f}</td><td class=\"num\">{:.0f}% (by "
          "{})</td><td><code>{}</code></td></tr>\n",
          g.rank, html_escape(g.effect), html_escape(g.term), html_escape(g.variable), html_escape(g.form),
          html_escape(identify::scanned_value_text(g)), g.rms_before * kUm,
          g.rms_after * kUm, g.bic_delta, 100 * g.held_out, html_escape(g.held_out_by), html_escape(g.spec));
    s.html += "</table>\n";
    s.figures = effect_figures(in, ids);
  }
  for (const identify::Tie& t : d.ties)
    s.html += fmt::format(
        "<p>The data cannot tell <code>{}</code> from <code>{}</code> (correlation {:.2f}): measure "
        "next: {}</p>\n",
        html_escape(d.suggestions[t.first].spec), html_escape(d.suggestions[t.second].spec), t.correlation,
        html_escape(t.measurement));
  if (!d.unexplained.empty()) s.html += "<p>" + html_escape(d.unexplained) + "</p>\n";
  if (!d.regions.empty()) {
    s.html +=
        "<h3>Where the residual concentrates</h3>\n<p class=\"note\">Axis variables are machine axis positions "
        "(mm, deg), z the Z axis less the tool length L.</p>\n<table><tr><th>variable</th><th>from</th><th>to</th>"
        "<th>rms (&micro;m)</th><th>times the overall</th></tr>\n";
    for (const identify::Region& r : d.regions)
      s.html += fmt::format(
          "<tr><td>{}</td><td class=\"num\">{:.4g}</td><td class=\"num\">{:.4g}</td><td class=\"num\">{:.3f}</td><td "
          "class=\"num\">{:.1f}</td></tr>\n",
          html_escape(r.variable), r.from, r.to, r.rms * kUm, r.ratio);
    s.html += "</table>\n";
  }
  return s;
}

Section parameters_section(const CheckReportInput& in, FigureIds& ids) {
  Section s{"parameters", "Parameters and identifiability", "", {}, ""};
  const identify::FitReport& r = in.diagnosis.refit;
  if (r.parameters.empty()) {
    s.html = "<p>The model has no free parameters, or there was no refit.</p>\n";
    return s;
  }
  s.html = fmt::format(
      "<p>{} free parameters; the data determine {} combinations of them (condition number {:.3g}), {} of which "
      "changed by more than the noise. Values in the model file's units, as <code>ccomp fit</code> prints them; "
      "uncertainty one standard deviation; a change beyond 3 standard deviations is in bold. A parameter the data "
      "do not determine alone moves with the combinations it is part of (listed under the table).</p>\n",
      r.parameters.size(), r.rank, r.condition_number, r.significant);
  s.html +=
      "<table><tr><th>parameter</th><th>unit</th><th>as it is</th><th>refitted</th><th>&plusmn; "
      "1&sigma;</th><th>change "
      "/ &sigma;</th><th>determined</th></tr>\n";
  for (const identify::FittedParameter& p : r.parameters) {
    const model::ErrorTermSpec& t = in.model.terms[p.term];
    const std::size_t k = p.index - [&] {
      std::size_t offset = 0;
      for (std::size_t j = 0; j < p.term; ++j) offset += static_cast<std::size_t>(in.model.terms[j].parameters.size());
      return offset;
    }();
    const double unit = t.parameter_unit[k];
    const double magnitude = std::max(std::abs(p.before), std::abs(p.after));
    // A parameter the data do not determine alone moves with the combinations it is in:
    // its change against its own uncertainty says nothing.
    const double ratio = p.identified && p.uncertainty > 0 ? (p.after - p.before) / p.uncertainty : std::nan("");
    const bool moved = std::abs(ratio) > 3;
    s.html += fmt::format(
        "<tr><td>{}</td><td>{}</td><td class=\"num\">{:.6g}</td><td class=\"num\">{}{:.6g}{}</td><td "
        "class=\"num\">{}</td><td class=\"num\">{}</td><td>{}</td></tr>\n",
        html_escape(p.label), html_escape(model::parameter_unit_name(t, k, model::MicroSign::micro)), p.before / unit, moved ? "<b>" : "",
        p.after / unit, moved ? "</b>" : "",
        p.uncertainty > 0 && !(!p.identified && model::within_rounding(p.uncertainty, magnitude))
            ? html_escape(model::uncertainty_text(p.uncertainty / unit, magnitude / unit))
            : "&ndash;",
        std::isfinite(ratio) ? fmt::format("{:+.1f}", ratio) : "&ndash;",
        p.identified ? "yes" : "not alone (see below)");
  }
  s.html += "</table>\n";
  if (const std::string nothing = identify::nothing_identifiable(r); !nothing.empty())
    s.html += "<p class=\"note\"><b>" + html_escape(nothing) + "</b></p>\n";
  for (const std::string& u : r.unidentifiable) s.html += "<p class=\"note\">" + html_escape(u) + "</p>\n";
  if (r.singular_values.size() > 0 && r.singular_values[0] > 0) {
    std::vector<double> kept_x, kept_y, dropped_x, dropped_y;
    for (Eigen::Index k = 0; k < r.singular_values.size(); ++k) {
      const double v = r.singular_values[k] / r.singular_values[0];
      if (!(v > 0)) continue;
      (static_cast<std::size_t>(k) < r.rank ? kept_x : dropped_x).push_back(static_cast<double>(k + 1));
      (static_cast<std::size_t>(k) < r.rank ? kept_y : dropped_y).push_back(v);
    }
    Figure f;
    f.id = ids.next("singular");
    f.traces = "[" + xy_trace("determined", kept_x, kept_y, "markers", R"("marker":{"color":"#1f5fa8","size":6})") +
               "," +
               xy_trace("not determined (left as it is)", dropped_x, dropped_y, "markers",
                        R"("marker":{"color":"#c2410c","size":7,"symbol":"x"})") +
               "]";
    f.layout =
        R"j({"title":{"text":"Singular values of the scaled design matrix"},"xaxis":{"title":{"text":"combination of parameters (largest first)"}},"yaxis":{"type":"log","title":{"text":"relative to the largest"},"exponentformat":"power"}})j";
    f.caption =
        "How well the data determine each combination of the free parameters: a combination far below the "
        "others is fitted to noise, and was left as it is.";
    s.figures.push_back(std::move(f));
  }
  return s;
}

}  // namespace ccomp::report
