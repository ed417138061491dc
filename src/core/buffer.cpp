#include "isoforge/core/buffer.hpp"

#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace isoforge::detail {

namespace {
constexpr std::size_t kHugePage = std::size_t{2} << 20;
std::size_t round_up(std::size_t bytes) { return (bytes + kHugePage - 1) / kHugePage * kHugePage; }
}  // namespace

#if defined(__linux__)

void* allocate_large_block(std::size_t bytes) {
  if (bytes > SIZE_MAX - 2 * kHugePage) throw std::bad_alloc();
  const std::size_t size = round_up(bytes);
  // Over-map by one huge page and trim both ends, so the block starts on a 2 MiB boundary (the
  // kernel can only back aligned 2 MiB ranges with huge pages).
  const std::size_t mapped = size + kHugePage;
  void* raw = ::mmap(nullptr, mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (raw == MAP_FAILED) throw std::bad_alloc();
  const auto base = reinterpret_cast<std::uintptr_t>(raw);
  const std::uintptr_t aligned = (base + kHugePage - 1) & ~(std::uintptr_t{kHugePage} - 1);
  const std::size_t head = aligned - base;
  const std::size_t tail = mapped - head - size;
  if (head) ::munmap(raw, head);
  if (tail) ::munmap(reinterpret_cast<void*>(aligned + size), tail);
  // Advice only: without transparent huge pages the block simply stays on small pages.
  ::madvise(reinterpret_cast<void*>(aligned), size, MADV_HUGEPAGE);
  return reinterpret_cast<void*>(aligned);
}

void deallocate_large_block(void* p, std::size_t bytes) noexcept {
  if (p) ::munmap(p, round_up(bytes));
}

#else

void* allocate_large_block(std::size_t bytes) {
  return ::operator new(bytes, std::align_val_t{kHugePage});
}

void deallocate_large_block(void* p, std::size_t) noexcept {
  ::operator delete(p, std::align_val_t{kHugePage});
}

#endif

}  // namespace isoforge::detail
