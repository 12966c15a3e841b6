#pragma once
// Proving a program before cutting: predict() runs a program through the machine model as
// it is (the error the machine would make), verify() runs a compensated program through it
// and measures how far the executed tool tip strays from the path the original meant.
// Both sample every feed move and arc; rapids are the control's path, not cuts. Each
// point's tool direction is measured beside its tip.
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>

#include "ccomp/gcode/interpreter.hpp"
#include "ccomp/gcode/source.hpp"
#include "ccomp/model/forward.hpp"

namespace ccomp::compensate {

struct PathError {
  double max = 0.0;                                       ///< mm
  double rms = 0.0;                                       ///< mm, over the sampled points
  std::uint32_t worst_line = 0;                           ///< the block of the worst point (in the program checked)
  Eigen::Vector3d worst_point = Eigen::Vector3d::Zero();  ///< table frame, mm
  std::uint64_t points = 0;
  std::uint64_t moves = 0;
  /// verify: mm of the original's cuts the executed path never came to (a truncated
  /// output, a cut missing between rapids, more than 10 um of path passed over between
  /// two points; a canned cycle's pecks, which its compensated words move, not counted),
  /// and the original's line of the first of them (0: none).
  double uncut_length = 0.0;
  std::uint32_t uncut_line = 0;
  /// The tool's direction at the same points: the angle (rad) between the axis the tool
  /// has and the one the program meant there (its turn about its own axis, which an
  /// axisymmetric tool does not cut with, left out): the largest, its block, the rms.
  double orientation_max = 0.0;
  double orientation_rms = 0.0;
  std::uint32_t orientation_worst_line = 0;
};

struct CheckOptions {
  gcode::InterpreterOptions interpreter;
  model::Conditions conditions;
  int samples = 8;  ///< points checked inside each move
  /// Called with the fraction of the program read (the compensated one for verify), 0 to 1.
  std::function<void(double)> progress;
  /// predict: called once a term, at the first line that uses it beyond where it was fitted
  /// (its span: model/term_span.hpp), with what it holds there.
  std::function<void(const std::string& message, std::uint32_t line)> warning;
  /// predict: called at every point it checks, with the command's chain values, the
  /// conditions there and the line (the trust on the program gathers them: trust.hpp).
  std::function<void(const model::ChainQ& q, const model::Conditions& conditions, std::uint32_t line)> pose;
};

/// The uncompensated machine's error along the program: |actual - nominal| at each point.
[[nodiscard]] PathError predict(gcode::LineSource& program, const model::ForwardModel& model,
                                const CheckOptions& options);

/// The executed path of `compensated` against the nominal path of `original`.
[[nodiscard]] PathError verify(gcode::LineSource& original, gcode::LineSource& compensated,
                               const model::ForwardModel& model, const CheckOptions& options);

}  // namespace ccomp::compensate
