#pragma once
/// \file
/// `DataArray`: a named, typed, contiguous array of tuples (the attribute storage of every
/// dataset, and the storage of points).

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "isoforge/core/buffer.hpp"
#include "isoforge/core/error.hpp"

namespace isoforge {

/// Element type of a `DataArray`. Names follow VTK XML (`Float32`, `Int64`, ...).
enum class ScalarType : std::uint8_t {
  Int8,
  UInt8,
  Int16,
  UInt16,
  Int32,
  UInt32,
  Int64,
  UInt64,
  Float32,
  Float64,
};

/// Size of one element in bytes.
[[nodiscard]] std::size_t scalar_size(ScalarType t);
/// VTK XML name, e.g. "Float32".
[[nodiscard]] std::string_view scalar_type_name(ScalarType t);
/// Parses a VTK XML type name ("Float32", "UInt8", ...); nullopt-like: throws Error when unknown.
[[nodiscard]] ScalarType scalar_type_from_name(std::string_view name);
[[nodiscard]] bool is_floating(ScalarType t);

template <class T>
struct ScalarTypeOf;
template <> struct ScalarTypeOf<std::int8_t> { static constexpr ScalarType value = ScalarType::Int8; };
template <> struct ScalarTypeOf<std::uint8_t> { static constexpr ScalarType value = ScalarType::UInt8; };
template <> struct ScalarTypeOf<std::int16_t> { static constexpr ScalarType value = ScalarType::Int16; };
template <> struct ScalarTypeOf<std::uint16_t> { static constexpr ScalarType value = ScalarType::UInt16; };
template <> struct ScalarTypeOf<std::int32_t> { static constexpr ScalarType value = ScalarType::Int32; };
template <> struct ScalarTypeOf<std::uint32_t> { static constexpr ScalarType value = ScalarType::UInt32; };
template <> struct ScalarTypeOf<std::int64_t> { static constexpr ScalarType value = ScalarType::Int64; };
template <> struct ScalarTypeOf<std::uint64_t> { static constexpr ScalarType value = ScalarType::UInt64; };
template <> struct ScalarTypeOf<float> { static constexpr ScalarType value = ScalarType::Float32; };
template <> struct ScalarTypeOf<double> { static constexpr ScalarType value = ScalarType::Float64; };

/// Calls f(T{}) with the C++ type T of `t` (generic code over scalar types).
template <class F>
decltype(auto) visit_scalar_type(ScalarType t, F&& f) {
  switch (t) {
    case ScalarType::Int8: return f(std::int8_t{});
    case ScalarType::UInt8: return f(std::uint8_t{});
    case ScalarType::Int16: return f(std::int16_t{});
    case ScalarType::UInt16: return f(std::uint16_t{});
    case ScalarType::Int32: return f(std::int32_t{});
    case ScalarType::UInt32: return f(std::uint32_t{});
    case ScalarType::Int64: return f(std::int64_t{});
    case ScalarType::UInt64: return f(std::uint64_t{});
    case ScalarType::Float32: return f(float{});
    case ScalarType::Float64: break;
  }
  return f(double{});
}

/// A named array of `tuples()` tuples of `components()` values each, stored contiguously
/// (tuple-major: value (t, c) is at index t*components + c) in one of the `ScalarType`s.
///
/// Value type: copies are deep. Typed access goes through `values<T>()`, which checks the
/// type; generic code uses `visit` or the `get`/`set` double accessors.
class DataArray {
 public:
  using Storage = std::variant<Buffer<std::int8_t>, Buffer<std::uint8_t>, Buffer<std::int16_t>,
                               Buffer<std::uint16_t>, Buffer<std::int32_t>, Buffer<std::uint32_t>,
                               Buffer<std::int64_t>, Buffer<std::uint64_t>, Buffer<float>,
                               Buffer<double>>;

  DataArray() = default;
  /// A zero-filled array.
  /// \throw Error if components < 1.
  DataArray(std::string name, ScalarType type, int components, std::size_t tuples = 0);

