#pragma once
// Private: a small JSON value, writer and parser for glTF (objects keep their key order; numbers
// are doubles). The parser limits nesting and reports the byte offset of a problem.

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

namespace isoforge::io_detail {

class Json {
 public:
  using Array = std::vector<Json>;
  using Object = std::vector<std::pair<std::string, Json>>;

  Json() = default;
  Json(std::nullptr_t) {}
  Json(bool b) : value_(b) {}
  Json(double d) : value_(d) {}
  Json(int i) : value_(static_cast<double>(i)) {}
  Json(std::int64_t i) : value_(static_cast<double>(i)) {}
  Json(std::size_t i) : value_(static_cast<double>(i)) {}
  Json(std::string s) : value_(std::move(s)) {}
  Json(std::string_view s) : value_(std::string(s)) {}
  Json(const char* s) : value_(std::string(s)) {}
  Json(Array a) : value_(std::move(a)) {}
  Json(Object o) : value_(std::move(o)) {}
  [[nodiscard]] static Json array() { return Json(Array{}); }
  [[nodiscard]] static Json object() { return Json(Object{}); }

  [[nodiscard]] bool is_null() const { return value_.index() == 0; }
  [[nodiscard]] bool is_bool() const { return value_.index() == 1; }
  [[nodiscard]] bool is_number() const { return value_.index() == 2; }
  [[nodiscard]] bool is_string() const { return value_.index() == 3; }
  [[nodiscard]] bool is_array() const { return value_.index() == 4; }
  [[nodiscard]] bool is_object() const { return value_.index() == 5; }

  [[nodiscard]] bool as_bool() const { return std::get<bool>(value_); }
  [[nodiscard]] double as_number() const { return std::get<double>(value_); }
  [[nodiscard]] const std::string& as_string() const { return std::get<std::string>(value_); }
  [[nodiscard]] const Array& as_array() const { return std::get<Array>(value_); }
  [[nodiscard]] Array& as_array() { return std::get<Array>(value_); }
  [[nodiscard]] const Object& as_object() const { return std::get<Object>(value_); }

  /// Object member `key`, added (null) if missing. Turns a null value into an object.
  Json& operator[](std::string_view key);
  /// Object member or nullptr (also when this is not an object).
  [[nodiscard]] const Json* find(std::string_view key) const;
  /// Appends to an array (a null value becomes an array). Returns the new element's index.
  std::size_t push(Json element);
  [[nodiscard]] std::size_t size() const;

  /// Compact text. Integral numbers below 2^53 print as integers, others with 17 digits.
  [[nodiscard]] std::string dump() const;

 private:
  void dump_to(std::string& out) const;
  std::variant<std::nullptr_t, bool, double, std::string, Array, Object> value_{nullptr};
};

/// Parses `text` (UTF-8, RFC 8259; nesting at most 128). \throw Error
/// "NAME: JSON byte N: problem".
[[nodiscard]] Json parse_json(std::string_view text, std::string_view name);

}  // namespace isoforge::io_detail
