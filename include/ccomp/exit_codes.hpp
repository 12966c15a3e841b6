#pragma once
// Every exit code the command returns besides 0 and the signals' 128+N: each ErrorKind's
// (error.hpp: a failure, its output not written) and the verdict's 1, which is not an
// Error: the main job wrote its output, and the output fails its verdict
// (compensate/verdict.hpp). README's exit-code table and `ccomp --help` list exactly these
// (a test holds them together).
#include <array>

#include "ccomp/error.hpp"

namespace ccomp {

/// The main job wrote its output, and verify() of it finds the contour error left over the
/// tolerance, worse than the program as written, or a cut left out. Below every ErrorKind,
/// so with several programs a refusal (nothing written) outranks it.
inline constexpr int kVerdictExitCode = 1;

/// Every ErrorKind (a kind added to error.hpp belongs here too).
inline constexpr std::array kErrorKinds = {ErrorKind::usage,  ErrorKind::program, ErrorKind::unsupported,
                                           ErrorKind::model,  ErrorKind::io,      ErrorKind::safety,
                                           ErrorKind::data,   ErrorKind::internal};

/// Every code but 0 and 128+N, in ascending order.
[[nodiscard]] constexpr std::array<int, kErrorKinds.size() + 1> exit_codes() {
  std::array<int, kErrorKinds.size() + 1> codes{kVerdictExitCode};
  for (std::size_t i = 0; i < kErrorKinds.size(); ++i) codes[i + 1] = exit_code(kErrorKinds[i]);
  return codes;
}

}  // namespace ccomp
