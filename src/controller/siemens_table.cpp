// Siemens 840D sl's leadscrew (LEC) and sag/cross (CEC) tables, as one part program.
#include <fmt/format.h>

#include <cmath>
#include <string>
#include <vector>

#include "ccomp/controller/control_tables.hpp"
#include "table_format.hpp"

namespace ccomp::controller {
namespace {

using format::written;
using format::axis_number;
using format::points_of;
using format::rounded;
using format::step_of;

// --- Siemens 840D sl (K3, interpolatory compensation): the leadscrew table
// $AA_ENC_COMP holds the measuring system's error (a positive value moves the axis the
// negative way); sag/cross tables $AN_CEC hold the correction added to the output axis,
// one with $AN_CEC_DIRECTION -1 carrying what differs travelling down.
std::string siemens_cec(int index, const std::string& input, const std::string& output, const AxisTable& t,
                        const std::vector<double>& values, int direction) {
  std::string text;
  for (std::size_t k = 0; k < values.size(); ++k) text += fmt::format("$AN_CEC[{},{}]={:.6f}\n", index, k, written(values[k], 6));
  text += fmt::format(
      "$AN_CEC_INPUT_AXIS[{0}]={1}\n$AN_CEC_OUTPUT_AXIS[{0}]={2}\n$AN_CEC_STEP[{0}]={3:.4f}\n$AN_CEC_MIN[{0}]={4:."
      "4f}\n$AN_CEC_MAX[{0}]={5:.4f}\n$AN_CEC_DIRECTION[{0}]={6}\n$AN_CEC_MULT_BY_TABLE[{0}]=0\n$AN_CEC_IS_MODULO[{0}]="
      "{7}\n",
      index, input, output, step_of(t), t.positions.front(), t.positions.back(), direction, t.rotary ? 1 : 0);
  return text;
}

std::string write_siemens(const AxisTable& t, const WriteOptions& o) {
  const std::string ax = fmt::format("AX{}", axis_number(t, o));
  std::string text;
  for (const std::string& line : o.header) text += "; " + line + "\n";
  text += fmt::format(
      "; machine data: MD32700 $MA_ENC_COMP_ENABLE[0,{0}]=1, MD38000 $MA_MM_ENC_COMP_MAX_POINTS[0,{0}]>={1}", ax,
      points_of(t));
  text += ", MD32710 $MA_CEC_ENABLE[AXn]=1 on each output axis, MD18342 $MN_MM_CEC_MAX_POINTS[table]>=" +
          std::to_string(points_of(t)) + "\n; the other axes are AX1 AX2 AX3 for X Y Z\nCHANDATA(1)\n";
  // The leadscrew table: the error travelling up (0 at the reference point); a table that
  // acts travelling down only adds what differs then (position-dependent backlash).
  for (std::size_t k = 0; k < points_of(t); ++k)
    text += fmt::format("$AA_ENC_COMP[0,{},{}]={:.6f}\n", k, ax, written(-t.forward[k], 6));
  text += fmt::format(
      "$AA_ENC_COMP_STEP[0,{0}]={1:.4f}\n$AA_ENC_COMP_MIN[0,{0}]={2:.4f}\n$AA_ENC_COMP_MAX[0,{0}]={3:.4f}\n$AA_ENC_"
      "COMP_"
      "IS_MODULO[0,{0}]={4}\n",
      ax, step_of(t), t.positions.front(), t.positions.back(), t.rotary ? 1 : 0);
  int index = o.siemens_first_cec_table;
  if (t.bidirectional()) {
    std::vector<double> down(points_of(t));
    for (std::size_t k = 0; k < down.size(); ++k) down[k] = t.reverse[k] - t.forward[k];
    text += siemens_cec(index++, ax, ax, t, down, -1);
  }
  for (const AxisTable::Cross& c : t.cross)
    text += siemens_cec(index++, ax, fmt::format("AX{}", c.axis_index + 1), t, c.correction, 0);
  return text + "M17\n";
}

AxisTable siemens_applies(const AxisTable& table, const WriteOptions&) {
  AxisTable applied = table;
  applied.forward = rounded(table.forward, 6);
  for (std::size_t k = 0; k < table.forward.size(); ++k)
    applied.reverse[k] = applied.forward[k] + std::round((table.reverse[k] - table.forward[k]) * 1e6) / 1e6;
  for (AxisTable::Cross& c : applied.cross) c.correction = rounded(c.correction, 6);
  return applied;
}

}  // namespace

extern const ControlTable kSiemensTable{"siemens", "Siemens 840D sl LEC and CEC tables",
                                        {1000, 0.5, true},  // MD38000 / MD18342 are the machine's; 1000 is common
                                        write_siemens, siemens_applies, nullptr};

}  // namespace ccomp::controller
