#include "g_codes.hpp"

#include <fmt/format.h>

namespace ccomp::gcode {

int g_group(int code) {
  switch (code) {
    case 0:
    case 10:
    case 20:
    case 30:
    case 330:
    case 331:
    case 382:
    case 383:
    case 384:
    case 385:
    case 730:
    case 760:
    case 800:
    case 810:
    case 820:
    case 830:
    case 840:
    case 850:
    case 860:
    case 870:
    case 880:
    case 890:
    case 50:
    case 51:
    case 52:
      return 1;
    case 170:
    case 171:
    case 180:
    case 181:
    case 190:
    case 191:
      return 2;
    case 900:
    case 910:
      return 3;
    case 901:
    case 911:
      return 4;
    case 930:
    case 940:
    case 950:
      return 5;
    case 200:
    case 210:
      return 6;
    case 400:
    case 410:
    case 411:
    case 420:
    case 421:
      return 7;
    case 430:
    case 431:
    case 432:
    case 490:
      return 8;
    case 980:
    case 990:
      return 10;
    case 540:
    case 550:
    case 560:
    case 570:
    case 580:
    case 590:
    case 591:
    case 592:
    case 593:
      return 12;
    case 610:
    case 611:
    case 640:
      return 13;
    case 960:
    case 970:
      return 14;
    case 70:
    case 80:
      return 15;
    case 40:
    case 100:
    case 280:
    case 281:
    case 300:
    case 301:
    case 520:
    case 530:
    case 920:
    case 921:
    case 922:
    case 923:
      return 0;
    default:
      return -1;
  }
}

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

bool is_cycle(int code) {
  return code == 730 || (code >= 810 && code <= 890);
}

std::string g_name(int code) {
  return code % 10 == 0 ? fmt::format("G{}", code / 10) : fmt::format("G{}.{}", code / 10, code % 10);
}

std::string fixed4(double v) {
  return fmt::format("{:.4f}", v);
}

}  // namespace ccomp::gcode
