#pragma once
// What the compensator's stages share about an axis' travel: when it counts as standing
// still, and a point part of the way along a move.
#include <cstddef>

#include "ccomp/axis.hpp"
#include "ccomp/model/forward.hpp"

namespace ccomp::compensate {

/// Below these an axis is taken as not moving: a nanometre, 1e-8 rad.
[[nodiscard]] inline double still(std::size_t axis) {
  return angular_at(axis) ? 1e-8 : 1e-6;
}

/// The chain values at fraction s of the move from start to end (its ends exactly).
[[nodiscard]] inline model::ChainQ along(const model::ChainQ& start, const model::ChainQ& end, double s) {
  return s == 0.0 ? start : s == 1.0 ? end : model::ChainQ(start + s * (end - start));
}

}  // namespace ccomp::compensate
