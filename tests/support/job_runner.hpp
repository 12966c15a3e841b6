#pragma once
// Test support: the main job on a program in memory, and random programs that exercise it
// (straight moves, arcs in every plane, helices, G91, G93 rotary moves, canned cycles).
#include <string>

#include "ccomp/compensate/program_job.hpp"
#include "ccomp/gcode/tool_table.hpp"

namespace ccomp::test {

/// H1: 100 mm, as in every program of these tests.
inline const gcode::ToolEntry kTool1{1, 1, {0, 0, 100.0}, 10, ""};

/// A sample machine model: samples/machines/`name`.yaml.
model::MachineModel sample_machine(const std::string& name);

/// The main job on `program` in memory, with tool 1 in the table: the output program.
std::string compensate(const std::string& program, const model::MachineModel& mm, compensate::JobOptions o,
                       compensate::JobReport* report = nullptr);
std::string compensate(const std::string& program, const model::MachineModel& mm, double tolerance,
                       compensate::JobReport* report = nullptr);

/// Random straight moves over the workspace at several table angles, G90 and G91; with
/// `cycles`, drilling cycles too (absolute, and incremental with L repeats), which the job
/// must then expand (--expand-cycles).
std::string random_program(unsigned seed, bool cycles = false);

}  // namespace ccomp::test
