#pragma once
// Private to the interpreter: what G codes are (times ten, as the interpreter keeps them).
#include <string>

namespace ccomp::gcode {

/// Modal group of a G code; -1 when unknown. Group numbers follow RS-274/NGC. (Inline:
/// asked of every G word.)
[[nodiscard]] inline int g_group(int code) {
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
/// Modal group of an M code; -1 when unknown.
[[nodiscard]] int m_group(int code);
/// A canned cycle (G73, G81-G89).
[[nodiscard]] inline bool is_cycle(int code) {
  return code == 730 || (code >= 810 && code <= 890);
}
/// "G81", "G92.1".
[[nodiscard]] std::string g_name(int code);
/// A number as rs274 prints canonical arguments.
[[nodiscard]] std::string fixed4(double v);

}  // namespace ccomp::gcode
