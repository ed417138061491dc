#pragma once
// Private: progress of reading and writing, counted in units of work (bytes of a file read,
// values written) and reported through a ProgressCallback about every `step` units — never per
// element: the fast path of add()/set() is one comparison.

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <ostream>
#include <span>
#include <vector>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"
#include "file_source.hpp"

namespace isoforge::io_detail {

class Progress {
 public:
  static constexpr std::uint64_t kStep = std::uint64_t{1} << 20;  // ~1 MB of bytes or values

  /// Inactive: add() and set() do nothing.
  Progress() = default;
  /// `total` units of work map onto fractions [from, to] of `callback` (which may be empty).
  /// `operation` names it in `Cancelled` ("reading", "writing").
  Progress(const ProgressCallback& callback, std::uint64_t total, const char* operation,
           double from = 0, double to = 1)
      : callback_(callback ? &callback : nullptr),
        operation_(operation),
        total_(total),
        from_(from),
        to_(to) {
    if (callback_) {
      next_ = 0;  // the first add/set reports `from`
    }
  }

  /// `n` more units done.
  void add(std::uint64_t n) {
    done_ += n;
    if (done_ >= next_) report();
  }
  /// `done` units done in all (never goes back).
  void set(std::uint64_t done) {
    if (done >= next_) {
      done_ = std::max(done_, done);
      report();
    }
  }
  /// All done: reports `to`.
  void finish() {
    if (!callback_) return;
    done_ = total_;
    report_fraction(to_);
  }
  [[nodiscard]] bool active() const { return callback_ != nullptr; }
  [[nodiscard]] double to() const { return to_; }
  [[nodiscard]] const ProgressCallback* callback() const { return callback_; }

 private:
  void report() {
    const double f =
        total_ == 0 ? 0.0 : std::min(1.0, static_cast<double>(done_) / static_cast<double>(total_));
    report_fraction(from_ + (to_ - from_) * f);
    next_ = done_ + kStep;
  }
  void report_fraction(double f) {
    if (f <= last_) return;  // monotone, and each fraction once
    last_ = f;
    report_progress(*callback_, f, operation_);
  }

  const ProgressCallback* callback_ = nullptr;
  const char* operation_ = "";
  std::uint64_t total_ = 0;
  std::uint64_t done_ = 0;
  std::uint64_t next_ = std::numeric_limits<std::uint64_t>::max();
  double from_ = 0, to_ = 1;
  double last_ = -1;
};

/// The size of a file (0 if it cannot be told; reading it then reports the error).
[[nodiscard]] std::uint64_t file_size_or_zero(const std::filesystem::path& path);

/// Calls f(values, bytes per value) for each part a writer emits for `ds`: points, cell lists
/// (connectivity and offsets; unstructured cell types) and every point, cell and field array.
template <class F>
void for_each_payload(DatasetRef ds, F&& f) {
  for (const Attributes* at : {&point_data(ds), &cell_data(ds), &field_data(ds)}) {
    for (const DataArray& a : *at) f(std::uint64_t{a.size()}, scalar_size(a.type()));
  }
  const auto cells = [&f](const CellArray& c) {
    f(std::uint64_t{c.connectivity().size() + c.offsets().size()}, sizeof(Index));
  };
  const auto points = [&f](const Points& p) {
    f(std::uint64_t{3} * p.size(), scalar_size(p.type()));
  };
  if (const auto* sg = ds.get_if<StructuredGrid>()) points(sg->points);
  if (const auto* pd = ds.get_if<PolyData>()) {
    points(pd->points);
    for (const CellArray* c : {&pd->verts, &pd->lines, &pd->polys, &pd->strips}) cells(*c);
  }
  if (const auto* ug = ds.get_if<UnstructuredGrid>()) {
    points(ug->points);
    f(std::uint64_t{ug->types.size()}, sizeof(CellType));
    cells(ug->cells);
  }
}

/// The values (scalars) a writer emits for `ds`, to measure its progress.
[[nodiscard]] inline std::uint64_t payload_values(DatasetRef ds) {
  std::uint64_t n = 0;
  for_each_payload(ds, [&n](std::uint64_t values, std::size_t) { n += values; });
  return n;
}

/// The bytes of `ds`'s arrays as stored in memory: about the size of a binary file of it, for
/// AtomicFile::reserve.
[[nodiscard]] inline std::uint64_t payload_bytes(DatasetRef ds) {
  std::uint64_t n = 0;
  for_each_payload(ds, [&n](std::uint64_t values, std::size_t size) { n += values * size; });
  return n;
}

/// Writes `n` bytes in blocks, adding each block's bytes to `progress`.
inline void write_blocks(std::ostream& out, const char* data, std::size_t n, Progress& progress) {
  constexpr std::size_t kBlock = std::size_t{8} << 20;
  for (std::size_t at = 0; at < n; at += kBlock) {
    const std::size_t m = std::min(kBlock, n - at);
    out.write(data + at, static_cast<std::streamsize>(m));
    progress.add(m);
  }
}

/// Reads the file `path` with progress: the file is mapped (file_source.hpp), and
/// `parse(source, progress, base)` reports `base` + the bytes it has consumed (e.g. through
/// `Scanner::track`), which is all the work; then reports the end.
template <class Parse>
auto read_with_progress(const std::filesystem::path& path, const ProgressCallback& callback,
                        Parse&& parse) {
  const MappedFile file(path);
  Progress progress(callback, file.bytes().size(), "reading");
  auto result = parse(FileSource(file), &progress, std::uint64_t{0});
  progress.finish();
  return result;
}

}  // namespace isoforge::io_detail
