// Fuzz target: Draco .drc reader (Draco's decoder plus isoforge's conversion to polydata).
#include <cstddef>
#include <cstdint>
#include <span>

#include "isoforge/io/draco.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto bytes = std::as_bytes(std::span(data, size));
  try {
    (void)isoforge::read_draco(bytes, "fuzz.drc");
  } catch (const isoforge::Error&) {
    // Rejecting bad input with a clear error is the expected outcome.
  }
  return 0;
}
