#pragma once
// A program as it runs: loops and subroutine calls unrolled into straight-line G-code, so
// that every line runs once and a compensation may rewrite each line for the one place it
// runs at (a subroutine called at three places needs three different corrections).
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "ccomp/error.hpp"
#include "ccomp/gcode/interpreter.hpp"
#include "ccomp/gcode/source.hpp"

namespace ccomp::gcode {

/// Where each line of a flattened program came from (file and line), kept as runs of
/// consecutive lines: a loop of ten lines run a thousand times is a thousand runs.
class LineOrigins {
 public:
  /// Flattened line `flat_line` (1-based, each one after the last) came from `line` of `file`.
  void add(std::uint32_t flat_line, const std::string& file, std::uint32_t line);
  /// The origin of a flattened line; an unknown line keeps its number and has no file.
  [[nodiscard]] SourceLocation at(std::uint32_t flat_line) const;
  [[nodiscard]] std::size_t runs() const { return runs_.size(); }

 private:
  struct Run {
    std::uint32_t flat_first = 0;
    std::uint32_t line_first = 0;
    std::uint32_t count = 0;
    std::uint32_t file = 0;  ///< index into files_
  };
  std::vector<std::string> files_;
  std::vector<Run> runs_;
};

/// Writes `program` as it runs to `out`: every line the interpreter executes, in the order
/// it executes them, with
/// - each value that is an expression or a parameter replaced by the number it was then;
/// - parameter settings, O-word statements (sub, call, loops, conditions) and Fanuc's
///   subprogram calls and returns (M98 with its P and L, M99 with its P) taken out, and a
///   line left with nothing to do dropped (a line of comments stays);
/// - `%` lines (the closing one after M2/M30 too) and a program number before the first
///   executed line kept.
/// Lines a block-delete switch skips are not run, so not written. Every other byte of a
/// written line is as it was. Throws what the interpreter throws, at the original's lines;
/// a program that runs more than kFlattenMaxBlocks blocks (or options.max_blocks, if fewer)
/// is taken for an endless loop, before its spool fills a disk.
/// The written program is bounded by its size too: more than `max_bytes` (kFlattenMaxBytes)
/// is refused (exit 3) at the line that would pass it, before a loop of long lines (a line may
/// be 1 MiB) fills a disk within the block limit.
inline constexpr std::uint64_t kFlattenMaxBlocks = 20'000'000;
inline constexpr std::uint64_t kFlattenMaxBytes = std::uint64_t{1} << 30;
[[nodiscard]] LineOrigins flatten(LineSource& program, std::FILE* out, const InterpreterOptions& options,
                                  std::uint64_t max_bytes = kFlattenMaxBytes);

/// How flatten() writes a computed value: a code (G, M, T, H, D, N, O, P, L, S) that is a
/// whole number without decimals, anything else with a decimal point and up to 6 decimals
/// (1 nm in mm, 1e-6 degree), trailing zeros dropped.
[[nodiscard]] std::string flat_number(char letter, double value);

}  // namespace ccomp::gcode
