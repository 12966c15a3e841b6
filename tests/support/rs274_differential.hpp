#pragma once
// Test support: ccomp against LinuxCNC's own interpreter (rs274) on any program, random
// programs of every block kind both read, and the smallest program that still shows a
// difference. Used by the differential tests and by tools/rs274-diff.sh (many programs).
#include <optional>
#include <string>
#include <vector>

namespace ccomp::test {

/// The motions of a trace without zero-length straight moves: rs274 emits some where its
/// positions, converted between inches and mm, are 1e-12 short of an R plane, and one
/// after G84's feed out. Geometry is what counts.
std::vector<std::string> geometry(const std::vector<std::string>& lines);

/// How ccomp's motions for the program file `path` differ from rs274's (to 1e-4, rs274's
/// print precision), both run with the tool table file `tool_table` in inch machine units
/// as LinuxCNC's suite runs rs274; nothing when they agree, or both refuse the program after
/// the same motions. `refused` (if given) says whether rs274 refused it.
std::optional<std::string> rs274_divergence(const std::string& path, const std::string& tool_table,
                                            bool* refused = nullptr);

/// A random program of `blocks` blocks of every kind the milling dialect has (moves, arcs in
/// every plane with IJK or R and turns, units, G91, G10 L2, G92/G52, drilling cycles with L
/// and G91, tool changes and offsets, loops, subroutine calls, G93, G53), the same for the
/// same seed.
std::string generated_program(unsigned seed, int blocks);

/// The program with as many of its lines removed as can be while it still diverges from
/// rs274 in the same way (a refusal by either, or different motions), whole halves first,
/// then smaller pieces, then single lines; `scratch` is a file
/// path the candidates are written to.
std::string smallest_divergent(const std::string& program, const std::string& tool_table, const std::string& scratch);

}  // namespace ccomp::test
