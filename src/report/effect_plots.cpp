// Each missing effect on a line that sees it: the refitted residual against the effect's
// axis, and what is left with the effect added, up and down runs apart (a reversal shows
// as the two collapsing onto each other, a screw's error as its wave going).
#include <fmt/format.h>

#include <algorithm>
#include <optional>

#include "report/figures.hpp"
#include "report/source_shape.hpp"

namespace ccomp::report {
namespace {

constexpr std::string_view kUp = "#1f5fa8", kDown = "#c2410c", kUnknown = "#555555";

/// The axis an effect varies with ("x", "x,T_bed" and an approach "vy" give x, y); 9: none.
std::size_t effect_axis(const std::string& variable) {
  std::string name = variable.substr(0, variable.find(','));
  if (name.size() == 2 && name[0] == 'v') name.erase(0, 1);
  if (name.size() != 1) return 9;
  const std::size_t axis = std::string_view("xyzabcuvw").find(name[0]);
  return axis == std::string_view::npos ? 9 : axis;
}

}  // namespace

std::vector<Figure> effect_figures(const CheckReportInput& in, FigureIds& ids) {
  std::vector<Figure> out;
  const auto n = static_cast<Eigen::Index>(in.data.observations.size());
  if (in.diagnosis.residual.size() != n) return out;
  const std::vector<SourceShape> shapes = source_shapes(in.data, in.model);
  for (const identify::Suggestion& g : in.diagnosis.suggestions) {
    const std::size_t axis = effect_axis(g.variable);
    if (axis > 8 || g.residual.size() != n) continue;
    // The direction the term's error is in (E<direction><axis>), where it is a translation.
    const int direction = g.term.size() >= 2 && g.term[1] >= 'X' && g.term[1] <= 'Z' ? g.term[1] - 'X' : -1;
    // The line (or rotary source) moving the effect's axis with the most readings along it.
    struct Candidate {
      ReadingDirection read;
      std::string source;
    };
    std::optional<Candidate> chosen;
    for (std::size_t k = 0; k < shapes.size(); ++k) {
      if (shapes[k].kind == SourceKind::volumetric || shapes[k].axis != axis) continue;
      for (ReadingDirection& read : reading_directions(in.data, shapes[k].readings))
        if ((direction < 0 || read.axis == direction) &&
            (!chosen || read.readings.size() > chosen->read.readings.size()))
          chosen = Candidate{std::move(read), in.data.sources[k]};
    }
    if (!chosen) continue;
    const ReadingDirection* best = &chosen->read;
    const std::string& along = best->label;
    const std::string& source = chosen->source;
    std::string traces;
    for (int way : {1, -1, 0}) {
      std::vector<std::pair<double, std::pair<double, double>>> points;
      for (std::size_t k = 0; k < best->readings.size(); ++k) {
        const std::size_t i = best->readings[k];
        const identify::Observation& o = in.data.observations[i];
        const int approach = o.directions[axis] > 0 ? 1 : o.directions[axis] < 0 ? -1 : 0;
        if (approach != way) continue;
        points.emplace_back(axis_value(o, axis),
                            std::pair{best->sign[k] * in.diagnosis.residual[static_cast<Eigen::Index>(i)] * kUm,
                                      best->sign[k] * g.residual[static_cast<Eigen::Index>(i)] * kUm});
      }
      if (points.empty()) continue;
      std::sort(points.begin(), points.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
      std::vector<double> x, before, after;
      for (const auto& [p, r] : points) x.push_back(p), before.push_back(r.first), after.push_back(r.second);
      const std::string_view colour = way > 0 ? kUp : way < 0 ? kDown : kUnknown;
      const std::string name = way > 0 ? "up" : way < 0 ? "down" : "approach unknown";
      if (!traces.empty()) traces += ",";
      traces +=
          xy_trace("refitted residual, " + name, x, before, "markers",
                   fmt::format(R"("marker":{{"color":"{}","size":5,"symbol":"circle-open","opacity":0.6}})", colour));
      traces += ",";
      traces += xy_trace("with the effect added, " + name, x, after, "markers",
                         fmt::format(R"("marker":{{"color":"{}","size":4}})", colour));
    }
    Figure f;
    f.id = ids.next("effect");
    f.traces = fmt::format("[{}]", traces);
    f.layout = fmt::format(
        R"j({{"title":{{"text":{}}},"xaxis":{{"title":{{"text":{}}}}},"yaxis":{{"title":{{"text":"residual along {} (µm)"}}}}}})j",
        json_string(fmt::format("{}. {} {} on {}", g.rank, g.term, g.form, source)),
        json_string(position_title(axis)), along);
    f.caption = fmt::format(
        "{}. {}: on {} (readings along {}), what the refitted model leaves (open) and what is left with the effect "
        "added (filled). Over all readings: rms {:.3f} &rarr; {:.3f} &micro;m. {} A place the suggestion names "
        "(<code>at:</code>, a period's phase) is in these axis positions.",
        g.rank, html_escape(g.effect), html_escape(source), html_escape(along), g.rms_before * kUm, g.rms_after * kUm,
        frame_note(in.data, best->readings.front()));
    f.height = 340;
    out.push_back(std::move(f));
  }
  return out;
}

}  // namespace ccomp::report
