#include "detail/file_source.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "detail/progress.hpp"
#include "detail/tuple_stream.hpp"
#include "isoforge/core/error.hpp"
#include "isoforge/core/parallel.hpp"

namespace isoforge::io_detail {

namespace {

/// Below this a copy from the mapping is cheaper than a system call.
constexpr std::size_t kPreadMin = std::size_t{64} << 10;
/// Copies from this size on are split into reads of kParallelPiece on all threads: most of the
/// time of a big read is the kernel zeroing the fresh pages of the array (measured: 70% of
/// reading a 512 MB raw volume), which happens in the thread that first writes them. The readers
/// copy an array in sixteen pieces (progress between them), so a 64 MiB array comes in pieces
/// of 4 MiB and a 12 MiB one in pieces of 768 KiB: those too are split.
constexpr std::size_t kParallelMin = std::size_t{512} << 10;
constexpr std::size_t kParallelPiece = std::size_t{256} << 10;
/// copy_elements works in slices of this (progress between them).
constexpr std::size_t kSliceBytes = std::size_t{64} << 20;

std::string errno_text() { return std::strerror(errno); }

}  // namespace

MappedFile::MappedFile(const std::filesystem::path& path) : name_(path.string()) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw Error(name_ + ": is a directory, not a file");
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) throw Error(name_ + ": cannot open: " + errno_text());
  struct stat st {};
  if (::fstat(fd_, &st) != 0) {
    const std::string why = errno_text();
    ::close(fd_);
    throw Error(name_ + ": cannot determine the file size: " + why);
  }
  if (S_ISREG(st.st_mode) && st.st_size > 0) {
    map_size_ = static_cast<std::size_t>(st.st_size);
    map_ = ::mmap(nullptr, map_size_, PROT_READ, MAP_PRIVATE, fd_, 0);
    if (map_ == MAP_FAILED) {
      map_ = nullptr;
      map_size_ = 0;
    } else {
      bytes_ = {static_cast<const std::byte*>(map_), static_cast<std::size_t>(st.st_size)};
      return;
    }
  }
  if (S_ISREG(st.st_mode) && st.st_size == 0) return;  // empty: nothing to map
  // Not mappable (a pipe, a character device, or mmap refused): read it all.
  constexpr std::size_t kChunk = std::size_t{1} << 20;
  std::size_t used = 0;
  while (true) {
    if (owned_.size() - used < kChunk) owned_.resize(std::max(owned_.size() * 2, used + kChunk));
    const ssize_t r = ::read(fd_, owned_.data() + used, owned_.size() - used);
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) {
      const std::string why = errno_text();
      ::close(fd_);
      throw Error(name_ + ": read failed: " + why);
    }
    if (r == 0) break;
    used += static_cast<std::size_t>(r);
  }
  owned_.resize(used);
  bytes_ = owned_;
  ::close(fd_);
  fd_ = -1;
}

MappedFile::~MappedFile() {
  if (map_) ::munmap(map_, map_size_);
  if (fd_ >= 0) ::close(fd_);
}

void MappedFile::copy(std::uint64_t offset, std::byte* dst, std::size_t n) const {
  if (offset > bytes_.size() || n > bytes_.size() - offset) {
    throw Error(name_ + ": internal: copy of " + std::to_string(n) + " bytes at byte " +
                std::to_string(offset) + " past the end of the file");
  }
  if (!map_ || fd_ < 0) {
    if (n > 0) std::memcpy(dst, bytes_.data() + offset, n);
    return;
  }
  while (n > 0) {
    const ssize_t r = ::pread(fd_, dst, n, static_cast<off_t>(offset));
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) throw Error(at_byte(name_, offset, "read failed: " + errno_text()));
    if (r == 0) throw Error(at_byte(name_, offset, "read failed: the file became shorter"));
    dst += r;
    n -= static_cast<std::size_t>(r);
    offset += static_cast<std::uint64_t>(r);
  }
}

void MappedFile::release(std::uint64_t offset, std::size_t n) const {
  if (!map_ || offset >= map_size_) return;
  n = std::min<std::size_t>(n, map_size_ - static_cast<std::size_t>(offset));
  const auto page = static_cast<std::uint64_t>(::sysconf(_SC_PAGESIZE));
  const std::uint64_t b = (offset + page - 1) / page * page;
  const std::uint64_t e = (offset + n) / page * page;
  // Advice only: the mapping is read-only and private, so dropped pages read back unchanged.
  if (e > b) ::madvise(static_cast<char*>(map_) + b, static_cast<std::size_t>(e - b), MADV_DONTNEED);
}

void FileSource::release(const std::byte* from, const std::byte* to) const {
  if (file && to > from) {
    file->release(static_cast<std::uint64_t>(from - bytes.data()),
                  static_cast<std::size_t>(to - from));
  }
}

void FileSource::copy(const std::byte* from, std::byte* dst, std::size_t n) const {
  if (n == 0) return;
  if (file && n >= kParallelMin) {
    const auto offset = static_cast<std::uint64_t>(from - bytes.data());
    parallel_for_range((n + kParallelPiece - 1) / kParallelPiece, 1,
                       [&](std::size_t b, std::size_t e) {
                         const std::size_t lo = b * kParallelPiece;
                         const std::size_t hi = std::min(n, e * kParallelPiece);
                         file->copy(offset + lo, dst + lo, hi - lo);
                       });
  } else if (file && n >= kPreadMin) {
    file->copy(static_cast<std::uint64_t>(from - bytes.data()), dst, n);
  } else {
    std::memcpy(dst, from, n);
  }
}

