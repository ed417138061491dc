// PLOT3D file format (NASA Ames PLOT3D User's Manual, NASA TM-101067, chapter 8 "Data File
// Formats"): reader for the "whole" binary format — a single 3D grid (optionally preceded by a
// grid count of 1), no Fortran record markers, big or little endian, float32 or float64, with or
// without IBLANK — and its Q (solution) file: dims, fsmach/alpha/re/time, then density, the three
// momentum components and stagnation energy per point. Layout and byte order are detected from
// the file size (the only unambiguous evidence a binary PLOT3D file carries).

#include <tbb/enumerable_thread_specific.h>

#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "detail/progress.hpp"
#include "detail/scanner.hpp"
#include "detail/summaries.hpp"
#include "isoforge/core/parallel.hpp"
#include "isoforge/core/summary.hpp"
#include "isoforge/io/io.hpp"
#include "isoforge/io/plot3d.hpp"

namespace isoforge {

namespace {

using io_detail::Endian;
using io_detail::Scanner;

struct Layout {
  Endian endian = Endian::Big;
  std::size_t header_bytes = 12;  // 12: ni nj nk; 16: ngrid ni nj nk
  Dims dims{1, 1, 1};
  std::size_t count = 0;  // points
  std::size_t prec = 4;   // bytes per real
  bool iblank = false;
};

const char* endian_name(Endian e) {
  return e == Endian::Little ? "little endian" : "big endian";
}

std::string dims_text(const Dims& d) {
  return std::to_string(d[0]) + " x " + std::to_string(d[1]) + " x " + std::to_string(d[2]);
}

std::vector<Endian> orders(Plot3dByteOrder order, Endian preferred) {
  switch (order) {
    case Plot3dByteOrder::Big:
      return {Endian::Big};
    case Plot3dByteOrder::Little:
      return {Endian::Little};
    case Plot3dByteOrder::Auto:
      break;
  }
  return {preferred, preferred == Endian::Little ? Endian::Big : Endian::Little};
}

std::int32_t int_at(std::span<const std::byte> data, std::size_t offset, Endian e) {
  std::int32_t v;
  std::memcpy(&v, data.data() + offset, 4);
  if (e != io_detail::kHostEndian) v = io_detail::byteswap_value(v);
  return v;
}

/// Header candidates (with / without a leading grid count) of a file, in one byte order.
struct Header {
  std::size_t header_bytes;
  Dims dims;
  bool valid;  // all dims positive and the point count fits in 64 bits
  std::uint64_t count;
};

std::vector<Header> headers(std::span<const std::byte> data, Endian e) {
  std::vector<Header> out;
  auto make = [&](std::size_t off) {
    Header h{off + 12,
             {int_at(data, off, e), int_at(data, off + 4, e), int_at(data, off + 8, e)},
             true,
             1};
    for (Index d : h.dims) {
      if (d < 1 || io_detail::mul_overflow(h.count, static_cast<std::uint64_t>(d), h.count)) {
        h.valid = false;
      }
    }
    return h;
  };
  if (data.size() >= 16 && int_at(data, 0, e) == 1) out.push_back(make(4));
  if (data.size() >= 12) out.push_back(make(0));
  return out;
}

/// size = header + count * per_point, or nullopt on overflow.
std::optional<std::uint64_t> layout_size(std::uint64_t header, std::uint64_t count,
                                         std::uint64_t per_point) {
  std::uint64_t s = 0;
  if (io_detail::mul_overflow(count, per_point, s) || __builtin_add_overflow(s, header, &s)) {
    return std::nullopt;
  }
  return s;
}

std::string size_text(std::optional<std::uint64_t> s) {
  return s ? std::to_string(*s) : std::string("(overflow)");
}

Layout detect_grid(std::span<const std::byte> data, const std::string& name,
                   Plot3dByteOrder order) {
  if (data.size() < 12) {
    throw Error(at_byte(name, 0,
                        "truncated: a PLOT3D grid header needs 12 bytes (ni nj nk), the file has " +
                            std::to_string(data.size())));
  }
  std::string tried;
  for (Endian e : orders(order, Endian::Big)) {
    for (const Header& h : headers(data, e)) {
      if (!tried.empty()) tried += "; ";
      tried += std::string(endian_name(e)) + (h.header_bytes == 16 ? " with grid count" : "") +
               ": dims " + dims_text(h.dims);
      if (!h.valid) {
        tried += " (not a valid point count)";
        continue;
      }
      std::string sizes;
      for (std::size_t prec : {4u, 8u}) {
        for (bool iblank : {false, true}) {
          const auto s = layout_size(h.header_bytes, h.count, 3 * prec + (iblank ? 4 : 0));
          if (s && *s == data.size()) {
            Layout l;
            l.endian = e;
            l.header_bytes = h.header_bytes;
            l.dims = h.dims;
            l.count = static_cast<std::size_t>(h.count);
            l.prec = prec;
            l.iblank = iblank;
            return l;
          }
          if (!sizes.empty()) sizes += ", ";
          sizes += size_text(s) + (prec == 4 ? " (float32" : " (float64") +
                   (iblank ? " + iblank)" : ")");
        }
      }
      tried += " expect " + sizes + " bytes";
    }
  }
  throw Error(at_byte(name, 0,
                      "file size " + std::to_string(data.size()) +
                          " bytes matches no PLOT3D grid layout [" + tried + "]"));
}

Layout detect_q(std::span<const std::byte> data, const std::string& name, const Layout& grid,
                const std::string& grid_name, Plot3dByteOrder order) {
  if (data.size() < 12) {
    throw Error(at_byte(name, 0,
                        "truncated: a PLOT3D Q header needs 12 bytes (ni nj nk), the file has " +
                            std::to_string(data.size())));
  }
  std::string sizes;
  bool dims_matched = false;
  for (Endian e : orders(order, grid.endian)) {
    for (const Header& h : headers(data, e)) {
      if (h.dims != grid.dims) continue;
      dims_matched = true;
      for (std::size_t prec : {4u, 8u}) {
        const auto s = layout_size(h.header_bytes + 4 * prec, grid.count, 5 * prec);
        if (s && *s == data.size()) {
          Layout l = grid;
          l.endian = e;
          l.header_bytes = h.header_bytes;
          l.prec = prec;
          l.iblank = false;
          return l;
        }
        if (!sizes.empty()) sizes += ", ";
        sizes += size_text(s) + (prec == 4 ? " (float32)" : " (float64)");
      }
    }
  }
  if (!dims_matched) {
    const Endian e = order == Plot3dByteOrder::Little ? Endian::Little
                     : order == Plot3dByteOrder::Big  ? Endian::Big
                                                      : grid.endian;
    const auto hs = headers(data, e);
    const Header& h = hs.back();  // the plain ni nj nk reading
    throw Error(at_byte(name, 0,
                        "Q file dimensions " + dims_text(h.dims) + " (" + endian_name(e) +
                            ") do not match the grid file " + grid_name + " (" +
                            dims_text(grid.dims) + ")"));
  }
  throw Error(at_byte(name, 0,
                      "Q file size " + std::to_string(data.size()) +
                          " bytes matches no layout for dims " + dims_text(grid.dims) +
                          " (expected " + sizes + " bytes)"));
}

// ---- Reading in blocks -------------------------------------------------------------------
// The planes of a file (x, y, z of the grid; density, momentum and energy of the solution) are
// read in blocks of points with pread (FileSource::copy: the mapped pages stay untouched),
// byte-swapped, checked and written straight into the final arrays — or, for a summary, into
// the ranges. Blocks run on all threads; memory is the arrays plus a block per thread.

constexpr std::size_t kBlockPoints = std::size_t{1} << 16;  // points per task
constexpr std::size_t kSlicePoints = std::size_t{1} << 18;  // points between progress reports

/// Calls work(first, n) on blocks of at most kBlockPoints points covering [0, count), in parallel,
/// setting `progress` to `base` + `bytes_per_point` × the points done between slices.
void for_blocks(std::size_t count, io_detail::Progress* progress, std::uint64_t base,
                std::uint64_t bytes_per_point,
                const std::function<void(std::size_t, std::size_t)>& work) {
  for (std::size_t s = 0; s < count; s += kSlicePoints) {
    const std::size_t m = std::min(kSlicePoints, count - s);
    parallel_for_range((m + kBlockPoints - 1) / kBlockPoints, 1, [&](std::size_t b, std::size_t e) {
      for (std::size_t k = b; k < e; ++k) {
        const std::size_t first = s + k * kBlockPoints;
        work(first, std::min(kBlockPoints, s + m - first));
      }
    });
    if (progress) progress->set(base + (s + m) * bytes_per_point);
  }
}

/// The scratch values of blocks: buffers per thread (two slots), reused by the blocks of one read
/// and freed with it.
class Scratch {
 public:
  template <class T>
  T* get(std::size_t slot, std::size_t n) {
    std::vector<std::byte>& b = local_.local()[slot];
    if (b.size() < n * sizeof(T)) b.resize(n * sizeof(T));
    return reinterpret_cast<T*>(b.data());
  }

