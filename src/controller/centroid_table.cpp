// Centroid's ballscrew ("laser") compensation table, version 3 of its format (CNC10 v2.61
// on; CNC10's cnc10x.tab, CNC11's and CNC12's cnc-x.tab):
//
//   CNC10 TAB FILE VERSION 3
//   AXIS X
//   UNITS MM
//   INTERVAL 25
//   ENTRIES 10
//   0<TAB>forward<TAB>reverse
//   -25<TAB>...
//
// One row a point from machine home (0) to the far end of the travel, every INTERVAL mm,
// the position then the correction applied travelling forward and travelling in reverse
// (docs/controller-tables.md: what the sources settle and what ccomp assumes).
#include <fmt/format.h>

#include <cmath>
#include <string>

#include "ccomp/controller/control_tables.hpp"
#include "ccomp/error.hpp"
#include "table_format.hpp"

namespace ccomp::controller {
namespace {

using format::points_of;
using format::rounded;
using format::step_of;
using format::written;

/// Decimals of a correction in mm: 10 nm, below any encoder a Centroid reads.
constexpr int kDecimals = 5;

void check_centroid(const AxisTable& t, const WriteOptions&) {
  if (t.rotary)
    throw Error(ErrorKind::usage, fmt::format("--control centroid: {} is a rotary axis; Centroid's ballscrew table is "
                                              "written for a linear axis only",
                                              t.axis));
  const double step = step_of(t);
  if (std::abs(step - std::round(step)) > 1e-9)
    throw Error(ErrorKind::usage, fmt::format("--step {:g}: Centroid's INTERVAL is written in whole mm; give a whole "
                                              "--step",
                                              step));
  if (t.positions.front() != 0.0 && t.positions.back() != 0.0)
    throw Error(ErrorKind::usage,
                fmt::format("--control centroid: the table of {} runs from {:g} to {:g} mm, but Centroid's starts at "
                            "machine home (0) and runs to one end: give --from 0 or --to 0",
                            t.axis, t.positions.front(), t.positions.back()));
}

std::string write_centroid(const AxisTable& t, const WriteOptions&) {
  const std::size_t n = points_of(t);
  std::string text = fmt::format("CNC10 TAB FILE VERSION 3\nAXIS {}\nUNITS MM\nINTERVAL {}\nENTRIES {}\n", t.axis,
                                 std::lround(step_of(t)), n);
  // From home (0) outwards: down the positions when the travel lies below 0.
  const bool downwards = t.positions.front() != 0.0;
  for (std::size_t j = 0; j < n; ++j) {
    const std::size_t k = downwards ? n - 1 - j : j;
    text += fmt::format("{}\t{:.{}f}\t{:.{}f}\n", std::lround(t.positions[k]), written(t.forward[k], kDecimals),
                        kDecimals, written(t.reverse[k], kDecimals), kDecimals);
  }
  return text;
}

AxisTable centroid_applies(const AxisTable& table, const WriteOptions&) {
  AxisTable applied = table;
  applied.forward = rounded(table.forward, kDecimals), applied.reverse = rounded(table.reverse, kDecimals);
  applied.cross.clear();
  return applied;
}

}  // namespace

extern const ControlTable kCentroidTable{"centroid", "Centroid CNC10/CNC11/CNC12 ballscrew table (cnc-x.tab)",
                                         // whole-mm INTERVAL; 256 points is ccomp's bound, not Centroid's
                                         {256, 1.0, false, true}, write_centroid, centroid_applies, check_centroid};

}  // namespace ccomp::controller
