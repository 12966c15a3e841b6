#pragma once
// The header comment that marks a compensated program: which model (by its hash) and which
// tolerance it was compensated to, and what the run assumed (work offsets, sensor readings,
// time). The job writes it; the job, verify, predict and the CLI read it (a program with it
// is not compensated twice; a check takes the run's conditions from it).
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ccomp/model/conditions.hpp"
#include "ccomp/model/machine.hpp"

namespace ccomp::compensate {

/// What a run assumed beyond the model: where program zero lies, and the conditions of the
/// thermal terms. A check of the output needs the same, or it measures another run.
struct RunConditions {
  /// The work offsets the program started with (machine coordinates).
  model::WorkOffsets work_offsets;
  /// The --sensor readings given (degC), in the model's sensor order when written.
  std::vector<model::SensorReading> sensors;
  /// --time (s since the warm-up started), when given.
  std::optional<double> time;
};

/// The header comment that marks a compensated program, names the model by its hash and
/// says the tolerance (mm) it was compensated to and what the run assumed: the work
/// offsets (always), the sensor readings and the time (where given), as
/// "; work offsets G54 X0 Y0 Z-400; sensors bed=20, column=21.5; time 3600 s". In `( ... )`,
/// or after `;` where the dialect's parentheses are no comment (Siemens).
[[nodiscard]] std::string header_line(const model::MachineModel& model, double tolerance,
                                      const RunConditions& conditions = {}, bool parenthesis_comments = true);
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
  /// The sensor readings and the time it was compensated with; absent where none was given
  /// (or the header is older than them).
  std::optional<std::vector<model::SensorReading>> sensors;
  std::optional<double> time;
};
[[nodiscard]] std::optional<HeaderFacts> read_header(std::string_view line);

}  // namespace ccomp::compensate
