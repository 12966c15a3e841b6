// ccomp_rs274_diff: the differential fuzzer against LinuxCNC's rs274. Generates programs
// seed by seed, compares ccomp's motions with rs274's, and writes each program that diverges,
// cut down to the smallest that still does (and whole), with what differs (tools/rs274-diff.sh).
//   ccomp_rs274_diff FIRST_SEED COUNT BLOCKS OUT_DIR
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "rs274_differential.hpp"
#include "rs274_oracle.hpp"
#include "trace_capture.hpp"

using namespace ccomp::test;

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: ccomp_rs274_diff FIRST_SEED COUNT BLOCKS OUT_DIR\n");
    return 2;
  }
  if (!have_rs274()) {
    std::fprintf(stderr, "rs274 not found at %s: run tools/rs274/fetch.sh build/rs274\n", rs274().c_str());
    return 2;
  }
  const auto first = static_cast<unsigned>(std::strtoul(argv[1], nullptr, 10));
  const auto count = static_cast<unsigned>(std::strtoul(argv[2], nullptr, 10));
  const int blocks = std::atoi(argv[3]);
  const std::filesystem::path out = std::filesystem::absolute(argv[4]);  // rs274 runs in a folder of its own
  std::filesystem::create_directories(out);
  const std::string tools = (out / "tools.tbl").string();
  write_file(tools, "T1 P1 Z0.5 D0.25\nT2 P2 Z1.25 D0.5\n");
  const std::string program = (out / "program.ngc").string(), scratch = (out / "candidate.ngc").string();
  unsigned diverged = 0, refused = 0;
  for (unsigned seed = first; seed < first + count; ++seed) {
    const std::string text = generated_program(seed, blocks);
    write_file(program, text);
    bool both_refused = false;
    const auto divergence = rs274_divergence(program, tools, &both_refused);
    if (!divergence) {
      if (both_refused) ++refused;  // both refuse, after the same motions
      continue;
    }
    ++diverged;
    const std::string smallest = smallest_divergent(text, tools, scratch);
    const auto still = rs274_divergence(scratch, tools);
    const std::string name = "seed-" + std::to_string(seed);
    write_file((out / (name + ".ngc")).string(), smallest);
    write_file((out / (name + ".whole.ngc")).string(), text);
    write_file((out / (name + ".txt")).string(), "whole program: " + *divergence + "\nsmallest: " +
                                                     still.value_or("(none: the cut program agrees)") + "\n");
    std::printf("seed %u diverges: %s\n", seed, still.value_or(*divergence).c_str());
  }
  std::filesystem::remove(program);
  std::filesystem::remove(scratch);
  std::printf(
      "%u programs of %d blocks (seeds %u..%u): %u diverge from rs274; %u both refuse (a gouge), "
      "after the same motions\n",
      count, blocks, first, first + count - 1, diverged, refused);
  return diverged == 0 ? 0 : 1;
}
