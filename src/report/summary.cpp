// The page's first and last sections: what the check found, in figures and per source; and
// what it was made from (versions, files and their SHA-256, the conditions measured).
#include <fmt/chrono.h>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "ccomp/util/sha256.hpp"
#include "ccomp/version.hpp"
#include "report/figures.hpp"
#include "report/source_shape.hpp"

namespace ccomp::report {
namespace {

double rms_of(const Eigen::VectorXd& residual, const std::vector<std::size_t>& rows) {
  double sum = 0;
  for (std::size_t i : rows) sum += residual[static_cast<Eigen::Index>(i)] * residual[static_cast<Eigen::Index>(i)];
  return rows.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(rows.size()));
}

std::string kpi(const std::string& value, const std::string& what) {
  return fmt::format("<div class=\"kpi\"><b>{}</b><span>{}</span></div>", value, what);
}

}  // namespace

Section summary_section(const CheckReportInput& in, FigureIds& ids) {
  Section s{"summary", "Summary", "", {}, ""};
  const identify::Diagnosis& d = in.diagnosis;
  s.html += "<div class=\"kpis\">";
  s.html += kpi(fmt::format("{:.3f} &micro;m", in.check.rms * kUm), "rms residual, model as it is");
  s.html += kpi(fmt::format("{:.3f} &micro;m", in.check.max * kUm), "largest residual, model as it is");
  if (d.skipped.empty()) s.html += kpi(fmt::format("{:.3f} &micro;m", d.rms_refit * kUm), "rms residual, refitted");
  s.html += kpi(fmt::format("{:.3f} &micro;m", in.check.noise_floor * kUm), "noise floor");
  s.html += kpi(fmt::format("{}", in.data.observations.size()), "readings");
  s.html += kpi(fmt::format("{}", in.data.sources.size()), "sources");
  s.html += "</div>\n";
  s.html += fmt::format(
      "<p>Model <b>{}</b> against {} readings from {} file(s). <i>As it is</i>: the model's parameters as the "
      "file gives them. <i>Refitted</i>: its free parameters fitted again to these data (the model's form "
      "unchanged), which separates errors the model can describe but has out of date from effects it lacks. The "
      "noise floor ({}) is what no model can go below.</p>\n",
      html_escape(in.model.name), in.data.observations.size(), in.data.files.size(),
      html_escape(in.check.noise_method));
  if (!d.skipped.empty()) s.html += fmt::format("<p class=\"note\">{}</p>\n", html_escape(d.skipped));
  // Against the noise floor: a residual near 1x it is all the data can show.
  if (in.check.noise_floor > 0 && d.skipped.empty())
    s.html += fmt::format(
        "<p>Residual against the noise floor: <b>{:.1f}&times;</b> for the model as it is, <b>{:.1f}&times;</b> "
        "refitted.</p>\n",
        in.check.rms / in.check.noise_floor, d.rms_refit / in.check.noise_floor);
  if (!d.suggestions.empty())
    s.html += fmt::format(
        "<p>Most significant missing effect: <b>{}</b> (rms {:.3f} &rarr; {:.3f} &micro;m); see "
        "<a href=\"#effects\">Missing effects</a>.</p>\n",
        html_escape(d.suggestions.front().effect), d.suggestions.front().rms_before * kUm,
        d.suggestions.front().rms_after * kUm);
  else if (d.skipped.empty())
    s.html += fmt::format("<p>No missing effect is significant against the noise floor ({} candidates tried).</p>\n",
                          d.candidates_tried);
  // Per source.
  const std::vector<SourceShape> shapes = source_shapes(in.data, in.model);
  s.beside +=
      "<table><tr><th>source</th><th>kind</th><th>readings</th><th>rms as it is (&micro;m)</th><th>max as it is "
      "(&micro;m)</th><th>rms refitted (&micro;m)</th></tr>\n";
  std::vector<double> rms_as_is, rms_refitted;
  std::vector<std::string> names;
  const bool refitted = in.diagnosis.residual.size() == in.check.residual.size();
  for (std::size_t k = 0; k < shapes.size(); ++k) {
    const SourceShape& shape = shapes[k];
    names.push_back(in.data.sources[k]);
    rms_as_is.push_back(rms_of(in.check.residual, shape.readings) * kUm);
    rms_refitted.push_back(refitted ? rms_of(in.diagnosis.residual, shape.readings) * kUm : std::nan(""));
    double max = 0;
    for (std::size_t i : shape.readings) max = std::max(max, std::abs(in.check.residual[static_cast<Eigen::Index>(i)]));
    const std::string kind = shape.kind == SourceKind::volumetric
                                 ? "volumetric"
                                 : fmt::format("{} ({})", kind_name(shape.kind), axis_letter(shape.axis));
    s.beside += fmt::format(
        "<tr><td>{}</td><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{:.3f}</td><td "
        "class=\"num\">{:.3f}</td><td class=\"num\">{}</td></tr>\n",
        html_escape(in.data.sources[k]), kind, shape.readings.size(), rms_of(in.check.residual, shape.readings) * kUm,
        max * kUm,
        in.diagnosis.residual.size() == in.check.residual.size()
            ? fmt::format("{:.3f}", rms_of(in.diagnosis.residual, shape.readings) * kUm)
            : "&ndash;");
  }
  s.beside += "</table>\n";
  // The same as bars, against the noise floor: which sources the model fits, which not.
  std::reverse(names.begin(), names.end()), std::reverse(rms_as_is.begin(), rms_as_is.end()),
      std::reverse(rms_refitted.begin(), rms_refitted.end());
  Figure f;
  f.id = ids.next("sources");
  f.height = 90 + 24 * static_cast<int>(names.size());
  f.traces = fmt::format(
      R"j([{{"type":"bar","orientation":"h","name":"model as it is","x":{},"y":{},"marker":{{"color":"#9aa5b1"}}}},{{"type":"bar","orientation":"h","name":"refitted","x":{},"y":{},"marker":{{"color":"#1f5fa8"}}}}])j",
      json_numbers(rms_as_is), json_strings(names), json_numbers(rms_refitted), json_strings(names));
  f.layout = fmt::format(
      R"j({{"title":{{"text":"rms residual per source"}},"barmode":"group","bargap":0.25,"xaxis":{{"title":{{"text":"rms residual (µm)"}},"rangemode":"tozero"}},"yaxis":{{"showgrid":false,"automargin":true}},"margin":{{"l":80,"t":30}},"legend":{{"y":-0.12}},"shapes":[{{"type":"line","xref":"x","yref":"paper","x0":{0},"x1":{0},"y0":0,"y1":1,"line":{{"color":"#c2410c","width":1.2,"dash":"dash"}}}}],"annotations":[{{"x":{0},"y":1,"xref":"x","yref":"paper","text":"noise floor","showarrow":false,"xanchor":"left","yanchor":"bottom","font":{{"size":10,"color":"#c2410c"}}}}]}})j",
      json_number(in.check.noise_floor * kUm));
  s.figures.push_back(std::move(f));
  return s;
}

