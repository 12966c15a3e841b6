#include "ccomp/gcode/source.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <utility>

#include "ccomp/error.hpp"

namespace ccomp::gcode {
namespace {

constexpr std::size_t kChunk = 1 << 20;

std::shared_ptr<const int> share_fd(int fd) {
  return std::shared_ptr<const int>(new int(fd), [](const int* p) {
    ::close(*p);
    delete p;
  });
}

}  // namespace

LineSource LineSource::open(const std::string& path) {
  LineSource s;
  s.name_ = path == "-" ? "<stdin>" : path;
  int fd = -1;
  if (path == "-") {
    // Spool stdin to an unnamed file so the program can be seeked and read twice.
    std::FILE* tmp = std::tmpfile();
    if (!tmp) throw Error(ErrorKind::io, "cannot create a temporary file to spool standard input");
    std::vector<char> chunk(kChunk);
    std::size_t n = 0;
    while ((n = std::fread(chunk.data(), 1, chunk.size(), stdin)) > 0)
      if (std::fwrite(chunk.data(), 1, n, tmp) != n)
        throw Error(ErrorKind::io, "cannot spool standard input to a temporary file");
    std::fflush(tmp);
    fd = ::dup(fileno(tmp));
    std::fclose(tmp);
  } else {
    fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw Error(ErrorKind::io, "cannot open '" + path + "': " + std::strerror(errno));
  }
  s.fd_ = share_fd(fd);
  const off_t end = ::lseek(fd, 0, SEEK_END);
  if (end < 0) throw Error(ErrorKind::io, "cannot read '" + s.name_ + "': not a regular file");
  s.size_ = static_cast<std::uint64_t>(end);
  s.buffer_.resize(kChunk);
  return s;
}

LineSource LineSource::from_string(std::string text, std::string name) {
  LineSource s;
  s.name_ = std::move(name);
  s.size_ = text.size();
  s.memory_ = std::make_shared<const std::string>(std::move(text));
  return s;
}

LineSource LineSource::another_reader() const {
  LineSource s;
  s.name_ = name_;
  s.fd_ = fd_;
  s.memory_ = memory_;
  s.size_ = size_;
  if (fd_) s.buffer_.resize(kChunk);
  return s;
}

bool LineSource::fill() {
  // Move the unread tail to the front, grow when one line fills the buffer, read more.
  if (eof_) return false;
  const std::size_t tail = end_ - begin_;
  if (begin_ > 0) {
    std::memmove(buffer_.data(), buffer_.data() + begin_, tail);
    buffer_offset_ += begin_;
    begin_ = 0;
    end_ = tail;
  }
  if (end_ == buffer_.size()) {
    // A line end may still come (CRLF: one byte more), but a tail longer than that is a
    // line no program has: refused here, before the buffer grows again.
    if (tail > kMaxLineBytes + 1)
      throw Error(ErrorKind::program,
                  "a line of more than " + std::to_string(kMaxLineBytes) +
                      " bytes without a line end: not a line of G-code (a binary file, or /dev/zero?)",
                  SourceLocation{name_, position_.line, static_cast<std::uint32_t>(kMaxLineBytes + 1)});
    buffer_.resize(buffer_.size() * 2);
  }
  ssize_t n = 0;
  do {
    n = ::pread(*fd_, buffer_.data() + end_, buffer_.size() - end_, static_cast<off_t>(read_offset_));
  } while (n < 0 && errno == EINTR);
  if (n < 0) throw Error(ErrorKind::io, "cannot read '" + name_ + "': " + std::strerror(errno));
  if (n == 0) eof_ = true;
  end_ += static_cast<std::size_t>(n);
  read_offset_ += static_cast<std::uint64_t>(n);
  return n > 0;
}

bool LineSource::next(SourceLine& line) {
  if (memory_) {
    const std::string& m = *memory_;
    if (position_.offset >= m.size()) return false;
    const std::size_t start = position_.offset;
    const std::size_t nl = m.find('\n', start);
    const std::size_t stop = nl == std::string::npos ? m.size() : nl;
    const std::string_view all(m);
    line.text = all.substr(start, stop - start);
    line.terminator = nl == std::string::npos ? std::string_view{} : all.substr(nl, 1);
    if (!line.text.empty() && line.text.back() == '\r' && !line.terminator.empty()) {
      line.text.remove_suffix(1);
      line.terminator = all.substr(nl - 1, 2);
    }
    line.offset = start;
    line.number = position_.line;
    line.file = name_;
    position_.offset = nl == std::string::npos ? m.size() : nl + 1;
    ++position_.line;
    return true;
  }
  for (;;) {
    const char* data = buffer_.data();
    const void* nl = std::memchr(data + begin_, '\n', end_ - begin_);
    if (nl || eof_) {
      const auto stop = nl ? static_cast<std::size_t>(static_cast<const char*>(nl) - data) : end_;
      if (!nl && stop == begin_) return false;
      line.text = std::string_view(data + begin_, stop - begin_);
      line.terminator = nl ? std::string_view(data + stop, 1) : std::string_view{};
      if (nl && !line.text.empty() && line.text.back() == '\r') {
        line.text.remove_suffix(1);
        line.terminator = std::string_view(data + stop - 1, 2);
      }
      line.offset = buffer_offset_ + begin_;
      line.number = position_.line;
      line.file = name_;
      begin_ = nl ? stop + 1 : stop;
      position_.offset = buffer_offset_ + begin_;
      ++position_.line;
      return true;
    }
    fill();
  }
}

void LineSource::seek(SourcePosition position) {
  position_ = position;
  if (memory_) return;
  if (position.offset >= buffer_offset_ && position.offset <= buffer_offset_ + end_) {
    begin_ = static_cast<std::size_t>(position.offset - buffer_offset_);
    return;
  }
  buffer_offset_ = read_offset_ = position.offset;
  begin_ = end_ = 0;
  eof_ = false;
}

}  // namespace ccomp::gcode
