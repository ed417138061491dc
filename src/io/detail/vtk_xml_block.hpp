#pragma once
// Private: the VTK XML reader's decoder of one DataArray payload (base64 or raw; a byte-count
// header, or a compression header and zlib, LZ4 or LZMA blocks), exposed on its own so it can be
// fuzzed directly (tests/fuzz/fuzz_vtk_xml_block.cpp). read_vtk_xml uses the same code.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "vtk_xml_codecs.hpp"

namespace isoforge::io_detail {

/// How a payload is stored: the VTKFile's header_type, byte_order and compressor, and the
/// array's encoding (format="binary" or appended base64: base64 text; appended raw: bytes).
struct VtkXmlBlockFormat {
  bool base64 = true;       ///< base64 text, else raw bytes
  bool compressed = false;  ///< compressed blocks, else one byte-count header
  bool header64 = false;    ///< UInt64 header words, else UInt32
  bool big_endian = false;  ///< byte_order="BigEndian" (header words; data is returned as stored)
  BlockCodec codec = BlockCodec::Zlib;  ///< the compressor of the blocks, when `compressed`
};

/// Decodes the payload at the start of `data` as the reader does, with the same checks and the
/// same decoded-size budget (about 1040 times the input; 8200 times for LZMA). `expected`: the bytes the array
/// needs, when known; otherwise the decoded size must be a multiple of `unit` bytes.
/// \throw Error naming `name`, the byte offset and the problem.
[[nodiscard]] std::vector<std::byte> decode_vtk_xml_block(std::span<const std::byte> data,
                                                          const VtkXmlBlockFormat& format,
                                                          std::optional<std::uint64_t> expected,
                                                          std::size_t unit, std::string_view name);

}  // namespace isoforge::io_detail
