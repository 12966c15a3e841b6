#pragma once
// The header comment that marks a compensated program: which model (by its hash) and which
// tolerance it was compensated to. The job writes it; the job, verify and the CLI read it
// (a program with it is not compensated twice).
#include <limits>
#include <optional>
#include <string>
#include <string_view>

#include "ccomp/model/machine.hpp"

namespace ccomp::compensate {

/// The header comment that marks a compensated program, names the model by its hash and
/// says the tolerance (mm) it was compensated to and the work offsets the program started
/// with (where its zero lies in machine coordinates, which verify and predict need).
[[nodiscard]] std::string header_line(const model::MachineModel& model, double tolerance,
                                      const model::WorkOffsets& work_offsets = {});
/// True when `line` is a header that header_line() wrote, as a transfer or a control may
/// have kept it: in any case, respaced, `( ccomp ...)` or `; ccomp ...` (a whole-line comment
/// starting with "ccomp" that says "compensated for machine").
[[nodiscard]] bool is_header_line(std::string_view line);
/// How many of a program's first lines the job looks through for a header.
inline constexpr int kHeaderSearchLines = 10;
/// What a header line says: the model's SHA-256 (hex) and the tolerance in mm (NaN when
/// the header is older than the tolerance in it).
struct HeaderFacts {
  std::string model_sha256;
  double tolerance = std::numeric_limits<double>::quiet_NaN();
  /// The work offsets the program was compensated with; absent in a header older than them.
  std::optional<model::WorkOffsets> work_offsets;
};
[[nodiscard]] std::optional<HeaderFacts> read_header(std::string_view line);

}  // namespace ccomp::compensate
