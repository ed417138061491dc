#include "isoforge/core/data_array.hpp"

#include <cmath>
#include <limits>
#include <type_traits>
#include <vector>

#include "core/detail/ranges.hpp"
#include "isoforge/core/parallel.hpp"

namespace isoforge {

namespace {
constexpr std::string_view kNames[] = {"Int8",   "UInt8",  "Int16", "UInt16",  "Int32",
                                       "UInt32", "Int64",  "UInt64", "Float32", "Float64"};
constexpr std::size_t kSizes[] = {1, 1, 2, 2, 4, 4, 8, 8, 4, 8};

template <class T>
Buffer<T> make_buffer(std::size_t n, bool zero) {
  Buffer<T> b;
  if (zero) {
    b.resize(n, T{});
  } else {
    b.resize(n);
  }
  return b;
}

DataArray::Storage make_storage(ScalarType type, std::size_t n, bool zero) {
  switch (type) {
    case ScalarType::Int8: return make_buffer<std::int8_t>(n, zero);
    case ScalarType::UInt8: return make_buffer<std::uint8_t>(n, zero);
    case ScalarType::Int16: return make_buffer<std::int16_t>(n, zero);
    case ScalarType::UInt16: return make_buffer<std::uint16_t>(n, zero);
    case ScalarType::Int32: return make_buffer<std::int32_t>(n, zero);
    case ScalarType::UInt32: return make_buffer<std::uint32_t>(n, zero);
    case ScalarType::Int64: return make_buffer<std::int64_t>(n, zero);
    case ScalarType::UInt64: return make_buffer<std::uint64_t>(n, zero);
    case ScalarType::Float32: return make_buffer<float>(n, zero);
    case ScalarType::Float64: return make_buffer<double>(n, zero);
  }
  throw Error("DataArray: invalid scalar type");
}
}  // namespace

std::size_t scalar_size(ScalarType t) { return kSizes[static_cast<int>(t)]; }
std::string_view scalar_type_name(ScalarType t) { return kNames[static_cast<int>(t)]; }
bool is_floating(ScalarType t) { return t == ScalarType::Float32 || t == ScalarType::Float64; }

ScalarType scalar_type_from_name(std::string_view name) {
  for (int i = 0; i < 10; ++i) {
    if (kNames[i] == name) return static_cast<ScalarType>(i);
  }
  throw Error("unknown scalar type '" + std::string(name) + "'");
}

DataArray::DataArray(std::string name, ScalarType type, int components, std::size_t tuples)
    : name_(std::move(name)), components_(components) {
  if (components < 1) throw Error("DataArray '" + name_ + "': components must be >= 1");
  storage_ = make_storage(type, tuples * static_cast<std::size_t>(components), true);
}

DataArray DataArray::uninitialized(std::string name, ScalarType type, int components, std::size_t tuples) {
  DataArray a;
  a.name_ = std::move(name);
  if (components < 1) throw Error("DataArray '" + a.name_ + "': components must be >= 1");
  a.components_ = components;
  a.storage_ = make_storage(type, tuples * static_cast<std::size_t>(components), false);
  return a;
}

std::size_t DataArray::size() const {
  return std::visit([](const auto& v) { return v.size(); }, storage_);
}

void DataArray::resize(std::size_t tuples) {
  std::visit(
      [&](auto& v) {
        using T = typename std::decay_t<decltype(v)>::value_type;
        v.resize(tuples * static_cast<std::size_t>(components_), T{});
      },
      storage_);
}

void DataArray::reserve(std::size_t tuples) {
  std::visit([&](auto& v) { v.reserve(tuples * static_cast<std::size_t>(components_)); }, storage_);
}

const std::byte* DataArray::bytes() const {
  return std::visit([](const auto& v) { return reinterpret_cast<const std::byte*>(v.data()); },
                    storage_);
}

std::byte* DataArray::bytes() {
  return std::visit([](auto& v) { return reinterpret_cast<std::byte*>(v.data()); }, storage_);
}

double DataArray::get(std::size_t tuple, int component) const {
  const std::size_t i = tuple * static_cast<std::size_t>(components_) + static_cast<std::size_t>(component);
  return std::visit([i](const auto& v) { return static_cast<double>(v[i]); }, storage_);
}

void DataArray::set(std::size_t tuple, int component, double value) {
  const std::size_t i = tuple * static_cast<std::size_t>(components_) + static_cast<std::size_t>(component);
  std::visit(
      [i, value](auto& v) {
        using T = typename std::decay_t<decltype(v)>::value_type;
        v[i] = static_cast<T>(value);
      },
      storage_);
}

void DataArray::push_back(std::span<const double> tuple) {
  if (tuple.size() != static_cast<std::size_t>(components_)) {
    throw Error("DataArray '" + name_ + "': push_back of " + std::to_string(tuple.size()) +
                " values into an array of " + std::to_string(components_) + " components");
  }
  std::visit(
      [&](auto& v) {
        using T = typename std::decay_t<decltype(v)>::value_type;
        for (double x : tuple) v.push_back(static_cast<T>(x));
      },
      storage_);
}


std::pair<double, double> DataArray::range(int component) const {
  const std::size_t nc = static_cast<std::size_t>(components_);
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  std::visit(
      [&](const auto& v) {
        const std::size_t n = v.size() / nc;
        if (n == 0) return;
        const auto part = [&](std::size_t b, std::size_t e) {
          return component < 0
                     ? core_detail::magnitude_range(v.data(), nc, b, e)
                     : core_detail::column_range(v.data() + component, nc, b, e);
        };
        // Pieces of 64k tuples on all threads; min and max do not depend on the order.
        constexpr std::size_t kPiece = std::size_t{1} << 16;
        const std::size_t pieces = (n + kPiece - 1) / kPiece;
        std::vector<std::pair<double, double>> r(pieces);
        if (pieces == 1) {
          r[0] = part(0, n);
        } else {
          parallel_for_range(pieces, 1, [&](std::size_t b, std::size_t e) {
            for (std::size_t p = b; p < e; ++p) r[p] = part(p * kPiece, std::min(n, (p + 1) * kPiece));
          });
        }
        for (const auto& [a, z] : r) {
          lo = std::min(lo, a);
          hi = std::max(hi, z);
        }
      },
      storage_);
  return {lo, hi};
}

DataArray DataArray::converted(ScalarType type) const {
  DataArray out(name_, type, components_, tuples());
  out.lookup_table_ = lookup_table_;
  std::visit(
      [&](const auto& src) {
        std::visit(
            [&](auto& dst) {
              using D = typename std::decay_t<decltype(dst)>::value_type;
              for (std::size_t i = 0; i < src.size(); ++i) dst[i] = static_cast<D>(src[i]);
            },
            out.storage_);
      },
      storage_);
  return out;
}

void DataArray::type_mismatch(ScalarType requested) const {
  throw Error("DataArray '" + name_ + "': stored as " + std::string(scalar_type_name(type())) +
              ", accessed as " + std::string(scalar_type_name(requested)));
}

}  // namespace isoforge
