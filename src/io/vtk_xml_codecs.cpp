// Block codecs of the VTK XML formats (io/detail/vtk_xml_codecs.hpp): VTK's compressors
// (vtkZLibDataCompressor, vtkLZ4DataCompressor, vtkLZMADataCompressor) cut a payload into blocks
// and compress each on its own — a zlib stream (RFC 1950), a raw LZ4 block (LZ4 block format,
// no frame) or an .xz stream — so every block is (de)compressed independently, in parallel.
// zlib streams are read and written with libdeflate (E. Biggers), which produces and accepts the
// same RFC 1950 format as zlib's compress2/uncompress, faster (measured in
// docs/algorithms/vtk_xml_io.md).

#include "detail/vtk_xml_codecs.hpp"
#include "detail/file_source.hpp"

#include <libdeflate.h>
#include <lz4.h>
#include <lz4hc.h>
#include <lzma.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>

#include "isoforge/core/error.hpp"
#include "isoforge/core/parallel.hpp"

namespace isoforge::io_detail {

namespace {

/// Blocks per task: a few hundred kilobytes of work, enough to amortize the codec state.
constexpr std::size_t kBlocksPerTask = 8;
/// Blocks per compression task: two of the writer's 256 KiB blocks, so that the 4 MiB slice a
/// streaming writer compresses at a time still makes eight tasks for the threads to share.
constexpr std::size_t kCompressBlocksPerTask = 2;
/// LZMA decoders may use at most this much memory (a forged header can ask for gigabytes).
constexpr std::uint64_t kLzmaMemLimit = std::uint64_t{256} << 20;
/// Default levels. zlib 5 (VTK's default level too): on the size/time curve of
/// docs/algorithms/vtk_xml_io.md, libdeflate's lazy matching from level 5 on makes surfaces
/// (float points and normals, Int32 ids) 1.4-2.1% smaller than levels 3-4, for 14% (a distance
/// field) to 35% (surfaces) more time; it is the lowest level whose files are no larger than
/// VTK's on every input measured. Levels 10-12 are smaller still at a quarter of the speed.
/// LZ4 1: its fast compressor.
constexpr int kDefaultZlibLevel = 5;
constexpr int kDefaultLz4Level = 1;
/// LZ4's fast compressor skips ahead faster where it finds no match: at 2, a distance field
/// (nearly incompressible floats) compresses at 1.26 GB/s per core instead of 0.85, 1.3% larger;
/// a surface's connectivity is as fast and 0.7% larger (docs/algorithms/vtk_xml_io.md). VTK's
/// writers use 5 (their default level) on 32 KiB blocks, 13% larger than this on the volume.
constexpr int kLz4Acceleration = 2;

struct DeflateDecompressorDeleter {
  void operator()(libdeflate_decompressor* d) const { libdeflate_free_decompressor(d); }
};
struct DeflateCompressorDeleter {
  void operator()(libdeflate_compressor* c) const { libdeflate_free_compressor(c); }
};

std::string decompress_one(BlockCodec codec, const BlockJob& job, libdeflate_decompressor* d) {
  switch (codec) {
    case BlockCodec::Zlib: {
      std::size_t got = 0;
      const libdeflate_result r =
          libdeflate_zlib_decompress(d, job.in, job.in_size, job.out, job.out_size, &got);
      if (r == LIBDEFLATE_SUCCESS) {
        if (got != job.out_size) {
          return "inflates to " + std::to_string(got) + " bytes but the header says " +
                 std::to_string(job.out_size);
        }
        return {};
      }
      if (r == LIBDEFLATE_INSUFFICIENT_SPACE) {
        return "zlib data inflates to more than the " + std::to_string(job.out_size) +
               " bytes the header says";
      }
      return "corrupt or truncated zlib data";
    }
    case BlockCodec::Lz4: {
      if (job.in_size > static_cast<std::size_t>(std::numeric_limits<int>::max()) ||
          job.out_size > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
        return "block too large for LZ4";
      }
      const int got = LZ4_decompress_safe(reinterpret_cast<const char*>(job.in),
                                          reinterpret_cast<char*>(job.out),
                                          static_cast<int>(job.in_size),
                                          static_cast<int>(job.out_size));
      if (got < 0) {
        return "corrupt or truncated LZ4 data (or it decodes to more than the " +
               std::to_string(job.out_size) + " bytes the header says)";
      }
      if (static_cast<std::size_t>(got) != job.out_size) {
        return "LZ4 data decodes to " + std::to_string(got) + " bytes but the header says " +
               std::to_string(job.out_size);
      }
      return {};
    }
    case BlockCodec::Lzma: {
      std::uint64_t memlimit = kLzmaMemLimit;
      std::size_t in_pos = 0, out_pos = 0;
      const lzma_ret r = lzma_stream_buffer_decode(
          &memlimit, 0, nullptr, reinterpret_cast<const std::uint8_t*>(job.in), &in_pos,
          job.in_size, reinterpret_cast<std::uint8_t*>(job.out), &out_pos, job.out_size);
      switch (r) {
        case LZMA_OK:
          break;
        case LZMA_FORMAT_ERROR:
          return "not an LZMA (.xz) stream";
        case LZMA_OPTIONS_ERROR:
          return "unsupported LZMA options";
        case LZMA_DATA_ERROR:
          return "corrupt LZMA data";
        case LZMA_BUF_ERROR:
          return "truncated LZMA data, or it decodes to more than the " +
                 std::to_string(job.out_size) + " bytes the header says";
        case LZMA_MEMLIMIT_ERROR:
          return "LZMA data needs more than " + std::to_string(kLzmaMemLimit >> 20) +
                 " MiB of memory to decode";
        case LZMA_MEM_ERROR:
          return "out of memory";
        default:
          return "LZMA error " + std::to_string(static_cast<int>(r));
      }
      if (out_pos != job.out_size) {
        return "LZMA data decodes to " + std::to_string(out_pos) + " bytes but the header says " +
               std::to_string(job.out_size);
      }
      return {};
    }
  }
  return "unknown codec";
}

int effective_level(BlockCodec codec, int level) {
  if (level > 0) return level;
  return codec == BlockCodec::Lz4 ? kDefaultLz4Level : kDefaultZlibLevel;
}

}  // namespace

const char* block_codec_vtk_name(BlockCodec codec) {
  switch (codec) {
    case BlockCodec::Zlib:
      return "vtkZLibDataCompressor";
    case BlockCodec::Lz4:
      return "vtkLZ4DataCompressor";
    case BlockCodec::Lzma:
      return "vtkLZMADataCompressor";
  }
  return "";
}

std::uint64_t block_codec_max_ratio(BlockCodec codec) {
  switch (codec) {
    case BlockCodec::Zlib:
      return 1032;  // deflate: at most 258 bytes per 2-bit code, about 1032:1
    case BlockCodec::Lz4:
      return 256;  // LZ4: a run costs at least one byte per 255 bytes of match length
    case BlockCodec::Lzma:
      return 8192;  // .xz: a 32 KiB block costs >= 60 bytes of headers; ~5000:1 for 1 MiB of zeros
  }
  return 1032;
}

BlockFailure decompress_blocks(BlockCodec codec, std::span<const BlockJob> jobs,
                               const FileSource* file) {
  std::mutex mutex;
  BlockFailure first{jobs.size(), {}};
  parallel_for_range(jobs.size(), kBlocksPerTask, [&](std::size_t begin, std::size_t end) {
    std::unique_ptr<libdeflate_decompressor, DeflateDecompressorDeleter> d;
    if (codec == BlockCodec::Zlib) {
      d.reset(libdeflate_alloc_decompressor());
      if (!d) {
        const std::lock_guard<std::mutex> lock(mutex);
        if (begin < first.index) first = {begin, "out of memory"};
        return;
      }
    }
    std::vector<std::byte> scratch;
    for (std::size_t i = begin; i < end; ++i) {
      BlockJob job = jobs[i];
      if (file && file->file) {
        scratch.resize(job.in_size);
        file->copy(job.in, scratch.data(), job.in_size);
        job.in = scratch.data();
      }
      std::string why = decompress_one(codec, job, d.get());
      if (!why.empty()) {
        const std::lock_guard<std::mutex> lock(mutex);
        if (i < first.index) first = {i, std::move(why)};
        return;  // the rest of this range cannot hold a lower failure than i
      }
    }
  });
  return first;
}

namespace {

/// The most bytes one block of `block` bytes compresses to.
std::size_t block_bound(BlockCodec codec, std::size_t block) {
  if (codec == BlockCodec::Zlib) return libdeflate_zlib_compress_bound(nullptr, block);
  if (block > static_cast<std::size_t>(LZ4_MAX_INPUT_SIZE)) {
    throw Error("VTK XML writer: block too large for LZ4");
  }
  return static_cast<std::size_t>(LZ4_compressBound(static_cast<int>(block)));
}

}  // namespace

CompressedBlocks compress_storage(BlockCodec codec, std::size_t block, std::size_t nblocks) {
  CompressedBlocks out;
  out.capacity = nblocks * block_bound(codec, block);
  out.data.reset(new std::byte[out.capacity]);  // no zero fill: only written pages count
  return out;
}

CompressedBlocks compress_blocks(BlockCodec codec, int level, const std::byte* in, std::size_t n,
                                 std::size_t block,
                                 const std::function<void(std::size_t)>& progress,
                                 CompressedBlocks reuse) {
  if (codec == BlockCodec::Lzma) throw Error("VTK XML writer: LZMA compression is not supported");
  level = effective_level(codec, level);
  CompressedBlocks out;
  const std::size_t nblocks = block == 0 ? 0 : (n + block - 1) / block;
  out.sizes.assign(nblocks, 0);
  if (nblocks == 0) return out;
  // Every block gets a slot of the codec's bound; the slots are compacted afterwards.
  const std::size_t bound = block_bound(codec, block);
  if (reuse.data && reuse.capacity >= nblocks * bound) {
    out.data = std::move(reuse.data);
    out.capacity = reuse.capacity;
  } else {
    CompressedBlocks storage = compress_storage(codec, block, nblocks);
    out.data = std::move(storage.data);
    out.capacity = storage.capacity;
  }
  std::mutex mutex;
  bool failed = false;
  const auto body = [&](std::size_t begin, std::size_t end) {
    std::unique_ptr<libdeflate_compressor, DeflateCompressorDeleter> c;
    std::unique_ptr<char[]> lz4_state;
    if (codec == BlockCodec::Zlib) {
      c.reset(libdeflate_alloc_compressor(level));
    } else {
      lz4_state.reset(new (std::nothrow) char[static_cast<std::size_t>(
          level <= 1 ? LZ4_sizeofState() : LZ4_sizeofStateHC())]);
    }
    if (!c && !lz4_state) {
      const std::lock_guard<std::mutex> lock(mutex);
      failed = true;
      return;
    }
    for (std::size_t b = begin; b < end; ++b) {
      const std::size_t len = std::min(block, n - b * block);
      const std::byte* src = in + b * block;
      std::byte* dst = out.data.get() + b * bound;
      std::size_t got = 0;
      if (codec == BlockCodec::Zlib) {
        got = libdeflate_zlib_compress(c.get(), src, len, dst, bound);
      } else if (level <= 1) {
        const int r = LZ4_compress_fast_extState(
            lz4_state.get(), reinterpret_cast<const char*>(src), reinterpret_cast<char*>(dst),
            static_cast<int>(len), static_cast<int>(bound), kLz4Acceleration);
        got = r > 0 ? static_cast<std::size_t>(r) : 0;
      } else {
        const int r = LZ4_compress_HC_extStateHC(lz4_state.get(), reinterpret_cast<const char*>(src),
                                                 reinterpret_cast<char*>(dst),
                                                 static_cast<int>(len), static_cast<int>(bound),
                                                 level);
        got = r > 0 ? static_cast<std::size_t>(r) : 0;
      }
      if (got == 0 && len > 0) {
        const std::lock_guard<std::mutex> lock(mutex);
        failed = true;
        return;
      }
      out.sizes[b] = got;
    }
  };
  // Slices of the input, each compressed in parallel, with progress between them.
  constexpr std::size_t kSliceBlocks = 256;  // 64 MiB of the writer's 256 KiB blocks
  const std::size_t slice = progress ? kSliceBlocks : nblocks;
  for (std::size_t begin = 0; begin < nblocks; begin += slice) {
    const std::size_t end = std::min(nblocks, begin + slice);
    parallel_for_range(end - begin, kCompressBlocksPerTask,
                       [&](std::size_t b, std::size_t e) { body(begin + b, begin + e); });
    if (failed) throw Error("VTK XML writer: compression failed (out of memory)");
    if (progress) progress(std::min(n, end * block));
  }
  // Compact the slots in order (deterministic: the layout depends only on the sizes).
  std::size_t at = 0;
  for (std::size_t b = 0; b < nblocks; ++b) {
    if (at != b * bound) std::memmove(out.data.get() + at, out.data.get() + b * bound, out.sizes[b]);
    at += out.sizes[b];
  }
  out.bytes = at;
  return out;
}

}  // namespace isoforge::io_detail
