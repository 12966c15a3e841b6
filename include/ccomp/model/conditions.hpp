#pragma once
// The conditions a machine model is evaluated in (the time and the temperatures) from what
// a command line gives: `--sensor NAME=DEGC` readings and `--time S`. The one place that
// checks them, so that every command refuses the same mistakes alike (exit 2: usage).
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ccomp/model/forward.hpp"
#include "ccomp/model/machine.hpp"

namespace ccomp::model {

/// A temperature reading: the sensor's name and degC (as compensate::JobOptions::sensors
/// holds them).
using SensorReading = std::pair<std::string, double>;

/// A reading from its text, "NAME=DEGC": a name, '=' and a whole, finite number. Throws
/// ccomp::Error (usage) quoting the text.
[[nodiscard]] SensorReading parse_sensor_reading(const std::string& text);

/// The readings of `texts`, in their order (parse_sensor_reading() each).
[[nodiscard]] std::vector<SensorReading> parse_sensor_readings(const std::vector<std::string>& texts);

/// The conditions for `model` at `time` (s since the warm-up started) with `readings`:
/// the temperatures in the model's sensor order, NaN for a sensor that is not read and
/// that no term depends on. Throws ccomp::Error (usage) for a time or reading that is not
/// finite, a sensor read twice, a reading of a sensor the model lacks (naming the machine
/// and its sensors), and a term's sensor left unread (naming the term, the sensor and the
/// fix, --sensor NAME=VALUE), and a term over the time (a warm-up) without `time`, as a
/// thermal term without its sensor (t = 0 would silently take the warm-up out).
[[nodiscard]] Conditions conditions_for(const MachineModel& model, const std::vector<SensorReading>& readings,
                                        std::optional<double> time);

}  // namespace ccomp::model
