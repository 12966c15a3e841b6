// The registry of the controls' per-axis tables, and the checks every one of them gets
// before a value is printed.
#include "ccomp/controller/control_tables.hpp"

#include <fmt/format.h>

#include "ccomp/error.hpp"
#include "correction_bound.hpp"
#include "table_format.hpp"

namespace ccomp::controller {

// Each defined in its own file (src/controller/NAME_table.cpp).
extern const ControlTable kLinuxcncTable;
extern const ControlTable kFanucTable;
extern const ControlTable kSiemensTable;
extern const ControlTable kHeidenhainTable;
extern const ControlTable kCentroidTable;

namespace {

void check_fits(const ControlTable& control, const AxisTable& t) {
  if (format::points_of(t) > control.limits.max_points)
    throw Error(ErrorKind::usage, fmt::format("--control {}: {} points on {}, more than its table holds ({}): a larger "
                                              "--step",
                                              control.name, format::points_of(t), t.axis, control.limits.max_points));
}

/// No value that is not a number reaches a table (a NaN prints as -nan, and Fanuc's
/// rounding makes it P0).
void check_finite(const ControlTable& control, const AxisTable& t) {
  for (std::size_t k = 0; k < t.positions.size(); ++k) {
    const std::string where = fmt::format("{} {:g}", t.axis, t.positions[k]);
    check_written(t.positions[k], control.name, where);
    check_written(t.forward[k], control.name, where);
    check_written(t.reverse[k], control.name, where);
    for (const AxisTable::Cross& c : t.cross) check_written(c.correction[k], control.name, where);
  }
}

}  // namespace

const std::vector<const ControlTable*>& control_tables() {
  // The functions' statics, not namespace-scope copies: the descriptors live in other
  // files, whose initialisation order is not this one's.
  static const std::vector<const ControlTable*> tables{&kLinuxcncTable, &kFanucTable, &kSiemensTable,
                                                       &kHeidenhainTable, &kCentroidTable};
  return tables;
}

const ControlTable* control_named(std::string_view name) {
  for (const ControlTable* t : control_tables())
    if (t->name == name) return t;
  return nullptr;
}

std::string write_table(const ControlTable& control, const AxisTable& table, const WriteOptions& options) {
  check_fits(control, table);
  check_finite(control, table);
  if (control.check != nullptr) control.check(table, options);
  return control.write(table, options);
}

AxisTable as_control_applies(const ControlTable& control, const AxisTable& table, const WriteOptions& options) {
  return control.applies(table, options);
}

}  // namespace ccomp::controller