  /// Takes ownership of `values` (size must be a multiple of `components`).
  /// \throw Error if components < 1 or the size is not a multiple of it.
  template <class T>
  static DataArray from_buffer(std::string name, int components, Buffer<T> values) {
    DataArray a;
    a.name_ = std::move(name);
    if (components < 1) throw Error("DataArray '" + a.name_ + "': components must be >= 1");
    if (values.size() % static_cast<std::size_t>(components) != 0) {
      throw Error("DataArray '" + a.name_ + "': " + std::to_string(values.size()) +
                  " values is not a multiple of " + std::to_string(components) + " components");
    }
    a.components_ = components;
    a.storage_ = std::move(values);
    return a;
  }
  /// Copies `values` (size must be a multiple of `components`). \throw Error as from_buffer.
  template <class T>
  static DataArray from_vector(std::string name, int components, const std::vector<T>& values) {
    return from_buffer(std::move(name), components, Buffer<T>(values.begin(), values.end()));
  }
  /// An array whose values are left uninitialized, for algorithms that write every value.
  /// \throw Error if components < 1.
  [[nodiscard]] static DataArray uninitialized(std::string name, ScalarType type, int components,
                                               std::size_t tuples);

  [[nodiscard]] const std::string& name() const { return name_; }
  void set_name(std::string name) { name_ = std::move(name); }
  [[nodiscard]] ScalarType type() const { return static_cast<ScalarType>(storage_.index()); }
  [[nodiscard]] int components() const { return components_; }
  [[nodiscard]] std::size_t tuples() const { return size() / static_cast<std::size_t>(components_); }
  /// Number of values (tuples * components).
  [[nodiscard]] std::size_t size() const;
  [[nodiscard]] std::size_t size_bytes() const { return size() * scalar_size(type()); }
  [[nodiscard]] bool empty() const { return size() == 0; }

  /// Resizes to `n` tuples (new values are zero).
  void resize(std::size_t tuples);
  void reserve(std::size_t tuples);

  /// Typed view. \throw Error if T is not the stored type.
  template <class T>
  [[nodiscard]] std::span<T> values() {
    auto* v = std::get_if<Buffer<T>>(&storage_);
    if (!v) type_mismatch(ScalarTypeOf<T>::value);
    return {v->data(), v->size()};
  }
  template <class T>
  [[nodiscard]] std::span<const T> values() const {
    auto* v = std::get_if<Buffer<T>>(&storage_);
    if (!v) type_mismatch(ScalarTypeOf<T>::value);
    return {v->data(), v->size()};
  }
  /// Typed storage (for push_back). \throw Error if T is not the stored type.
  template <class T>
  [[nodiscard]] Buffer<T>& vector() {
    auto* v = std::get_if<Buffer<T>>(&storage_);
    if (!v) type_mismatch(ScalarTypeOf<T>::value);
    return *v;
  }

  /// Raw bytes of the storage (host byte order).
  [[nodiscard]] const std::byte* bytes() const;
  [[nodiscard]] std::byte* bytes();

  /// Value (tuple, component) converted to double. Unchecked beyond an assertion in debug.
  [[nodiscard]] double get(std::size_t tuple, int component = 0) const;
  /// Sets value (tuple, component), converting from double (rounded/truncated as C++ does).
  void set(std::size_t tuple, int component, double value);
  /// Appends one tuple given as doubles (size must equal components()).
  void push_back(std::span<const double> tuple);

  /// Calls f(Buffer<T>&) with the concrete storage.
  template <class F>
  decltype(auto) visit(F&& f) {
    return std::visit(std::forward<F>(f), storage_);
  }
  template <class F>
  decltype(auto) visit(F&& f) const {
    return std::visit(std::forward<F>(f), storage_);
  }

  /// [min, max] of one component, or of the tuple magnitude when component == -1. NaNs are
  /// ignored; an empty (or all-NaN) array gives {+inf, -inf}.
  [[nodiscard]] std::pair<double, double> range(int component = 0) const;

  /// A copy converted to another element type (name and components kept).
  [[nodiscard]] DataArray converted(ScalarType type) const;

  /// Optional lookup-table name (VTK legacy `LOOKUP_TABLE name`); "" means default.
  [[nodiscard]] const std::string& lookup_table() const { return lookup_table_; }
  void set_lookup_table(std::string name) { lookup_table_ = std::move(name); }

  friend bool operator==(const DataArray&, const DataArray&) = default;

 private:
  [[noreturn]] void type_mismatch(ScalarType requested) const;

  std::string name_;
  int components_ = 1;
  Storage storage_ = Buffer<float>{};
  std::string lookup_table_;
};

}  // namespace isoforge
