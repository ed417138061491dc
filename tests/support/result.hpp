#pragma once
// Tests that check both what an algorithm made and its statistics.

#include <utility>

#include "isoforge/core/result.hpp"

namespace isoforge::test {

/// The output of `r`, with its statistics stored in `stats`.
template <class Output, class Stats>
Output split_result(Result<Output, Stats> r, Stats& stats) {
  stats = std::move(r.stats);
  return std::move(r.output);
}

}  // namespace isoforge::test
