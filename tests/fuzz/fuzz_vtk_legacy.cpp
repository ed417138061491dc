// Fuzz target: VTK legacy reader.
#include <cstddef>
#include <cstdint>
#include <span>

#include "isoforge/io/vtk_legacy.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto bytes = std::as_bytes(std::span(data, size));
  try {
    (void)isoforge::read_vtk_legacy(bytes, "fuzz.vtk");
  } catch (const isoforge::Error&) {
    // Rejecting bad input with a clear error is the expected outcome.
  }
  return 0;
}
