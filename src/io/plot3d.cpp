// PLOT3D file format (NASA Ames PLOT3D User's Manual, NASA TM-101067, chapter 8 "Data File
// Formats"): reader for the "whole" binary format — a single 3D grid (optionally preceded by a
// grid count of 1), no Fortran record markers, big or little endian, float32 or float64, with or
// without IBLANK — and its Q (solution) file: dims, fsmach/alpha/re/time, then density, the three
// momentum components and stagnation energy per point. Layout and byte order are detected from
// the file size (the only unambiguous evidence a binary PLOT3D file carries).

#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "detail/scanner.hpp"
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

/// Reads `n` reals of the layout's precision as doubles.
std::vector<double> read_reals(Scanner& sc, std::size_t n, const Layout& l, const char* what) {
  std::vector<double> out;
  if (l.prec == 4) {
    std::vector<float> f;
    sc.read_array(n, l.endian, f, what);
    out.assign(f.begin(), f.end());
  } else {
    sc.read_array(n, l.endian, out, what);
  }
  return out;
}

/// A point array of the layout's precision from doubles.
DataArray make_array(const std::string& name, int comps, const std::vector<double>& v,
                     std::size_t prec) {
  if (prec == 4) {
    std::vector<float> f(v.begin(), v.end());
    return DataArray::from_vector(name, comps, std::move(f));
  }
  return DataArray::from_vector(name, comps, v);
}

void read_q(StructuredGrid& grid, const io_detail::FileSource& q, const std::string& q_name,
            const Layout& gl, const std::string& grid_name, const Plot3dOptions& options,
            io_detail::Progress* progress, std::uint64_t progress_base) {
  const Layout l = detect_q(q.bytes, q_name, gl, grid_name, options.byte_order);
  Scanner sc(q, q_name);
  sc.track(progress, progress_base);
  sc.seek(l.header_bytes);
  const auto cond = read_reals(sc, 4, l, "fsmach, alpha, re, time");
  const char* field_names[4] = {"FreeStreamMach", "AngleOfAttack", "ReynoldsNumber", "Time"};
  for (int i = 0; i < 4; ++i) {
    grid.field_data.add(make_array(field_names[i], 1, {cond[static_cast<std::size_t>(i)]}, l.prec));
  }
  const std::size_t n = l.count;
  const auto rho = read_reals(sc, n, l, "density");
  const auto mu = read_reals(sc, n, l, "x momentum");
  const auto mv = read_reals(sc, n, l, "y momentum");
  const auto mw = read_reals(sc, n, l, "z momentum");
  const auto energy = read_reals(sc, n, l, "stagnation energy");

  std::vector<double> momentum(3 * n), velocity(3 * n), pressure(n);
  const double gm1 = options.gamma - 1.0;
  for (std::size_t i = 0; i < n; ++i) {
    momentum[3 * i] = mu[i];
    momentum[3 * i + 1] = mv[i];
    momentum[3 * i + 2] = mw[i];
    const double r = rho[i];
    double vel[3] = {0, 0, 0};
    if (r != 0.0) {
      vel[0] = mu[i] / r;
      vel[1] = mv[i] / r;
      vel[2] = mw[i] / r;
    }
    for (int a = 0; a < 3; ++a) velocity[3 * i + static_cast<std::size_t>(a)] = vel[a];
    const double v2 = vel[0] * vel[0] + vel[1] * vel[1] + vel[2] * vel[2];
    pressure[i] = gm1 * (energy[i] - 0.5 * r * v2);
  }
  grid.point_data.add(make_array("Density", 1, rho, l.prec), AttributeRole::Scalars);
  grid.point_data.add(make_array("Momentum", 3, momentum, l.prec), AttributeRole::Vectors);
  grid.point_data.add(make_array("StagnationEnergy", 1, energy, l.prec));
  grid.point_data.add(make_array("Velocity", 3, velocity, l.prec));
  grid.point_data.add(make_array("Pressure", 1, pressure, l.prec));
}

