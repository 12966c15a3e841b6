#pragma once
// Test support: LinuxCNC's own interpreter, rs274, as an oracle. tools/rs274/fetch.sh
// unpacks it from Debian's package into build/rs274; CCOMP_RS274 names another.
#include <string>

#include "trace_capture.hpp"

namespace ccomp::test {

/// Where rs274 is looked for.
std::string rs274();
/// Whether it is there (tests that need it skip otherwise).
bool have_rs274();
/// rs274's trace of the program file `program` with the tool table file `tool_table`, run
/// as LinuxCNC's suite runs it (inch machine units); its error, if it stopped on one.
TraceResult rs274_trace(const std::string& program, const std::string& tool_table);

}  // namespace ccomp::test
