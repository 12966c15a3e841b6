// The model over the workspace: volumetric error maps before and after compensation, and
// each term's share of the error. "Before": the machine's error as the model refitted to
// these data describes it, uncompensated. "After": what compensating with the model checked
// leaves of it (to first order, the refitted model's error minus the checked model's): where
// the model checked is out of date. docs/report.md says why.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "ccomp/identify/fit.hpp"
#include "ccomp/model/forward.hpp"
#include "ccomp/model/term_forms.hpp"
#include "ccomp/util/interval.hpp"
#include "report/figures.hpp"
#include "report/source_shape.hpp"

namespace ccomp::report {
namespace {

/// Evaluates a model's deviation at program points under given parameters.
class ErrorProbe {
 public:
  explicit ErrorProbe(const model::ForwardModel& model) : model_(model), data_(model) {
    conditions_.temperatures.assign(model.machine().sensors.size(), 20.0);
  }
  /// mm, machine directions: the axes X Y Z at machine positions (mm; what the maps' axes
  /// and the model's terms read), a rotary axis' angle (deg), tool length L.
  Eigen::Vector3d at(const Eigen::VectorXd& parameters, const std::array<double, 3>& xyz, std::size_t rotary,
                     double angle, double tool, double approach) {
    data_.set_parameters(parameters);
    model::ChainQ q = model::ChainQ::Zero();
    q[0] = xyz[0], q[1] = xyz[1], q[2] = xyz[2];
    if (rotary < 9) q[static_cast<Eigen::Index>(rotary)] = angle * std::numbers::pi / 180.0;
    q[static_cast<Eigen::Index>(model::kToolLengthIndex)] = tool;
    conditions_.directions.fill(approach);
    model::forward(model_, data_, q, conditions_);
    return model::deviation(data_);
  }

