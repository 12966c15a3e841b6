// The page: sections in order, a table of contents, the style, plotly.js inlined, the
// figures as one JSON document and the script that draws them with a common style.
#include <fmt/format.h>

#include <cmath>

#include "ccomp/report/html_report.hpp"
#include "report/embedded_plotly.hpp"
#include "report/figures.hpp"

namespace ccomp::report {

std::string json_string(std::string_view text) {
  std::string out = "\"";
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '"' || c == '\\')
      out += '\\', out += c;
    else if (c == '/' && i > 0 && text[i - 1] == '<')
      out += "\\/";  // "</script>" inside a string would end the page's script element
    else if (static_cast<unsigned char>(c) < 0x20)
      out += fmt::format("\\u{:04x}", c);
    else
      out += c;
  }
  return out + "\"";
}

std::string json_number(double v) {
  return std::isfinite(v) ? fmt::format("{:.6g}", v) : "null";
}

std::string json_numbers(const std::vector<double>& v) {
  std::string out = "[";
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (i > 0) out += ',';
    out += json_number(v[i]);
  }
  return out + "]";
}

std::string json_strings(const std::vector<std::string>& v) {
  std::string out = "[";
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (i > 0) out += ',';
    out += json_string(v[i]);
  }
  return out + "]";
}

std::string xy_trace(std::string_view name, const std::vector<double>& x, const std::vector<double>& y,
                     std::string_view mode, std::string_view style) {
  return fmt::format("{{\"type\":\"scatter\",\"name\":{},\"x\":{},\"y\":{},\"mode\":\"{}\"{}{}}}", json_string(name),
                     json_numbers(x), json_numbers(y), mode, style.empty() ? "" : ",", style);
}

