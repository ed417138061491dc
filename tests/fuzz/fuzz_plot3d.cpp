// Fuzz target: PLOT3D reader; the first byte chooses where the input splits into grid and Q file.
#include <cstddef>
#include <cstdint>
#include <span>

#include "isoforge/io/plot3d.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto bytes = std::as_bytes(std::span(data, size));
  try {
    const std::size_t split = size == 0 ? 0 : (size * data[0]) / 256;
    (void)isoforge::read_plot3d(bytes.subspan(0, split), "fuzz.xyz", bytes.subspan(split), "fuzz.q");
    (void)isoforge::read_plot3d(bytes, "fuzz.xyz", {}, "");
  } catch (const isoforge::Error&) {
    // Rejecting bad input with a clear error is the expected outcome.
  }
  return 0;
}
