#include "ccomp/model/conditions.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>

#include "ccomp/error.hpp"

namespace ccomp::model {
namespace {

[[noreturn]] void refuse(const std::string& message) {
  throw Error(ErrorKind::usage, message);
}

/// "its sensors: a, b" or "it has no sensors", for a message about a sensor it lacks.
std::string sensors_of(const MachineModel& model) {
  if (model.sensors.empty()) return "it has no sensors";
  std::string list;
  for (const std::string& s : model.sensors) list += (list.empty() ? "" : ", ") + s;
  return "its sensors: " + list;
}

/// The index of `name` among the model's sensors.
std::size_t sensor_index(const MachineModel& model, const std::string& name) {
  const auto it = std::find(model.sensors.begin(), model.sensors.end(), name);
  if (it == model.sensors.end())
    refuse(
        fmt::format("--sensor {}: machine '{}' has no sensor of that name ({})", name, model.name, sensors_of(model)));
  return static_cast<std::size_t>(it - model.sensors.begin());
}

/// Refuses a term that depends on a sensor without a reading: evaluating it would take
/// NaN for the temperature.
void check_read(const MachineModel& model, const std::vector<double>& temperatures) {
  for (const ErrorTermSpec& t : model.terms)
    for (const Variable* v : {&t.primary, &t.secondary})
      if (v->kind == VariableKind::temperature && std::isnan(temperatures[v->index]))
        refuse(fmt::format("term {} depends on sensor '{}', and no reading was given: --sensor {}=VALUE", t.name,
                           model.sensors[v->index], model.sensors[v->index]));
}

}  // namespace

SensorReading parse_sensor_reading(const std::string& text) {
  const auto eq = text.find('=');
  const char* value = eq == std::string::npos ? "" : text.c_str() + eq + 1;
  char* end = nullptr;
  // strtod would skip leading blanks: the number must be all the text after '='.
  const double v = *value == '\0' || std::isspace(static_cast<unsigned char>(*value)) ? 0.0 : std::strtod(value, &end);
  if (eq == std::string::npos || eq == 0 || !end || *end != '\0' || !std::isfinite(v))
    refuse(fmt::format("--sensor takes NAME=DEGC, not '{}'", text));
  return {text.substr(0, eq), v};
}

std::vector<SensorReading> parse_sensor_readings(const std::vector<std::string>& texts) {
  std::vector<SensorReading> readings;
  readings.reserve(texts.size());
  for (const std::string& text : texts) readings.push_back(parse_sensor_reading(text));
  return readings;
}

Conditions conditions_for(const MachineModel& model, const std::vector<SensorReading>& readings,
                          std::optional<double> time) {
  if (time && !std::isfinite(*time)) refuse(fmt::format("the time must be finite, not {}", *time));
  if (!time)
    for (const ErrorTermSpec& t : model.terms)
      for (const Variable* v : {&t.primary, &t.secondary})
        if (v->kind == VariableKind::time)
          refuse(fmt::format("term {} depends on the time since the warm-up started, and none was given: --time "
                             "SECONDS",
                             t.name));
  Conditions c;
  c.time = time.value_or(0.0);
  c.temperatures.assign(model.sensors.size(), std::nan(""));
  for (const auto& [name, value] : readings) {
    if (!std::isfinite(value)) refuse(fmt::format("sensor '{}' must read a finite temperature, not {}", name, value));
    double& temperature = c.temperatures[sensor_index(model, name)];
    if (!std::isnan(temperature))
      refuse(fmt::format("--sensor {}: read twice ({} and {}); give one reading", name, temperature, value));
    temperature = value;
  }
  check_read(model, c.temperatures);
  return c;
}

}  // namespace ccomp::model
