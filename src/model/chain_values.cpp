#include "ccomp/model/chain_values.hpp"

#include "ccomp/constants.hpp"

namespace ccomp::model {

ChainQ chain_of(const gcode::Axes& controlled, const gcode::Offsets& o) {
  ChainQ q = ChainQ::Zero();
  for (std::size_t i = 0; i < gcode::kAxisCount; ++i) {
    const double axis = controlled[i] + o.tool[i];  // the machine axis carries the tool
    q[static_cast<Eigen::Index>(i)] = gcode::is_rotary(i) ? axis * kRadPerDeg : axis;
  }
  q[static_cast<Eigen::Index>(kToolLengthIndex)] = o.tool[2];
  return q;
}

gcode::Axes controlled_of_chain(const ChainQ& q, const gcode::Offsets& o) {
  gcode::Axes controlled{};
  for (std::size_t i = 0; i < gcode::kAxisCount; ++i) {
    const double axis = q[static_cast<Eigen::Index>(i)];
    controlled[i] = (gcode::is_rotary(i) ? axis / kRadPerDeg : axis) - o.tool[i];
  }
  return controlled;
}

}  // namespace ccomp::model
