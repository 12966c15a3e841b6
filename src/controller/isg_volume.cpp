#include "ccomp/controller/isg_volume.hpp"

#include <fmt/format.h>

#include <cmath>

namespace ccomp::controller {
namespace {

/// Errors to the nanometre: below what any axis resolves, and what isg_as_applied() keeps.
constexpr int kDecimals = 6;

double to_written(double v) {
  const double scale = std::pow(10.0, kDecimals);
  const double r = std::round(v * scale) / scale;
  return r == 0.0 ? 0.0 : r;  // no "-0.000000"
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
      "// {} x {} x {} nodes, X fastest; X Y Z in mm; EXX EYY EZZ: the tool tip's error relative to the\n"
      "// workpiece (mm, actual less nominal), 0 at X {:g} Y {:g} Z {:g}\n",
      table.positions[0].size(), table.positions[1].size(), table.positions[2].size(), table.reference[0],
      table.reference[1], table.reference[2]);
  csv += "X Y Z EXX EYY EZZ\n";
  for (std::size_t k = 0; k < table.positions[2].size(); ++k)
    for (std::size_t j = 0; j < table.positions[1].size(); ++j)
      for (std::size_t i = 0; i < table.positions[0].size(); ++i) {
        const Eigen::Vector3d& c = table.correction[table.index(i, j, k)];
        csv += fmt::format("{} {} {} {:.{}f} {:.{}f} {:.{}f}\n", table.positions[0][i], table.positions[1][j],
                           table.positions[2][k], to_written(-c[0]), kDecimals, to_written(-c[1]), kDecimals,
                           to_written(-c[2]), kDecimals);
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
