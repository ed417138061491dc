// Fuzz target: MetaImage reader (LOCAL data; detached files resolve in an empty directory).
#include <cstddef>
#include <cstdint>
#include <span>

#include "isoforge/io/raw_volume.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto bytes = std::as_bytes(std::span(data, size));
  try {
    (void)isoforge::read_metaimage(bytes, "fuzz.mha", "/nonexistent-fuzz-dir");
  } catch (const isoforge::Error&) {
    // Rejecting bad input with a clear error is the expected outcome.
  }
  return 0;
}
