#pragma once
// The machine model file (YAML): which axes the machine has, their limits, the G-code
// dialect of its control. (The kinematic chain and error terms are added on top.)
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace ccomp::model {

enum class AxisType : std::uint8_t { linear, rotary };

struct AxisSpec {
  char letter = 'X';
  AxisType type = AxisType::linear;
  double min = -std::numeric_limits<double>::infinity();  ///< mm or deg
  double max = std::numeric_limits<double>::infinity();
};

struct MachineModel {
  std::string name;
  std::string description;
  std::vector<AxisSpec> axes;
  std::string dialect = "linuxcnc";
  std::string path;    ///< where it was read from
  std::string sha256;  ///< of the file's bytes: names the model in compensated programs

  [[nodiscard]] const AxisSpec* axis(char letter) const {
    for (const AxisSpec& a : axes)
      if (a.letter == letter) return &a;
    return nullptr;
  }
};

/// Reads and validates a model file. Throws ccomp::Error (model) naming the file, the key
/// and the bad value.
[[nodiscard]] MachineModel load_machine_model(const std::string& path);
[[nodiscard]] MachineModel parse_machine_model(const std::string& text, const std::string& name);

/// Checks a model: known axis letters, no duplicates, limits ordered and not NaN, a dialect
/// ccomp knows. Throws ccomp::Error (model) with the offending entry.
void validate(const MachineModel& model);

}  // namespace ccomp::model
