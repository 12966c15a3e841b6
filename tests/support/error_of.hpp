#pragma once
// Test support: the ccomp::Error a call throws, for the test to read its kind, message and
// place; a call that throws none is a test failure (and an internal-kind error comes back).
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <utility>

#include "ccomp/error.hpp"

namespace ccomp::test {

/// `what` says what was given, in parts streamed one after the other ("rows, \" readings\"").
template <typename Call, typename... What>
Error error_of(Call&& call, const What&... what) {
  try {
    std::forward<Call>(call)();
  } catch (const Error& e) {
    return e;
  }
  std::ostringstream said;
  (said << ... << what);
  ADD_FAILURE() << "accepted: " << said.str();
  return Error(ErrorKind::internal, "accepted");
}

}  // namespace ccomp::test
