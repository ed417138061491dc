// zlib against libdeflate on VTK XML blocks (32 KiB, each its own zlib stream), one thread:
// compression CPU time and size per level of each, and inflate time of the same streams (zlib's
// streams decoded by both libraries). The size/time curve of docs/algorithms/vtk_xml_io.md.
// LZ4 (fast, level 1) on the same blocks for comparison.
// Build: g++ -O2 -std=c++20 zlib_vs_libdeflate.cpp -lz -ldeflate -llz4 -o zlib_vs_libdeflate
// Usage: zlib_vs_libdeflate FILE...   (the bytes of each file are cut into 32 KiB blocks)
#include <libdeflate.h>
#include <lz4.h>
#include <zlib.h>

#include <time.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace {

constexpr std::size_t kBlock = 32768;

// Thread CPU time: the machine may be shared, and one thread's work is what is compared.
double now() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

using Blocks = std::vector<std::string>;

Blocks zlib_compress(const std::string& in, int level, double& sec) {
  Blocks out;
  const double t = now();
  for (std::size_t at = 0; at < in.size(); at += kBlock) {
    const std::size_t n = std::min(kBlock, in.size() - at);
    std::string c(compressBound(n), '\0');
    uLongf len = c.size();
    compress2(reinterpret_cast<Bytef*>(c.data()), &len, reinterpret_cast<const Bytef*>(in.data() + at), n,
              level);
    c.resize(len);
    out.push_back(std::move(c));
  }
  sec = now() - t;
  return out;
}

Blocks deflate_compress(const std::string& in, int level, double& sec) {
  Blocks out;
  libdeflate_compressor* c = libdeflate_alloc_compressor(level);
  const double t = now();
  for (std::size_t at = 0; at < in.size(); at += kBlock) {
    const std::size_t n = std::min(kBlock, in.size() - at);
    std::string b(libdeflate_zlib_compress_bound(c, n), '\0');
    b.resize(libdeflate_zlib_compress(c, in.data() + at, n, b.data(), b.size()));
    out.push_back(std::move(b));
  }
  sec = now() - t;
  libdeflate_free_compressor(c);
  return out;
}

double zlib_inflate(const Blocks& blocks, std::size_t total) {
  std::string out(kBlock, '\0');
  const double t = now();
  std::size_t left = total;
  for (const auto& b : blocks) {
    uLongf n = std::min(kBlock, left);
    uncompress(reinterpret_cast<Bytef*>(out.data()), &n, reinterpret_cast<const Bytef*>(b.data()), b.size());
    left -= n;
  }
  return now() - t;
}

double deflate_inflate(const Blocks& blocks, std::size_t total) {
  libdeflate_decompressor* d = libdeflate_alloc_decompressor();
  std::string out(kBlock, '\0');
  const double t = now();
  std::size_t left = total;
  for (const auto& b : blocks) {
    const std::size_t n = std::min(kBlock, left);
    if (libdeflate_zlib_decompress(d, b.data(), b.size(), out.data(), n, nullptr) != LIBDEFLATE_SUCCESS)
      std::fprintf(stderr, "libdeflate failed\n");
    left -= n;
  }
  libdeflate_free_decompressor(d);
  return now() - t;
}

std::size_t bytes(const Blocks& b) {
  std::size_t n = 0;
  for (const auto& s : b) n += s.size();
  return n;
}

}  // namespace

int main(int argc, char** argv) {
  for (int f = 1; f < argc; ++f) {
    std::ifstream in(argv[f], std::ios::binary);
    const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const double mb = static_cast<double>(data.size()) / 1e6;
    std::printf("%s: %.1f MB\n", argv[f], mb);
    std::printf("| level | zlib ratio | zlib MB/s | libdeflate ratio | libdeflate MB/s | inflate zlib MB/s | inflate libdeflate MB/s |\n|---|---|---|---|---|---|---|\n");
    for (int level : {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12}) {
      double tz = 0, td = 0;
      Blocks z;
      if (level <= 9) z = zlib_compress(data, level, tz);
      const Blocks d = deflate_compress(data, level, td);
      const Blocks& s = level <= 9 ? z : d;  // the same streams for both inflaters
      const double iz = zlib_inflate(s, data.size()), id = deflate_inflate(s, data.size());
      if (level <= 9) {
        std::printf("| %d | %.3f | %.0f | %.3f | %.0f | %.0f | %.0f |\n", level,
                    static_cast<double>(data.size()) / bytes(z), mb / tz,
                    static_cast<double>(data.size()) / bytes(d), mb / td, mb / iz, mb / id);
      } else {
        std::printf("| %d | - | - | %.3f | %.0f | %.0f | %.0f |\n", level,
                    static_cast<double>(data.size()) / bytes(d), mb / td, mb / iz, mb / id);
      }
    }
    // LZ4's fast compressor and its decoder on the same blocks.
    Blocks l;
    double t = now();
    for (std::size_t at = 0; at < data.size(); at += kBlock) {
      const int n = static_cast<int>(std::min(kBlock, data.size() - at));
      std::string c(static_cast<std::size_t>(LZ4_compressBound(n)), '\0');
      c.resize(static_cast<std::size_t>(
          LZ4_compress_default(data.data() + at, c.data(), n, static_cast<int>(c.size()))));
      l.push_back(std::move(c));
    }
    const double tc = now() - t;
    std::string out(kBlock, '\0');
    t = now();
    std::size_t left = data.size();
    for (const auto& b : l) {
      const int n = static_cast<int>(std::min(kBlock, left));
      LZ4_decompress_safe(b.data(), out.data(), static_cast<int>(b.size()), n);
      left -= static_cast<std::size_t>(n);
    }
    const double td = now() - t;
    std::printf("LZ4 (fast): ratio %.3f, compress %.0f MB/s, decompress %.0f MB/s\n",
                static_cast<double>(data.size()) / bytes(l), mb / tc, mb / td);
  }
}
