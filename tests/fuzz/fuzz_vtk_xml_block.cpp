// Fuzz target: the VTK XML reader's DataArray payload decoder on its own (base64 or raw bytes;
// a byte-count header, or a compression header and zlib, LZ4 or LZMA blocks; UInt32 or UInt64
// header words, either byte order), through io/detail/vtk_xml_block.hpp. Input layout:
//   byte 0: bit 0 base64, bit 1 compressed, bit 2 UInt64 header, bit 3 big-endian,
//           bit 4 the expected size is given, bits 5-6 the codec (0 zlib, 1 LZ4, 2 LZMA,
//           3 zlib);
//   byte 1: the tuple size in bytes, 1 + (byte % 16);
//   bytes 2..5: the expected decoded size (little-endian uint32; used when bit 4 is set);
//   the rest: the payload.
// Only isoforge::Error may escape, and a decoded payload must have the size asked for.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include "io/detail/vtk_xml_block.hpp"
#include "isoforge/core/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace isoforge;
  if (size < 6) return 0;
  io_detail::VtkXmlBlockFormat f;
  f.base64 = data[0] & 1;
  f.compressed = data[0] & 2;
  f.header64 = data[0] & 4;
  f.big_endian = data[0] & 8;
  static constexpr io_detail::BlockCodec kCodecs[4] = {
      io_detail::BlockCodec::Zlib, io_detail::BlockCodec::Lz4, io_detail::BlockCodec::Lzma,
      io_detail::BlockCodec::Zlib};
  f.codec = kCodecs[(data[0] >> 5) & 3];
  const std::size_t unit = 1 + data[1] % 16;
  std::optional<std::uint64_t> expected;
  if (data[0] & 16) {
    expected = std::uint64_t{data[2]} | std::uint64_t{data[3]} << 8 |
               std::uint64_t{data[4]} << 16 | std::uint64_t{data[5]} << 24;
  }
  const auto payload = std::as_bytes(std::span(data + 6, size - 6));
  try {
    const auto out = io_detail::decode_vtk_xml_block(payload, f, expected, unit, "fuzz.vtu");
    if (expected ? out.size() != *expected : out.size() % unit != 0) __builtin_trap();
  } catch (const Error&) {
    // Rejecting bad input with a clear error is the expected outcome.
  }
  return 0;
}
