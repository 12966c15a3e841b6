#pragma once
// RS-274/NGC parameters: numbered #1..#5601, global named #<_name>, and named locals that
// live as long as the subroutine call that made them.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace ccomp::gcode {

inline constexpr int kParameterCount = 5602;  ///< valid numbers are 1..5601

struct StringHash {
  using is_transparent = void;
  std::size_t operator()(std::string_view s) const { return std::hash<std::string_view>{}(s); }
};
using NamedValues = std::unordered_map<std::string, double, StringHash, std::equal_to<>>;

class Parameters {
 public:
  Parameters();

  [[nodiscard]] double numbered(int n) const { return numbered_[static_cast<std::size_t>(n)]; }
  void set_numbered(int n, double v) { numbered_[static_cast<std::size_t>(n)] = v; }

  /// A user-defined named parameter: the innermost local scope, or a global when the name
  /// starts with '_'. Names are folded (upper case, no blanks).
  [[nodiscard]] std::optional<double> named(std::string_view name) const;
  void set_named(std::string_view name, double v);

  /// Subroutine calls: a new local scope, and #1..#30 saved and restored around it.
  void push_scope();
  void pop_scope();
  [[nodiscard]] std::size_t depth() const { return locals_.size() - 1; }

 private:
  std::array<double, kParameterCount> numbered_{};
  NamedValues globals_;
  std::vector<NamedValues> locals_;
  std::vector<std::array<double, 30>> saved_arguments_;
};

}  // namespace ccomp::gcode
