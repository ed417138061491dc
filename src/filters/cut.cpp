// Cutting datasets with implicit functions (filters/cut.hpp).
//
// References:
// - W. Schroeder, K. Martin, B. Lorensen, *The Visualization Toolkit* (4th ed.), section 6.x
//   "Cutting": the cut surface is the contour F = c of the function sampled at the points.
// - M. Dowell, P. Jarratt, "A modified regula falsi method for computing the root of an
//   equation", BIT 11 (1971): the Illinois method placing cut points on F = c.
// Method (face walking, point merging by edge keys): docs/algorithms/cut.md.

#include "isoforge/filters/cut.hpp"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "cut_cells.hpp"
#include "cut_internal.hpp"
#include "isoforge/core/append.hpp"
#include "isoforge/core/cell.hpp"
#include "isoforge/core/interpolate.hpp"
#include "isoforge/core/parallel.hpp"
#include "isoforge/core/polylines.hpp"

namespace isoforge {

namespace {

// A cut point: value number, then the edge's smaller and larger point id (equal for a point
// where F = c exactly).
constexpr int kValueShift = 40;
constexpr std::uint64_t kIdMask = (std::uint64_t{1} << kValueShift) - 1;

struct Key {
  std::uint64_t a = 0, b = 0;
  friend bool operator<(const Key& x, const Key& y) { return x.a < y.a || (x.a == y.a && x.b < y.b); }
  friend bool operator==(const Key& x, const Key& y) = default;
};

struct Block {
  std::vector<Key> poly_keys;
  std::vector<std::uint32_t> poly_size;
  std::vector<Index> poly_src;
  std::vector<Key> seg_keys;  // two per segment
  std::vector<Index> seg_src;
  std::vector<Key> vert_keys;
  std::vector<Index> vert_src;
  std::size_t cells_cut = 0;
};

constexpr std::size_t kBlockCells = 8192;

/// The local point rings of the 2D types (pixels in voxel order).
std::span<const int> ring_of(CellType type, std::size_t n, std::vector<int>& storage) {
  static constexpr int kTri[3] = {0, 1, 2};
  static constexpr int kQuad[4] = {0, 1, 2, 3};
  static constexpr int kPixel[4] = {0, 1, 3, 2};
  switch (type) {
    case CellType::Triangle: return kTri;
    case CellType::Quad: return kQuad;
    case CellType::Pixel: return kPixel;
    default: break;
  }
  storage.resize(n);
  for (std::size_t i = 0; i < n; ++i) storage[i] = static_cast<int>(i);
  return storage;
}

/// The general path: every cell with points on both sides of a value is cut.
PolyData cut_general(DatasetRef input, const ImplicitFunction& f, const Buffer<double>& F,
                     const CutOptions& options, CutStats& stats) {
  const std::size_t nc = num_cells(input);
  const std::size_t blocks = (nc + kBlockCells - 1) / kBlockCells;
  std::vector<Block> out(blocks);
  const std::vector<double>& values = options.values;
  // Structured 3D input: the range of F along every point line (i), so that whole rows of
  // cells on one side of every value are skipped (a plane crosses few rows).
  const Dims* dims = nullptr;
  if (const auto* im = input.get_if<ImageData>()) dims = &im->dims;
  if (const auto* sg = input.get_if<StructuredGrid>()) dims = &sg->dims;
  if (dims && structured_dimension(*dims) != 3) dims = nullptr;
  std::vector<char> row_cut;
  if (dims) {
    const Index nx = (*dims)[0], ny = (*dims)[1], nz = (*dims)[2];
    std::vector<std::pair<double, double>> line(static_cast<std::size_t>(ny * nz));
    parallel_for_range(line.size(), 256, [&](std::size_t l0, std::size_t l1) {
      for (std::size_t l = l0; l < l1; ++l) {
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        const double* v = F.data() + l * static_cast<std::size_t>(nx);
        for (Index i = 0; i < nx; ++i) {
          const double x = v[i];
          if (std::isnan(x)) lo = -std::numeric_limits<double>::infinity();
          else lo = std::min(lo, x), hi = std::max(hi, x);
        }
        line[l] = {lo, hi};
      }
    });
    const std::size_t rows = static_cast<std::size_t>((ny - 1) * (nz - 1));
    row_cut.resize(rows);
    parallel_for_range(rows, 1024, [&](std::size_t r0, std::size_t r1) {
      for (std::size_t r = r0; r < r1; ++r) {
        const Index j = static_cast<Index>(r) % (ny - 1), k = static_cast<Index>(r) / (ny - 1);
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (int q = 0; q < 4; ++q) {
          const auto& [a, b] = line[static_cast<std::size_t>((j + (q & 1)) + ny * (k + (q >> 1)))];
          lo = std::min(lo, a), hi = std::max(hi, b);
        }
        bool cut = false;
        for (double c : values) cut |= hi >= c && lo < c;
        row_cut[r] = cut;
      }
    });
  }
  auto row_ok = [&](std::size_t r) { return row_cut.empty() || row_cut[r] != 0; };
  parallel_for_range(
      blocks, 1,
      [&](std::size_t b0, std::size_t b1) {
        std::vector<double> vals;
        std::vector<int> ring_storage;
        std::vector<cutting::Crossing> crossings;
        std::vector<double> scratch;
        std::vector<Key> loop;
        cutting::PolyhedronCut pc;
        bool above[8];
        for (std::size_t b = b0; b < b1; ++b) {
          Block& blk = out[b];
          cutting::visit_cells(input, b * kBlockCells, std::min(nc, (b + 1) * kBlockCells),
                      [&](Index cell, CellType type, std::span<const Index> ids) {
            const std::size_t n = ids.size();
            if (n < 2) return;
            double lo = std::numeric_limits<double>::infinity(), hi = -lo;
            bool nan = false;
            for (Index id : ids) {
              const double v = F[static_cast<std::size_t>(id)];
              if (std::isnan(v)) nan = true;
              lo = std::min(lo, v), hi = std::max(hi, v);
            }
            vals.resize(n);
            for (std::size_t vi = 0; vi < values.size(); ++vi) {
              const double c = values[vi];
              if (!(hi >= c) || !(nan || lo < c)) continue;
              ++blk.cells_cut;
              for (std::size_t i = 0; i < n; ++i) {
                const double v = F[static_cast<std::size_t>(ids[i])] - c;
                vals[i] = std::isnan(v) ? -1.0 : v;
              }
              const std::uint64_t vbits = static_cast<std::uint64_t>(vi) << kValueShift;
              auto key = [&](const cutting::LocalEdge& e) {
                const auto ga = static_cast<std::uint64_t>(ids[static_cast<std::size_t>(e.a)]);
                const auto gb = static_cast<std::uint64_t>(ids[static_cast<std::size_t>(e.b)]);
                if (vals[static_cast<std::size_t>(e.b)] == 0) return Key{vbits | gb, gb};
                return Key{vbits | std::min(ga, gb), std::max(ga, gb)};
              };
              const int dim = cell_dimension(type);
              if (dim == 3) {
                for (std::size_t i = 0; i < n; ++i) above[i] = vals[i] >= 0;
                cutting::cut_polyhedron(cell_faces(type), above, vals.data(), pc);
                int start = 0;
                for (int l = 0; l < pc.loops; ++l) {
                  loop.clear();
                  for (int e = start; e < pc.loop_end[static_cast<std::size_t>(l)]; ++e) {
                    const Key k = key(pc.edges[static_cast<std::size_t>(e)]);
                    if (loop.empty() || !(loop.back() == k)) loop.push_back(k);
                  }
                  start = pc.loop_end[static_cast<std::size_t>(l)];
                  while (loop.size() > 1 && loop.back() == loop.front()) loop.pop_back();
                  if (loop.size() < 3) continue;
                  if (options.triangulate) {
                    for (std::size_t t = 1; t + 1 < loop.size(); ++t) {
                      blk.poly_keys.insert(blk.poly_keys.end(), {loop[0], loop[t], loop[t + 1]});
                      blk.poly_size.push_back(3);
                      blk.poly_src.push_back(cell);
                    }
                  } else {
                    blk.poly_keys.insert(blk.poly_keys.end(), loop.begin(), loop.end());
                    blk.poly_size.push_back(static_cast<std::uint32_t>(loop.size()));
                    blk.poly_src.push_back(cell);
                  }
                }
              } else if (dim == 2) {
                auto emit = [&](const cutting::LocalEdge& a, const cutting::LocalEdge& b) {
                  const Key ka = key(a), kb = key(b);
                  if (ka == kb) return;
                  blk.seg_keys.push_back(ka);
                  blk.seg_keys.push_back(kb);
                  blk.seg_src.push_back(cell);
                };
                if (type == CellType::TriangleStrip) {
                  for (std::size_t s = 0; s + 2 < n; ++s) {
                    const int r[3] = {static_cast<int>(s % 2 ? s + 1 : s),
                                      static_cast<int>(s % 2 ? s : s + 1), static_cast<int>(s + 2)};
                    cutting::cut_polygon(std::span<const int>(r, 3), vals.data(), emit, crossings,
                                         scratch);
                  }
                } else {
                  cutting::cut_polygon(ring_of(type, n, ring_storage), vals.data(), emit,
                                       crossings, scratch);
                }
              } else if (dim == 1) {
                for (std::size_t s = 0; s + 1 < n; ++s) {
                  const bool a0 = vals[s] >= 0, a1 = vals[s + 1] >= 0;
                  if (a0 == a1) continue;
                  const auto e = a0 ? cutting::LocalEdge{static_cast<int>(s + 1), static_cast<int>(s)}
                                    : cutting::LocalEdge{static_cast<int>(s), static_cast<int>(s + 1)};
                  blk.vert_keys.push_back(key(e));
                  blk.vert_src.push_back(cell);
                }
              }
            }
          }, row_ok);
        }
      },
      progress_range(options.progress, 0.3, 0.8), "cut");

  // Unique cut points, numbered in key order (deterministic).
  std::vector<Key> keys;
  std::size_t total = 0;
  for (const Block& b : out) total += b.poly_keys.size() + b.seg_keys.size() + b.vert_keys.size();
  keys.reserve(total);
  for (const Block& b : out) {
    keys.insert(keys.end(), b.poly_keys.begin(), b.poly_keys.end());
    keys.insert(keys.end(), b.seg_keys.begin(), b.seg_keys.end());
    keys.insert(keys.end(), b.vert_keys.begin(), b.vert_keys.end());
    stats.cells_cut += b.cells_cut;
  }
  tbb::parallel_sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  auto id_of = [&](const Key& k) {
    return static_cast<Index>(std::lower_bound(keys.begin(), keys.end(), k) - keys.begin());
  };
  const std::size_t np = keys.size();

  PolyData result;
  // Cells: vertices (unique), polylines, polygons; with their source cells.
  std::vector<Index> vert_src, line_src, poly_src;
  {
    std::vector<char> used(np, 0);
    for (const Block& b : out) {
      for (std::size_t i = 0; i < b.vert_keys.size(); ++i) {
        const Index id = id_of(b.vert_keys[i]);
        if (used[static_cast<std::size_t>(id)]) continue;
        used[static_cast<std::size_t>(id)] = 1;
        result.verts.add({id});
        vert_src.push_back(b.vert_src[i]);
      }
    }
  }
  {
    std::vector<Index> segs;
    std::vector<Index> seg_src;
    for (const Block& b : out) {
      for (const Key& k : b.seg_keys) segs.push_back(id_of(k));
      seg_src.insert(seg_src.end(), b.seg_src.begin(), b.seg_src.end());
    }
    if (!segs.empty()) {
      const Attributes& cd = cell_data(input);
      SameCellData same(cd);
      std::function<bool(std::size_t, std::size_t)> joinable;
      if (options.interpolate_attributes && !cd.empty()) {
        joinable = [&](std::size_t s, std::size_t t) {
          return same(static_cast<std::size_t>(seg_src[s]), static_cast<std::size_t>(seg_src[t]));
        };
      }
      Polylines pl = join_segments(segs, np, joinable);
      result.lines = CellArray(std::move(pl.offsets), std::move(pl.connectivity));
      for (std::size_t s : pl.first) line_src.push_back(seg_src[s]);
    }
  }
  {
    // Each block's polygons written in parallel at its offsets.
    std::vector<std::size_t> poly_at(out.size() + 1, 0), id_at(out.size() + 1, 0);
    for (std::size_t b = 0; b < out.size(); ++b) {
      poly_at[b + 1] = poly_at[b] + out[b].poly_size.size();
      id_at[b + 1] = id_at[b] + out[b].poly_keys.size();
    }
    Buffer<Index> offsets(poly_at.back() + 1), conn(id_at.back());
    offsets[0] = 0;
    poly_src.resize(poly_at.back());
    parallel_for_range(out.size(), 1, [&](std::size_t b0, std::size_t b1) {
      for (std::size_t b = b0; b < b1; ++b) {
        const Block& blk = out[b];
        std::size_t at = id_at[b];
        for (std::size_t k = 0; k < blk.poly_keys.size(); ++k) conn[at + k] = id_of(blk.poly_keys[k]);
        for (std::size_t p = 0; p < blk.poly_size.size(); ++p) {
          at += blk.poly_size[p];
          offsets[poly_at[b] + p + 1] = static_cast<Index>(at);
          poly_src[poly_at[b] + p] = blk.poly_src[p];
        }
      }
    });
    result.polys = CellArray(std::move(offsets), std::move(conn));
  }

  // Points and their attributes.
  const ImageData* image = input.get_if<ImageData>();
  const Points* pts = nullptr;
  input.visit([&](const auto& d) {
    if constexpr (!std::is_same_v<std::decay_t<decltype(d)>, ImageData>) pts = &d.points;
  });
  auto position = [&](std::uint64_t id) {
    return image ? image->point(static_cast<Index>(id)) : (*pts)[id];
  };
  result.points = Points(np, pts ? pts->type() : ScalarType::Float32);
  const std::size_t ncells_out = vert_src.size() + line_src.size() + poly_src.size();
  AttributeInterpolator interp;
  if (options.interpolate_attributes) {
    interp = AttributeInterpolator(point_data(input), cell_data(input), np, ncells_out);
  }
  DataArray value_index("CutValueIndex", ScalarType::Int32, 1, np);
  auto vi_out = value_index.values<std::int32_t>();
  const bool linear = f.kind() == ImplicitFunction::Kind::Plane || !options.refine;
  parallel_for_range(
      np, 1024,
      [&](std::size_t k0, std::size_t k1) {
        for (std::size_t k = k0; k < k1; ++k) {
          const std::uint64_t v = keys[k].a >> kValueShift;
          const std::uint64_t lo = keys[k].a & kIdMask, hi = keys[k].b;
          vi_out[k] = static_cast<std::int32_t>(v);
          if (lo == hi) {
            result.points.set(k, position(lo));
            interp.copy_point(k, lo);
            continue;
          }
          const double c = values[v];
          const double ga = F[lo] - c, gb = F[hi] - c;
          double t = std::isfinite(ga) && std::isfinite(gb) ? ga / (ga - gb) : 0.5;
          t = std::clamp(t, 0.0, 1.0);
          const Vec3 pa = position(lo), pb = position(hi);
          if (!linear && std::isfinite(ga) && std::isfinite(gb)) {
            t = cutting::refine_root(f, pa, pb, ga, gb, c, t);
          }
          result.points.set(k, pa + (pb - pa) * t);
          interp.interpolate(k, lo, hi, t);
        }
      },
      progress_range(options.progress, 0.8, 1.0), "cut");
  std::size_t cell_out = 0;
  for (const auto* src : {&vert_src, &line_src, &poly_src}) {
    for (Index c : *src) interp.copy_cell(cell_out++, static_cast<std::size_t>(c));
  }
  interp.move_into(result.point_data, result.cell_data);
  result.point_data.add(std::move(value_index));
  stats.points = np;
  stats.vertices = result.verts.size();
  stats.lines = result.lines.size();
  stats.polygons = result.polys.size();
  return result;
}

}  // namespace

namespace cutting {

/// Values of F at the points: the plane directly, any other function in blocks.
Buffer<double> evaluate_at_points(DatasetRef ds, const ImplicitFunction& f,
                                  const cutting::LinearField* plane,
                                  const ProgressCallback& progress) {
  const std::size_t n = num_points(ds);
  Buffer<double> values(n);
  const ImageData* image = ds.get_if<ImageData>();
  const Points* pts = nullptr;
  ds.visit([&](const auto& d) {
    if constexpr (!std::is_same_v<std::decay_t<decltype(d)>, ImageData>) pts = &d.points;
  });
  constexpr std::size_t kChunk = 4096;
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  parallel_for_range(
      chunks, 1,
      [&](std::size_t b0, std::size_t b1) {
        std::vector<double> xyz(3 * kChunk);
        for (std::size_t b = b0; b < b1; ++b) {
          const std::size_t p0 = b * kChunk, p1 = std::min(n, p0 + kChunk);
          if (plane && pts && pts->type() == ScalarType::Float32) {
            const float* x = pts->floats().data();
            const double a = plane->a, gx = plane->g.x, gy = plane->g.y, gz = plane->g.z;
            for (std::size_t i = p0; i < p1; ++i) {
              values[i] = a + gx * x[3 * i] + gy * x[3 * i + 1] + gz * x[3 * i + 2];
            }
            continue;
          }
          if (image) {
            // (i, j, k) stepped along, a line at a time (the coordinates of
            // ImageData::point(id)).
            const auto id = static_cast<Index>(p0);
            const Index nx = image->dims[0];
            Index ii = id % nx, jj = (id / nx) % image->dims[1], kk = id / (nx * image->dims[1]);
            for (std::size_t i = p0; i < p1;) {
              const auto run = std::min<std::size_t>(p1 - i, static_cast<std::size_t>(nx - ii));
              const Vec3 first = image->point(ii, jj, kk);
              double* out = xyz.data() + 3 * (i - p0);
              for (std::size_t q = 0; q < run; ++q) {
                out[3 * q] = image->origin.x + static_cast<double>(ii + static_cast<Index>(q)) * image->spacing.x;
                out[3 * q + 1] = first.y;
                out[3 * q + 2] = first.z;
              }
              if (plane) {
                for (std::size_t q = 0; q < run; ++q) {
                  const Vec3 p{out[3 * q], out[3 * q + 1], out[3 * q + 2]};
                  values[i + q] = plane->a + dot(plane->g, p);
                }
              }
              i += run;
              ii = 0;
              if (++jj == image->dims[1]) jj = 0, ++kk;
            }
          } else {
            for (std::size_t i = p0; i < p1; ++i) {
              const Vec3 p = (*pts)[i];
              xyz[3 * (i - p0)] = p.x, xyz[3 * (i - p0) + 1] = p.y, xyz[3 * (i - p0) + 2] = p.z;
              if (plane) values[i] = plane->a + dot(plane->g, p);
            }
          }
          if (!plane) {
            f.evaluate(std::span<const double>(xyz.data(), 3 * (p1 - p0)),
                       std::span<double>(values.data() + p0, p1 - p0));
          }
        }
      },
      progress, "cut");
  return values;
}

/// The edge parameter t in [0, 1] of the root of F − c between pa (t = 0, F − c = ga) and pb
/// (t = 1, gb of the other sign), by the Illinois method from the linear estimate t0.
double refine_root(const ImplicitFunction& f, const Vec3& pa, const Vec3& pb, double ga,
                   double gb, double c, double t0) {
  double lo = 0, hi = 1, glo = ga, ghi = gb, t = t0;
  int side = 0;
  const Vec3 d = pb - pa;
  // Stop when the bracket is below a tenth of a float ulp of the coordinates.
  const double scale = std::max({std::abs(pa.x), std::abs(pa.y), std::abs(pa.z), std::abs(pb.x),
                                 std::abs(pb.y), std::abs(pb.z), norm(d)});
  const double stop = 0.1 * std::ldexp(scale, -24) / std::max(norm(d), 1e-300);
  for (int it = 0; it < 60; ++it) {
    const double g = f.value(pa + d * t) - c;
    if (g == 0 || !std::isfinite(g)) return t;
    if ((g < 0) == (glo < 0)) {
      lo = t, glo = g;
      if (side == -1) ghi *= 0.5;
      side = -1;
    } else {
      hi = t, ghi = g;
      if (side == 1) glo *= 0.5;
      side = 1;
    }
    if (hi - lo <= stop) break;
    t = (it % 8 == 7) ? 0.5 * (lo + hi) : (lo * ghi - hi * glo) / (ghi - glo);
    if (!(t > lo && t < hi)) t = 0.5 * (lo + hi);
  }
  return t;
}

}  // namespace cutting

std::vector<double> generate_values(int n, double min, double max) {
  if (n < 1) throw Error("generate_values: the number of values must be >= 1, got " + std::to_string(n));
  if (!std::isfinite(min) || !std::isfinite(max)) {
    throw Error("generate_values: the range must be finite");
  }
  if (min > max) throw Error("generate_values: the first value is above the last");
  if (n == 1) {
    if (min != max) throw Error("generate_values: one value needs the first and last to be equal");
    return {min};
  }
  std::vector<double> v(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    v[static_cast<std::size_t>(i)] = i == n - 1 ? max : min + (max - min) * i / (n - 1);
  }
  return v;
}

CutResult cut(DatasetRef input, const ImplicitFunction& f, const CutOptions& options) {
  if (options.values.empty()) throw Error("cut: no cut value given");
  for (double v : options.values) {
    if (!std::isfinite(v)) throw Error("cut: cut value " + std::to_string(v) + " is not finite");
  }
  if (options.values.size() >= (std::size_t{1} << (64 - kValueShift - 1))) {
    throw Error("cut: too many cut values");
  }
  validate(input);
  if (num_points(input) > kIdMask) throw Error("cut: more than 2^40 points");
  CutResult r;
  cutting::LinearField plane;
  const bool is_plane = f.kind() == ImplicitFunction::Kind::Plane;
  if (is_plane) plane = {f.value(Vec3{0, 0, 0}), f.gradient(Vec3{0, 0, 0})};
  if (const auto* image = input.get_if<ImageData>();
      image && is_plane && structured_dimension(image->dims) == 3) {
    std::vector<PolyData> parts;
    bool ok = true;
    for (std::size_t v = 0; v < options.values.size() && ok; ++v) {
      report_progress(options.progress, static_cast<double>(v) / options.values.size(), "cut");
      auto part = cutting::cut_image_plane(*image, plane, options.values[v], static_cast<int>(v),
                                           options);
      if (!part) ok = false;
      else parts.push_back(std::move(*part));
    }
    if (ok) {
      r.output = append(std::move(parts));
      r.stats.fast_path = true;
      r.stats.points = r.output.points.size();
      r.stats.polygons = r.output.polys.size();
      report_progress(options.progress, 1.0, "cut");
      return r;
    }
  }
  if (const auto* sg = input.get_if<StructuredGrid>();
      sg && is_plane && options.values.size() == 1 && structured_dimension(sg->dims) == 3) {
    CutStats stats;
    if (auto out = cutting::cut_structured_plane(*sg, plane, options.values[0], options, stats)) {
      r.output = std::move(*out);
      r.stats = stats;
      r.stats.fast_path = true;
      return r;
    }
  }
  const Buffer<double> F =
      cutting::evaluate_at_points(input, f, is_plane ? &plane : nullptr, progress_range(options.progress, 0, 0.3));
  r.stats.fast_path = is_plane && input.get_if<StructuredGrid>() != nullptr;
  r.output = cut_general(input, f, F, options, r.stats);
  return r;
}

}  // namespace isoforge
