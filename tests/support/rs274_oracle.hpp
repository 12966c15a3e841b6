#pragma once
// Test support: LinuxCNC's own interpreter, rs274, as an oracle. tools/rs274/fetch.sh
// unpacks it from Debian's package into build/rs274; CCOMP_RS274 names another.
#include <gtest/gtest.h>

#include <string>

#include "trace_capture.hpp"

namespace ccomp::test {

/// Where rs274 is looked for.
std::string rs274();
/// Whether it is there.
bool have_rs274();
/// rs274's trace of the program file `program` with the tool table file `tool_table`, run
/// as LinuxCNC's suite runs it (inch machine units); its error, if it stopped on one.
TraceResult rs274_trace(const std::string& program, const std::string& tool_table);

}  // namespace ccomp::test

/// The oracle is part of the suite (tools/test.sh unpacks it): a test that compares with it
/// fails where it is missing, saying how to get it, rather than passing over the comparison.
#define CCOMP_REQUIRE_RS274()                                                                                   \
  do {                                                                                                          \
    if (!::ccomp::test::have_rs274())                                                                           \
      GTEST_FAIL() << "rs274 not found at " << ::ccomp::test::rs274()                                           \
                   << ": run tools/rs274/fetch.sh <build>/rs274 (tools/test.sh does), or name it in CCOMP_RS274"; \
  } while (false)
