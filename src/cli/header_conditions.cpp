#include "header_conditions.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "ccomp/compensate/program_header.hpp"

namespace ccomp::cli {
namespace {

void warn(const gcode::LineSource& program, std::uint32_t line, const std::string& message) {
  fmt::print(stderr, "{}:{}: warning: {}\n", program.name(), line, message);
}

/// --work-offset's systems that differ from the header's: measured there, and said.
void take_work_offsets(const CheckArgs& args, const compensate::HeaderFacts& facts, const gcode::LineSource& program,
                       std::uint32_t line, Assumed& out) {
  if (!facts.work_offsets) return;
  out.work_offsets.override_with(*facts.work_offsets);
  const model::WorkOffsets told = work_offsets_of(args.program.work_offsets);
  for (std::size_t s = 1; s <= model::kCoordinateSystems; ++s)
    if (told.of(s) && facts.work_offsets->of(s) && *told.of(s) != *facts.work_offsets->of(s))
      warn(program, line,
           fmt::format("compensated with {}, measured with --work-offset's {}: this measures the program run there",
                       model::describe_work_offset(s, *facts.work_offsets->of(s)),
                       model::describe_work_offset(s, *told.of(s))));
}

/// The header's readings, each --sensor given replacing its sensor's (a reading given
/// twice is left for conditions_for() to refuse).
void take_sensors(const std::vector<model::SensorReading>& told, const compensate::HeaderFacts& facts,
                  const gcode::LineSource& program, std::uint32_t line, Assumed& out) {
  auto given = [&told](const std::string& name) {
    return std::find_if(told.begin(), told.end(), [&](const auto& r) { return r.first == name; });
  };
  if (facts.sensors)
    for (const model::SensorReading& recorded : *facts.sensors) {
      const auto it = given(recorded.first);
      if (it == told.end()) {
        out.sensors.push_back(recorded);
        continue;
      }
      if (it->second != recorded.second)
        warn(program, line,
             fmt::format("compensated with --sensor {}={}, measured with --sensor {}={}: this measures the program "
                         "run at that temperature",
                         recorded.first, recorded.second, it->first, it->second));
    }
  out.sensors.insert(out.sensors.end(), told.begin(), told.end());
}

void take_time(const CheckArgs& args, const compensate::HeaderFacts& facts, const gcode::LineSource& program,
               std::uint32_t line, Assumed& out) {
  if (!args.time) out.time = facts.time;
  if (args.time && facts.time && *args.time != *facts.time)
    warn(program, line,
         fmt::format("compensated with --time {}, measured with --time {}: this measures the program run then",
                     *facts.time, *args.time));
}

}  // namespace

Assumed assumed_by(const CheckArgs& args, const model::MachineModel& m, const gcode::LineSource& program) {
  Assumed out;
  out.work_offsets = m.work_offsets;
  out.time = args.time;
  const std::vector<model::SensorReading> told = model::parse_sensor_readings(args.sensors);
  gcode::LineSource head = program.another_reader();
  gcode::SourceLine line;
  for (int k = 0; k < 2 && head.next(line); ++k) {
    const std::optional<compensate::HeaderFacts> facts = compensate::read_header(line.text);
    if (!facts) continue;
    out.header_tolerance = facts->tolerance;
    take_work_offsets(args, *facts, program, line.number, out);
    take_sensors(told, *facts, program, line.number, out);
    take_time(args, *facts, program, line.number, out);
    if (!facts->model_sha256.empty() && facts->model_sha256 != m.sha256)
      warn(program, line.number,
           fmt::format("compensated with another model (sha256:{}), not {} (sha256:{}): this measures what {} makes "
                       "of it",
                       facts->model_sha256.substr(0, 12), args.model, m.sha256.substr(0, 12), args.model));
    return out;
  }
  out.sensors = told;
  return out;
}

}  // namespace ccomp::cli
