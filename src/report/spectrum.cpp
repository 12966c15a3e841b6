// Spectra of what the refitted model leaves along each linear axis' positioning lines: the
// amplitude of the best sinusoid by period, from the Nyquist limit of the lines' sampling
// step (two steps: a shorter period only aliases onto a longer one) to the travel.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "report/figures.hpp"
#include "report/source_shape.hpp"

namespace ccomp::report {

Section spectrum_section(const CheckReportInput& in, FigureIds& ids) {
  Section s{"spectrum", "Spectra of the residual", "", {}, ""};
  const bool refitted = in.diagnosis.residual.size() == in.check.residual.size();
  const Eigen::VectorXd& residual = refitted ? in.diagnosis.residual : in.check.residual;
  const std::vector<SourceShape> shapes = source_shapes(in.data, in.model);
  for (std::size_t axis = 0; axis < 3; ++axis) {
    std::vector<std::pair<double, double>> rows;  // position, residual less its line's and approach's mean
    std::vector<double> steps;
    double travel = 0;
    std::size_t lines = 0;
    for (const SourceShape& shape : shapes) {
      if (shape.kind != SourceKind::line || shape.axis != axis) continue;
      std::map<int, std::vector<std::pair<double, double>>> by_approach;
      for (const ReadingDirection& read : reading_directions(in.data, shape.readings)) {
        if (read.axis != static_cast<int>(axis)) continue;
        for (std::size_t k = 0; k < read.readings.size(); ++k) {
          const identify::Observation& o = in.data.observations[read.readings[k]];
          by_approach[o.directions[axis] > 0   ? 1
                      : o.directions[axis] < 0 ? -1
                                               : 0]
              .emplace_back(axis_value(o, axis), read.sign[k] * residual[static_cast<Eigen::Index>(read.readings[k])]);
        }
      }
      if (by_approach.empty()) continue;
      ++lines;
      for (auto& [approach, points] : by_approach) {
        double mean = 0;
        for (const auto& [p, r] : points) mean += r;
        mean /= static_cast<double>(points.size());
        std::vector<double> positions;
        for (const auto& [p, r] : points) rows.emplace_back(p, r - mean), positions.push_back(p);
        std::sort(positions.begin(), positions.end());
        for (std::size_t i = 1; i < positions.size(); ++i)
          if (positions[i] - positions[i - 1] > 1e-6) steps.push_back(positions[i] - positions[i - 1]);
        travel = std::max(travel, positions.back() - positions.front());
      }
    }
    if (rows.size() < 20 || steps.empty() || !(travel > 0)) continue;
    std::nth_element(steps.begin(), steps.begin() + static_cast<long>(steps.size() / 2), steps.end());
    const double step = steps[steps.size() / 2], nyquist = 2 * step;
    if (!(travel > 2 * nyquist)) continue;
    // Frequencies evenly spaced (the resolution a finite travel gives is even in frequency).
    constexpr int kFrequencies = 600;
    std::vector<double> period, amplitude;
    for (int f = kFrequencies; f >= 0; --f) {
      const double frequency = 1.0 / travel + (1.0 / nyquist - 1.0 / travel) * f / kFrequencies;
      double cc = 0, ss = 0, cs = 0, rc = 0, rs = 0;
      for (const auto& [p, r] : rows) {
        const double c = std::cos(2 * std::numbers::pi * frequency * p),
                     sn = std::sin(2 * std::numbers::pi * frequency * p);
        cc += c * c, ss += sn * sn, cs += c * sn, rc += r * c, rs += r * sn;
      }
      // Near the Nyquist limit the samples barely see one of the two (the sine at a
      // position grid's nodes): fitting both would blow up noise; the other alone is fitted.
      const double n = static_cast<double>(rows.size()), det = cc * ss - cs * cs;
      double a = 0, b = 0;
      if (cc > 1e-3 * n && ss > 1e-3 * n && det > 1e-3 * cc * ss)
        a = (rc * ss - rs * cs) / det, b = (rs * cc - rc * cs) / det;
      else if (cc >= ss)
        a = rc / cc;
      else
        b = rs / ss;
      period.push_back(1.0 / frequency), amplitude.push_back(std::hypot(a, b) * kUm);
    }
    const auto peak =
        static_cast<std::size_t>(std::max_element(amplitude.begin(), amplitude.end()) - amplitude.begin());
    Figure f;
    f.id = ids.next("spectrum");
    f.traces = fmt::format(
        "[{}]",
        xy_trace(
            "amplitude", period, amplitude, "lines",
            R"("line":{"color":"#1f5fa8","width":1.4},"hovertemplate":"period %{x:.4g} mm<br>%{y:.3f} µm<extra></extra>")"));
    f.layout = fmt::format(
        R"j({{"title":{{"text":"Residual along {}: amplitude by period"}},"showlegend":false,"xaxis":{{"type":"log","title":{{"text":"period (mm)"}},"range":[{},{}]}},"yaxis":{{"title":{{"text":"amplitude (µm)"}},"rangemode":"tozero"}},"shapes":[{{"type":"line","xref":"x","yref":"paper","x0":{},"x1":{},"y0":0,"y1":1,"line":{{"color":"#c2410c","width":1,"dash":"dash"}}}}],"annotations":[{{"x":{},"y":{},"xref":"x","yref":"y","text":{},"showarrow":true,"arrowhead":2,"ax":{},"ay":-25,"font":{{"size":10}}}},{{"x":{},"y":1,"xref":"x","yref":"paper","text":"Nyquist limit","textangle":-90,"showarrow":false,"xanchor":"left","yanchor":"top","bgcolor":"rgba(255,255,255,0.85)","font":{{"size":10,"color":"#c2410c"}}}}]}})j",
        "XYZ"[axis], json_number(std::log10(nyquist)), json_number(std::log10(travel)), json_number(nyquist),
        json_number(nyquist), json_number(std::log10(period[peak])), json_number(amplitude[peak]),
        json_string(fmt::format("{:.4g} mm, {:.2f} µm", period[peak], amplitude[peak])),
        period[peak] > std::sqrt(nyquist * travel) ? -50 : 50, json_number(std::log10(nyquist)));
    f.caption = fmt::format(
        "{} positioning readings on {} line(s) along {}, sampled every {:g} mm: periods from the Nyquist limit "
        "{:g} mm to the travel {:g} mm. Each line's and approach's mean is taken out first.",
        rows.size(), lines, "XYZ"[axis], step, nyquist, travel);
    s.figures.push_back(std::move(f));
  }
  s.html = fmt::format(
      "<p>What the model {} leaves along each linear axis' laser lines (the positioning readings), as the amplitude "
      "of the best-fitting sinusoid against its period. A peak well above the rest is a periodic error the model "
      "lacks (a lead screw's pitch, a scale's). Periods shorter than two sampling steps are not shown: the "
      "readings cannot tell them from longer ones (aliasing).</p>\n",
      refitted ? "refitted" : "as it is");
  if (s.figures.empty()) s.html += "<p class=\"note\">No laser lines with enough readings along a linear axis.</p>\n";
  return s;
}

}  // namespace ccomp::report
