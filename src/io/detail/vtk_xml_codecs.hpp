#pragma once
// Private: the block codecs of VTK XML files (vtkZLibDataCompressor, vtkLZ4DataCompressor,
// vtkLZMADataCompressor): each block of a DataArray payload is one independent stream, so whole
// payloads are (de)compressed in parallel, block by block, straight into / out of the arrays.
// zlib streams go through libdeflate (the same zlib format, faster: docs/algorithms/vtk_xml_io.md).

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace isoforge::io_detail {

struct FileSource;

enum class BlockCodec {
  Zlib,  ///< zlib stream (RFC 1950) per block
  Lz4,   ///< raw LZ4 block per block (no frame)
  Lzma,  ///< .xz stream per block (read only)
};

/// The `compressor=` attribute VTK writes for `codec`.
[[nodiscard]] const char* block_codec_vtk_name(BlockCodec codec);

/// The largest ratio uncompressed/compressed a block of `codec` can reach (plus a small
/// constant): block headers claiming more are lying.
[[nodiscard]] std::uint64_t block_codec_max_ratio(BlockCodec codec);

/// One block to decompress: `in` into exactly `out_size` bytes at `out`.
struct BlockJob {
  const std::byte* in = nullptr;
  std::size_t in_size = 0;
  std::byte* out = nullptr;
  std::size_t out_size = 0;
};

/// A block that failed: its index in the jobs and what is wrong ("corrupt data", ...).
struct BlockFailure {
  std::size_t index = 0;
  std::string why;
};

/// Decompresses `jobs` in parallel (TBB). Returns the failure of the lowest-numbered bad block
/// (the same whatever the thread count), or index == jobs.size() when all succeed. With `file`
/// (the inputs lie in its bytes), each input is first copied out of the file into a buffer of
/// the thread (FileSource::copy: pread), so the compressed payload never becomes resident.
[[nodiscard]] BlockFailure decompress_blocks(BlockCodec codec, std::span<const BlockJob> jobs,
                                             const FileSource* file = nullptr);

/// A payload compressed block by block: `data` holds the blocks one after another, `sizes` the
/// compressed size of each.
struct CompressedBlocks {
  std::unique_ptr<std::byte[]> data;  ///< uninitialized beyond `bytes` (pages never touched)
  std::size_t capacity = 0;           ///< bytes allocated at `data`
  std::size_t bytes = 0;
  std::vector<std::uint64_t> sizes;
};

/// Storage for the compressed blocks of `nblocks` blocks of `block` bytes, to pass as `reuse`
/// (allocated, no page touched).
[[nodiscard]] CompressedBlocks compress_storage(BlockCodec codec, std::size_t block,
                                                std::size_t nblocks);

/// Compresses `n` bytes at `in` in blocks of `block` bytes (the last may be shorter), in
/// parallel; the result depends only on the input, `codec` and `level` (1-12; 0: the default).
/// `progress(bytes)` is called from the calling thread as slices of the input are done.
/// `reuse`: a result no longer needed, whose storage is taken when large enough (a writer that
/// compresses slice after slice then touches the same pages again instead of fresh ones).
/// \throw Error if the codec fails (out of memory).
[[nodiscard]] CompressedBlocks compress_blocks(BlockCodec codec, int level, const std::byte* in,
                                               std::size_t n, std::size_t block,
                                               const std::function<void(std::size_t)>& progress,
                                               CompressedBlocks reuse = {});

}  // namespace isoforge::io_detail