Section provenance_section(const CheckReportInput& in) {
  Section s{"provenance", "Provenance", "", {}, ""};
  std::string when = in.generated_at;
  if (when.empty())
    when = fmt::format("{:%Y-%m-%d %H:%M:%S} UTC",
                       std::chrono::floor<std::chrono::seconds>(std::chrono::system_clock::now()));
  s.html += "<table>";
  s.html += fmt::format("<tr><th>generated</th><td>{}</td></tr>", html_escape(when));
  s.html += fmt::format("<tr><th>by</th><td>ccomp {} ({})</td></tr>", kVersion, html_escape(in.command));
  s.html += fmt::format("<tr><th>model</th><td>{} &mdash; <code>{}</code></td></tr>", html_escape(in.model.name),
                        html_escape(in.model.path));
  s.html += fmt::format("<tr><th>model SHA-256</th><td><code>{}</code></td></tr>", html_escape(in.model.sha256));
  s.html +=
      "</table>\n<h3>Measurement files</h3>\n<table><tr><th>file</th><th>SHA-256</th><th>rows</th>"
      "<th>readings</th></tr>\n";
  for (std::size_t f = 0; f < in.data.files.size(); ++f) {
    std::set<std::uint32_t> rows;
    std::size_t readings = 0;
    for (const identify::Observation& o : in.data.observations)
      if (o.file == f) rows.insert(o.row), ++readings;
    // Read again for its digest: the page names exactly the bytes it was made from as long
    // as the file is unchanged since the run read it (the same run, moments before).
    std::ifstream file(in.data.files[f], std::ios::binary);
    std::string digest = "(not readable now)";
    if (file) {
      std::ostringstream text;
      text << file.rdbuf();
      digest = util::sha256_hex(text.str());
    }
    s.html += fmt::format(
        "<tr><td><code>{}</code></td><td><code>{}</code></td><td class=\"num\">{}</td><td class=\"num\">{}</td></tr>\n",
        html_escape(in.data.files[f]), digest, rows.size(), readings);
  }
  s.html +=
      "</table>\n<h3>Ranges the data span</h3>\n<p class=\"note\">Positions as the files write them, each in its "
      "own frame (its <code># frame:</code> line: program coordinates of a work offset, the tool length applied, or "
      "machine coordinates); the plots show machine axis positions.</p>\n<table><tr><th>variable</th><th>min</th>"
      "<th>max</th>"
      "<th>unit</th></tr>\n";
  bool temperatures = false;
  for (const identify::VariableRange& r : in.data.ranges) {
    temperatures = temperatures || r.name.starts_with("T_");
    s.html += fmt::format("<tr><td>{}</td><td class=\"num\">{:.6g}</td><td class=\"num\">{:.6g}</td><td>{}</td></tr>\n",
                          html_escape(r.name), r.min, r.max, html_escape(r.unit));
  }
  s.html += "</table>\n";
  if (!temperatures)
    s.html +=
        "<p class=\"note\">No temperatures were recorded (no T_ columns): the model's thermal terms, if any, "
        "were evaluated at 20 &deg;C.</p>\n";
  return s;
}

}  // namespace ccomp::report
