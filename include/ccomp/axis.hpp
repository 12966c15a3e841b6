#pragma once
// The nine axes a program and a machine model name (RS-274's X Y Z A B C U V W) as a type:
// an axis, a set of axes, an array indexed by axis. Programs give A B C in degrees and the
// others in lengths; whether a machine's axis turns is its model's to say (AxisSpec::type),
// and the model refuses a type its letter's program words would contradict.
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <iterator>
#include <optional>
#include <string>
#include <string_view>

namespace ccomp {

enum class Axis : std::uint8_t { X, Y, Z, A, B, C, U, V, W };

inline constexpr std::size_t kAxisCount = 9;
inline constexpr std::string_view kAxisLetters = "XYZABCUVW";
inline constexpr std::array<Axis, kAxisCount> kAllAxes = {Axis::X, Axis::Y, Axis::Z, Axis::A, Axis::B,
                                                          Axis::C, Axis::U, Axis::V, Axis::W};

/// The axis' place in X Y Z A B C U V W (arrays of all nine axes are in that order).
[[nodiscard]] constexpr std::size_t index(Axis a) {
  return static_cast<std::size_t>(a);
}
[[nodiscard]] constexpr char letter(Axis a) {
  return kAxisLetters[index(a)];
}
/// The axis of an upper-case letter; nothing for any other character.
[[nodiscard]] constexpr std::optional<Axis> axis_named(char letter) {
  const std::size_t i = kAxisLetters.find(letter);
  if (i == std::string_view::npos) return std::nullopt;
  return static_cast<Axis>(i);
}
/// The place of a letter already known to be an axis' (a validated model's axes and links;
/// any other letter throws std::bad_optional_access).
[[nodiscard]] constexpr std::size_t index_of_letter(char letter) {
  return index(axis_named(letter).value());
}
/// The axis at place i of X Y Z A B C U V W; nothing past W.
[[nodiscard]] constexpr std::optional<Axis> axis_at(std::size_t i) {
  if (i >= kAxisCount) return std::nullopt;
  return static_cast<Axis>(i);
}
/// Whether a program's words for this axis are angles (A B C, degrees) rather than lengths.
[[nodiscard]] constexpr bool angular_in_programs(Axis a) {
  return a == Axis::A || a == Axis::B || a == Axis::C;
}
/// Whether place i of X Y Z A B C U V W holds an angle (A B C): where a program's words, the
/// files' axis columns and the chain's joint vector (ChainQ, in rad) keep angles.
[[nodiscard]] constexpr bool angular_at(std::size_t i) {
  return i < kAxisCount && angular_in_programs(static_cast<Axis>(i));
}

/// A set of axes (which a program turns, which a machine holds...), iterated in X..W order.
class AxisSet {
 public:
  constexpr AxisSet() = default;
  constexpr AxisSet(std::initializer_list<Axis> axes) {
    for (const Axis a : axes) insert(a);
  }
  constexpr void insert(Axis a) { bits_ = static_cast<std::uint16_t>(bits_ | bit(a)); }
  constexpr void erase(Axis a) { bits_ = static_cast<std::uint16_t>(bits_ & ~bit(a)); }
  [[nodiscard]] constexpr bool contains(Axis a) const { return (bits_ & bit(a)) != 0; }
  /// The axis at place i of X..W (arrays of all nine axes are in that order); i past W is no axis.
  constexpr void insert_at(std::size_t i) {
    if (const std::optional<Axis> a = axis_at(i)) insert(*a);
  }
  [[nodiscard]] constexpr bool contains_at(std::size_t i) const {
    const std::optional<Axis> a = axis_at(i);
    return a && contains(*a);
  }
  constexpr AxisSet& operator|=(AxisSet other) {
    bits_ = static_cast<std::uint16_t>(bits_ | other.bits_);
    return *this;
  }
  /// The axes of this set that are not in `other`.
  [[nodiscard]] constexpr AxisSet operator-(AxisSet other) const {
    AxisSet out;
    out.bits_ = static_cast<std::uint16_t>(bits_ & ~other.bits_);
    return out;
  }
  constexpr AxisSet& operator-=(AxisSet other) { return *this = *this - other; }
  [[nodiscard]] constexpr AxisSet operator|(AxisSet other) const { return AxisSet(*this) |= other; }
  [[nodiscard]] constexpr bool empty() const { return bits_ == 0; }
  [[nodiscard]] constexpr std::size_t size() const { return static_cast<std::size_t>(std::popcount(bits_)); }
  /// The letters of the set's axes in X..W order ("AC").
  [[nodiscard]] std::string letters() const {
    std::string out;
    for (const Axis a : kAllAxes)
      if (contains(a)) out += letter(a);
    return out;
  }
  [[nodiscard]] constexpr bool operator==(const AxisSet&) const = default;

  /// Iterates the set's axes in X..W order.
  class Iterator {
   public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = Axis;
    using difference_type = std::ptrdiff_t;
    using pointer = const Axis*;
    using reference = Axis;
    constexpr Iterator() = default;
    constexpr Iterator(std::uint16_t bits, std::size_t at) : bits_(bits), at_(at) { skip(); }
    [[nodiscard]] constexpr Axis operator*() const { return static_cast<Axis>(at_); }
    constexpr Iterator& operator++() {
      ++at_;
      skip();
      return *this;
    }
    constexpr Iterator operator++(int) {
      Iterator before = *this;
      ++*this;
      return before;
    }
    [[nodiscard]] constexpr bool operator==(const Iterator&) const = default;

   private:
    constexpr void skip() {
      while (at_ < kAxisCount && (bits_ >> at_ & 1U) == 0) ++at_;
    }
    std::uint16_t bits_ = 0;
    std::size_t at_ = kAxisCount;
  };
  [[nodiscard]] constexpr Iterator begin() const { return {bits_, 0}; }
  [[nodiscard]] constexpr Iterator end() const { return {bits_, kAxisCount}; }

 private:
  [[nodiscard]] static constexpr std::uint16_t bit(Axis a) { return static_cast<std::uint16_t>(1U << index(a)); }
  std::uint16_t bits_ = 0;
};

/// One value per axis, in X..W order, indexed by Axis (or by place, as the std::array it is).
template <typename T>
struct AxisArray : std::array<T, kAxisCount> {
  using std::array<T, kAxisCount>::operator[];
  [[nodiscard]] constexpr T& operator[](Axis a) { return (*this)[index(a)]; }
  [[nodiscard]] constexpr const T& operator[](Axis a) const { return (*this)[index(a)]; }
};

}  // namespace ccomp
