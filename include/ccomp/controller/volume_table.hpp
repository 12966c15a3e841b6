#pragma once
// A volumetric table: the correction of X, Y and Z at the nodes of a grid over their
// travel, for controls that interpolate such a grid trilinearly between the eight nodes of
// its cell. It carries what no table along one line can: the angular errors' effect through
// lever arms that change over the workspace, squareness, and straightness, together. It
// holds for one tool length, one position of the rotary axes and one thermal state (the
// export's); between its nodes it is linear, so features shorter than a few steps (a lead
// screw's periodic error) it carries only in part: volume_residual() measures what is left.
//
// Like the axis tables, every correction is relative to the reference node's, where the
// work offset takes the machine's error.
#include <array>
#include <cstddef>
#include <vector>

#include "ccomp/controller/axis_table.hpp"
#include "ccomp/model/forward.hpp"

namespace ccomp::controller {

/// Where the grid lies and what the machine is doing meanwhile.
struct VolumeOptions {
  std::array<Grid, 3> grids;                            ///< X, Y, Z: span and step (mm)
  Eigen::Vector3d reference = Eigen::Vector3d::Zero();  ///< mm: a node, where every correction is 0
  /// The rotary axes (rad) and the tool length (mm, index model::kToolLengthIndex); X, Y
  /// and Z are ignored.
  model::ChainQ line = model::ChainQ::Zero();
  model::Conditions conditions;  ///< time and temperatures; the axes travel both ways (the mean)
  /// Harmonics of periodic terms sampled as 0: a period shorter than a few steps would
  /// alias into the nodes and, interpolated, err by up to twice its amplitude; left out,
  /// by its amplitude.
  struct LeftOut {
    std::size_t term = 0;    ///< into the model's terms; a periodic one
    int first_harmonic = 1;  ///< this harmonic and the higher ones
  };
  std::vector<LeftOut> left_out;
};

struct VolumeTable {
  std::array<std::vector<double>, 3> positions;  ///< mm, each axis' node positions, ascending
  Eigen::Vector3d reference = Eigen::Vector3d::Zero();
  /// mm added to the commanded X, Y, Z at node (i, j, k): correction[index(i, j, k)].
  std::vector<Eigen::Vector3d> correction;
  [[nodiscard]] std::size_t index(std::size_t i, std::size_t j, std::size_t k) const {
    return (k * positions[1].size() + j) * positions[0].size() + i;  // X fastest
  }
  [[nodiscard]] std::size_t nodes() const { return positions[0].size() * positions[1].size() * positions[2].size(); }
  /// The correction at commanded X Y Z (mm): trilinear in the cell holding it, each axis
  /// held at its end node beyond the grid.
  [[nodiscard]] Eigen::Vector3d correction_at(const Eigen::Vector3d& p) const;
};

/// Samples the model at every node: the correction t with which the commanded p + t puts
/// the tool tip where a perfect machine puts it at p (solved to 1e-9 mm), the mean of
/// travelling up and down, less its value at the reference node. Throws ccomp::Error
/// (usage) when the machine lacks linear X, Y or Z, the reference is not a node, or a
/// term left out is not periodic; ccomp::Error (model) when X, Y or Z does not move the
/// tip along itself, or where the solve does not converge; ccomp::Error (safety) for a
/// correction beyond the model's max_correction or not finite, naming the node.
[[nodiscard]] VolumeTable sample_volume_table(const model::ForwardModel& model, const VolumeOptions& options);

/// Points spread evenly through the grid's box (a Halton sequence: cell centres and
/// corners alike, where linear interpolation errs most and least), the rotary axes and
/// tool length as `line` has them.
[[nodiscard]] std::vector<model::ChainQ> volume_points(const VolumeTable& table, const model::ChainQ& line,
                                                       std::size_t count);

/// The corrector a control applying `table` adds to X, Y, Z.
[[nodiscard]] Corrector volume_corrector(const VolumeTable& table);

}  // namespace ccomp::controller
