#pragma once
// What a fuzz target counts as a normal outcome: the reader accepts the input, or refuses it
// with a ccomp::Error (what the CLI prints with its position and exit code). Any other
// exception is a finding: the CLI would report it as an internal error (exit 70).
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <typeinfo>

#include "ccomp/error.hpp"

namespace ccomp::fuzz {

template <class Read>
int read_or_refuse(Read read) {
  try {
    read();
  } catch (const ccomp::Error&) {
    // A refusal with a position: what bad input should get.
  } catch (const std::exception& e) {
    std::fprintf(stderr, "finding: %s escaped instead of ccomp::Error: %s\n", typeid(e).name(), e.what());
    std::abort();
  }
  return 0;
}

}  // namespace ccomp::fuzz
