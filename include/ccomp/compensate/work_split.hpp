#pragma once
// Who does the work of the main job that either of its two threads may do (each move's
// nominal end pose, the uncompensated machine's error at its probes).
#include <cstdint>

namespace ccomp::compensate {

enum class WorkSplit : std::uint8_t {
  adaptive,   ///< the reading thread while it would wait for the worker, else the worker
  reader,     ///< always the reading thread
  worker,     ///< always the worker
  alternate,  ///< batch by batch in turn (for tests: the hand-over between the two)
};

}  // namespace ccomp::compensate
