#include "ccomp/controller/isg_volume.hpp"

#include <fmt/format.h>

#include <cmath>

#include "correction_bound.hpp"

namespace ccomp::controller {
namespace {

/// Errors to the nanometre: below what any axis resolves, and what isg_as_applied() keeps.
constexpr int kDecimals = 6;

double to_written(double v) {
  const double scale = std::pow(10.0, kDecimals);
  const double r = std::round(v * scale) / scale;
  return r == 0.0 ? 0.0 : r;  // no "-0.000000"
}

/// A node's position to the nanometre, without trailing zeros: "-500", "0.3", "12.25".
std::string position(double p) {
  std::string text = fmt::format("{:.6f}", p);
  text.erase(text.find_last_not_of('0') + 1);
  if (text.back() == '.') text.pop_back();
  return text == "-0" ? "0" : text;
}

}  // namespace

IsgVolumeFiles write_isg_volume(const VolumeTable& table, const std::string& csv_name,
                                const std::vector<std::string>& header) {
  IsgVolumeFiles files;
  // No kinematic chain beyond X, Y and Z and no workpiece axes: the parameters are the
  // tool tip's error itself, which no chain order or side changes.
  files.list = fmt::format(
      "workpiece_axes           0\n"
      "X                        1\n"
      "Y                        2\n"
      "Z                        3\n"
      "interpolation            GRID\n"
      "file[0]                  {}\n"
      "file_format[0]           ISG_CSV\n",
      csv_name);
  std::string& csv = files.csv;
  for (const std::string& line : header) csv += "// " + line + "\n";
  csv += fmt::format(
      "// {} x {} x {} nodes, X fastest; X Y Z in mm; EXX EYY EZZ (mm): what the control subtracts from\n"
      "// the commanded X, Y, Z, the negative of the correction: where an axis moves the tool along its\n"
      "// own + direction (ISO 841), the tool tip's error along it (ISO 230-1: actual less nominal).\n"
      "// 0 at X {} Y {} Z {}\n",
      table.positions[0].size(), table.positions[1].size(), table.positions[2].size(), position(table.reference[0]),
      position(table.reference[1]), position(table.reference[2]));
  csv += "X Y Z EXX EYY EZZ\n";
  for (std::size_t k = 0; k < table.positions[2].size(); ++k)
    for (std::size_t j = 0; j < table.positions[1].size(); ++j)
      for (std::size_t i = 0; i < table.positions[0].size(); ++i) {
        const Eigen::Vector3d& c = table.correction[table.index(i, j, k)];
        for (Eigen::Index a = 0; a < 3 && !c.allFinite(); ++a)
          check_written(c[a], "isg",
                        fmt::format("X {} Y {} Z {}", position(table.positions[0][i]), position(table.positions[1][j]),
                                    position(table.positions[2][k])));
        csv += fmt::format("{} {} {} {:.{}f} {:.{}f} {:.{}f}\n", position(table.positions[0][i]),
                           position(table.positions[1][j]), position(table.positions[2][k]), to_written(-c[0]),
                           kDecimals, to_written(-c[1]), kDecimals, to_written(-c[2]), kDecimals);
      }
  return files;
}

VolumeTable isg_as_applied(const VolumeTable& table) {
  VolumeTable applied = table;
  for (Eigen::Vector3d& c : applied.correction)
    for (Eigen::Index a = 0; a < 3; ++a) c[a] = -to_written(-c[a]);
  return applied;
}

}  // namespace ccomp::controller
