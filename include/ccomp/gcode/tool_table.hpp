#pragma once
// LinuxCNC's tool table: one tool a line, `T1 P1 Z0.5 D0.0625 ;comment`.
#include <cstdint>
#include <istream>
#include <map>
#include <string>

#include "ccomp/gcode/axes.hpp"

namespace ccomp::gcode {

struct ToolEntry {
  int tool = 0;
  int pocket = 0;
  Axes offset{};  ///< in the table's units (the machine's, as LinuxCNC reads it)
  double diameter = 0.0;
  std::string comment;
};

struct ToolTable {
  std::map<int, ToolEntry> tools;  ///< offsets in the machine's units
  [[nodiscard]] const ToolEntry* find(int tool) const {
    auto it = tools.find(tool);
    return it == tools.end() ? nullptr : &it->second;
  }
};

/// Reads LinuxCNC's format. Errors name the file, line and the bad field.
[[nodiscard]] ToolTable read_tool_table(std::istream& in, const std::string& name);
[[nodiscard]] ToolTable read_tool_table_file(const std::string& path);

}  // namespace ccomp::gcode