 private:
  const model::ForwardModel& model_;
  model::ForwardData data_;
  model::Conditions conditions_;
};

struct Workspace {
  std::array<double, 3> lo{}, hi{};
  std::size_t rotary = 9;  ///< the first rotary axis, 9: none
  double tool = 0.0;       ///< mm: the tool length most readings have
};

Workspace workspace(const CheckReportInput& in) {
  Workspace w;
  for (std::size_t k = 0; k < 3; ++k) {
    util::Interval data;
    for (const identify::Observation& o : in.data.observations) data.add(axis_value(o, k));
    const model::AxisSpec* a = in.model.axis(axis_letter(k));
    const bool limited = a != nullptr && std::isfinite(a->min) && std::isfinite(a->max) && a->max > a->min;
    w.lo[k] = limited ? a->min : data.empty() ? -100.0 : data.lo;
    w.hi[k] = limited ? a->max : data.empty() ? 100.0 : data.hi;
    if (!(w.hi[k] > w.lo[k])) w.lo[k] -= 100, w.hi[k] += 100;
  }
  for (const model::AxisSpec& a : in.model.axes)
    if (a.type == model::AxisType::rotary && w.rotary == 9)
      w.rotary = static_cast<std::size_t>(a.index());
  std::vector<double> tools;
  for (const identify::Observation& o : in.data.observations)
    tools.push_back(o.q[static_cast<Eigen::Index>(model::kToolLengthIndex)]);
  if (!tools.empty()) {
    std::nth_element(tools.begin(), tools.begin() + static_cast<long>(tools.size() / 2), tools.end());
    w.tool = tools[tools.size() / 2];
  }
  return w;
}

/// The term's parameters that scale its error (zeroing them removes the term); a period,
/// a time constant, a bump's place and width only shape it.
bool scales_error(const model::ErrorTermSpec& t, std::size_t k) {
  return !model::term_form(t.shape.form).shapes_only(k);
}

std::string term_label(const model::ErrorTermSpec& t) { return model::term_form(t.shape.form).term_label(t); }

double largest(const std::vector<std::vector<double>>& z) {
  double top = 0;
  for (const std::vector<double>& row : z)
    for (double value : row) top = std::max(top, value);
  return top;
}

/// A map of |e| over a plane, coloured from 0 to `top` (um): a before and after pair share it.
Figure map_figure(const std::string& id, const std::string& title, const std::vector<double>& u,
                  const std::vector<double>& v, const std::vector<std::vector<double>>& z, char u_axis, char v_axis,
                  const std::string& colour_title, double top) {
  std::string rows = "[";
  for (std::size_t j = 0; j < z.size(); ++j) {
    if (j > 0) rows += ',';
    rows += json_numbers(z[j]);
  }
  rows += "]";
  Figure f;
  f.id = id;
  f.traces = fmt::format(
      R"j([{{"type":"contour","x":{},"y":{},"z":{},"colorscale":"Viridis","zmin":0,"zmax":{},"ncontours":12,"contours":{{"coloring":"heatmap","showlabels":true,"labelfont":{{"size":9,"color":"#fff"}}}},"line":{{"width":0.5,"color":"rgba(255,255,255,0.6)"}},"colorbar":{{"title":{{"text":{},"side":"right"}},"ticks":"outside","thickness":14,"len":0.9}},"hovertemplate":"{} %{{x:.0f}} mm<br>{} %{{y:.0f}} mm<br>%{{z:.2f}} µm<extra></extra>"}}])j",
      json_numbers(u), json_numbers(v), rows, json_number(top), json_string(colour_title), u_axis, v_axis);
  f.layout = fmt::format(
      R"j({{"title":{{"text":{}}},"xaxis":{{"title":{{"text":"{} axis position, machine (mm)"}},"constrain":"domain"}},"yaxis":{{"title":{{"text":"{} axis position, machine (mm)"}},"scaleanchor":"x","constrain":"domain"}},"margin":{{"r":10}}}})j",
      json_string(title), u_axis, v_axis);
  f.height = 380;
  return f;
}

}  // namespace

std::vector<Section> model_sections(const CheckReportInput& in, FigureIds& ids) {
  const model::ForwardModel forward(in.model);
  const Eigen::VectorXd checked = identify::model_parameters(forward);
  const bool refitted = in.diagnosis.refit.all_parameters.size() == checked.size();
  const Eigen::VectorXd& machine = refitted ? in.diagnosis.refit.all_parameters : checked;
  const Workspace w = workspace(in);
  ErrorProbe probe(forward);

  Section maps{"maps", "Volumetric error maps", "", {}, ""};
  maps.html = fmt::format(
      "<p>The length of the volumetric error vector |e| (&micro;m) over three mid-planes of the workspace, at "
      "{}{} and tool length L {:g} mm, 20 &deg;C, approach unknown (reversals at mid-play). <b>Before "
      "compensation</b>: the machine's error as the model refitted to these data describes it, with no compensation. "
      "<b>After compensation</b>: what compensating with the model checked (<code>{}</code>) would leave of that "
      "error, to first order the refitted model's error minus the checked model's; it shows where the model "
      "checked is out of date{}. Errors the model cannot describe at all are not in either map: they are the "
      "residual (the summary's rms refitted). A plane's before and after maps share one colour scale (a colour is "
      "the same error in both), reaching at least the noise floor. Positions are the machine's axis positions "
      "(G53, as the control shows them and the model's terms read them), the planes through each axis' travel.</p>\n",
      w.rotary < 9 ? fmt::format("{} 0&deg;", axis_letter(w.rotary)) : "", w.rotary < 9 ? "" : "no rotary axis", w.tool,
      html_escape(in.model.path.empty() ? in.model.name : in.model.path),
      in.command == "fit" ? " (for a model just fitted to the same data, close to zero)" : "");
  constexpr int kCells = 41;
  const std::array<std::array<std::size_t, 3>, 3> planes = {{{0, 1, 2}, {0, 2, 1}, {1, 2, 0}}};  // u, v, fixed
  for (const auto& [a, b, fixed] : planes) {
    std::vector<double> u, v;
    for (int i = 0; i < kCells; ++i) {
      u.push_back(w.lo[a] + (w.hi[a] - w.lo[a]) * i / (kCells - 1));
      v.push_back(w.lo[b] + (w.hi[b] - w.lo[b]) * i / (kCells - 1));
    }
    const double middle = w.lo[fixed] <= 0 && w.hi[fixed] >= 0 ? 0.0 : (w.lo[fixed] + w.hi[fixed]) / 2;
    std::vector<std::vector<double>> before(kCells, std::vector<double>(kCells)), after = before;
    for (int j = 0; j < kCells; ++j)
      for (int i = 0; i < kCells; ++i) {
        std::array<double, 3> p{};
        p[a] = u[static_cast<std::size_t>(i)], p[b] = v[static_cast<std::size_t>(j)], p[fixed] = middle;
        const Eigen::Vector3d e = probe.at(machine, p, w.rotary, 0.0, w.tool, 0.0);
        const Eigen::Vector3d left = e - probe.at(checked, p, w.rotary, 0.0, w.tool, 0.0);
        before[static_cast<std::size_t>(j)][static_cast<std::size_t>(i)] = e.norm() * kUm;
        after[static_cast<std::size_t>(j)][static_cast<std::size_t>(i)] = left.norm() * kUm;
      }
    const std::string plane =
        fmt::format("{}{} plane at {} axis position {:g} mm", axis_letter(a), axis_letter(b), axis_letter(fixed), middle);
    // One colour scale for the pair, so that the same colour is the same error in both: the
    // larger map's top, at least the noise floor (an after map near zero shows dark, not as
    // magnified noise).
    const double top = std::max({largest(before), largest(after), in.check.noise_floor * kUm, 1e-3});
    maps.figures.push_back(map_figure(ids.next("map"), fmt::format("Before compensation: {}", plane), u, v, before,
                                      axis_letter(a), axis_letter(b), "|e| before (µm)", top));
    maps.figures.push_back(map_figure(ids.next("map"), fmt::format("After compensation: {}", plane), u, v, after,
                                      axis_letter(a), axis_letter(b), "|e| after (µm)", top));
  }

  // Shares: each term's error alone (the model with the term's amplitudes zeroed, subtracted
  // from the whole), rms over a 9x9x9 grid, rotary angles 0 90 180 270, both approaches.
  Section shares{"shares", "Effect shares", "", {}, ""};
  std::vector<Eigen::VectorXd> without;
  for (std::size_t t = 0; t < in.model.terms.size(); ++t) {
    Eigen::VectorXd p = machine;
    for (std::size_t k = 0; k < static_cast<std::size_t>(in.model.terms[t].parameters.size()); ++k)
      if (scales_error(in.model.terms[t], k)) p[static_cast<Eigen::Index>(forward.parameter_offset(t) + k)] = 0.0;
    without.push_back(std::move(p));
  }
  std::vector<double> sum(in.model.terms.size(), 0.0);
  double total = 0.0;
  std::size_t points = 0;
  constexpr int kSteps = 9;
  const std::vector<double> angles = w.rotary < 9 ? std::vector<double>{0, 90, 180, 270} : std::vector<double>{0};
  for (int i = 0; i < kSteps; ++i)
    for (int j = 0; j < kSteps; ++j)
      for (int k = 0; k < kSteps; ++k)
        for (double angle : angles)
          for (double approach : {1.0, -1.0}) {
            const std::array<int, 3> step{i, j, k};
            std::array<double, 3> p{};
            for (std::size_t c = 0; c < 3; ++c) p[c] = w.lo[c] + (w.hi[c] - w.lo[c]) * step[c] / (kSteps - 1);
            const Eigen::Vector3d e = probe.at(machine, p, w.rotary, angle, w.tool, approach);
            total += e.squaredNorm();
            for (std::size_t t = 0; t < without.size(); ++t)
              sum[t] += (e - probe.at(without[t], p, w.rotary, angle, w.tool, approach)).squaredNorm();
            ++points;
          }
  std::vector<std::size_t> order(sum.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return sum[x] > sum[y]; });
  const double all = std::accumulate(sum.begin(), sum.end(), 0.0);
  std::vector<double> bars;
  std::vector<std::string> names, labels;
  constexpr std::size_t kShown = 16;
  double others = 0;
  for (std::size_t r = 0; r < order.size(); ++r) {
    const double rms = std::sqrt(sum[order[r]] / static_cast<double>(points)) * kUm;
    if (r < kShown) {
      bars.push_back(rms), names.push_back(term_label(in.model.terms[order[r]]));
      labels.push_back(fmt::format("{:.1f}%", all > 0 ? 100 * sum[order[r]] / all : 0.0));
    } else {
      others += sum[order[r]];
    }
  }
  if (others > 0) {
    bars.push_back(std::sqrt(others / static_cast<double>(points)) * kUm);
    names.push_back(fmt::format("{} other terms", order.size() - kShown));
    labels.push_back(fmt::format("{:.1f}%", 100 * others / all));
  }
  // Largest at the top: plotly draws a horizontal bar chart's categories from the bottom.
  std::reverse(bars.begin(), bars.end()), std::reverse(names.begin(), names.end()),
      std::reverse(labels.begin(), labels.end());
  shares.html = fmt::format(
      "<p>Which terms make the machine's error (the model refitted), over a {}&times;{}&times;{} grid of the "
      "workspace{}, both approach directions, tool length {:g} mm: each term's error alone as an rms over the points "
      "(bar, &micro;m), and its share of the sum of the terms' mean squares (label). The whole error's rms is "
      "{:.2f} &micro;m. Shares add up to 100% where the terms' errors are uncorrelated; two terms that cancel "
      "each other (a tilt and an offset) both show large.</p>\n",
      kSteps, kSteps, kSteps,
      w.rotary < 9 ? fmt::format(", {} at 0, 90, 180 and 270&deg;", axis_letter(w.rotary)) : std::string(), w.tool,
      std::sqrt(total / static_cast<double>(std::max<std::size_t>(points, 1))) * kUm);
  if (!bars.empty()) {
    Figure f;
    f.id = ids.next("shares");
    f.wide = true;
    f.height = 120 + 22 * static_cast<int>(bars.size());
    f.traces = fmt::format(
        R"([{{"type":"bar","orientation":"h","name":"rms of the term's error","x":{},"y":{},"text":{},"textposition":"outside","marker":{{"color":"#1f5fa8"}},"hovertemplate":"%{{y}}: %{{x:.2f}} µm rms (%{{text}})<extra></extra>"}}])",
        json_numbers(bars), json_strings(names), json_strings(labels));
    f.layout =
        R"j({"title":{"text":"Each term's error over the workspace"},"showlegend":false,"xaxis":{"title":{"text":"rms of the term's error alone (µm)"},"rangemode":"tozero"},"yaxis":{"automargin":true,"showgrid":false},"margin":{"l":140}})j";
    shares.figures.push_back(std::move(f));
  }
  return {std::move(maps), std::move(shares)};
}

}  // namespace ccomp::report