 private:
  tbb::enumerable_thread_specific<std::array<std::vector<std::byte>, 2>> local_;
};

/// The planes of one file: `planes` arrays of `count` values of T from byte `start`.
struct PlaneFile {
  io_detail::FileSource src;
  std::size_t start = 0;
  std::size_t count = 0;
  bool swap = false;

  /// Values [first, first + n) of plane `plane` into `dst`, in host order.
  template <class T>
  void load(int plane, std::size_t first, std::size_t n, T* dst) const {
    const std::byte* from =
        src.bytes.data() + start + (static_cast<std::size_t>(plane) * count + first) * sizeof(T);
    src.copy(from, reinterpret_cast<std::byte*>(dst), n * sizeof(T));
    if (swap) io_detail::swap_elements(reinterpret_cast<std::byte*>(dst), n, sizeof(T));
  }
};

/// The lowest key offered (atomic): the first bad value in file order over blocks run in any
/// order.
class FirstBad {
 public:
  void offer(std::uint64_t key) {
    std::uint64_t cur = key_.load(std::memory_order_relaxed);
    while (key < cur && !key_.compare_exchange_weak(cur, key, std::memory_order_relaxed)) {
    }
  }
  [[nodiscard]] std::optional<std::uint64_t> get() const {
    const std::uint64_t k = key_.load();
    if (k == kNone) return std::nullopt;
    return k;
  }

