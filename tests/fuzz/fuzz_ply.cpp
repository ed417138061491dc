// Fuzz target: PLY reader, and its streaming summary, which must describe every file the reader
// accepts exactly as the reader's dataset does (a mismatch aborts).
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include "io/detail/summaries.hpp"
#include "isoforge/core/summary.hpp"
#include "isoforge/io/ply.hpp"

namespace {

bool same_arrays(const isoforge::AttributesSummary& a, const isoforge::AttributesSummary& b) {
  if (a.arrays.size() != b.arrays.size()) return false;
  for (std::size_t i = 0; i < a.arrays.size(); ++i) {
    const auto& x = a.arrays[i];
    const auto& y = b.arrays[i];
    if (x.name != y.name || x.type != y.type || x.components != y.components ||
        x.tuples != y.tuples) {
      return false;
    }
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto bytes = std::as_bytes(std::span(data, size));
  std::optional<isoforge::DatasetSummary> read;
  try {
    read = isoforge::summarize(isoforge::read_ply(bytes, "fuzz.ply"));
  } catch (const isoforge::Error&) {
    // Rejecting bad input with a clear error is the expected outcome.
  }
  try {  // the streaming summary of `isoforge info` (src/io/detail/summaries.hpp)
    const isoforge::DatasetSummary s = isoforge::io_detail::summarize_ply(bytes, "fuzz.ply");
    if (read && (s.points != read->points || s.cells != read->cells ||
                 s.cell_types != read->cell_types || !same_arrays(s.point_data, read->point_data) ||
                 !same_arrays(s.cell_data, read->cell_data))) {
      __builtin_trap();  // the summary disagrees with the dataset read
    }
  } catch (const isoforge::Error&) {
    if (read) __builtin_trap();  // the summary rejects a file the reader accepts
  }
  return 0;
}
