#pragma once
// SHA-256 (FIPS 180-4), to name a machine model by its content in compensated programs.
#include <string>
#include <string_view>

namespace ccomp::util {

/// Lower-case hex digest of `data`.
[[nodiscard]] std::string sha256_hex(std::string_view data);

}  // namespace ccomp::util