 private:
  static constexpr std::uint64_t kNone = std::numeric_limits<std::uint64_t>::max();
  std::atomic<std::uint64_t> key_{kNone};
};

template <class T>
bool finite_values(const T* v, std::size_t n) {
  bool ok = true;
  for (std::size_t i = 0; i < n; ++i) ok &= std::isfinite(v[i]);
  return ok;
}

/// Points [first, first + n) of the grid, interleaved into `xyz`; a non-finite coordinate is
/// offered to `bad` as plane × count + point.
template <class T>
void grid_block(const PlaneFile& f, std::size_t first, std::size_t n, T* xyz, FirstBad& bad,
                Scratch& scratch) {
  T* c = scratch.get<T>(0, 3 * n);
  for (int a = 0; a < 3; ++a) {
    T* plane = c + static_cast<std::size_t>(a) * n;
    f.load(a, first, n, plane);
    if (!finite_values(plane, n)) {
      for (std::size_t i = 0; i < n; ++i) {
        if (!std::isfinite(plane[i])) {
          bad.offer(static_cast<std::uint64_t>(a) * f.count + first + i);
          break;
        }
      }
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    xyz[3 * i] = c[i];
    xyz[3 * i + 1] = c[n + i];
    xyz[3 * i + 2] = c[2 * n + i];
  }
}

[[noreturn]] void fail_non_finite(const std::string& name, const Layout& l, std::uint64_t key) {
  const std::size_t a = static_cast<std::size_t>(key / l.count);
  const std::size_t i = static_cast<std::size_t>(key % l.count);
  const Index ii = static_cast<Index>(i) % l.dims[0];
  const Index jj = (static_cast<Index>(i) / l.dims[0]) % l.dims[1];
  const Index kk = static_cast<Index>(i) / (l.dims[0] * l.dims[1]);
  throw Error(at_byte(name, l.header_bytes + (a * l.count + i) * l.prec,
                      "point " + std::to_string(i) + " (i, j, k = " + std::to_string(ii) + ", " +
                          std::to_string(jj) + ", " + std::to_string(kk) + ") has a non-finite " +
                          std::string(1, "xyz"[a]) + " coordinate"));
}

/// Where a block of the solution goes: each pointer at the block's first point.
template <class T>
struct QBlock {
  T* density;
  T* momentum;  // 3 per point
  T* energy;
  T* velocity;  // 3 per point
  T* pressure;
};

/// Points [first, first + n) of the solution, with the derived velocity and pressure (in double
/// precision from the stored values).
template <class T>
void q_block(const PlaneFile& f, std::size_t first, std::size_t n, double gm1, const QBlock<T>& out,
             Scratch& scratch) {
  T* m = scratch.get<T>(0, 3 * n);
  f.load(0, first, n, out.density);
  for (int a = 0; a < 3; ++a) f.load(1 + a, first, n, m + static_cast<std::size_t>(a) * n);
  f.load(4, first, n, out.energy);
  for (std::size_t i = 0; i < n; ++i) {
    const double mom[3] = {m[i], m[n + i], m[2 * n + i]};
    const double r = out.density[i];
    double vel[3] = {0, 0, 0};
    if (r != 0.0) {
      for (int a = 0; a < 3; ++a) vel[a] = mom[a] / r;
    }
    for (int a = 0; a < 3; ++a) {
      out.momentum[3 * i + static_cast<std::size_t>(a)] = static_cast<T>(mom[a]);
      out.velocity[3 * i + static_cast<std::size_t>(a)] = static_cast<T>(vel[a]);
    }
    const double v2 = vel[0] * vel[0] + vel[1] * vel[1] + vel[2] * vel[2];
    out.pressure[i] = static_cast<T>(gm1 * (static_cast<double>(out.energy[i]) - 0.5 * r * v2));
  }
}

/// "Valid" flags of the cells between two k planes of IBLANK values (`lo`, `hi`; the same plane
/// for a grid of one k plane): 1 when every corner is unblanked.
void valid_layer(const Dims& dims, const std::int32_t* lo, const std::int32_t* hi,
                 std::uint8_t* out) {
  const Index ci = dims[0] > 1 ? dims[0] - 1 : 1;
  const Index cj = dims[1] > 1 ? dims[1] - 1 : 1;
  const Index di = dims[0] > 1 ? 1 : 0, dj = dims[1] > 1 ? 1 : 0;
  for (Index j = 0; j < cj; ++j) {
    const auto r0 = static_cast<std::size_t>(dims[0] * j);
    const auto r1 = static_cast<std::size_t>(dims[0] * (j + dj));
    for (Index i = 0; i < ci; ++i) {
      const auto a = static_cast<std::size_t>(i), b = static_cast<std::size_t>(i + di);
      const bool ok = lo[r0 + a] != 0 && lo[r0 + b] != 0 && lo[r1 + a] != 0 && lo[r1 + b] != 0 &&
                      hi[r0 + a] != 0 && hi[r0 + b] != 0 && hi[r1 + a] != 0 && hi[r1 + b] != 0;
      *out++ = ok ? 1 : 0;
    }
  }
}

std::size_t cell_layers(const Dims& dims) {
  return dims[2] > 1 ? static_cast<std::size_t>(dims[2] - 1) : 1;
}

/// "Valid" cell flags of a whole IBLANK array.
DataArray valid_cells(const Dims& dims, std::span<const std::int32_t> iblank) {
  const std::size_t nc = structured_cell_count(dims);
  const std::size_t slab = static_cast<std::size_t>(dims[0] * dims[1]);
  const std::size_t layers = cell_layers(dims), per_layer = nc / layers;
  const std::size_t dk = dims[2] > 1 ? slab : 0;
  DataArray valid = DataArray::uninitialized("Valid", ScalarType::UInt8, 1, nc);
  std::uint8_t* out = valid.values<std::uint8_t>().data();
  parallel_for_range(layers, 1, [&](std::size_t b, std::size_t e) {
    for (std::size_t k = b; k < e; ++k) {
      valid_layer(dims, iblank.data() + k * slab, iblank.data() + k * slab + dk,
                  out + k * per_layer);
    }
  });
  return valid;
}

/// The byte offset of the IBLANK plane and of the solution's planes.
std::size_t iblank_start(const Layout& l) {
  return l.header_bytes + 3 * l.count * l.prec;
}
std::size_t q_start(const Layout& q) {
  return q.header_bytes + 4 * q.prec;
}

const char* const kFieldNames[4] = {"FreeStreamMach", "AngleOfAttack", "ReynoldsNumber", "Time"};
const char* const kQNames[5] = {"Density", "Momentum", "StagnationEnergy", "Velocity", "Pressure"};
constexpr int kQComponents[5] = {1, 3, 1, 3, 1};

/// The four flow conditions of a Q file as field data.
void read_conditions(const io_detail::FileSource& q, const std::string& q_name, const Layout& l,
                     Attributes& field_data) {
  Scanner sc(q, q_name);
  sc.seek(l.header_bytes);
  for (const char* field : kFieldNames) {
    if (l.prec == 4) {
      const auto v = sc.read<float>(l.endian, "fsmach, alpha, re, time");
      field_data.add(DataArray::from_vector(field, 1, std::vector<float>{v}));
    } else {
      const auto v = sc.read<double>(l.endian, "fsmach, alpha, re, time");
      field_data.add(DataArray::from_vector(field, 1, std::vector<double>{v}));
    }
  }
}

template <class T>
void read_points(StructuredGrid& grid, const io_detail::FileSource& xyz, const std::string& name,
                 const Layout& l, io_detail::Progress* progress, std::uint64_t base) {
  // Not zero-filled: every block writes its points.
  grid.points = Points(DataArray::uninitialized(
      "Points", l.prec == 8 ? ScalarType::Float64 : ScalarType::Float32, 3, l.count));
  T* p = grid.points.array().values<T>().data();
  const PlaneFile f{xyz, l.header_bytes, l.count, l.endian != io_detail::kHostEndian};
  FirstBad bad;
  Scratch scratch;
  for_blocks(l.count, progress, base + l.header_bytes, 3 * l.prec,
             [&](std::size_t first, std::size_t n) {
               grid_block(f, first, n, p + 3 * first, bad, scratch);
             });
  if (const auto k = bad.get()) fail_non_finite(name, l, *k);
}

template <class T>
void read_solution(StructuredGrid& grid, const io_detail::FileSource& q, const Layout& l,
                   double gm1, io_detail::Progress* progress, std::uint64_t base) {
  const ScalarType type = l.prec == 8 ? ScalarType::Float64 : ScalarType::Float32;
  std::vector<DataArray> arrays;
  for (int k = 0; k < 5; ++k) {
    arrays.push_back(DataArray::uninitialized(kQNames[k], type, kQComponents[k], l.count));
  }
  const QBlock<T> at{arrays[0].values<T>().data(), arrays[1].values<T>().data(),
                     arrays[2].values<T>().data(), arrays[3].values<T>().data(),
                     arrays[4].values<T>().data()};
  const PlaneFile f{q, q_start(l), l.count, l.endian != io_detail::kHostEndian};
  Scratch scratch;
  for_blocks(l.count, progress, base + q_start(l), 5 * l.prec,
             [&](std::size_t first, std::size_t n) {
               q_block(f, first, n, gm1,
                       QBlock<T>{at.density + first, at.momentum + 3 * first, at.energy + first,
                                 at.velocity + 3 * first, at.pressure + first},
                       scratch);
             });
  grid.point_data.add(std::move(arrays[0]), AttributeRole::Scalars);
  grid.point_data.add(std::move(arrays[1]), AttributeRole::Vectors);
  for (int k = 2; k < 5; ++k) grid.point_data.add(std::move(arrays[static_cast<std::size_t>(k)]));
}

// Parses the grid (reporting `progress_base` + its bytes consumed) and then the solution.
StructuredGrid read_plot3d_impl(const io_detail::FileSource& xyz, std::string_view xyz_name,
                                const io_detail::FileSource& q, std::string_view q_name,
                                const Plot3dOptions& options, io_detail::Progress* progress,
                                std::uint64_t progress_base) {
  const std::string name(xyz_name);
  if (!std::isfinite(options.gamma)) throw Error(name + ": PLOT3D gamma is not finite");
  const Layout l = detect_grid(xyz.bytes, name, options.byte_order);
  StructuredGrid grid;
  grid.dims = l.dims;
  if (l.prec == 4) {
    read_points<float>(grid, xyz, name, l, progress, progress_base);
  } else {
    read_points<double>(grid, xyz, name, l, progress, progress_base);
  }
  if (l.iblank) {
    Scanner sc(xyz, name);
    sc.track(progress, progress_base);
    sc.seek(iblank_start(l));
    Buffer<std::int32_t> ib;
    sc.read_array(l.count, l.endian, ib, "iblank");
    grid.cell_data.add(valid_cells(l.dims, ib));
    grid.point_data.add(DataArray::from_buffer("IBlank", 1, std::move(ib)));
  }
  if (!q.bytes.empty() || !q_name.empty()) {
    const std::string qn(q_name);
    const Layout ql = detect_q(q.bytes, qn, l, name, options.byte_order);
    read_conditions(q, qn, ql, grid.field_data);
    const std::uint64_t base = progress_base + xyz.bytes.size();
    if (ql.prec == 4) {
      read_solution<float>(grid, q, ql, options.gamma - 1.0, progress, base);
    } else {
      read_solution<double>(grid, q, ql, options.gamma - 1.0, progress, base);
    }
  }
  grid.validate();
  return grid;
}

// ---- Summaries (`info`) ----------------------------------------------------------------------

template <class T>
ArraySummary stream_points(const io_detail::FileSource& xyz, const std::string& name,
                           const Layout& l, io_detail::Progress* progress) {
  const PlaneFile f{xyz, l.header_bytes, l.count, l.endian != io_detail::kHostEndian};
  const ScalarType type = l.prec == 8 ? ScalarType::Float64 : ScalarType::Float32;
  FirstBad bad;
  std::mutex mutex;
  ValueRanges ranges(3);
  Scratch scratch;
  for_blocks(l.count, progress, l.header_bytes, 3 * l.prec, [&](std::size_t first, std::size_t n) {
    T* xyz_block = scratch.get<T>(1, 3 * n);
    grid_block(f, first, n, xyz_block, bad, scratch);
    ValueRanges r(3);
    r.add(type, xyz_block, n);
    const std::lock_guard lock(mutex);
    ranges.merge(r);
  });
  if (const auto k = bad.get()) fail_non_finite(name, l, *k);
  return {"Points", type, 3, l.count, ranges};
}

template <class T>
std::vector<ArraySummary> stream_solution(const io_detail::FileSource& q, const Layout& l,
                                          double gm1, io_detail::Progress* progress,
                                          std::uint64_t base) {
  const ScalarType type = l.prec == 8 ? ScalarType::Float64 : ScalarType::Float32;
  const PlaneFile f{q, q_start(l), l.count, l.endian != io_detail::kHostEndian};
  std::vector<ValueRanges> ranges;
  for (int k = 0; k < 5; ++k) ranges.emplace_back(kQComponents[k]);
  std::mutex mutex;
  Scratch scratch;
  for_blocks(
      l.count, progress, base + q_start(l), 5 * l.prec, [&](std::size_t first, std::size_t n) {
        T* v = scratch.get<T>(1, 9 * n);
        const QBlock<T> out{v, v + n, v + 4 * n, v + 5 * n, v + 8 * n};
        q_block(f, first, n, gm1, out, scratch);
        const T* arrays[5] = {out.density, out.momentum, out.energy, out.velocity, out.pressure};
        std::vector<ValueRanges> r;
        for (int k = 0; k < 5; ++k) {
          r.emplace_back(kQComponents[k]);
          r.back().add(type, arrays[k], n);
        }
        const std::lock_guard lock(mutex);
        for (std::size_t k = 0; k < 5; ++k) ranges[k].merge(r[k]);
      });
  std::vector<ArraySummary> out;
  for (std::size_t k = 0; k < 5; ++k) {
    out.push_back({kQNames[k], type, kQComponents[k], l.count, ranges[k]});
  }
  return out;
}

/// IBLANK and the "Valid" cells streamed a k plane at a time.
std::pair<ArraySummary, ArraySummary> stream_iblank(const io_detail::FileSource& xyz,
                                                    const Layout& l) {
  const std::size_t slab = static_cast<std::size_t>(l.dims[0] * l.dims[1]);
  const PlaneFile f{xyz, iblank_start(l), slab, l.endian != io_detail::kHostEndian};
  std::vector<std::int32_t> lo(slab), hi(slab);
  const std::size_t nc = structured_cell_count(l.dims);
  std::vector<std::uint8_t> valid(nc / cell_layers(l.dims));
  ValueRanges ib(1), ok(1);
  for (Index k = 0; k < l.dims[2]; ++k) {
    f.load(static_cast<int>(k), 0, slab, hi.data());  // plane k of `slab` values
    ib.add(ScalarType::Int32, hi.data(), slab);
    if (k > 0 || l.dims[2] == 1) {
      valid_layer(l.dims, k > 0 ? lo.data() : hi.data(), hi.data(), valid.data());
      ok.add(ScalarType::UInt8, valid.data(), valid.size());
    }
    std::swap(lo, hi);
  }
  return {{"IBlank", ScalarType::Int32, 1, l.count, ib}, {"Valid", ScalarType::UInt8, 1, nc, ok}};
}

DatasetSummary summarize_impl(const io_detail::FileSource& xyz, std::string_view xyz_name,
                              const io_detail::FileSource& q, std::string_view q_name,
                              const Plot3dOptions& options, io_detail::Progress* progress) {
  const std::string name(xyz_name);
  if (!std::isfinite(options.gamma)) throw Error(name + ": PLOT3D gamma is not finite");
  const Layout l = detect_grid(xyz.bytes, name, options.byte_order);
  // The dataset without values: dims, array names, types and roles (summarize() of it gives
  // the counts, cell types and the arrays' order); the streamed ranges replace the empty ones.
  StructuredGrid grid;
  grid.dims = l.dims;
  const ScalarType gtype = l.prec == 8 ? ScalarType::Float64 : ScalarType::Float32;
  grid.points = Points(0, gtype);
  std::vector<ArraySummary> streamed;
  const ArraySummary points = l.prec == 4 ? stream_points<float>(xyz, name, l, progress)
                                          : stream_points<double>(xyz, name, l, progress);
  if (l.iblank) {
    grid.cell_data.add(DataArray("Valid", ScalarType::UInt8, 1));
    grid.point_data.add(DataArray("IBlank", ScalarType::Int32, 1));
    auto [ib, valid] = stream_iblank(xyz, l);
    streamed.push_back(std::move(ib));
    streamed.push_back(std::move(valid));
  }
  if (!q.bytes.empty() || !q_name.empty()) {
    const std::string qn(q_name);
    const Layout ql = detect_q(q.bytes, qn, l, name, options.byte_order);
    read_conditions(q, qn, ql, grid.field_data);
    const ScalarType qtype = ql.prec == 8 ? ScalarType::Float64 : ScalarType::Float32;
    grid.point_data.add(DataArray(kQNames[0], qtype, 1), AttributeRole::Scalars);
    grid.point_data.add(DataArray(kQNames[1], qtype, 3), AttributeRole::Vectors);
    for (int k = 2; k < 5; ++k) grid.point_data.add(DataArray(kQNames[k], qtype, kQComponents[k]));
    const std::uint64_t base = xyz.bytes.size();
    auto solution = ql.prec == 4
                        ? stream_solution<float>(q, ql, options.gamma - 1.0, progress, base)
                        : stream_solution<double>(q, ql, options.gamma - 1.0, progress, base);
    for (ArraySummary& a : solution) streamed.push_back(std::move(a));
  }
  DatasetSummary s = isoforge::summarize(grid);
  s.streamed = true;
  s.points = points.tuples;
  for (int a = 0; a < 3; ++a) {
    s.bounds.min[a] = points.ranges.component(a).first;
    s.bounds.max[a] = points.ranges.component(a).second;
  }
  for (ArraySummary& a : streamed) {
    AttributesSummary& into = a.name == "Valid" ? s.cell_data : s.point_data;
    if (ArraySummary* old = into.find(a.name)) *old = std::move(a);
  }
  return s;
}

}  // namespace

StructuredGrid read_plot3d(std::span<const std::byte> xyz, std::string_view xyz_name,
                           std::span<const std::byte> q, std::string_view q_name,
                           const Plot3dOptions& options) {
  io_detail::Progress progress(options.progress, xyz.size() + q.size(), "reading");
  StructuredGrid grid = read_plot3d_impl(xyz, xyz_name, q, q_name, options, &progress, 0);
  progress.finish();
  return grid;
}

StructuredGrid read_plot3d(const std::filesystem::path& xyz_path,
                           const std::filesystem::path& q_path, const Plot3dOptions& options) {
  // Both files mapped (io/detail/file_source.hpp); parsing them is the work.
  const io_detail::MappedFile xyz(xyz_path);
  std::optional<io_detail::MappedFile> q;
  if (!q_path.empty()) q.emplace(q_path);
  const io_detail::FileSource q_source = q ? io_detail::FileSource(*q) : io_detail::FileSource();
  io_detail::Progress progress(options.progress, xyz.bytes().size() + q_source.bytes.size(),
                               "reading");
  StructuredGrid grid = read_plot3d_impl(io_detail::FileSource(xyz), xyz_path.string(), q_source,
                                         q_path.string(), options, &progress, 0);
  progress.finish();
  return grid;
}

namespace io_detail {

DatasetSummary summarize_plot3d(std::span<const std::byte> xyz, std::string_view xyz_name,
                                std::span<const std::byte> q, std::string_view q_name,
                                const Plot3dOptions& options) {
  return summarize_impl(xyz, xyz_name, q, q_name, options, nullptr);
}

DatasetSummary summarize_plot3d(const std::filesystem::path& xyz_path,
                                const std::filesystem::path& q_path, const Plot3dOptions& options) {
  const MappedFile xyz(xyz_path);
  std::optional<MappedFile> q;
  if (!q_path.empty()) q.emplace(q_path);
  const FileSource q_source = q ? FileSource(*q) : FileSource();
  Progress progress(options.progress, xyz.bytes().size() + q_source.bytes.size(), "reading");
  DatasetSummary s = summarize_impl(FileSource(xyz), xyz_path.string(), q_source, q_path.string(),
                                    options, &progress);
  progress.finish();
  return s;
}

}  // namespace io_detail

}  // namespace isoforge
