// Parallel loops that report progress (core/parallel.hpp).

#include "isoforge/core/parallel.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>

namespace isoforge {

void parallel_for_range(std::size_t n, std::size_t grain,
                        const std::function<void(std::size_t, std::size_t)>& body,
                        const ProgressCallback& progress, const char* operation) {
  grain = std::max<std::size_t>(grain, 1);
  const auto run = [&](std::size_t begin, std::size_t end) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, grain),
                      [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
  };
  if (!progress) {
    if (n > 0) run(0, n);
    return;
  }
  constexpr std::size_t kSlices = 64;
  // Slices of at least a few grains each, so that every slice still keeps the threads busy.
  const std::size_t slice = std::max((n + kSlices - 1) / kSlices, 4 * grain);
  for (std::size_t begin = 0; begin < n; begin += slice) {
    const std::size_t end = std::min(n, begin + slice);
    run(begin, end);
    report_progress(progress, static_cast<double>(end) / static_cast<double>(n), operation);
  }
  if (n == 0) report_progress(progress, 1.0, operation);
}

std::size_t parallel_find_first(std::size_t n, std::size_t grain,
                                const std::function<std::size_t(std::size_t, std::size_t)>& first) {
  std::atomic<std::size_t> found{n};
  if (n == 0) return n;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, std::max<std::size_t>(grain, 1)),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      if (r.begin() >= found.load(std::memory_order_relaxed)) return;
                      const std::size_t i = first(r.begin(), r.end());
                      if (i >= r.end()) return;
                      std::size_t seen = found.load(std::memory_order_relaxed);
                      while (i < seen && !found.compare_exchange_weak(seen, i)) {
                      }
                    });
  return found.load();
}

}  // namespace isoforge
