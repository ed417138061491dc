#pragma once
/// \file
/// `Buffer<T>`: the contiguous storage of arrays and cell lists — a std::vector whose
/// `resize(n)` leaves new trivial elements uninitialized, so algorithms that write every element
/// (in parallel) do not pay for zero-filling first. `resize(n, T{})` still zero-fills.

#include <algorithm>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

namespace isoforge {

/// std::allocator that default-initializes instead of value-initializing.
template <class T>
struct DefaultInitAllocator : std::allocator<T> {
  using std::allocator<T>::allocator;
  DefaultInitAllocator() noexcept = default;
  template <class U>
  DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}
  template <class U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

template <class T, class U>
bool operator==(const DefaultInitAllocator<T>&, const DefaultInitAllocator<U>&) noexcept {
  return true;
}

/// Contiguous storage; see the file comment for the resize semantics.
template <class T>
using Buffer = std::vector<T, DefaultInitAllocator<T>>;

/// Element-wise comparison with a plain std::vector (tests and callers holding std::vector).
template <class T>
bool operator==(const Buffer<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin());
}

}  // namespace isoforge
