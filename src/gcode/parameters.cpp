#include "ccomp/gcode/parameters.hpp"

#include <algorithm>

namespace ccomp::gcode {

Parameters::Parameters() {
  locals_.emplace_back();
}

std::optional<double> Parameters::named(std::string_view name) const {
  const NamedValues& scope = name.starts_with('_') ? globals_ : locals_.back();
  if (auto it = scope.find(name); it != scope.end()) return it->second;
  return std::nullopt;
}

void Parameters::set_named(std::string_view name, double v) {
  NamedValues& scope = name.starts_with('_') ? globals_ : locals_.back();
  if (auto it = scope.find(name); it != scope.end())
    it->second = v;
  else
    scope.emplace(std::string(name), v);
}

void Parameters::push_scope() {
  locals_.emplace_back();
  std::array<double, 30> saved{};
  std::copy_n(numbered_.begin() + 1, 30, saved.begin());
  saved_arguments_.push_back(saved);
}

void Parameters::pop_scope() {
  if (locals_.size() <= 1) return;
  locals_.pop_back();
  std::copy_n(saved_arguments_.back().begin(), 30, numbered_.begin() + 1);
  saved_arguments_.pop_back();
}

}  // namespace ccomp::gcode