std::string html_escape(std::string_view text) {
  std::string out;
  for (char c : text) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

std::string FigureIds::next(std::string_view stem) {
  return fmt::format("fig-{}-{}", stem, ++count_);
}

namespace {

// Print-friendly, sober: black on white, one accent colour, tables ruled as in a
// calibration certificate.
constexpr std::string_view kStyle = R"(
body{font-family:"Helvetica Neue",Helvetica,Arial,sans-serif;color:#1d1d1d;margin:0;background:#fff}
header{background:#0b3d63;color:#fff;padding:18px 32px 14px}
header h1{margin:0;font-size:22px;font-weight:600}
header p{margin:4px 0 0;font-size:13px;opacity:.9}
main{max-width:1240px;margin:0 auto;padding:8px 32px 40px}
nav{font-size:12px;margin:12px 0 4px;line-height:1.9}
nav a{color:#0b3d63;text-decoration:none;margin-right:14px;white-space:nowrap}
h2{font-size:17px;color:#0b3d63;border-bottom:2px solid #0b3d63;padding-bottom:3px;margin:28px 0 8px}
h3{font-size:14px;margin:16px 0 6px}
p,li{font-size:13px;line-height:1.45}
table{border-collapse:collapse;margin:6px 0 10px;font-size:12px}
th{background:#eef2f6;font-weight:600;text-align:left}
td,th{border:1px solid #c9d1d9;padding:3px 8px;vertical-align:top}
td.num{text-align:right;font-variant-numeric:tabular-nums}
.kpis{display:flex;flex-wrap:wrap;gap:10px;margin:10px 0}
.kpi{border:1px solid #c9d1d9;border-left:4px solid #0b3d63;padding:6px 12px;min-width:128px}
.kpi b{display:block;font-size:20px;font-weight:600}
.kpi span{font-size:11px;color:#555}
.figs{display:flex;flex-wrap:wrap;gap:8px 16px}
figure{margin:0;width:calc(50% - 8px)}
figure.wide{width:100%}
.beside{width:calc(50% - 8px)}
.beside td{white-space:nowrap}
figcaption{font-size:11px;color:#444;margin:0 0 6px 8px}
.note{font-size:12px;color:#555}
code{font-size:11px;word-break:break-all}
@media print{header{-webkit-print-color-adjust:exact;print-color-adjust:exact}figure{break-inside:avoid}}
)";

// Draws every figure with the common style: gridlines, outside ticks, a zero line, a framed
// plot area, legends under the plot. The figures' own layout overrides it.
constexpr std::string_view kDrawScript = R"(
(function () {
  const figures = JSON.parse(document.getElementById('ccomp-figures').textContent);
  const axis = {showgrid: true, gridcolor: '#e2e6ea', zeroline: true, zerolinecolor: '#7a7a7a',
    zerolinewidth: 1, showline: true, linecolor: '#333', mirror: true, ticks: 'outside', ticklen: 4,
    automargin: true, title: {font: {size: 11}}, tickfont: {size: 10}};
  const polarAxis = {gridcolor: '#d5dbe1', linecolor: '#333', ticks: 'outside', tickfont: {size: 10}};
  const merge = (a, b) => {
    const out = Object.assign({}, a);
    for (const [k, v] of Object.entries(b || {}))
      out[k] = v && typeof v === 'object' && !Array.isArray(v) && a[k] && typeof a[k] === 'object' ? merge(a[k], v) : v;
    return out;
  };
  for (const f of figures) {
    let layout = merge({font: {family: 'Helvetica Neue, Helvetica, Arial, sans-serif', size: 11, color: '#1d1d1d'},
      margin: {l: 60, r: 20, t: 34, b: 40}, paper_bgcolor: '#fff', plot_bgcolor: '#fff', hovermode: 'closest',
      title: {font: {size: 12}, x: 0.01, xanchor: 'left'},
      legend: {orientation: 'h', x: 0, y: -0.3, yanchor: 'top', font: {size: 10}},
      xaxis: axis, yaxis: axis}, f.layout);
    for (const k of Object.keys(layout)) {
      if (/^[xy]axis\d+$/.test(k)) layout[k] = merge(axis, layout[k]);
      if (/^polar\d*$/.test(k)) {
        layout[k].radialaxis = merge(polarAxis, layout[k].radialaxis);
        layout[k].angularaxis = merge(polarAxis, layout[k].angularaxis);
      }
    }
    // No mode bar: the page reads like a printed report; dragging still zooms, a double
    // click resets, hovering reads values.
    Plotly.newPlot(f.id, f.data, layout, {displaylogo: false, displayModeBar: false, responsive: true});
  }
  document.body.setAttribute('data-plots-drawn', String(figures.length));
})();
)";

}  // namespace

std::string html_check_report(const CheckReportInput& in) {
  FigureIds ids;
  std::vector<Section> sections;
  sections.push_back(summary_section(in, ids));
  for (Section& s : source_sections(in, ids)) sections.push_back(std::move(s));
  for (Section& s : model_sections(in, ids)) sections.push_back(std::move(s));
  sections.push_back(spectrum_section(in, ids));
  sections.push_back(effects_section(in, ids));
  sections.push_back(parameters_section(in, ids));
  sections.push_back(provenance_section(in));

  const std::string title = fmt::format("ccomp {}: {}", in.command, in.model.name);
  // No network at all: the policy refuses any fetch, whatever a script would try.
  std::string html = fmt::format(
      "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
      "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; script-src 'unsafe-inline' "
      "'unsafe-eval'; style-src 'unsafe-inline'; img-src data: blob:; font-src data:\">\n"
      "<title>{}</title>\n<style>{}</style></head>\n<body>\n<header><h1>{}</h1><p>{}</p></header>\n<main>\n<nav>",
      html_escape(title), kStyle, html_escape(title),
      html_escape(in.command == "fit" ? "The fitted model checked against the measurements it was fitted to"
                                      : "The machine model checked against measurements"));
  for (const Section& s : sections)
    if (!s.title.empty()) html += fmt::format("<a href=\"#{}\">{}</a>", s.id, html_escape(s.title));
  html += "</nav>\n";
  std::string figures_json = "[";
  for (const Section& s : sections) {
    if (s.title.empty()) continue;
    html += fmt::format("<section id=\"{}\">\n<h2>{}</h2>\n{}", s.id, html_escape(s.title), s.html);
    if (!s.figures.empty()) html += "<div class=\"figs\">\n";
    if (!s.beside.empty()) html += "<div class=\"beside\">" + s.beside + "</div>\n";
    for (const Figure& f : s.figures) {
      html += fmt::format("<figure{}><div id=\"{}\" class=\"plot\" style=\"height:{}px\"></div>{}</figure>\n",
                          f.wide ? " class=\"wide\"" : "", f.id, f.height,
                          f.caption.empty() ? "" : "<figcaption>" + f.caption + "</figcaption>");
      figures_json += fmt::format("{}{{\"id\":{},\"data\":{},\"layout\":{}}}", figures_json.size() > 1 ? ",\n" : "",
                                  json_string(f.id), f.traces, f.layout);
    }
    if (!s.figures.empty()) html += "</div>\n";
    html += "</section>\n";
  }
  figures_json += "]";
  html += "</main>\n<script type=\"application/json\" id=\"ccomp-figures\">" + figures_json + "</script>\n<script>";
  html += plotly_js();
  html += "</script>\n<script>";
  html += kDrawScript;
  html += "</script>\n</body></html>\n";
  return html;
}

}  // namespace ccomp::report
