// Large allocations of the isoforge program are backed by transparent huge pages where the
// system offers them on request (/sys/kernel/mm/transparent_hugepage/enabled = madvise, the
// Debian default). A run over a million-triangle mesh touches a few hundred megabytes of fresh
// vectors; with 4 KiB pages that is over 100,000 page faults, each costly under virtualisation
// (the 1M-triangle decimation: 128,000 faults and 30 % more CPU time than with 7,000 faults on
// 2 MiB pages). The global operator new of the program is replaced: it is malloc, plus
// madvise(MADV_HUGEPAGE) over the 2 MiB-aligned interior of blocks of 4 MiB or more (the advice
// only permits the kernel to use huge pages; it changes no contents and cannot fail in a way
// that matters). The library itself is unchanged: programs linking it keep their allocator.
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

#include <cstdint>
#include <cstdlib>
#include <new>

namespace {

constexpr std::uintptr_t kHugePage = std::uintptr_t{2} << 20;

void* allocate(std::size_t n) {
  void* p = std::malloc(n != 0 ? n : 1);
  if (p == nullptr) throw std::bad_alloc();
  if (n >= 2 * kHugePage) {
    const auto begin = reinterpret_cast<std::uintptr_t>(p);
    const std::uintptr_t first = (begin + kHugePage - 1) & ~(kHugePage - 1);
    const std::uintptr_t last = (begin + n) & ~(kHugePage - 1);
    if (last > first) {
      madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
    }
  }
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

#endif
