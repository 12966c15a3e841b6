#include "ccomp/gcode/writer.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "ccomp/error.hpp"

namespace ccomp::gcode {
namespace {
/// Writes to the program's stream without taking its lock (two atomic operations a call,
/// and a call a line): one thread, the one running the writer (the job's reading thread),
/// writes it (ProgramWriter's constructor).
void put(const char* data, std::size_t size, std::FILE* out) {
  fwrite_unlocked(data, 1, size, out);
}
}  // namespace

std::string apply_edits(std::string_view line, std::vector<Edit> edits) {
  std::string out;
  apply_edits(line, edits, out);
  return out;
}

void apply_edits(std::string_view line, std::span<Edit> edits, std::string& out) {
  // By position; an insertion before a replacement that starts at the same byte; two
  // insertions at one place in the order they came (a block's moves, one after the other).
  // A line has a handful of edits: an insertion sort, stable and without allocation.
  for (std::size_t i = 1; i < edits.size(); ++i)
    for (std::size_t j = i; j > 0; --j) {
      const Edit& a = edits[j - 1];
      const Edit& b = edits[j];
      const bool before = b.span.begin != a.span.begin ? b.span.begin < a.span.begin : b.span.end < a.span.end;
      if (!before) break;
      std::swap(edits[j - 1], edits[j]);
    }
  // The length first, then each piece copied into place: one allocation check, not two a piece.
  std::size_t length = line.size();
  std::uint32_t at = 0;
  for (const Edit& e : edits) {
    if (e.span.begin < at || e.span.end < e.span.begin || e.span.end > line.size())
      throw Error(ErrorKind::internal, "overlapping or out-of-line edit of a program line");
    length += e.text.size() - (e.span.end - e.span.begin);
    at = e.span.end;
  }
  out.resize(length);
  char* to = out.data();
  at = 0;
  for (const Edit& e : edits) {
    to = std::copy_n(line.data() + at, e.span.begin - at, to);
    to = std::copy_n(e.text.data(), e.text.size(), to);
    at = e.span.end;
  }
  std::copy_n(line.data() + at, line.size() - at, to);
}

void removal_edits(std::string_view line, std::vector<Span> words, std::vector<Edit>& edits) {
  const auto first_word = static_cast<std::uint32_t>(std::min(line.find_first_not_of(" \t"), line.size()));
  auto blank = [&](std::uint32_t i) { return i < line.size() && (line[i] == ' ' || line[i] == '\t'); };
  for (Span& s : words) {
    if (s.begin == first_word)
      while (blank(s.end)) ++s.end;
    else
      while (s.begin > first_word && blank(s.begin - 1)) --s.begin;
  }
  std::sort(words.begin(), words.end(), [](const Span& a, const Span& b) { return a.begin < b.begin; });
  for (std::size_t k = 0; k < words.size(); ++k) {
    if (k > 0 && words[k].begin <= edits.back().span.end) {
      edits.back().span.end = std::max(edits.back().span.end, words[k].end);
    } else {
      edits.push_back(Edit{words[k], ""});
    }
    // A removal that now starts the line takes the blanks after it, not one before the next word.
    if (edits.back().span.begin == first_word && edits.back().text.empty())
      while (blank(edits.back().span.end)) ++edits.back().span.end;
  }
}

ProgramWriter::ProgramWriter(LineSource reader, std::FILE* out, std::string header)
    : reader_(std::move(reader)), out_(out), header_(std::move(header)) {}

void ProgramWriter::edit(std::uint64_t line_offset, std::span<Edit> edits) {
  if (line_offset < next_offset_) throw Error(ErrorKind::internal, "an edit arrived for a line already written");
  // After the pending edits of its line and of the lines before it (nearly always at the end).
  // (Room made first: the two lists cannot fall out of step on an allocation that fails.)
  pending_.reserve(pending_.size() + edits.size());
  pending_offsets_.reserve(pending_offsets_.size() + edits.size());
  const auto at = std::upper_bound(pending_offsets_.begin(), pending_offsets_.end(), line_offset);
  const auto index = at - pending_offsets_.begin();
  pending_offsets_.insert(at, edits.size(), line_offset);
  pending_.insert(pending_.begin() + index, std::make_move_iterator(edits.begin()),
                  std::make_move_iterator(edits.end()));
}

void ProgramWriter::take_edits(std::uint64_t line_offset, std::vector<Edit>& edits) {
  if (!pending_.empty() || line_offset < next_offset_) {
    edit(line_offset, std::span<Edit>(edits));
    edits.clear();
    return;
  }
  pending_offsets_.reserve(edits.size());  // (before the swap: nothing can fail after it)
  pending_.swap(edits);
  pending_offsets_.assign(pending_.size(), line_offset);
  edits.clear();
}

void ProgramWriter::write_line(const SourceLine& line, bool terminate) {
  // A UTF-8 byte-order mark stays the file's first bytes, before the header.
  std::size_t skip = 0;
  if (!header_written_) {
    constexpr std::string_view kByteOrderMark = "\xEF\xBB\xBF";
    if (line.offset == 0 && line.text.starts_with(kByteOrderMark)) {
      put(kByteOrderMark.data(), kByteOrderMark.size(), out_);
      skip = kByteOrderMark.size();
    }
    const auto first = line.text.find_first_not_of(" \t", skip);
    const bool percent = first != std::string_view::npos && line.text[first] == '%';
    if (!(percent && line.offset == 0)) {
      const std::string_view terminator = line.terminator.empty() ? std::string_view("\n") : line.terminator;
      put(header_.data(), header_.size(), out_);
      put(terminator.data(), terminator.size(), out_);
      header_written_ = true;
    }
  }
  if (!pending_offsets_.empty() && pending_offsets_.front() < line.offset)
    throw Error(ErrorKind::internal, "an edit arrived for a place no line starts at");
  std::size_t n = 0;
  while (n < pending_offsets_.size() && pending_offsets_[n] == line.offset) ++n;
  if (n > 0) {
    apply_edits(line.text, std::span<Edit>(pending_.data(), n), edited_);
    pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(n));
    pending_offsets_.erase(pending_offsets_.begin(), pending_offsets_.begin() + static_cast<std::ptrdiff_t>(n));
    if (terminate) edited_.append(line.terminator);  // (one write a line)
    put(edited_.data() + skip, edited_.size() - skip, out_);
  } else if (!terminate) {
    put(line.text.data() + skip, line.text.size() - skip, out_);
  } else {
    // The text and its terminator are adjacent in the reader's buffer: one write.
    put(line.text.data() + skip, line.text.size() + line.terminator.size() - skip, out_);
  }
}

