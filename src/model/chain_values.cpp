#include "ccomp/model/chain_values.hpp"

#include <array>

#include "ccomp/constants.hpp"

namespace ccomp::model {

namespace {
/// Each axis' chain unit per program unit: radians per degree for the rotary axes, 1 for
/// the others (a product or quotient by 1 is exact: one branch-free loop serves all nine,
/// at every point a program moves to).
constexpr std::array<double, gcode::kAxisCount> kChainPerAxisUnit = [] {
  std::array<double, gcode::kAxisCount> scale{};
  for (std::size_t i = 0; i < gcode::kAxisCount; ++i) scale[i] = gcode::is_rotary(i) ? kRadPerDeg : 1.0;
  return scale;
}();
}  // namespace

ChainQ chain_of(const gcode::Axes& controlled, const gcode::Offsets& o) {
  ChainQ q;
  for (std::size_t i = 0; i < gcode::kAxisCount; ++i)  // the machine axis carries the tool
    q[static_cast<Eigen::Index>(i)] = (controlled[i] + o.tool[i]) * kChainPerAxisUnit[i];
  q[static_cast<Eigen::Index>(kToolLengthIndex)] = o.tool[2];
  return q;
}

gcode::Axes controlled_of_chain(const ChainQ& q, const gcode::Offsets& o) {
  gcode::Axes controlled;
  for (std::size_t i = 0; i < gcode::kAxisCount; ++i)
    controlled[i] = q[static_cast<Eigen::Index>(i)] / kChainPerAxisUnit[i] - o.tool[i];
  return controlled;
}

}  // namespace ccomp::model
