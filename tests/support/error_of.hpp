#pragma once
// Test support: the ccomp::Error a call throws, for the test to read its kind, message and
// place; a call that throws none is a test failure (and an internal-kind error comes back).
#include <gtest/gtest.h>

#include <string>
#include <utility>

#include "ccomp/error.hpp"

namespace ccomp::test {

template <typename Call>
Error error_of(Call&& call, const std::string& what) {
  try {
    std::forward<Call>(call)();
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "accepted: " << what;
  return Error(ErrorKind::internal, "accepted");
}

}  // namespace ccomp::test
