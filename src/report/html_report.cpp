#include "ccomp/report/html_report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

#include "ccomp/util/interval.hpp"

namespace ccomp::report {
namespace {

std::string escape(const std::string& text) {
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

struct Series {
  std::vector<double> x, y;
  std::string colour;
  bool line = false;
};

/// An SVG chart of point or line series, with its axes' ranges written at the corners.
std::string chart(const std::string& title, const std::string& x_label, const std::string& y_label,
                  const std::vector<Series>& series) {
  constexpr double kW = 520, kH = 300, kLeft = 70, kRight = 15, kTop = 30, kBottom = 45;
  util::Interval xs, ys;
  for (const Series& s : series)
    for (std::size_t i = 0; i < s.x.size(); ++i) xs.add(s.x[i]), ys.add(s.y[i]);
  if (xs.empty()) xs = {0.0, 0.0};  // no points (or none a number): an empty chart about zero
  if (ys.empty()) ys = {0.0, 0.0};
  double x0 = xs.lo, x1 = xs.hi, y0 = ys.lo, y1 = ys.hi;
  if (!(x1 > x0)) x0 -= 1, x1 += 1;
  if (!(y1 > y0)) y0 -= 1, y1 += 1;
  auto px = [&](double x) { return kLeft + (x - x0) / (x1 - x0) * (kW - kLeft - kRight); };
  auto py = [&](double y) { return kH - kBottom - (y - y0) / (y1 - y0) * (kH - kTop - kBottom); };
  std::string svg = fmt::format(
      "<svg class=\"chart\" xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" viewBox=\"0 0 {} {}\">"
      "<text x=\"{}\" y=\"18\" font-size=\"13\" font-weight=\"bold\">{}</text>"
      "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#888\"/>",
      kW, kH, kW, kH, kLeft, escape(title), kLeft, kTop, kW - kLeft - kRight, kH - kTop - kBottom);
  svg += fmt::format(
      "<text x=\"{}\" y=\"{}\" font-size=\"11\">{:.4g}</text><text x=\"{}\" y=\"{}\" font-size=\"11\" "
      "text-anchor=\"end\">{:.4g}</text><text x=\"{}\" y=\"{}\" font-size=\"12\" text-anchor=\"middle\">{}</text>",
      kLeft, kH - kBottom + 14, x0, kW - kRight, kH - kBottom + 14, x1, (kLeft + kW - kRight) / 2, kH - 8,
      escape(x_label));
  svg += fmt::format(
      "<text x=\"{}\" y=\"{}\" font-size=\"11\" text-anchor=\"end\">{:.4g}</text><text x=\"{}\" y=\"{}\" "
      "font-size=\"11\" text-anchor=\"end\">{:.4g}</text><text x=\"14\" y=\"{}\" font-size=\"12\" "
      "transform=\"rotate(-90 14 {})\" text-anchor=\"middle\">{}</text>",
      kLeft - 4, kTop + 10, y1, kLeft - 4, kH - kBottom, y0, (kTop + kH - kBottom) / 2, (kTop + kH - kBottom) / 2,
      escape(y_label));
  if (y0 < 0 && y1 > 0)
    svg += fmt::format("<line x1=\"{}\" x2=\"{}\" y1=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"#ccc\"/>", kLeft, kW - kRight,
                       py(0), py(0));
  for (const Series& s : series) {
    if (s.line) {
      std::string points;
      for (std::size_t i = 0; i < s.x.size(); ++i) points += fmt::format("{:.1f},{:.1f} ", px(s.x[i]), py(s.y[i]));
      svg +=
          fmt::format("<polyline fill=\"none\" stroke=\"{}\" stroke-width=\"1.2\" points=\"{}\"/>", s.colour, points);
    } else {
      for (std::size_t i = 0; i < s.x.size(); ++i)
        svg += fmt::format("<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"1.6\" fill=\"{}\"/>", px(s.x[i]), py(s.y[i]),
                           s.colour);
    }
  }
  return svg + "</svg>\n";
}

/// At most `limit` indices spread evenly over n: a plot of 100k points says no more.
std::vector<std::size_t> thin(std::size_t n, std::size_t limit) {
  std::vector<std::size_t> out;
  const double step = n > limit ? static_cast<double>(n) / static_cast<double>(limit) : 1.0;
  for (double i = 0; i < static_cast<double>(n); i += step) out.push_back(static_cast<std::size_t>(i));
  return out;
}

}  // namespace

std::string html_check_report(const CheckReportInput& in) {
  const auto& obs = in.data.observations;
  const double um = 1e3;
  std::string html =
      "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>ccomp check: " + escape(in.model.name) +
      "</"
      "title><style>body{font-family:sans-serif;margin:20px;max-width:1100px}table{border-collapse:collapse;margin:8px "
      "0}td,th{border:1px solid #ccc;padding:3px "
      "7px;font-size:13px;text-align:left}.charts{display:flex;flex-wrap:wrap;"
      "gap:10px}code{font-size:12px}</style></head><body>\n";
  html += fmt::format(
      "<h1>ccomp check: model '{}'</h1>\n<p>{} readings from {} file(s). The model as it is: rms "
      "<b>{:.3f} um</b>, max {:.3f} um. Refitted (its free parameters): rms <b>{:.3f} um</b>. Noise floor "
      "{:.3f} um ({}).</p>\n",
      escape(in.model.name), obs.size(), in.data.files.size(), in.check.rms * um, in.check.max * um,
      in.diagnosis.rms_refit * um, in.check.noise_floor * um, escape(in.check.noise_method));
  // Missing effects.
  html += "<h2>Missing effects</h2>\n";
  if (in.diagnosis.suggestions.empty()) {
    html += fmt::format("<p>None of {} candidates is significant against the noise floor.</p>\n",
                        in.diagnosis.candidates_tried);
  } else {
    html +=
        "<table><tr><th>rank</th><th>effect</th><th>term</th><th>variable</th><th>form</th><th>period</th><th>rms "
        "before / after (um)</th><th>BIC</th><th>add</th></tr>\n";
    for (const identify::Suggestion& s : in.diagnosis.suggestions)
      html += fmt::format(
          "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{:.3f} / {:.3f}</td>"
          "<td>{:+.1f}</td><td><code>{}</code></td></tr>\n",
          s.rank, escape(s.effect), escape(s.term), escape(s.variable), escape(s.form),
          s.period > 0 ? fmt::format("{:.6g} &plusmn; {:.2g}", s.period, s.period_uncertainty) : "", s.rms_before * um,
          s.rms_after * um, s.bic_delta, escape(s.spec));
    html += "</table>\n";
  }
  if (!in.diagnosis.regions.empty()) {
    html +=
        "<h2>Where the residual concentrates</h2>\n<table><tr><th>variable</th><th>from</th><th>to</th><th>rms "
        "(um)</th><th>times the overall</th></tr>\n";
    for (const identify::Region& r : in.diagnosis.regions)
      html += fmt::format("<tr><td>{}</td><td>{:.4g}</td><td>{:.4g}</td><td>{:.3f}</td><td>{:.1f}</td></tr>\n",
                          escape(r.variable), r.from, r.to, r.rms * um, r.ratio);
    html += "</table>\n";
  }
  // Residual against every variable that varies.
  struct Variable {
    std::string name;
    std::function<double(const identify::Observation&)> get;
  };
  std::vector<Variable> variables;
  for (const model::AxisSpec& a : in.model.axes) {
    const std::size_t i = std::string_view("XYZABCUVW").find(a.letter);
    const bool rotary = a.type == model::AxisType::rotary;
    variables.push_back(
        {std::string(1, static_cast<char>(std::tolower(a.letter))) + (rotary ? " (deg)" : " (mm)"),
         [i, rotary](const identify::Observation& o) { return identify::file_axis_value(o, i, rotary); }});
  }
  variables.push_back({"L (mm)", [](const identify::Observation& o) {
                         return o.q[static_cast<Eigen::Index>(model::kToolLengthIndex)];
                       }});
  variables.push_back({"t (s)", [](const identify::Observation& o) { return o.time; }});
  for (std::size_t s = 0; s < in.model.sensors.size(); ++s)
    variables.push_back(
        {"T_" + in.model.sensors[s] + " (degC)", [s](const identify::Observation& o) { return o.temperatures[s]; }});
  const std::vector<std::size_t> shown = thin(obs.size(), 3000);
  html +=
      "<h2>Residual against each variable</h2>\n<p>Grey: the model as it is; blue: refitted.</p>\n<div "
      "class=\"charts\">\n";
  for (const Variable& v : variables) {
    util::Interval range;
    for (const identify::Observation& o : obs) range.add(v.get(o));
    if (!(range.width() > 0)) continue;
    Series before{{}, {}, "#aaa", false}, after{{}, {}, "#1565c0", false};
    for (std::size_t i : shown) {
      before.x.push_back(v.get(obs[i])), before.y.push_back(in.check.residual[static_cast<Eigen::Index>(i)] * um);
      after.x.push_back(v.get(obs[i])), after.y.push_back(in.diagnosis.residual[static_cast<Eigen::Index>(i)] * um);
    }
    html += chart("residual against " + v.name, v.name, "residual (um)", {before, after});
  }
  html += "</div>\n";
  // Each missing effect added: the refitted residual against the effect's variable, and
  // what is left with the effect's terms fitted too.
  if (!in.diagnosis.suggestions.empty()) {
    html +=
        "<h2>Each missing effect, added</h2>\n<p>Blue: refitted; green: refitted with the effect added.</p>\n"
        "<div class=\"charts\">\n";
    for (const identify::Suggestion& s : in.diagnosis.suggestions) {
      if (s.residual.size() != static_cast<Eigen::Index>(obs.size())) continue;
      // The effect's first variable ("x,T_bed" -> x; an approach direction "vy" -> y).
      std::string name = s.variable.substr(0, s.variable.find(','));
      if (name.size() == 2 && name[0] == 'v') name.erase(0, 1);
      const auto v = std::find_if(variables.begin(), variables.end(),
                                  [&](const Variable& candidate) { return candidate.name.starts_with(name + " "); });
      if (v == variables.end()) continue;
      Series refitted{{}, {}, "#1565c0", false}, added{{}, {}, "#2e7d32", false};
      for (std::size_t i : shown) {
        refitted.x.push_back(v->get(obs[i])),
            refitted.y.push_back(in.diagnosis.residual[static_cast<Eigen::Index>(i)] * um);
        added.x.push_back(v->get(obs[i])), added.y.push_back(s.residual[static_cast<Eigen::Index>(i)] * um);
      }
      html += chart(
          fmt::format("{}: {} {} ({:.3f} -> {:.3f} um)", s.rank, s.term, s.form, s.rms_before * um, s.rms_after * um),
          v->name, "residual (um)", {refitted, added});
    }
    html += "</div>\n";
  }
  // Error maps: the residual over the workspace, coloured (blue negative, red positive).
  html +=
      "<h2>Error maps over the workspace</h2>\n<p>Each reading at its position, coloured by the refitted residual "
      "(blue below zero, red above; full colour at 3 noise floors).</p>\n<div class=\"charts\">\n";
  const double full = std::max(3 * in.check.noise_floor, 1e-9);
  for (const auto& [a, b] : {std::pair<int, int>{0, 1}, std::pair<int, int>{0, 2}, std::pair<int, int>{1, 2}}) {
    std::vector<Series> cells;
    for (int bucket = -4; bucket <= 4; ++bucket) {
      const double f = bucket / 4.0;
      const int red = f > 0 ? 255 : static_cast<int>(255 * (1 + f)),
                blue = f < 0 ? 255 : static_cast<int>(255 * (1 - f));
      // Darkened a little, so a zero residual shows as light grey on the white page.
      cells.push_back({{},
                       {},
                       fmt::format("rgb({},{},{})", red * 85 / 100, std::min(red, blue) * 85 / 100, blue * 85 / 100),
                       false});
    }
    for (std::size_t i : shown) {
      const double f = std::clamp(in.diagnosis.residual[static_cast<Eigen::Index>(i)] / full, -1.0, 1.0);
      Series& s = cells[static_cast<std::size_t>(std::lround(f * 4) + 4)];
      s.x.push_back(variables[static_cast<std::size_t>(a)].get(obs[i]));
      s.y.push_back(variables[static_cast<std::size_t>(b)].get(obs[i]));
    }
    html += chart(fmt::format("refitted residual over {} and {}", variables[static_cast<std::size_t>(a)].name,
                              variables[static_cast<std::size_t>(b)].name),
                  variables[static_cast<std::size_t>(a)].name, variables[static_cast<std::size_t>(b)].name, cells);
  }
  html += "</div>\n";
  // Spectra: the refitted residual of readings along each linear axis, amplitude by period.
  html +=
      "<h2>Spectra along each axis</h2>\n<p>Amplitude of the best sinusoid in the refitted residual of the readings "
      "along the axis, by period.</p>\n<div class=\"charts\">\n";
  for (std::size_t axis = 0; axis < 3; ++axis) {
    std::vector<std::pair<double, double>> rows;  // position, residual
    for (std::size_t i = 0; i < obs.size(); ++i)
      if (std::abs(std::abs(obs[i].direction[static_cast<Eigen::Index>(axis)]) - 1.0) < 1e-6)
        rows.emplace_back(variables[axis].get(obs[i]), in.diagnosis.residual[static_cast<Eigen::Index>(i)]);
    if (rows.size() < 20) continue;
    util::Interval range;
    for (const auto& [p, r] : rows) range.add(p);
    if (!(range.width() > 10)) continue;
    const double lo = range.lo, hi = range.hi;
    Series spectrum{{}, {}, "#c62828", true};
    for (int k = 0; k < 300; ++k) {
      const double period = 2.0 * std::pow((hi - lo) / 2.0 / 2.0, k / 299.0);
      double cc = 0, ss = 0, cs = 0, rc = 0, rs = 0;
      for (const auto& [p, r] : rows) {
        const double c = std::cos(2 * std::numbers::pi * p / period), s = std::sin(2 * std::numbers::pi * p / period);
        cc += c * c, ss += s * s, cs += c * s, rc += r * c, rs += r * s;
      }
      const double det = cc * ss - cs * cs;
      if (!(det > 0)) continue;
      const double a = (rc * ss - rs * cs) / det, b = (rs * cc - rc * cs) / det;
      spectrum.x.push_back(std::log10(period));
      spectrum.y.push_back(std::hypot(a, b) * um);
    }
    html += chart(fmt::format("spectrum along {}", "XYZ"[axis]), "log10 period (mm)", "amplitude (um)", {spectrum});
  }
  html += "</div>\n";
  // Identifiability.
  html += fmt::format(
      "<h2>Identifiability</h2>\n<p>{} free parameters; the data determine {} combinations "
      "(condition number {:.3g}), {} of which changed by more than the noise.</p>\n",
      in.diagnosis.refit.parameters.size(), in.diagnosis.refit.rank, in.diagnosis.refit.condition_number,
      in.diagnosis.refit.significant);
  if (in.diagnosis.refit.singular_values.size() > 0) {
    Series sv{{}, {}, "#2e7d32", false};
    for (Eigen::Index k = 0; k < in.diagnosis.refit.singular_values.size(); ++k)
      if (in.diagnosis.refit.singular_values[k] > 0) {
        sv.x.push_back(static_cast<double>(k + 1));
        sv.y.push_back(std::log10(in.diagnosis.refit.singular_values[k] / in.diagnosis.refit.singular_values[0]));
      }
    html += "<div class=\"charts\">" +
            chart("singular values (log10, relative)", "combination", "log10 relative", {sv}) + "</div>\n";
  }
  html +=
      "<table><tr><th>parameter</th><th>refitted value (mm, rad)</th><th>uncertainty (1 sigma)</th><th>determined "
      "alone</th></tr>\n";
  for (const identify::FittedParameter& p : in.diagnosis.refit.parameters)
    html += fmt::format("<tr><td>{}</td><td>{:.6g}</td><td>{:.3g}</td><td>{}</td></tr>\n", escape(p.label), p.after,
                        p.uncertainty, p.identified ? "yes" : "no");
  html += "</table>\n";
  for (const std::string& u : in.diagnosis.refit.unidentifiable) html += "<p>" + escape(u) + "</p>\n";
  return html + "</body></html>\n";
}

}  // namespace ccomp::report
