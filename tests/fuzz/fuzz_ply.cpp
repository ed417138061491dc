// Fuzz target: PLY reader.
#include <cstddef>
#include <cstdint>
#include <span>

#include "isoforge/io/ply.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto bytes = std::as_bytes(std::span(data, size));
  try {
    (void)isoforge::read_ply(bytes, "fuzz.ply");
  } catch (const isoforge::Error&) {
    // Rejecting bad input with a clear error is the expected outcome.
  }
  return 0;
}
