#include "g_codes.hpp"

#include <fmt/format.h>

namespace ccomp::gcode {

/// Modal group of an M code; -1 for codes outside the standard set.
int m_group(int code) {
  switch (code) {
    case 0:
    case 1:
    case 2:
    case 30:
    case 60:
      return 4;
    case 6:
    case 61:
      return 6;
    case 3:
    case 4:
    case 5:
    case 19:
      return 7;
    case 7:
    case 8:
    case 9:
      return 8;
    case 48:
    case 49:
    case 50:
    case 51:
    case 52:
    case 53:
      return 9;
    case 62:
    case 63:
    case 64:
    case 65:
    case 66:
    case 67:
    case 68:
    case 70:
    case 71:
    case 72:
    case 73:
      return 5;
    case 98:
    case 99:
      return 10;
    default:
      return code >= 100 && code <= 199 ? 11 : -1;
  }
}

std::string g_name(int code) {
  return code % 10 == 0 ? fmt::format("G{}", code / 10) : fmt::format("G{}.{}", code / 10, code % 10);
}

std::string fixed4(double v) {
  return fmt::format("{:.4f}", v);
}

}  // namespace ccomp::gcode
