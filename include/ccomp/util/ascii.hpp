#pragma once
// Text in the ASCII letters G-code, the model's keys and the instruments' files use.
#include <cctype>
#include <string>
#include <string_view>

namespace ccomp::util {

/// `text` with its ASCII letters in lower case (bytes beyond ASCII as they are).
[[nodiscard]] inline std::string lower_ascii(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

}  // namespace ccomp::util
