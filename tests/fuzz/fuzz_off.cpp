// Fuzz target: OFF reader, and its streaming summary.
#include <cstddef>
#include <cstdint>
#include <span>

#include "io/detail/summaries.hpp"
#include "isoforge/io/off_obj.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto bytes = std::as_bytes(std::span(data, size));
  try {
    (void)isoforge::read_off(bytes, "fuzz.off");
  } catch (const isoforge::Error&) {
    // Rejecting bad input with a clear error is the expected outcome.
  }
  try {  // the streaming summary of `isoforge info` (src/io/detail/summaries.hpp)
    (void)isoforge::io_detail::summarize_off(bytes, "fuzz.off");
  } catch (const isoforge::Error&) {
  }
  return 0;
}
