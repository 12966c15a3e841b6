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

/// What the terms need and were not given: each unread sensor a term depends on (in the
/// model's sensor order, with the first term that needs it) and the time, if a term
/// depends on it and none was given. Evaluating such a term would take NaN, or t = 0,
/// which silently takes a warm-up out.
std::vector<std::string> missing_conditions(const MachineModel& model, const std::vector<double>& temperatures,
                                            bool time_given) {
  std::vector<std::string> needing(model.sensors.size());  // the first term needing each sensor
  std::string time_term;
  for (const ErrorTermSpec& t : model.terms)
    for (const Variable* v : {&t.primary, &t.secondary}) {
      if (v->kind == VariableKind::temperature && std::isnan(temperatures[v->index]) && needing[v->index].empty())
        needing[v->index] = t.name;
      if (v->kind == VariableKind::time && !time_given && time_term.empty()) time_term = t.name;
    }
  std::vector<std::string> missing;
  for (std::size_t i = 0; i < needing.size(); ++i)
    if (!needing[i].empty())
      missing.push_back(fmt::format("--sensor {}=VALUE (term {} depends on sensor '{}')", model.sensors[i],
                                    needing[i], model.sensors[i]));
  if (!time_term.empty())
    missing.push_back(fmt::format("--time SECONDS (term {} depends on the time since the warm-up started)", time_term));
  return missing;
}

/// Refuses, in one message, everything missing_conditions() finds: a user fixing the
/// command line learns all of it at once.
void check_given(const MachineModel& model, const std::vector<double>& temperatures, bool time_given) {
  const std::vector<std::string> missing = missing_conditions(model, temperatures, time_given);
  if (missing.empty()) return;
  if (missing.size() == 1) refuse(fmt::format("a reading the model needs was not given: {}", missing[0]));
  std::string list;
  for (const std::string& m : missing) list += "\n  " + m;
  refuse(fmt::format("{} readings the model needs were not given:{}", missing.size(), list));
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
  check_given(model, c.temperatures, time.has_value());
  return c;
}

}  // namespace ccomp::model
