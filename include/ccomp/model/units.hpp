#pragma once
// Units of the machine model file. Inside ccomp a length is in mm, an angle in rad, a time
// in s, a temperature in degC; a file may write any of the units below, and a unit that
// does not fit the quantity (an angle where a length belongs) is refused by name.
#include <array>
#include <optional>
#include <string>
#include <string_view>

namespace ccomp::model {

/// Powers of length, angle, time and temperature: um/degC is {1, 0, 0, -1}.
struct Dimension {
  std::array<int, 4> powers{};
  friend bool operator==(const Dimension&, const Dimension&) = default;
  [[nodiscard]] Dimension operator*(const Dimension& o) const;
  [[nodiscard]] Dimension operator/(const Dimension& o) const;
  [[nodiscard]] Dimension pow(int k) const;
  [[nodiscard]] std::string describe() const;  ///< "length", "angle / temperature", ...
};

inline constexpr Dimension kDimensionless{{0, 0, 0, 0}};
inline constexpr Dimension kLength{{1, 0, 0, 0}};
inline constexpr Dimension kAngle{{0, 1, 0, 0}};
inline constexpr Dimension kTime{{0, 0, 1, 0}};
inline constexpr Dimension kTemperature{{0, 0, 0, 1}};

/// A unit: how many internal units one of it is, and what it measures.
struct Unit {
  double scale = 1.0;
  Dimension dimension;
};

/// Parses "um", "urad", "arcsec", "deg", "mm/m", "um/degC", "1/degC", "um/mm^2"...
/// nullopt for an unknown unit.
[[nodiscard]] std::optional<Unit> parse_unit(std::string_view text);

/// Parses "350 mm", "-3.5 urad", "20 degC" (or a bare number in `default_unit`) into
/// internal units, checking the dimension. Throws ccomp::Error (model) naming `what`.
[[nodiscard]] double parse_quantity(std::string_view text, const Dimension& expected, std::string_view default_unit,
                                    const std::string& what);

}  // namespace ccomp::model
