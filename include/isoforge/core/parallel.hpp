#pragma once
/// \file
/// Parallel loops that report progress: every long stage of an algorithm runs through
/// `parallel_for_range`, so a progress bar advances while it works (house rule 8).

#include <cstddef>
#include <functional>

#include "isoforge/core/progress.hpp"

namespace isoforge {

/// Calls body(begin, end) on disjoint subranges covering [0, n), in parallel (TBB), of about
/// `grain` items each (TBB's grain size: split while longer). With a `progress` callback the range
/// is cut into up to 64 consecutive slices run one after another, and the fraction done is reported
/// after each (from the calling thread; `Cancelled`, naming `operation`, if the callback returns
/// false). Bodies that write only their own items give the same result for any slicing and thread
/// count.
void parallel_for_range(std::size_t n, std::size_t grain,
                        const std::function<void(std::size_t, std::size_t)>& body,
                        const ProgressCallback& progress = {}, const char* operation = "");

/// The lowest index in [0, n) that `first` finds, or n if none: `first(begin, end)` returns the
/// lowest index in [begin, end) it looks for, or `end`. Ranges of about `grain` items run in
/// parallel, and a range wholly past an index already found is skipped. The result does not
/// depend on the thread count (a check of every element that reports the first bad one).
[[nodiscard]] std::size_t parallel_find_first(
    std::size_t n, std::size_t grain,
    const std::function<std::size_t(std::size_t, std::size_t)>& first);

}  // namespace isoforge
