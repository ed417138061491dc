// Large allocations of the isoforge program are backed by transparent huge pages where the
// system offers them on request (/sys/kernel/mm/transparent_hugepage/enabled = madvise, the
// Debian default). A run over a million-triangle mesh touches a few hundred megabytes of fresh
// vectors; with 4 KiB pages that is over 100,000 page faults, each costly under virtualisation
// (the 1M-triangle decimation: 128,000 faults and 30 % more CPU time than with 7,000 faults on
// 2 MiB pages). The global operator new of the program is replaced: it is malloc, plus
// madvise(MADV_HUGEPAGE) over the 2 MiB-aligned interior of blocks of 4 MiB or more (the advice
// only permits the kernel to use huge pages; it changes no contents and cannot fail in a way
// that matters). The over-aligned forms (`alignas` types such as the decimation's 128-byte
// vertex quadrics) are replaced the same way, with aligned_alloc: left to the default they
// took 4 KiB pages, and the 67 MB of quadrics of the 1M-triangle decimation alone cost 0.18 s
// of page faults. The library itself is unchanged: programs linking it keep their allocator.
// Left out under the sanitizers, which bring their own operator new.

#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(memory_sanitizer) || \
    __has_feature(thread_sanitizer)
#define ISOFORGE_NO_HUGE_PAGES 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define ISOFORGE_NO_HUGE_PAGES 1
#endif

#ifndef ISOFORGE_NO_HUGE_PAGES

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>

namespace {

constexpr std::uintptr_t kHugePage = std::uintptr_t{2} << 20;

// Advises huge pages over the 2 MiB-aligned interior of the block [p, p + n).
void advise(void* p, std::size_t n) {
  if (n >= 2 * kHugePage) {
    const auto begin = reinterpret_cast<std::uintptr_t>(p);
    const std::uintptr_t first = (begin + kHugePage - 1) & ~(kHugePage - 1);
    const std::uintptr_t last = (begin + n) & ~(kHugePage - 1);
    if (last > first) {
      madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
    }
  }
}

void* allocate(std::size_t n) {
  void* p = std::malloc(n != 0 ? n : 1);
  if (p == nullptr) throw std::bad_alloc();
  advise(p, n);
  return p;
}

void* allocate(std::size_t n, std::align_val_t alignment) {
  const auto a = static_cast<std::size_t>(alignment);
  // aligned_alloc wants a size that is a multiple of the alignment (a power of two).
  const std::size_t rounded = n <= SIZE_MAX - (a - 1) ? (n + a - 1) & ~(a - 1) : 0;
  if (rounded == 0 && n != 0) throw std::bad_alloc();
  void* p = std::aligned_alloc(a, rounded != 0 ? rounded : a);
  if (p == nullptr) throw std::bad_alloc();
  advise(p, n);
  return p;
}

}  // namespace

void* operator new(std::size_t n) {
  return allocate(n);
}
void* operator new[](std::size_t n) {
  return allocate(n);
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return allocate(n);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return allocate(n);
  } catch (...) {
    return nullptr;
  }
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}

void* operator new(std::size_t n, std::align_val_t a) {
  return allocate(n, a);
}
void* operator new[](std::size_t n, std::align_val_t a) {
  return allocate(n, a);
}
void* operator new(std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  try {
    return allocate(n, a);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  try {
    return allocate(n, a);
  } catch (...) {
    return nullptr;
  }
}
void operator delete(void* p, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept {
  std::free(p);
}

#endif
