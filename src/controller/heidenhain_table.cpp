// Heidenhain TNC's compensation-value table (*.COM).
#include <fmt/format.h>

#include <string>

#include "ccomp/controller/control_tables.hpp"
#include "table_format.hpp"

namespace ccomp::controller {
namespace {

using format::written;
using format::points_of;
using format::rounded;

// --- Heidenhain TNC: a compensation-value table (*.COM) for the axis' dependences: AXISPOS
// the axis' positions from the machine datum, a column per axis compensated (the axis
// itself: its pitch, the others: their straightness), BACKLASH the axis' own values for
// travel the negative way. Entered in the *.CMA assignment table's column of this axis.
std::string write_heidenhain(const AxisTable& t, const WriteOptions&) {
  std::string text = fmt::format("BEGIN {}.COM MM\n{:<6}{:<14}{:<14}", t.axis, "NR", "AXISPOS", std::string(1, t.axis));
  for (const AxisTable::Cross& c : t.cross) text += fmt::format("{:<14}", std::string(1, c.axis));
  text += "BACKLASH\n";
  for (std::size_t k = 0; k < points_of(t); ++k) {
    text += fmt::format("{:<6}{:<+14.4f}{:<+14.5f}", k, written(t.positions[k], 4), written(t.forward[k], 5));
    for (const AxisTable::Cross& c : t.cross) text += fmt::format("{:<+14.5f}", written(c.correction[k], 5));
    text += fmt::format("{:+.5f}\n", written(t.reverse[k], 5));
  }
  return text + "[END]\n";
}

AxisTable heidenhain_applies(const AxisTable& table, const WriteOptions&) {
  AxisTable applied = table;
  applied.forward = rounded(table.forward, 5), applied.reverse = rounded(table.reverse, 5);
  for (AxisTable::Cross& c : applied.cross) c.correction = rounded(c.correction, 5);
  return applied;
}

}  // namespace

extern const ControlTable kHeidenhainTable{"heidenhain", "Heidenhain TNC *.COM compensation-value table",
                                           {256, 0.5, true},  // entries of one *.COM
                                           write_heidenhain, heidenhain_applies, nullptr};

}  // namespace ccomp::controller
