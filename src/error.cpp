#include "ccomp/error.hpp"

#include <fmt/format.h>

namespace ccomp {
namespace {

std::string headline(ErrorKind kind, const std::string& message, const SourceLocation& where) {
  std::string prefix;
  if (!where.file.empty()) prefix = where.file + ":";
  if (where.line > 0) prefix += fmt::format("{}:", where.line);
  if (where.column > 0) prefix += fmt::format("{}:", where.column);
  if (!prefix.empty()) prefix += " ";
  const char* label = kind == ErrorKind::safety ? "refused" : "error";
  return fmt::format("{}{}: {}", prefix, label, message);
}

/// An error about a whole line (a block, a row) points at where its text starts.
SourceLocation at_start(SourceLocation where, const std::string& source_line) {
  if (where.line > 0 && where.column == 0)
    if (const auto first = source_line.find_first_not_of(" \t"); first != std::string::npos)
      where.column = static_cast<std::uint32_t>(first + 1);
  return where;
}

}  // namespace

Error::Error(ErrorKind kind, std::string message, SourceLocation where, std::string source_line)
    : std::runtime_error(headline(kind, message, at_start(where, source_line))),
      kind_(kind),
      message_(std::move(message)),
      where_(at_start(std::move(where), source_line)),
      source_line_(std::move(source_line)) {}

std::string format_error(const Error& error) {
  std::string out = error.what();
  if (!error.source_line().empty()) {
    out += "\n  ";
    out += error.source_line();
    if (error.where().column > 0) {
      out += "\n  ";
      // Keep tabs so the caret lines up under tab-indented text.
      for (std::uint32_t i = 0; i + 1 < error.where().column && i < error.source_line().size(); ++i)
        out += error.source_line()[i] == '\t' ? '\t' : ' ';
      out += '^';
    }
  }
  return out;
}

}  // namespace ccomp
