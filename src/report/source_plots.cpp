// Each source on its own plots, one per direction read: a laser line's deviations against
// the moving axis' position, up and down runs apart, with the model's error motion (refitted,
// and as it is) as curves through them and ISO 230-2's bands where runs repeat; a grid's
// deviations point by point; a rotary axis' readings as polar plots of the angle.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "ccomp/axis.hpp"
#include "ccomp/error.hpp"
#include "ccomp/identify/positioning.hpp"
#include "ccomp/identify/stated_conditions.hpp"
#include "ccomp/util/interval.hpp"
#include "report/figures.hpp"
#include "report/source_shape.hpp"

namespace ccomp::report {
namespace {

constexpr std::string_view kUp = "#1f5fa8", kDown = "#c2410c", kUnknown = "#555555";
constexpr std::array<std::string_view, 3> kAxisColour = {"#1f5fa8", "#2b8a3e", "#c2410c"};

/// A reading's measured deviation and the two models' predictions of it, in um along the
/// direction's label.
struct Values {
  double measured, refitted, as_is;
};

Values values(const CheckReportInput& in, std::size_t i, double sign) {
  const double v = in.data.observations[i].value;
  const auto k = static_cast<Eigen::Index>(i);
  const bool refitted = in.diagnosis.residual.size() == in.check.residual.size();
  return {sign * v * kUm, refitted ? sign * (v - in.diagnosis.residual[k]) * kUm : std::nan(""),
          sign * (v - in.check.residual[k]) * kUm};
}

/// What a reading along `read` on a line moving `moving` measures, in ISO 230-1's words.
std::string line_quantity(const ReadingDirection& read, std::size_t moving) {
  const char m = axis_letter(moving);
  if (read.axis < 0) return "deviation along " + read.label;
  const char r = "XYZ"[read.axis];
  if (static_cast<std::size_t>(read.axis) == moving) return fmt::format("positioning deviation E{}{}", r, m);
  return fmt::format("straightness in {} (E{}{})", r, r, m);
}

/// The fixed coordinates of a line: "Y -360 mm, Z -400 mm, L 100 mm".
std::string line_place(const identify::Observation& o, const model::MachineModel& model, std::size_t moving) {
  std::string out;
  for (const model::AxisSpec& a : model.axes) {
    const auto axis = static_cast<std::size_t>(a.index());
    if (axis == moving) continue;
    out += fmt::format("{}{} {:g} {}", out.empty() ? "" : ", ", a.letter, axis_value(o, axis),
                       angular_at(axis) ? "&deg;" : "mm");
  }
  return out + fmt::format(", L {:g} mm", o.q[static_cast<Eigen::Index>(model::kToolLengthIndex)]);
}

/// ISO 230-2 on one source's positioning readings, when they allow it.
/// (`forward`: the model's chain, for a rotary axis' deviations, angles over the readings' lever.)
std::optional<identify::PositioningReport> positioning(const CheckReportInput& in, std::size_t axis,
                                                       const std::string& source, const model::ForwardModel& forward) {
  if (axis > 5) return std::nullopt;
  try {
    if (axis > 2) return identify::analyse_positioning(in.data, axis, source, &forward);
    return identify::analyse_positioning(in.data, axis, source);
  } catch (const Error&) {
    return std::nullopt;  // no readings along it with an approach, or at one target only
  }
}

Figure line_figure(const CheckReportInput& in, const SourceShape& shape, const ReadingDirection& read,
                   const std::string& source, const identify::PositioningReport* iso, FigureIds& ids) {
  struct Run {
    std::string name;
    std::string_view colour, symbol;
    std::vector<std::pair<double, Values>> points;  // position, values
  };
  std::array<Run, 3> runs{Run{"up", kUp, "triangle-up", {}}, Run{"down", kDown, "triangle-down", {}},
                          Run{"approach unknown", kUnknown, "circle", {}}};
  for (std::size_t k = 0; k < read.readings.size(); ++k) {
    const identify::Observation& o = in.data.observations[read.readings[k]];
    const double approach = o.directions[shape.axis];
    Run& run = runs[approach > 0 ? 0 : approach < 0 ? 1 : 2];
    run.points.emplace_back(axis_value(o, shape.axis), values(in, read.readings[k], read.sign[k]));
  }
  std::string traces;
  auto add = [&](const std::string& trace) {
    if (!traces.empty()) traces += ',';
    traces += trace;
  };
  // A browser draws some thousands of points per plot smoothly; beyond, every stride-th.
  constexpr std::size_t kMostPoints = 6000;
  const std::size_t stride = (read.readings.size() + kMostPoints - 1) / kMostPoints;
  for (Run& run : runs) {
    if (run.points.empty()) continue;
    std::sort(run.points.begin(), run.points.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<double> x, measured, curve_x, refitted, as_is;
    for (std::size_t k = 0; k < run.points.size(); ++k) {
      const auto& [p, v] = run.points[k];
      if (k % stride == 0) x.push_back(p), measured.push_back(v.measured);
      // The models predict the same at a position however often it was measured: one point each.
      if (curve_x.empty() || p - curve_x.back() > 1e-6)
        curve_x.push_back(p), refitted.push_back(v.refitted), as_is.push_back(v.as_is);
    }
    // Every trace drawn has its own legend entry, in its own colour and dash: a curve of the
    // down run is named as the down run's, not hidden behind the up run's entry.
    const auto rank = &run - runs.data() + 1;
    add(xy_trace(
        "measured, " + run.name, x, measured, "markers",
        fmt::format(
            R"("legendrank":{0},"legendgroup":"measured {0}","marker":{{"color":"{1}","size":5,"symbol":"{2}","opacity":0.75}})",
            rank, run.colour, run.symbol)));
    add(xy_trace("model refitted, " + run.name, curve_x, refitted, "lines",
                 fmt::format(R"("legendrank":{},"line":{{"color":"{}","width":1.8}})", 10 + rank, run.colour)));
    add(xy_trace("model as it is, " + run.name, curve_x, as_is, "lines",
                 fmt::format(R"("legendrank":{},"line":{{"color":"{}","width":1.2,"dash":"dot"}})", 20 + rank,
                             run.colour)));
  }
  std::string caption =
      fmt::format("Line at {} (machine axis positions); {} readings ({} up, {} down{}){}.",
                  line_place(in.data.observations[read.readings.front()], in.model, shape.axis), read.readings.size(),
                  runs[0].points.size(), runs[1].points.size(),
                  runs[2].points.empty() ? "" : fmt::format(", {} unknown", runs[2].points.size()),
                  stride > 1 ? fmt::format(", one reading in {} shown (the curves use all)", stride) : "");
  // ISO 230-2's bands: the mean deviation at each target, each way, +- 2 s.
  if (iso != nullptr && (iso->A_up || iso->A_down)) {
    std::string bands;  // drawn first, under the points
    const auto add_band = [&](const std::string& trace) { bands += trace, bands += ","; };
    for (int way = 0; way < 2; ++way) {
      if (!(way == 0 ? iso->A_up : iso->A_down)) continue;  // no spread that way: one run
      std::vector<double> x, upper, lower;
      for (const identify::PositioningTarget& t : iso->targets) {
        const std::optional<double>& m = way == 0 ? t.mean_up : t.mean_down;
        const std::optional<double>& s = way == 0 ? t.s_up : t.s_down;
        if (!m || !s) continue;
        x.push_back(t.position), upper.push_back((*m + 2 * *s) * kUm), lower.push_back((*m - 2 * *s) * kUm);
      }
      const std::string_view colour = way == 0 ? kUp : kDown;
      const std::string name = way == 0 ? "up" : "down";
      const std::string fill = way == 0 ? "rgba(31,95,168,0.15)" : "rgba(194,65,12,0.15)";
      add_band(
          xy_trace("mean + 2s, " + name, x, upper, "lines",
                   fmt::format(R"("legendgroup":"iso {}","showlegend":false,"line":{{"width":0,"color":"{}"}})", name,
                               colour)));
      // The band of each way its own entry in its own fill (the edge above is invisible).
      add_band(xy_trace(
          "ISO 230-2: mean ± 2s, " + name, x, lower, "lines",
          fmt::format(
              R"("legendrank":{},"legendgroup":"iso {}","fill":"tonexty","fillcolor":"{}","line":{{"width":0,"color":"{}"}})",
              31 + way, name, fill, colour)));
    }
    traces = bands + traces;
    caption += fmt::format(" Bands: mean &plusmn; 2s of {} runs up, {} down (ISO 230-2).", iso->runs_up, iso->runs_down);
  }
  Figure f;
  f.id = ids.next("line");
  f.traces = "[" + traces + "]";
  f.layout = fmt::format(
      R"j({{"title":{{"text":{}}},"xaxis":{{"title":{{"text":{}}}}},"yaxis":{{"title":{{"text":"deviation along {} (µm)"}}}}}})j",
      json_string(source + ": " + line_quantity(read, shape.axis)), json_string(position_title(shape.axis)),
      read.label);
  f.caption = caption + " " + frame_note(in.data, read.readings.front());
  f.height = 360;
  return f;
}

Figure volumetric_figure(const CheckReportInput& in, const ReadingDirection& read, const std::string& source,
                         FigureIds& ids) {
  // Points measured over time (a thermal test) against the time; a grid in file order.
  util::Interval time;
  for (std::size_t i : read.readings) time.add(in.data.observations[i].time);
  const bool timed = time.width() > 0;
  std::vector<double> n, measured, refitted, as_is;
  std::vector<std::string> where;
  for (std::size_t k = 0; k < read.readings.size(); ++k) {
    const identify::Observation& o = in.data.observations[read.readings[k]];
    const Values v = values(in, read.readings[k], read.sign[k]);
    n.push_back(timed ? o.time : static_cast<double>(k + 1)), measured.push_back(v.measured),
        refitted.push_back(v.refitted), as_is.push_back(v.as_is);
    where.push_back(fmt::format("axes (machine) X {:g}, Y {:g}, Z {:g} mm, L {:g} mm, t {:g} s", axis_value(o, 0), axis_value(o, 1),
                                axis_value(o, 2), o.q[static_cast<Eigen::Index>(model::kToolLengthIndex)], o.time));
  }
  const std::string hover = R"("text":)" + json_strings(where) + R"(,"hovertemplate":"%{text}<br>%{y:.3f} µm")";
  Figure f;
  f.id = ids.next("grid");
  f.traces =
      "[" +
      xy_trace("measured", n, measured, "markers",
               hover + R"(,"marker":{"color":"#1d1d1d","size":5,"symbol":"circle-open"})") +
      "," +
      xy_trace("model refitted", n, refitted, "markers",
               hover + R"(,"marker":{"color":"#1f5fa8","size":4,"symbol":"circle"})") +
      "," +
      xy_trace(
          "model as it is", n, as_is, "markers",
          hover +
              R"(,"marker":{"color":"#c2410c","size":5,"symbol":"x-thin-open","line":{"width":1,"color":"#c2410c"}})") +
      "]";
  f.layout = fmt::format(
      R"j({{"title":{{"text":{}}},"xaxis":{{"title":{{"text":"{}"}}}},"yaxis":{{"title":{{"text":"deviation along {} (µm)"}}}}}})j",
      json_string(fmt::format("{}: deviation along {}", source, read.label)), timed ? "time (s)" : "point (file order)",
      read.label);
  f.caption = fmt::format("{} points spread over the workspace; hover for each point's position. {}",
                          read.readings.size(), frame_note(in.data, read.readings.front()));
  return f;
}

/// Readings as a rotary axis turns, one polar plot per probed point (the same point of the
/// table at every angle): the deviation in X, Y and Z against the angle.
std::vector<Figure> rotary_figures(const CheckReportInput& in, const SourceShape& shape, const std::string& source,
                                   FigureIds& ids) {
  // Probes at one angle appear in the same order at every angle: the k-th distinct position
  // at an angle is probe k.
  std::map<long long, std::vector<std::array<double, 4>>> positions_at;  // angle (1e-6 deg) -> positions seen
  std::vector<std::size_t> probe_of(shape.readings.size());
  std::size_t probes = 0;
  for (std::size_t k = 0; k < shape.readings.size(); ++k) {
    const identify::Observation& o = in.data.observations[shape.readings[k]];
    const std::array<double, 4> at{axis_value(o, 0), axis_value(o, 1), axis_value(o, 2),
                                   o.q[static_cast<Eigen::Index>(model::kToolLengthIndex)]};
    auto& seen = positions_at[std::llround(axis_value(o, shape.axis) * 1e6)];
    auto it = std::find_if(seen.begin(), seen.end(), [&](const auto& p) {
      return std::abs(p[0] - at[0]) + std::abs(p[1] - at[1]) + std::abs(p[2] - at[2]) + std::abs(p[3] - at[3]) < 1e-6;
    });
    probe_of[k] = static_cast<std::size_t>(it - seen.begin());
    if (it == seen.end()) seen.push_back(at);
    probes = std::max(probes, probe_of[k] + 1);
  }
  std::vector<Figure> out;
  for (std::size_t p = 0; p < probes && out.size() < 12; ++p) {
    std::string traces, place;
    double lo = 0, hi = 0;
    std::vector<std::size_t> rows;
    for (std::size_t k = 0; k < shape.readings.size(); ++k)
      if (probe_of[k] == p) rows.push_back(shape.readings[k]);
    const identify::Observation& first = in.data.observations[rows.front()];
    place = fmt::format("machine axis positions X {:g}, Y {:g}, Z {:g} mm, L {:g} mm", axis_value(first, 0),
                        axis_value(first, 1), axis_value(first, 2),
                        first.q[static_cast<Eigen::Index>(model::kToolLengthIndex)]);
    for (const ReadingDirection& read : reading_directions(in.data, rows)) {
      std::vector<std::pair<double, Values>> points;
      for (std::size_t k = 0; k < read.readings.size(); ++k)
        points.emplace_back(axis_value(in.data.observations[read.readings[k]], shape.axis),
                            values(in, read.readings[k], read.sign[k]));
      std::sort(points.begin(), points.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
      std::vector<double> angle, measured, refitted;
      for (const auto& [a, v] : points) {
        angle.push_back(a), measured.push_back(v.measured), refitted.push_back(v.refitted);
        lo = std::min({lo, v.measured, v.refitted}), hi = std::max({hi, v.measured, v.refitted});
      }
      std::vector<double> curve_angle = angle;
      if (!angle.empty() && angle.back() - angle.front() > 300)  // a full turn: close the curve
        curve_angle.push_back(angle.front() + 360), refitted.push_back(refitted.front());
      const std::string_view colour = read.axis >= 0 ? kAxisColour[static_cast<std::size_t>(read.axis)] : kUnknown;
      const auto polar = [&](const std::string& name, const std::vector<double>& r, const std::vector<double>& theta,
                             std::string_view mode, const std::string& style) {
        return fmt::format(R"({{"type":"scatterpolar","name":{},"r":{},"theta":{},"mode":"{}",{}}})", json_string(name),
                           json_numbers(r), json_numbers(theta), mode, style);
      };
      if (!traces.empty()) traces += ",";
      traces += polar("measured " + read.label, measured, angle, "markers",
                      fmt::format(R"("legendgroup":"{0}","marker":{{"color":"{1}","size":6}})", read.label, colour));
      traces += ",";
      traces += polar("model refitted " + read.label, refitted, curve_angle, "lines",
                      fmt::format(R"("legendgroup":"{0}","line":{{"color":"{1}","width":1.6}})", read.label, colour));
    }
    // Zero deviation as a reference circle: the radial axis starts below zero.
    std::vector<double> circle_theta, circle_r;
    for (int a = 0; a <= 360; a += 5) circle_theta.push_back(a), circle_r.push_back(0);
    traces += fmt::format(
        R"(,{{"type":"scatterpolar","name":"zero deviation","r":{},"theta":{},"mode":"lines","line":{{"color":"#333","width":1,"dash":"dash"}},"hoverinfo":"skip"}})",
        json_numbers(circle_r), json_numbers(circle_theta));
    const double pad = std::max(0.1 * (hi - lo), 0.5);
    Figure f;
    f.id = ids.next("polar");
    f.traces = "[" + traces + "]";
    f.layout = fmt::format(
        R"({{"title":{{"text":{}}},"margin":{{"l":40,"r":40,"t":50,"b":40}},"polar":{{"radialaxis":{{"range":[{},{}],"angle":112.5,"tickangle":112.5}},"angularaxis":{{"rotation":0,"direction":"counterclockwise","dtick":45,"ticksuffix":"°"}}}},"legend":{{"y":-0.12}}}})",
        json_string(fmt::format("{}: probe {} as {} turns, deviation (µm)", source, p + 1, axis_letter(shape.axis))),
        json_number(lo - pad), json_number(hi + pad));
    f.caption = fmt::format(
        "Probe {} ({} at the first angle). Radius: deviation in &micro;m along X, Y, Z (the dashed circle is zero; "
        "inside it, negative); angle: {} in degrees, 0&deg; to the right, counter-clockwise. {}",
        p + 1, place, axis_letter(shape.axis), frame_note(in.data, rows.front()));
    f.height = 430;
    out.push_back(std::move(f));
  }
  return out;
}

/// What the files state of the test (identify::StatedConditions), which ISO 230-2's report
/// gives beside the figures: "not stated" where nothing does.
std::string stated_note(const identify::MeasurementSet& data) {
  const identify::StatedConditions s = identify::sort_stated(data.stated);
  const std::string not_stated = "<em>not stated</em>";
  std::string temperatures;
  for (const auto& t : s.temperatures)
    temperatures += fmt::format("{}{} {:.2f} &deg;C", temperatures.empty() ? "" : ", ", html_escape(t.name), t.degc);
  return fmt::format(
      "<p class=\"note\">The test as its files state it: instrument {}; temperatures {}; uncertainty of measurement "
      "{}.</p>\n",
      s.instrument ? html_escape(s.instrument->value) : not_stated, temperatures.empty() ? not_stated : temperatures,
      s.uncertainty ? html_escape(s.uncertainty->value) : not_stated);
}

/// ISO 230-2's figures at each target of one source, as the standard's report lists them,
/// folded away under its summary.
std::string target_table(const std::string& source, const identify::PositioningReport& r, const std::string& unit,
                         double scale) {
  const auto shown = [&](const std::optional<double>& v) {
    return v ? fmt::format("<td class=\"num\">{:.3f}</td>", *v * scale) : std::string("<td class=\"num\">&ndash;</td>");
  };
  std::string html = fmt::format(
      "<details><summary>{}: per target ({}; s the estimator of the standard uncertainty, R&uarr; and R&darr; = 4s, "
      "R<sub>i</sub> = max(2s&uarr; + 2s&darr; + |B<sub>i</sub>|, R&uarr;, R&darr;))</summary>\n<table><tr><th>position "
      "({})</th><th>runs &uarr; / &darr;</th><th>mean &uarr;</th><th>mean &darr;</th><th>mean</th><th>B<sub>i</sub></th>"
      "<th>s&uarr;</th><th>s&darr;</th><th>R&uarr;</th><th>R&darr;</th><th>R<sub>i</sub></th></tr>\n",
      html_escape(source), unit, r.rotary ? "deg" : "mm");
  for (const identify::PositioningTarget& t : r.targets)
    html += fmt::format("<tr><td class=\"num\">{:g}</td><td class=\"num\">{} / {}</td>{}{}{}{}{}{}{}{}{}</tr>\n",
                        t.position, t.runs_up, t.runs_down, shown(t.mean_up), shown(t.mean_down), shown(t.mean),
                        shown(t.reversal), shown(t.s_up), shown(t.s_down), shown(t.repeatability_up),
                        shown(t.repeatability_down), shown(t.repeatability));
  return html + "</table></details>\n";
}

/// ISO 230-2's figures of the lines (linear axes, in um) or of the rotary axes' runs (in
/// arcseconds, as the standard gives an angle's), one row a source.
std::string iso_table(const std::vector<std::pair<std::string, identify::PositioningReport>>& reports,
                      const identify::MeasurementSet& data, bool rotary) {
  if (reports.empty()) return "";
  const std::string unit = rotary ? "arcsec" : "&micro;m";
  const double scale = rotary ? identify::kArcsecPerRad : kUm;
  std::string html = fmt::format(
      "<h3>ISO 230-2 positioning figures{}</h3>\n<table><tr><th>source</th><th>axis</th><th>targets</th><th>runs "
      "up / down</th><th>A ({})</th><th>A&uarr; / A&darr;</th><th>B ({})</th><th>mean B</th><th>E "
      "({})</th><th>M ({})</th><th>R ({})</th><th>R&uarr; / R&darr;</th></tr>\n",
      rotary ? " (rotary axes, in arcseconds)" : "", unit, unit, unit, unit, unit);
  bool missing = false;
  const auto shown = [&](const std::optional<double>& v) {
    missing = missing || !v;
    return v ? fmt::format("{:.3f}", *v * scale) : std::string("&ndash;");
  };
  for (const auto& [source, r] : reports) {
    html += fmt::format(
        "<tr><td>{}</td><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{} / {}</td><td class=\"num\">{}</td><td "
        "class=\"num\">{} / {}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td "
        "class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{} / "
        "{}</td></tr>\n",
        html_escape(source), axis_letter(r.axis), r.targets.size(), r.runs_up, r.runs_down, shown(r.A), shown(r.A_up),
        shown(r.A_down), shown(r.B), r.B_mean ? fmt::format("{:+.3f}", *r.B_mean * scale) : std::string("&ndash;"),
        shown(r.E), shown(r.M), shown(r.R), shown(r.R_up), shown(r.R_down));
  }
  html +=
      "</table>\n<p class=\"note\">A accuracy, B reversal (largest |B<sub>i</sub>|), E systematic deviation, M mean "
      "bidirectional deviation, R repeatability, all from the measured deviations (not the model).";
  if (missing)
    html +=
        " &ndash;: not stated: one run in a direction gives no spread, so A and R (which include 2s and 4s) are not "
        "stated, and a line read one way only has no bidirectional figures; ISO 230-2 asks for 5 runs each way.";
  html += "</p>\n";
  for (const auto& [source, r] : reports) html += target_table(source, r, unit, scale);
  return html + stated_note(data);
}

}  // namespace

std::vector<Section> source_sections(const CheckReportInput& in, FigureIds& ids) {
  Section lines{"lines", "Laser lines", "", {}, ""}, grids{"volumetric", "Volumetric measurements", "", {}, ""},
      rotary{"rotary", "Rotary axes", "", {}, ""};
  std::vector<std::pair<std::string, identify::PositioningReport>> iso_reports, rotary_iso;
  const model::ForwardModel forward(in.model);  // once, for every rotary source's figures
  const std::vector<SourceShape> shapes = source_shapes(in.data, in.model);
  for (std::size_t s = 0; s < shapes.size(); ++s) {
    const SourceShape& shape = shapes[s];
    const std::string& source = in.data.sources[s];
    if (shape.readings.empty()) continue;
    if (shape.kind == SourceKind::rotary) {
      for (Figure& f : rotary_figures(in, shape, source, ids)) rotary.figures.push_back(std::move(f));
      if (std::optional<identify::PositioningReport> iso = positioning(in, shape.axis, source, forward); iso && iso->rotary)
        rotary_iso.emplace_back(source, *iso);
      continue;
    }
    std::optional<identify::PositioningReport> iso;
    if (shape.kind == SourceKind::line) {
      iso = positioning(in, shape.axis, source, forward);
      if (iso) iso_reports.emplace_back(source, *iso);
    }
    for (const ReadingDirection& read : reading_directions(in.data, shape.readings)) {
      if (shape.kind == SourceKind::line)
        lines.figures.push_back(line_figure(in, shape, read, source,
                                            iso && read.axis == static_cast<int>(shape.axis) ? &*iso : nullptr, ids));
      else
        grids.figures.push_back(volumetric_figure(in, read, source, ids));
    }
  }
  lines.html =
      "<p>Each laser line on its own plots, one per direction read: the deviation against the position of the "
      "moving axis, runs moving up (&#9650;) and down (&#9660;) apart. Solid curves: the model's error motion "
      "refitted to these data; dotted: the model as it is. A gap between the up and down points that the curves do "
      "not follow is a reversal the model lacks.</p>\n" +
      iso_table(iso_reports, in.data, false);
  grids.html =
      "<p>Points spread over the workspace (a grid, a test piece), one plot per direction read, points in file "
      "order: measured (&#9675;), the model refitted (&#9679;) and as it is (&times;).</p>\n";
  rotary.html =
      "<p>Readings as a rotary axis turns (a sphere probed on the table): per probed point, the deviation in each "
      "direction against the angle, measured (points) and the model refitted (curves).</p>\n" +
      iso_table(rotary_iso, in.data, true);
  std::vector<Section> out;
  for (Section* s : {&lines, &grids, &rotary})
    if (!s->figures.empty()) out.push_back(std::move(*s));
  return out;
}

}  // namespace ccomp::report
