#include "ccomp/gcode/tool_table.hpp"

#include <fmt/format.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "ccomp/error.hpp"

namespace ccomp::gcode {

ToolTable read_tool_table(std::istream& in, const std::string& name) {
  ToolTable table;
  std::string text;
  std::uint32_t line_no = 0;
  while (std::getline(in, text)) {
    ++line_no;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    std::string_view line(text);
    ToolEntry entry;
    if (const auto semi = line.find(';'); semi != std::string_view::npos) {
      entry.comment = std::string(line.substr(semi + 1));
      line = line.substr(0, semi);
    }
    bool has_tool = false;
    std::string seen;  // the letters of this line so far
    std::size_t i = 0;
    while (i < line.size()) {
      if (std::isspace(static_cast<unsigned char>(line[i]))) {
        ++i;
        continue;
      }
      const char letter = static_cast<char>(std::toupper(static_cast<unsigned char>(line[i])));
      const std::size_t start = i++;
      while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
      const std::string_view field = line.substr(start + 1, i - start - 1);
      if (seen.find(letter) != std::string::npos)
        throw Error(ErrorKind::io, std::string("tool table: field '") + letter + "' is written twice on this line",
                    SourceLocation{name, line_no, static_cast<std::uint32_t>(start + 1)}, text);
      seen.push_back(letter);
      double value = 0.0;
      const auto [ptr, ec] = std::from_chars(field.data(), field.data() + field.size(), value);
      if (ec != std::errc() || ptr != field.data() + field.size() || !std::isfinite(value))
        throw Error(ErrorKind::io,
                    "tool table: bad number in field '" + std::string(line.substr(start, i - start)) + "'",
                    SourceLocation{name, line_no, static_cast<std::uint32_t>(start + 1)}, text);
      // A tool or pocket number beyond int cannot be one: its conversion would be undefined.
      if ((letter == 'T' || letter == 'P') &&
          !(value >= 0.0 && value <= static_cast<double>(std::numeric_limits<int>::max())))
        throw Error(ErrorKind::io,
                    fmt::format("tool table: {} number {} is out of range (0 to {})", letter,
                                line.substr(start + 1, i - start - 1), std::numeric_limits<int>::max()),
                    SourceLocation{name, line_no, static_cast<std::uint32_t>(start + 1)}, text);
      switch (letter) {
        case 'T':
          entry.tool = static_cast<int>(value);
          has_tool = true;
          break;
        case 'P':
          entry.pocket = static_cast<int>(value);
          break;
        case 'D':
          entry.diameter = value;
          break;
        case 'I':
        case 'J':
        case 'Q':
          break;  // lathe orientation and angles: not used here
        default:
          if (auto axis = axis_index(letter)) {
            entry.offset[*axis] = value;
          } else {
            throw Error(ErrorKind::io, std::string("tool table: unknown field '") + letter + "'",
                        SourceLocation{name, line_no, static_cast<std::uint32_t>(start + 1)}, text);
          }
      }
    }
    if (has_tool) table.tools[entry.tool] = entry;
  }
  return table;
}

ToolTable read_tool_table_file(const std::string& path) {
  // A folder opens and reads as nothing on Linux: it would be an empty table, every tool
  // then unknown, rather than the mistake it is.
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw Error(ErrorKind::io, "tool table '" + path + "' is a folder: name the tool table file (tool.tbl)",
                SourceLocation{path});
  std::ifstream in(path);
  if (!in) throw Error(ErrorKind::io, "cannot open tool table '" + path + "'", SourceLocation{path});
  ToolTable table = read_tool_table(in, path);
  if (in.bad()) throw Error(ErrorKind::io, "cannot read tool table '" + path + "'", SourceLocation{path});
  return table;
}

}  // namespace ccomp::gcode
