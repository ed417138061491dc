// Fuzz target: glTF binary (.glb) reader (plain, meshopt and Draco primitives), and its
// streaming summary.
#include <cstddef>
#include <cstdint>
#include <span>

#include "io/detail/summaries.hpp"
#include "isoforge/io/gltf.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto bytes = std::as_bytes(std::span(data, size));
  try {
    (void)isoforge::read_gltf(bytes, "fuzz.glb");
  } catch (const isoforge::Error&) {
    // Rejecting bad input with a clear error is the expected outcome.
  }
  try {  // the streaming summary of `isoforge info` (src/io/detail/summaries.hpp)
    (void)isoforge::io_detail::summarize_gltf(bytes, "fuzz.glb");
  } catch (const isoforge::Error&) {
  }
  return 0;
}
