#include "isoforge/core/buffer.hpp"

#include <mutex>
#include <new>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace isoforge::detail {

namespace {
constexpr std::size_t kHugePage = std::size_t{2} << 20;
std::size_t round_up(std::size_t bytes) { return (bytes + kHugePage - 1) / kHugePage * kHugePage; }
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
  std::vector<std::pair<void*, std::size_t>> blocks;  // (block, mapped size)
  std::size_t bytes = 0;
};

BlockCache& block_cache() {
  static BlockCache* cache = new BlockCache;  // never destroyed: blocks may be freed at exit
  return *cache;
}

/// A cached block of exactly `size` bytes (a multiple of the huge page), or nullptr.
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

/// Keeps a freed block of `size` bytes if the cache has room.
bool keep_cached(void* p, std::size_t size) {
  if (size > kCacheBlockBytes) return false;
  BlockCache& c = block_cache();
  std::lock_guard lock(c.mutex);
  if (c.bytes + size > kCacheBytes) return false;
  c.blocks.emplace_back(p, size);
  c.bytes += size;
  return true;
}

}  // namespace

void* allocate_large_block(std::size_t bytes) {
  if (bytes > SIZE_MAX - 2 * kHugePage) throw std::bad_alloc();
  const std::size_t size = round_up(bytes);
  if (void* p = take_cached(size)) return p;
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
  const std::size_t size = round_up(bytes);
  bool kept = false;
  try {
    kept = keep_cached(p, size);
  } catch (...) {  // no memory for the cache's bookkeeping: unmap instead
  }
  if (!kept) ::munmap(p, size);
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
