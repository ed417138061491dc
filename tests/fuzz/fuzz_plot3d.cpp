// Fuzz target: PLOT3D reader and its streaming summary; the first byte chooses where the input
// splits into grid and Q file.
#include <cstddef>
#include <cstdint>
#include <span>

#include "io/detail/summaries.hpp"
#include "isoforge/io/plot3d.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto bytes = std::as_bytes(std::span(data, size));
  const std::size_t split = size == 0 ? 0 : (size * data[0]) / 256;
  const auto xyz = bytes.subspan(0, split), q = bytes.subspan(split);
  try {
    (void)isoforge::read_plot3d(xyz, "fuzz.xyz", q, "fuzz.q");
  } catch (const isoforge::Error&) {
    // Rejecting bad input with a clear error is the expected outcome.
  }
  try {
    (void)isoforge::read_plot3d(bytes, "fuzz.xyz", {}, "");
  } catch (const isoforge::Error&) {
  }
  try {  // the streaming summary of `isoforge info` (src/io/detail/summaries.hpp)
    (void)isoforge::io_detail::summarize_plot3d(xyz, "fuzz.xyz", q, "fuzz.q", {});
  } catch (const isoforge::Error&) {
  }
  return 0;
}
