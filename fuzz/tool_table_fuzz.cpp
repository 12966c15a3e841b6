// libFuzzer target: LinuxCNC tool tables (gcode::read_tool_table), as --tool-table reads them.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "ccomp/gcode/tool_table.hpp"
#include "fuzz_outcome.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return ccomp::fuzz::read_or_refuse([&] {
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
    (void)ccomp::gcode::read_tool_table(in, "fuzz.tbl");
  });
}
