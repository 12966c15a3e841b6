// The writer: unedited lines byte for byte, edited lines change only the edited bytes,
// the header goes first or after a leading %.
#include "ccomp/gcode/writer.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "ccomp/error.hpp"
#include "ccomp/gcode/source.hpp"

namespace ccomp::gcode {
namespace {

/// A writer of `program` into memory; text() finishes it and gives what it wrote.
class WriterToMemory {
 public:
  WriterToMemory(const std::string& program, const std::string& header)
      : out_(open_memstream(&buffer_, &size_)),
        source_(LineSource::from_string(program)),
        writer(source_.another_reader(), out_, header) {}
  ~WriterToMemory() {
    if (out_) std::fclose(out_);
    std::free(buffer_);
  }
  WriterToMemory(const WriterToMemory&) = delete;
  WriterToMemory& operator=(const WriterToMemory&) = delete;
  std::string text() {
    writer.finish();
    std::fclose(out_);
    out_ = nullptr;
    return {buffer_, size_};
  }

 private:
  char* buffer_ = nullptr;
  std::size_t size_ = 0;
  std::FILE* out_;
  LineSource source_;

 public:
  ProgramWriter writer;
};

std::string write_program(const std::string& program, const std::string& header,
                          const std::vector<std::pair<std::uint64_t, std::vector<Edit>>>& edits = {}) {
  WriterToMemory memory(program, header);
  for (const auto& [offset, e] : edits) memory.writer.edit(offset, e);
  return memory.text();
}

TEST(Writer, CopiesUneditedLinesByteForByte) {
  const std::string program = "G0  x1.000 (keep)\r\n\tg1 Y2 ; tail\r\n\r\nM2";
  EXPECT_EQ(write_program(program, "(H)"), "(H)\r\n" + program);
}

TEST(Writer, HeaderGoesAfterALeadingPercent) {
  EXPECT_EQ(write_program("%\nG0 X1\n%\n", "(H)"), "%\n(H)\nG0 X1\n%\n");
  EXPECT_EQ(write_program("", "(H)"), "(H)\n");
}

TEST(Writer, EditsReplaceOnlyTheirBytes) {
  const std::string program = "G0 X1\nG1 x 1 . 5 (c) Y2 F100\nM2\n";
  // line 2 starts at byte 6; in it "1 . 5" is at [5, 10) and "2" at [16, 17)
  const std::string out = write_program(program, "(H)", {{6, {Edit{{5, 10}, "1.5003"}, Edit{{16, 17}, "1.9998"}}}});
  EXPECT_EQ(out, "(H)\nG0 X1\nG1 x 1.5003 (c) Y1.9998 F100\nM2\n");
}

TEST(Writer, ApplyEditsSortsAndKeepsTheRest) {
  EXPECT_EQ(apply_edits("abcdef", {Edit{{4, 5}, "E"}, Edit{{0, 1}, "A"}}), "AbcdEf");
  EXPECT_EQ(apply_edits("abc", {}), "abc");
  // Shorter and longer replacements, an insertion and a removal, out of order: the line's
  // length is worked out before the pieces are copied.
  EXPECT_EQ(apply_edits("G1 X1.5 Y2 Z-3",
                        {Edit{{12, 14}, "-3.0000"}, Edit{{4, 7}, "1"}, Edit{{7, 10}, ""}, Edit{{14, 14}, " B0.5"}}),
            "G1 X1 Z-3.0000 B0.5");
  EXPECT_EQ(apply_edits("X123456789", {Edit{{1, 10}, "1"}}), "X1");
  EXPECT_THROW((void)apply_edits("abc", {Edit{{2, 5}, "x"}}), Error);
  EXPECT_THROW((void)apply_edits("abcdef", {Edit{{1, 4}, "x"}, Edit{{3, 5}, "y"}}), Error);
}

TEST(Writer, AnOpenLineTakesTextUntilClosedThenEndsWithItsOwnTerminator) {
  // What a move in parts writes: its line, edited, then the lines of its parts as they
  // come, then the line's own terminator; the lines after it as they were.
  WriterToMemory memory("G0 X1\r\nG2 X5 (arc)\r\nM2\r\n", "(H)");
  ProgramWriter& writer = memory.writer;
  std::vector<Edit> edits{Edit{{4, 5}, "4.9"}};
  writer.write_open(7, edits);
  writer.append("\r\nG1 X5.1");
  EXPECT_THROW(writer.advance_to(100), Error) << "nothing else may be written while a line is open";
  writer.append("\r\nG1 X5.2");
  writer.close_line();
  EXPECT_THROW(writer.append("x"), Error);
  EXPECT_EQ(memory.text(), "(H)\r\nG0 X1\r\nG2 X4.9 (arc)\r\nG1 X5.1\r\nG1 X5.2\r\nM2\r\n");
}

TEST(Writer, EditsTakenWholeJoinTheOnesWaitingInOrder) {
  // take_edits() trades storage with the writer where nothing waits; where edits wait, they
  // keep their lines' order and, on one line, their order of arrival. The caller is left
  // with none.
  WriterToMemory memory("G0 X1\nG1 X2 Y3\nG1 X4\nM2\n", "(H)");
  ProgramWriter& writer = memory.writer;
  std::vector<Edit> edits{Edit{{4, 5}, "4.1"}};
  writer.take_edits(15, edits);  // nothing waits: taken whole
  EXPECT_TRUE(edits.empty());
  edits = {Edit{{4, 5}, "2.1"}, Edit{{8, 8}, " A1"}};
  writer.take_edits(6, edits);  // a line before the waiting one: before it
  EXPECT_TRUE(edits.empty());
  edits = {Edit{{8, 8}, " B2"}};
  writer.take_edits(6, edits);  // the same line, one insertion at the same place: after it
  writer.advance_to(6);
  EXPECT_THROW(writer.take_edits(0, edits = {Edit{{4, 5}, "9"}}), Error) << "line 1 is written already";
  EXPECT_EQ(memory.text(), "(H)\nG0 X1\nG1 X2.1 Y3 A1 B2\nG1 X4.1\nM2\n");
}

TEST(Writer, RefusesAnEditForALineAlreadyWritten) {
  std::FILE* out = std::tmpfile();
  LineSource source = LineSource::from_string("G0 X1\nG0 X2\n");
  ProgramWriter writer(source.another_reader(), out, "(H)");
  writer.advance_to(6);
  EXPECT_THROW(writer.edit(0, {Edit{{4, 5}, "9"}}), Error);
  std::fclose(out);
}

TEST(LineSource, SplitsLinesKeepingTerminatorsAndSeeks) {
  LineSource s = LineSource::from_string("a\r\nb\nc");
  SourceLine l;
  ASSERT_TRUE(s.next(l));
  EXPECT_EQ(l.text, "a");
  EXPECT_EQ(l.terminator, "\r\n");
  const SourcePosition after_a = s.tell();
  ASSERT_TRUE(s.next(l));
  EXPECT_EQ(l.text, "b");
  EXPECT_EQ(l.number, 2U);
  ASSERT_TRUE(s.next(l));
  EXPECT_EQ(l.text, "c");
  EXPECT_EQ(l.terminator, "");
  EXPECT_FALSE(s.next(l));
  s.seek(after_a);
  ASSERT_TRUE(s.next(l));
  EXPECT_EQ(l.text, "b");
  EXPECT_EQ(l.offset, 3U);
}

TEST(LineSource, FileReaderHandlesLinesUpToTheLimitAndRefusesLongerOnesWhileReading) {
  const std::string path = std::string(std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp") + "/ccomp-long-line.ngc";
  // A line of exactly kMaxLineBytes fills the first buffer: it grows once and reads it.
  const std::string long_line(kMaxLineBytes - 2, 'x');
  std::FILE* f = std::fopen(path.c_str(), "wb");
  std::fputs(("(" + long_line + ")\r\nG0 X1\n").c_str(), f);
  std::fclose(f);
  {
    LineSource s = LineSource::open(path);
    SourceLine l;
    ASSERT_TRUE(s.next(l));
    EXPECT_EQ(l.text.size(), kMaxLineBytes);
    ASSERT_TRUE(s.next(l));
    EXPECT_EQ(l.text, "G0 X1");
    EXPECT_FALSE(s.next(l));
  }
  // Longer, it is refused at its line while reading, not held whole (a file without a
  // newline, /dev/zero, grew the buffer until bad_alloc).
  f = std::fopen(path.c_str(), "wb");
  std::fputs(("G0 X1\n(" + std::string(3 << 20, 'x') + ")\n").c_str(), f);
  std::fclose(f);
  LineSource s = LineSource::open(path);
  SourceLine l;
  ASSERT_TRUE(s.next(l));
  try {
    (void)s.next(l);
    ADD_FAILURE() << "a line of 3 MiB was read";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::program);
    EXPECT_EQ(e.where().line, 2u);
  }
  std::remove(path.c_str());
}

}  // namespace
}  // namespace ccomp::gcode