namespace {

template <class U>
void swap_all(std::byte* data, std::size_t count) {
  // Through memcpy, so the loop vectorises to byte shuffles and needs no alignment.
  for (std::size_t i = 0; i < count; ++i) {
    U v;
    std::memcpy(&v, data + i * sizeof(U), sizeof(U));
    if constexpr (sizeof(U) == 2) v = static_cast<U>(__builtin_bswap16(v));
    if constexpr (sizeof(U) == 4) v = __builtin_bswap32(v);
    if constexpr (sizeof(U) == 8) v = __builtin_bswap64(v);
    std::memcpy(data + i * sizeof(U), &v, sizeof(U));
  }
}

}  // namespace

void swap_elements(std::byte* data, std::size_t count, std::size_t elem_size) {
  switch (elem_size) {
    case 2: swap_all<std::uint16_t>(data, count); return;
    case 4: swap_all<std::uint32_t>(data, count); return;
    case 8: swap_all<std::uint64_t>(data, count); return;
    default:
      for (std::size_t i = 0; i < count; ++i) {
        std::reverse(data + i * elem_size, data + (i + 1) * elem_size);
      }
  }
}

void copy_swapped(const std::byte* from, std::byte* dst, std::size_t count, std::size_t elem_size) {
  const std::size_t piece = std::max<std::size_t>(1, kParallelPiece / elem_size);
  const auto run = [&](std::size_t lo, std::size_t hi) {
    std::memcpy(dst + lo * elem_size, from + lo * elem_size, (hi - lo) * elem_size);
    swap_elements(dst + lo * elem_size, hi - lo, elem_size);  // while the piece is in cache
  };
  if (count * elem_size < kParallelMin) {
    for (std::size_t i = 0; i < count; i += piece) run(i, std::min(count, i + piece));
    return;
  }
  parallel_for_range((count + piece - 1) / piece, 1, [&](std::size_t b, std::size_t e) {
    for (std::size_t p = b; p < e; ++p) run(p * piece, std::min(count, (p + 1) * piece));
  });
}

void copy_elements(const FileSource& src, const std::byte* from, std::byte* dst,
                   std::size_t count, std::size_t elem_size, bool swap, Progress* progress,
                   std::uint64_t progress_base) {
  // In slices, with progress after each; the copy and the swap each on all threads.
  const std::size_t per = std::max<std::size_t>(1, kSliceBytes / elem_size);
  for (std::size_t i = 0; i < count; i += per) {
    const std::size_t m = std::min(per, count - i);
    std::byte* out = dst + i * elem_size;
    src.copy(from + i * elem_size, out, m * elem_size);
    if (swap && elem_size > 1) {
      const std::size_t piece = std::max<std::size_t>(1, kParallelPiece / elem_size);
      parallel_for_range((m + piece - 1) / piece, 1, [&](std::size_t b, std::size_t e) {
        const std::size_t lo = b * piece, hi = std::min(m, e * piece);
        swap_elements(out + lo * elem_size, hi - lo, elem_size);
      });
    }
    if (progress) progress->set(progress_base + (i + m) * elem_size);
  }
}

TupleStream::TupleStream(ScalarType type, int components, bool swap, Consumer consume)
    : elem_(scalar_size(type)),
      unit_(scalar_size(type) * static_cast<std::size_t>(components)),
      swap_(swap && scalar_size(type) > 1),
      consume_(std::move(consume)) {}

std::byte* TupleStream::window(std::size_t n) {
  if (buffer_.size() < carry_ + n) buffer_.resize(carry_ + n);
  return buffer_.data() + carry_;
}

void TupleStream::filled(std::size_t n) {
  const std::size_t have = carry_ + n;
  const std::size_t count = have / unit_;
  if (count > 0) {
    if (swap_) {
      const std::size_t elems = count * unit_ / elem_;
      const std::size_t piece = std::max<std::size_t>(1, kParallelPiece / elem_);
      parallel_for_range((elems + piece - 1) / piece, 1, [&](std::size_t b, std::size_t e) {
        const std::size_t lo = b * piece, hi = std::min(elems, e * piece);
        swap_elements(buffer_.data() + lo * elem_, hi - lo, elem_);
      });
    }
    consume_(buffer_.data(), count);
    tuples_ += count;
  }
  carry_ = have - count * unit_;
  if (carry_ > 0) std::memmove(buffer_.data(), buffer_.data() + count * unit_, carry_);
}

void stream_bytes(const FileSource& src, const std::byte* from, std::size_t n, TupleStream& stream,
                  Progress* progress, std::uint64_t progress_base) {
  for (std::size_t at = 0; at < n; at += TupleStream::kPiece) {
    const std::size_t m = std::min(TupleStream::kPiece, n - at);
    src.copy(from + at, stream.window(m), m);
    stream.filled(m);
    if (progress) progress->set(progress_base + at + m);
  }
}

}  // namespace isoforge::io_detail