void ProgramWriter::check_closed() const {
  if (open_) throw Error(ErrorKind::internal, "a line was left open");
}

void ProgramWriter::write_open(std::uint64_t line_offset, std::span<Edit> edits) {
  edit(line_offset, edits);
  advance_to(line_offset);
  SourceLine line;
  if (!reader_.next(line) || line.offset != line_offset)
    throw Error(ErrorKind::internal, "write_open() was given a place no line starts at");
  write_line(line, false);
  next_offset_ = reader_.tell().offset;
  open_terminator_.assign(line.terminator);
  open_ = true;
}

void ProgramWriter::append(std::string_view text) {
  if (!open_) throw Error(ErrorKind::internal, "append() without an open line");
  put(text.data(), text.size(), out_);
}

void ProgramWriter::close_line() {
  if (!open_) throw Error(ErrorKind::internal, "close_line() without an open line");
  put(open_terminator_.data(), open_terminator_.size(), out_);
  open_ = false;
}

void ProgramWriter::advance_to(std::uint64_t offset) {
  if (offset <= next_offset_) return;
  check_closed();
  SourceLine line;
  while (next_offset_ < offset && reader_.next(line)) {
    write_line(line);
    next_offset_ = reader_.tell().offset;
  }
}

void ProgramWriter::finish() {
  check_closed();
  advance_to(UINT64_MAX);
  if (!pending_.empty()) throw Error(ErrorKind::internal, "an edit arrived for a place no line starts at");
  if (!header_written_) {  // an empty program, or only a `%` line
    put(header_.data(), header_.size(), out_);
    std::fputc('\n', out_);
    header_written_ = true;
  }
  if (std::fflush(out_) != 0 || std::ferror(out_))
    throw Error(ErrorKind::io, std::string("cannot write the output: ") + std::strerror(errno));
}

}  // namespace ccomp::gcode
