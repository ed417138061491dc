#pragma once
/// \file
/// `Buffer<T>`: the contiguous storage of arrays and cell lists — a std::vector whose
/// `resize(n)` leaves new trivial elements uninitialized, so algorithms that write every element
/// (in parallel) do not pay for zero-filling first. `resize(n, T{})` still zero-fills.
///
/// Blocks of `kLargeBlockBytes` (128 KiB, glibc's first mmap threshold) or more are mapped
/// directly from the kernel; from `kHugeBlockBytes` (1 MiB) they are 2 MiB aligned and marked
/// for transparent huge pages: a 100 MB mesh is then first touched with ~50 page faults instead
/// of ~25 000, which is a third of the time of a large contour on Linux. On a virtual machine a
/// small-page fault costs ~10 µs, so even a 1 MiB array pays less for one zeroed huge page than
/// for 256 faults; the rounding is virtual (untouched pages cost nothing).
/// Freed blocks of up to 32 MiB are kept for reuse, 64 MiB in all (as malloc keeps its heap),
/// so an algorithm run again writes memory that is already mapped. Sizes are rounded up to four
/// classes per power of two so that blocks of similar size are interchangeable; when the cache
/// is full the oldest block is released first.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

namespace isoforge {

namespace detail {
/// Blocks at least this large bypass malloc (see the file comment).
inline constexpr std::size_t kLargeBlockBytes = std::size_t{128} << 10;
/// Blocks at least this large are 2 MiB aligned and huge-page advised.
inline constexpr std::size_t kHugeBlockBytes = std::size_t{1} << 20;
/// A `bytes`-long block (page aligned; 2 MiB aligned and huge-page advised from
/// kHugeBlockBytes). \throw std::bad_alloc.
void* allocate_large_block(std::size_t bytes);
/// Releases a block from allocate_large_block with the same `bytes`.
void deallocate_large_block(void* p, std::size_t bytes) noexcept;
}  // namespace detail

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
  [[nodiscard]] T* allocate(std::size_t n) {
    if (n >= detail::kLargeBlockBytes / sizeof(T) && n <= SIZE_MAX / sizeof(T))
      return static_cast<T*>(detail::allocate_large_block(n * sizeof(T)));
    return std::allocator<T>::allocate(n);
  }
  void deallocate(T* p, std::size_t n) noexcept {
    if (n >= detail::kLargeBlockBytes / sizeof(T))
      detail::deallocate_large_block(p, n * sizeof(T));
    else
      std::allocator<T>::deallocate(p, n);
  }
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
