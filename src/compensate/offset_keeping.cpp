#include "offset_keeping.hpp"

#include <fmt/format.h>

#include <cmath>
#include <optional>

#include "ccomp/error.hpp"
#include "ccomp/compensate/machine_coordinates.hpp"
#include "number_style.hpp"

namespace ccomp::compensate {
namespace {

std::optional<double> literal_of(const gcode::Block& b, char letter) {
  const gcode::Word* w = b.find(letter);
  if (!w || !w->value.is_literal()) return std::nullopt;
  return w->value.literal;
}

bool has_g(const gcode::Block& b, double code) {
  for (const gcode::Word& w : b.words)
    if (w.letter == 'G' && w.value.is_literal() && w.value.literal == code) return true;
  return false;
}

/// G10's L, NaN when it is not a number as written (then what it is shows only as it runs).
double g10_l(const gcode::Block& b) {
  return literal_of(b, 'L').value_or(std::nan(""));
}

/// The block's units: its own G20/G21, else those of the original's last motion.
gcode::Units units_of(const gcode::Block& b, gcode::Units last) {
  gcode::Units units = last;
  for (const gcode::Word& w : b.words)
    if (w.letter == 'G' && w.value.is_literal() && (w.value.literal == 20 || w.value.literal == 21))
      units = w.value.literal == 20 ? gcode::Units::inch : gcode::Units::mm;
  return units;
}

/// Where the machine is beyond where the original has it, per axis in program units.
struct PositionOff {
  gcode::Axes off{};
  bool any = false, xy = false;
};

PositionOff position_off(const OffsetContext& at, double unit) {
  const gcode::Offsets& o = at.offsets;
  const gcode::Axes written = program_of(chain_of(at.written.commanded, o), o, unit),
                    nominal = program_of(chain_of(at.nominal_end, o), o, unit);
  PositionOff p;
  for (std::size_t i = 0; i < gcode::kAxisCount; ++i) {
    p.off[i] = written[i] + at.written.rounding[i] - nominal[i];
    const bool moved = std::abs(p.off[i]) * (gcode::is_rotary(i) ? 1.0 : unit) > 1e-7;  // mm or deg
    p.any = p.any || moved;
    p.xy = p.xy || (moved && i < 2);
  }
  return p;
}

/// Refuses what no edit of the block's words can keep the original's.
void refuse_what_cannot_be_kept(const gcode::Block& b, const OffsetContext& at, const PositionOff& p, double unit) {
  const bool g92 = has_g(b, 92), g10 = has_g(b, 10);
  const double l = g10 ? g10_l(b) : std::nan("");
  const std::string what = g92 ? "G92" : std::isnan(l) ? "G10" : fmt::format("G10 L{:g}", l);
  auto refuse = [&](const std::string& why) {
    const double most = std::max(std::abs(p.off[0]), std::max(std::abs(p.off[1]), std::abs(p.off[2])));
    throw Error(ErrorKind::unsupported,
                fmt::format("{} sets an offset from where the machine is, which the compensation has moved by up to "
                            "{:.2f} um here; {}",
                            what, 1000.0 * unit * most, why),
                SourceLocation{std::string(at.file), b.line, 0}, std::string(b.text));
  };
  if (at.runs_again) refuse("its line runs more than once or is in another file: --flatten writes it once per run");
  if (g10 && std::isnan(l)) refuse("its L, an expression, shows what it sets only as the program runs");
  if (g10 && l == 11 && p.xy)
    refuse(
        "L11 counts in G59.3's frame, whose rotation would couple X and Y; give it before the first "
        "compensated move");
  if (g10 && l == 20) {  // a rotation couples X and Y, known here only for the system in force
    const std::optional<double> system = literal_of(b, 'P');
    const bool system_in_force = system && (*system == 0 || *system == at.offsets.coordinate_system);
    if (p.xy && (b.find('R') || !system_in_force))
      refuse(
          "with a rotation (R) or another coordinate system than the one in force, its X and Y cannot be "
          "rewritten to match; give it before the first compensated move");
  }
}

}  // namespace

bool sets_offset_from_position(const gcode::Block& b) {
  if (has_g(b, 92)) return true;
  if (!has_g(b, 10)) return false;
  const double l = g10_l(b);
  return std::isnan(l) || l == 20 || l == 10 || l == 11;
}

std::vector<gcode::Edit> offset_keeping_edits(const gcode::Block& b, const OffsetContext& at) {
  const bool inch = units_of(b, at.units) == gcode::Units::inch;
  const double unit = mm_per_unit(inch ? gcode::Units::inch : gcode::Units::mm);
  const PositionOff p = position_off(at, unit);
  if (!p.any) return {};
  refuse_what_cannot_be_kept(b, at, p, unit);
  std::vector<gcode::Edit> edits;
  for (const gcode::Word& w : b.words) {
    const auto axis = gcode::axis_index(w.letter);
    if (!axis || !w.has_value || std::abs(p.off[*axis]) == 0.0) continue;  // (a lone letter is ignored)
    const bool rotary = gcode::is_rotary(*axis);
    const std::string_view text = b.slice(w.value_span);
    const NumberStyle style = style_of(text, inch && !rotary, rotary, at.decimals.for_axis(rotary));
    if (w.value.is_literal()) {
      edits.push_back(gcode::Edit{w.value_span, format_value(w.value.literal + p.off[*axis], style).text});
    } else {  // an expression, a parameter: the same, moved
      const std::string by = format_value(std::abs(p.off[*axis]), style).text;
      edits.push_back(gcode::Edit{w.value_span, fmt::format("[{} {} {}]", text, p.off[*axis] < 0 ? '-' : '+', by)});
    }
  }
  return edits;
}

}  // namespace ccomp::compensate
