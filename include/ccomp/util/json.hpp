#pragma once
// A JSON text written in order: objects, arrays, keys and values, commas and escapes
// taken care of. Numbers that are not finite are written as null (JSON has no NaN).
#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace ccomp::util {

class JsonWriter {
 public:
  JsonWriter& begin_object();
  JsonWriter& end_object();
  JsonWriter& begin_array();
  JsonWriter& end_array();
  JsonWriter& key(std::string_view name);
  JsonWriter& value(double number);
  template <class Integer>
  requires(std::is_integral_v<Integer> && !std::is_same_v<Integer, bool>) JsonWriter& value(Integer number) {
    return integer(static_cast<std::int64_t>(number));
  }
  JsonWriter& value(bool flag);
  JsonWriter& value(std::string_view text);
  JsonWriter& value(const char* text) { return value(std::string_view(text)); }
  JsonWriter& null();
  /// key(name).value(v), for the common case.
  template <class T>
  JsonWriter& field(std::string_view name, const T& v) {
    key(name);
    return value(v);
  }
  /// The text, with a final newline once every object and array is closed.
  [[nodiscard]] std::string text() const;

 private:
  JsonWriter& integer(std::int64_t number);
  JsonWriter& open(char bracket);
  JsonWriter& close(char bracket);
  void before_value();
  std::string out_;
  std::vector<bool> first_;  ///< per open object/array: nothing written in it yet
  bool after_key_ = false;
};

/// `text` as a JSON string literal, quotes included.
[[nodiscard]] std::string json_quoted(std::string_view text);

}  // namespace ccomp::util
