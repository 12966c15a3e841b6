#pragma once
// The report's pieces: plots as plotly.js figures (data and layout as JSON, one div each),
// grouped in sections, and the small JSON and HTML helpers they are written with.
#include <string>
#include <string_view>
#include <vector>

#include "ccomp/report/html_report.hpp"

namespace ccomp::report {

/// One plot: plotly's `data` (a JSON array of traces) and `layout` (a JSON object); the
/// page's script adds the common style (gridlines, ticks, zero lines, fonts).
struct Figure {
  std::string id;       ///< the div's id, unique in the page
  std::string traces;   ///< JSON array
  std::string layout;   ///< JSON object
  std::string caption;  ///< HTML under the plot
  bool wide = false;    ///< takes the page's width (else half)
  int height = 330;     ///< px
};

/// A section of the page: a heading, HTML (text and tables), then its figures.
struct Section {
  std::string id, title;
  std::string html;
  std::vector<Figure> figures;
  std::string beside;  ///< HTML in a half-width column before the figures (a table next to its plot)
};

// JSON
[[nodiscard]] std::string json_string(std::string_view text);  ///< quoted; "</" written "<\/"
[[nodiscard]] std::string json_number(double v);               ///< NaN, inf: null
[[nodiscard]] std::string json_numbers(const std::vector<double>& v);
[[nodiscard]] std::string json_strings(const std::vector<std::string>& v);
/// A plotly trace of x, y points: `mode` "markers", "lines" or "lines+markers"; `style` more
/// of the trace's JSON members ("marker":{...},"line":{...}), without braces.
[[nodiscard]] std::string xy_trace(std::string_view name, const std::vector<double>& x, const std::vector<double>& y,
                                   std::string_view mode, std::string_view style);
// HTML
[[nodiscard]] std::string html_escape(std::string_view text);

/// Micrometres per internal length unit (mm): the report's deviations are in um.
inline constexpr double kUm = 1e3;

/// Unique ids for the figures of one page.
class FigureIds {
 public:
  std::string next(std::string_view stem);

 private:
  int count_ = 0;
};

// The sections, each in its own file.
[[nodiscard]] Section summary_section(const CheckReportInput& in, FigureIds& ids);
[[nodiscard]] Section provenance_section(const CheckReportInput& in);
/// Laser lines, grids, rotary sources: one plot per source and reading direction, and
/// ISO 230-2's figures for the positioning lines.
[[nodiscard]] std::vector<Section> source_sections(const CheckReportInput& in, FigureIds& ids);
/// Volumetric error maps (before and after compensation) and the terms' shares.
[[nodiscard]] std::vector<Section> model_sections(const CheckReportInput& in, FigureIds& ids);
[[nodiscard]] Section spectrum_section(const CheckReportInput& in, FigureIds& ids);
[[nodiscard]] Section effects_section(const CheckReportInput& in, FigureIds& ids);
/// Each missing effect on the line that sees it best: the residual before and after adding it.
[[nodiscard]] std::vector<Figure> effect_figures(const CheckReportInput& in, FigureIds& ids);
[[nodiscard]] Section parameters_section(const CheckReportInput& in, FigureIds& ids);

}  // namespace ccomp::report
