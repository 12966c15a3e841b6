#pragma once
// Writes a program back in file order. A line nobody edited is copied byte for byte (its
// spacing, case, comments and line terminator); an edited line has only the bytes of the
// edited values replaced. The writer follows the interpreter: advance_to(offset) writes
// every line before `offset`, so a straight program streams through in constant memory.
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "ccomp/gcode/block.hpp"
#include "ccomp/gcode/number.hpp"  // format_fixed, which writers use
#include "ccomp/gcode/source.hpp"

namespace ccomp::gcode {

/// Replace the bytes `span` of a line with `text`.
struct Edit {
  Span span;
  std::string text;
};

/// The line with the edits applied (edits must not overlap).
[[nodiscard]] std::string apply_edits(std::string_view line, std::vector<Edit> edits);
/// The same into `out` (replaced), reusing its storage; sorts `edits` in place.
void apply_edits(std::string_view line, std::span<Edit> edits, std::string& out);
/// Appends to `edits` the removal of `words` (spans of `line`), each with the blanks before
/// it (after it, when it starts the line: the line's indentation stays); neighbours' blanks
/// merge into one edit, as edits may not overlap.
void removal_edits(std::string_view line, std::vector<Span> words, std::vector<Edit>& edits);

class ProgramWriter {
 public:
  /// `reader` is a reader of the program (LineSource::another_reader()); `header` is one
  /// line (without terminator) written first, or after a leading `%` line. `out` is
  /// written without its lock: no other thread may write it while the writer lives.
  ProgramWriter(LineSource reader, std::FILE* out, std::string header);

  /// Edits for the line starting at `line_offset` (not yet written).
  void edit(std::uint64_t line_offset, std::vector<Edit> edits) { edit(line_offset, std::span<Edit>(edits)); }
  /// The same, taking the texts out of `edits` (the caller keeps its storage for the next).
  void edit(std::uint64_t line_offset, std::span<Edit> edits);
  /// The same, taking `edits` whole where nothing else waits (their storage traded for
  /// the writer's, no text moved): `edits` is left empty, with storage for the next.
  void take_edits(std::uint64_t line_offset, std::vector<Edit>& edits);
  /// Writes every line before `line_offset`, then that line with `edits` but not its
  /// terminator: the text append() is given follows it until close_line(). A line that
  /// gains more text than is worth holding (a move split into a great many pieces) is
  /// written so, as its pieces come.
  void write_open(std::uint64_t line_offset, std::span<Edit> edits);
  /// Text after the line write_open() left open.
  void append(std::string_view text);
  /// Ends the open line with its own terminator.
  void close_line();
  /// Writes every line that starts before `offset`.
  void advance_to(std::uint64_t offset);
  /// Writes the rest of the program and flushes.
  void finish();
  [[nodiscard]] std::uint64_t written_up_to() const { return next_offset_; }

 private:
  void write_line(const SourceLine& line, bool terminate = true);
  void check_closed() const;

  LineSource reader_;
  std::FILE* out_;
  std::string header_;
  bool header_written_ = false;
  std::uint64_t next_offset_ = 0;
  bool open_ = false;            ///< a line was written without its terminator
  std::string open_terminator_;  ///< its terminator
  /// Edits not yet written, by line offset (in arrival order for one line), and the line
  /// offset of each. Lines are edited just before they are written: flat lists, their
  /// storage kept, no allocation; a line's edits are applied where they lie.
  std::vector<Edit> pending_;
  std::vector<std::uint64_t> pending_offsets_;
  std::string edited_;
};

}  // namespace ccomp::gcode
