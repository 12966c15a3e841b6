// LinuxCNC's screw compensation file, [JOINT_n]COMP_FILE.
#include <fmt/format.h>

#include "ccomp/controller/control_tables.hpp"
#include "table_format.hpp"

namespace ccomp::controller {
namespace {

using format::written;
using format::points_of;
using format::rounded;

// --- LinuxCNC: [JOINT_n]COMP_FILE, read by usrmotLoadComp(): "nominal a b" triplets, one a
// line, ascending; reading stops at the first line that is not three numbers, so the file
// carries no comment. Type 0: a, b are where the joint really is travelling up and down
// (LinuxCNC adds nominal - a); type 1: a, b are the trims it adds.
std::string write_linuxcnc(const AxisTable& t, const WriteOptions& o) {
  std::string text;
  for (std::size_t k = 0; k < points_of(t); ++k) {
    const double p = t.positions[k];
    if (o.linuxcnc_file_type == 0)
      text += fmt::format("{:.6f} {:.6f} {:.6f}\n", written(p, 6), written(p - t.forward[k], 6),
                          written(p - t.reverse[k], 6));
    else
      text += fmt::format("{:.6f} {:.6f} {:.6f}\n", written(p, 6), written(t.forward[k], 6), written(t.reverse[k], 6));
  }
  return text;
}

AxisTable linuxcnc_applies(const AxisTable& table, const WriteOptions&) {
  AxisTable applied = table;
  applied.forward = rounded(table.forward, 6), applied.reverse = rounded(table.reverse, 6);
  applied.cross.clear();
  return applied;
}

}  // namespace

extern const ControlTable kLinuxcncTable{"linuxcnc", "LinuxCNC [JOINT_n]COMP_FILE",
                                         {256, 0.5, false},  // EMCMOT_COMP_SIZE; joint comp only
                                         write_linuxcnc, linuxcnc_applies, nullptr};

}  // namespace ccomp::controller
