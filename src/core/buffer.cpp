#include "isoforge/core/buffer.hpp"

#include <algorithm>
#include <cstdlib>
#include <mutex>
#include <new>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace isoforge::detail {

namespace {
constexpr std::size_t kPage = 4096;
constexpr std::size_t kHugePage = std::size_t{2} << 20;

std::size_t round_up(std::size_t bytes, std::size_t unit) { return (bytes + unit - 1) / unit * unit; }

/// The mapped size of a `bytes`-long block: its size class (four per power of two, so a block
/// can serve any request up to 25% smaller), then whole pages, or whole huge pages from
/// kHugeBlockBytes.
std::size_t block_size(std::size_t bytes) {
  std::size_t octave = kPage;
  while (octave * 2 < bytes) octave *= 2;  // octave < bytes <= 2 * octave
  const std::size_t size = round_up(bytes, std::max(kPage, octave / 4));
  return size >= kHugeBlockBytes ? round_up(size, kHugePage) : round_up(size, kPage);
}
}  // namespace

#if defined(__linux__)

namespace {

/// Freed blocks kept for reuse (up to kCacheBytes in all, each at most kCacheBlockBytes): an
/// algorithm run again, or the next stage of a pipeline, then writes memory that is already
/// mapped instead of paying the kernel again for zeroed pages (as malloc reuses its heap).
constexpr std::size_t kCacheBytes = std::size_t{64} << 20;
constexpr std::size_t kCacheBlockBytes = std::size_t{32} << 20;

struct BlockCache {
  std::mutex mutex;
  std::vector<std::pair<void*, std::size_t>> blocks;  // (block, mapped size), oldest first
  std::size_t bytes = 0;
};

BlockCache& block_cache() {
  static BlockCache* cache = new BlockCache;  // never destroyed: blocks may be freed at exit
  return *cache;
}

/// A cached block of exactly `size` mapped bytes (the newest), or nullptr.
void* take_cached(std::size_t size) {
  BlockCache& c = block_cache();
  std::lock_guard lock(c.mutex);
  for (std::size_t i = c.blocks.size(); i-- > 0;) {
    if (c.blocks[i].second == size) {
      void* p = c.blocks[i].first;
      c.blocks.erase(c.blocks.begin() + static_cast<std::ptrdiff_t>(i));
      c.bytes -= size;
      return p;
    }
  }
  return nullptr;
}

/// Keeps a freed block of `size` mapped bytes, releasing the oldest blocks to make room; the
/// blocks to unmap (the freed one itself if it is too large) are returned in `evicted`.
void keep_cached(void* p, std::size_t size, std::vector<std::pair<void*, std::size_t>>& evicted) {
  if (size > kCacheBlockBytes) {
    evicted.emplace_back(p, size);
    return;
  }
  BlockCache& c = block_cache();
  std::lock_guard lock(c.mutex);
  std::size_t drop = 0, released = 0;
  while (c.bytes - released + size > kCacheBytes) released += c.blocks[drop++].second;
  // Both may throw; nothing has changed yet then.
  evicted.assign(c.blocks.begin(), c.blocks.begin() + static_cast<std::ptrdiff_t>(drop));
  c.blocks.reserve(c.blocks.size() - drop + 1);
  c.blocks.erase(c.blocks.begin(), c.blocks.begin() + static_cast<std::ptrdiff_t>(drop));
  c.blocks.emplace_back(p, size);
  c.bytes += size - released;
}

/// glibc adapts its heap to the program: freeing a block it had mapped (128 KiB or more at
/// first) raises its mapping threshold to that size and its trim threshold to twice that, so
/// a program that works with large arrays keeps a heap instead of returning memory to the kernel
/// after every call. Blocks from here never reach malloc, so malloc would never see such a
/// free and would keep trimming its heaps above 128 KiB, making the small allocations of every
/// call fault their pages in again (measured: a curvilinear plane cut after large image cuts,
/// 1.4 ms with the heap kept, 5–6 ms trimmed). So the first large block shows malloc one free of
/// the size it would have seen. A program that set the thresholds itself (mallopt, MALLOC_*_
/// environment variables) has turned the adaptation off, and this changes nothing for it.
void show_malloc_a_large_free() {
  static const bool done = [] {
    void* volatile p = std::malloc(kHugeBlockBytes * 2);
    std::free(p);
    return true;
  }();
  (void)done;
}

}  // namespace

void* allocate_large_block(std::size_t bytes) {
  if (bytes > SIZE_MAX / 2 - 2 * kHugePage) throw std::bad_alloc();
  show_malloc_a_large_free();
  const std::size_t size = block_size(bytes);
  if (void* p = take_cached(size)) return p;
  if (size < kHugeBlockBytes) {
    void* p = ::mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    return p;
  }
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
  if (p == nullptr) return;
  const std::size_t size = block_size(bytes);
  try {
    std::vector<std::pair<void*, std::size_t>> evicted;
    keep_cached(p, size, evicted);
    for (const auto& [block, length] : evicted) ::munmap(block, length);
  } catch (...) {  // no memory for the cache's bookkeeping: unmap instead
    ::munmap(p, size);
  }
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