/// "Valid" cell flags: 1 when every corner of the cell is unblanked.
DataArray valid_cells(const Dims& dims, std::span<const std::int32_t> iblank) {
  const std::size_t nc = structured_cell_count(dims);
  std::vector<std::uint8_t> valid;
  valid.reserve(nc);
  const Index ci = dims[0] > 1 ? dims[0] - 1 : 1;
  const Index cj = dims[1] > 1 ? dims[1] - 1 : 1;
  const Index ck = dims[2] > 1 ? dims[2] - 1 : 1;
  const Index di = dims[0] > 1 ? 1 : 0, dj = dims[1] > 1 ? 1 : 0, dk = dims[2] > 1 ? 1 : 0;
  for (Index k = 0; k < ck; ++k) {
    for (Index j = 0; j < cj; ++j) {
      for (Index i = 0; i < ci; ++i) {
        bool ok = true;
        for (Index c = 0; c < 8 && ok; ++c) {
          const Index ii = i + ((c & 1) ? di : 0);
          const Index jj = j + ((c & 2) ? dj : 0);
          const Index kk = k + ((c & 4) ? dk : 0);
          ok = iblank[static_cast<std::size_t>(ii + dims[0] * (jj + dims[1] * kk))] != 0;
        }
        valid.push_back(ok ? 1 : 0);
      }
    }
  }
  return DataArray::from_vector("Valid", 1, std::move(valid));
}

// Parses the grid (reporting `progress_base` + its bytes consumed) and then the solution.
StructuredGrid read_plot3d_impl(const io_detail::FileSource& xyz, std::string_view xyz_name,
                                const io_detail::FileSource& q, std::string_view q_name,
                                const Plot3dOptions& options, io_detail::Progress* progress,
                                std::uint64_t progress_base) {
  const std::string name(xyz_name);
  if (!std::isfinite(options.gamma)) throw Error(name + ": PLOT3D gamma is not finite");
  const Layout l = detect_grid(xyz.bytes, name, options.byte_order);
  Scanner sc(xyz, name);
  sc.track(progress, progress_base);
  sc.seek(l.header_bytes);
  const std::size_t n = l.count;
  StructuredGrid grid;
  grid.dims = l.dims;
  grid.points = Points(n, l.prec == 8 ? ScalarType::Float64 : ScalarType::Float32);
  const char* axis_names[3] = {"x coordinates", "y coordinates", "z coordinates"};
  for (int a = 0; a < 3; ++a) {
    const std::size_t start = sc.offset();
    const auto c = read_reals(sc, n, l, axis_names[a]);
    for (std::size_t i = 0; i < n; ++i) {
      if (!std::isfinite(c[i])) {
        const Index ii = static_cast<Index>(i) % l.dims[0];
        const Index jj = (static_cast<Index>(i) / l.dims[0]) % l.dims[1];
        const Index kk = static_cast<Index>(i) / (l.dims[0] * l.dims[1]);
        throw Error(at_byte(name, start + i * l.prec,
                            "point " + std::to_string(i) + " (i, j, k = " + std::to_string(ii) +
                                ", " + std::to_string(jj) + ", " + std::to_string(kk) +
                                ") has a non-finite " + std::string(1, "xyz"[a]) + " coordinate"));
      }
    }
    if (l.prec == 4) {
      auto p = grid.points.array().values<float>();
      for (std::size_t i = 0; i < n; ++i)
        p[3 * i + static_cast<std::size_t>(a)] = static_cast<float>(c[i]);
    } else {
      auto p = grid.points.array().values<double>();
      for (std::size_t i = 0; i < n; ++i) p[3 * i + static_cast<std::size_t>(a)] = c[i];
    }
  }
  if (l.iblank) {
    std::vector<std::int32_t> ib;
    sc.read_array(n, l.endian, ib, "iblank");
    grid.cell_data.add(valid_cells(l.dims, ib));
    grid.point_data.add(DataArray::from_vector("IBlank", 1, std::move(ib)));
  }
  if (!q.bytes.empty() || !q_name.empty()) {
    read_q(grid, q, std::string(q_name), l, name, options, progress,
           progress_base + xyz.bytes.size());
  }
  grid.validate();
  return grid;
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

}  // namespace isoforge
