#pragma once
// Private: a file's bytes as the readers see them. The file is mapped read-only, so headers and
// text are parsed in place and only the pages a reader looks at are touched; a binary array is
// copied from the file into its final place with pread (FileSource::copy), which neither faults
// the mapped pages in nor keeps a resident copy of the file: reading a 512 MB raw array costs
// 512 MB of memory, not 1 GB, and runs at the kernel's copy speed (8 GB/s here against 1.6 for
// faulting the mapping). In-memory input (the span overloads of the readers) has no file:
// copy() is memcpy there.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace isoforge::io_detail {

class Progress;

/// A file mapped read-only (or, when it cannot be mapped — a pipe, a special file — read into
/// memory). \throw Error naming the path if it cannot be opened or read.
class MappedFile {
 public:
  explicit MappedFile(const std::filesystem::path& path);
  ~MappedFile();
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;

  [[nodiscard]] std::span<const std::byte> bytes() const { return bytes_; }
  [[nodiscard]] const std::string& name() const { return name_; }
  /// Copies the `n` file bytes at `offset` into `dst` (pread when mapped).
  /// \throw Error naming the file if the read fails or comes short.
  void copy(std::uint64_t offset, std::byte* dst, std::size_t n) const;
  /// Drops the mapped pages wholly inside [offset, offset + n) from this process's memory (they
  /// stay in the page cache and are mapped again if read again): a reader that has consumed
  /// them keeps its resident set to the arrays it made. Nothing when not mapped.
  void release(std::uint64_t offset, std::size_t n) const;

 private:
  std::string name_;
  int fd_ = -1;
  void* map_ = nullptr;
  std::size_t map_size_ = 0;
  std::vector<std::byte> owned_;  // when not mapped
  std::span<const std::byte> bytes_;
};

/// The bytes a reader parses, and the file they are mapped from (null for in-memory data).
struct FileSource {
  std::span<const std::byte> bytes;
  const MappedFile* file = nullptr;

  FileSource() = default;
  FileSource(std::span<const std::byte> b) : bytes(b) {}  // NOLINT: in-memory data converts
  explicit FileSource(const MappedFile& f) : bytes(f.bytes()), file(&f) {}

  /// Copies `n` bytes starting at `from` (a pointer into `bytes`) to `dst`: from the file when
  /// there is one and the copy is large (the mapped pages stay untouched; big copies in pieces
  /// on all threads), else memcpy.
  void copy(const std::byte* from, std::byte* dst, std::size_t n) const;
  /// MappedFile::release of the bytes [from, to) (pointers into `bytes`); nothing in memory.
  void release(const std::byte* from, const std::byte* to) const;
};

/// Copies `count` elements of `elem_size` bytes from `from` (inside `src.bytes`) to `dst`,
/// swapping each element's bytes when `swap`, in slices of 64 MiB (each copied and swapped on
/// all threads); `progress` (may be null) is set to `progress_base` + the bytes copied after each.
void copy_elements(const FileSource& src, const std::byte* from, std::byte* dst,
                   std::size_t count, std::size_t elem_size, bool swap, Progress* progress,
                   std::uint64_t progress_base = 0);

/// Swaps the bytes of `count` elements of `elem_size` (2, 4 or 8; 1 does nothing) in place.
void swap_elements(std::byte* data, std::size_t count, std::size_t elem_size);

/// For writers that encode variable-size records a slice at a time: the end of the run of
/// records from `first` that fits in `budget` bytes, where record r starts at place(r)
/// (increasing; place(n) is where the last one ends). The largest end in (first, n] with
/// place(end) - place(first) <= budget, and at least first + 1: a larger record goes alone.
template <class Place>
std::size_t slice_end(std::size_t first, std::size_t n, std::size_t budget, Place place) {
  std::size_t lo = first + 1, hi = n;
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo + 1) / 2;
    if (place(mid) - place(first) <= budget) {
      lo = mid;
    } else {
      hi = mid - 1;
    }
  }
  return lo;
}

/// Copies `count` elements of `elem_size` bytes from `from` to `dst` (not overlapping) with
/// each element's bytes swapped, on all threads from 512 KiB on: writers of big-endian files.
void copy_swapped(const std::byte* from, std::byte* dst, std::size_t count, std::size_t elem_size);

}  // namespace isoforge::io_detail
