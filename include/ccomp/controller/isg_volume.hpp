#pragma once
// A VolumeTable written for the Beckhoff TwinCAT CNC (ISG kernel) "Volumetric
// Compensation" (TF5280, #VOLCOMP): a configuration list naming the axes and the
// compensation file, and that file in ISG_CSV format: a complete grid of X, Y, Z with, at
// each node, what the control subtracts from the commanded X, Y, Z as the position
// parameters EXX, EYY, EZZ (mm; where an axis moves the tool along its own + direction,
// the tool tip's error along it, ISO 230-1's actual less nominal), interpolated linearly
// on the grid (interpolation GRID). docs/controller-tables.md gives the manual references.
#include <string>
#include <vector>

#include "ccomp/controller/volume_table.hpp"

namespace ccomp::controller {

struct IsgVolumeFiles {
  std::string list;  ///< the configuration list (*.lis)
  std::string csv;   ///< the compensation file
};

/// `csv_name`: how the list names the compensation file (as the control will find it);
/// `header`: provenance, written as // comments of the CSV. The axes' logical numbers
/// are X 1, Y 2, Z 3 (edit the list for another numbering).
[[nodiscard]] IsgVolumeFiles write_isg_volume(const VolumeTable& table, const std::string& csv_name,
                                              const std::vector<std::string>& header);

/// The table as the control reads it back from write_isg_volume()'s digits (1 nm).
[[nodiscard]] VolumeTable isg_as_applied(const VolumeTable& table);

}  // namespace ccomp::controller
