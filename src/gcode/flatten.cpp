#include "ccomp/gcode/flatten.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string_view>

#include "ccomp/gcode/canon.hpp"
#include "ccomp/gcode/writer.hpp"

namespace ccomp::gcode {

void LineOrigins::add(std::uint32_t flat_line, const std::string& file, std::uint32_t line) {
  std::uint32_t index = 0;
  while (index < files_.size() && files_[index] != file) ++index;
  if (index == files_.size()) files_.push_back(file);
  if (!runs_.empty()) {
    Run& last = runs_.back();
    if (last.file == index && last.flat_first + last.count == flat_line && last.line_first + last.count == line) {
      ++last.count;
      return;
    }
  }
  runs_.push_back({flat_line, line, 1, index});
}

SourceLocation LineOrigins::at(std::uint32_t flat_line) const {
  auto after = std::upper_bound(runs_.begin(), runs_.end(), flat_line,
                                [](std::uint32_t f, const Run& r) { return f < r.flat_first; });
  if (after == runs_.begin()) return {{}, flat_line, 0};
  const Run& r = *(after - 1);
  if (flat_line >= r.flat_first + r.count) return {{}, flat_line, 0};
  return {files_[r.file], r.line_first + (flat_line - r.flat_first), 0};
}

std::string flat_number(char letter, double value) {
  static constexpr std::string_view kCodes = "GMTHDNOPLS";
  if (kCodes.find(letter) != std::string_view::npos && value == std::round(value) && std::abs(value) < 1e15)
    return fmt::format("{}", static_cast<long long>(value));
  std::string text = fmt::format("{:.6f}", value);
  while (text.back() == '0' && text[text.size() - 2] != '.') text.pop_back();
  if (text == "-0.0") text = "0.0";
  return text;
}

namespace {

class FlattenSink : public CanonSink {
 public:
  FlattenSink(std::FILE* out, LineOrigins& origins, std::string main_file, std::uint64_t max_bytes)
      : out_(out), origins_(origins), main_file_(std::move(main_file)), max_bytes_(max_bytes) {}

  [[nodiscard]] bool wants_values() const override { return true; }

  void block(const Block& b, const SourceLine& line) override {
    // Not executed, but part of the tape.
    if (b.program_delimiter) write(line.text, line.terminator, main_file_, line.number);
  }

  void values(const Block& b, const SourceLine& line, std::string_view file, std::span<const double> values) override {
    edits_.clear();
    bool call = false, back = false;  // M98, M99
    for (std::size_t k = 0; k < b.words.size(); ++k)
      if (b.words[k].letter == 'M' && b.words[k].has_value) {
        call = call || values[k] == 98;
        back = back || values[k] == 99;
      }
    // A program's number (its name) is executed as a block, and so is a Siemens command.
    bool acts = b.o.present || !b.commands.empty();
    removed_.clear();
    for (std::size_t k = 0; k < b.words.size(); ++k) {
      const Word& w = b.words[k];
      if ((w.letter == 'M' && w.has_value && (values[k] == 98 || values[k] == 99)) ||
          (call && (w.letter == 'P' || w.letter == 'L')) || (back && w.letter == 'P')) {
        removed_.push_back(w.span);
        continue;
      }
      acts = true;
      if (w.has_value && !w.value.is_literal()) edits_.push_back({w.value_span, flat_number(w.letter, values[k])});
    }
    for (const ParameterSetting& s : b.settings) removed_.push_back(s.span);
    removal_edits(b.text, removed_, edits_);
    // A line that only set parameters or called: nothing is left for the machine to do.
    if (!acts && b.comments.empty() && !b.is_empty()) return;
    apply_edits(b.text, edits_, text_);
    write(text_, line.terminator, std::string(file), line.number);
  }

  /// What follows the end of the program is not run, but a closing `%` ends the tape.
  void after_end(LineSource& program) {
    SourceLine line;
    while (program.next(line)) {
      const auto first = line.text.find_first_not_of(" \t");
      if (first != std::string_view::npos && line.text[first] == '%') {
        write(line.text, line.terminator, main_file_, line.number);
        return;
      }
    }
  }

 private:
  void write(std::string_view text, std::string_view terminator, const std::string& file, std::uint32_t line) {
    if (!terminator.empty() && eol_.empty()) eol_ = terminator;
    const std::string_view eol = terminator.empty() ? (eol_.empty() ? std::string_view("\n") : eol_) : terminator;
    bytes_ += text.size() + eol.size();
    if (bytes_ > max_bytes_)
      throw Error(ErrorKind::program,
                  fmt::format("the program as it runs, loops unrolled, is more than {} of G-code here (line {} "
                              "of it): taken for a runaway loop",
                              max_bytes_ >= (1U << 20)   ? fmt::format("{} MiB", max_bytes_ >> 20)
                              : max_bytes_ >= (1U << 10) ? fmt::format("{} kB", max_bytes_ >> 10)
                                                         : fmt::format("{} bytes", max_bytes_),
                              written_ + 1),
                  SourceLocation{file, line, 0}, std::string(text));
    std::fwrite(text.data(), 1, text.size(), out_);
    std::fwrite(eol.data(), 1, eol.size(), out_);
    origins_.add(++written_, file, line);
  }

  std::FILE* out_;
  LineOrigins& origins_;
  std::string main_file_;
  std::string eol_;  ///< the program's line terminator, for a last line that had none
  std::uint32_t written_ = 0;
  std::uint64_t max_bytes_;
  std::uint64_t bytes_ = 0;  ///< written so far
  std::vector<Edit> edits_;
  std::vector<Span> removed_;
  std::string text_;
};

}  // namespace

LineOrigins flatten(LineSource& program, std::FILE* out, const InterpreterOptions& options, std::uint64_t max_bytes) {
  LineOrigins origins;
  FlattenSink sink(out, origins, program.name(), max_bytes);
  InterpreterOptions bounded = options;
  bounded.max_blocks = std::min(options.max_blocks, kFlattenMaxBlocks);
  Interpreter interpreter(bounded);
  interpreter.run(program, sink);
  sink.after_end(program);
  if (std::fflush(out) != 0 || std::ferror(out))
    throw Error(ErrorKind::io, fmt::format("cannot write the flattened form of '{}'", program.name()));
  return origins;
}

}  // namespace ccomp::gcode
