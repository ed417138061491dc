// Marching cells on unstructured grids and polygonal data (Lorensen & Cline, "Marching cubes",
// SIGGRAPH '87, generalised to every linear cell type through the generated case tables of
// tables.hpp; ambiguous quad faces resolved by the asymptotic decider of Nielson & Hamann,
// Visualization '91).
//
// Unstructured grids and polygonal data are contoured cell by cell
// in input order, after a parallel pass that finds the cells with points on both sides: 3D cells
// give triangles from their case tables, 2D cells give segments that are joined into polylines,
// 1D cells give one vertex per crossed segment. Points are merged by global edge (min point id,
// max point id) in a flat hash map and numbered in order of first use, so the output is the same
// on every run and for any number of threads. A table's cell-interior points are one new point
// per (cell, centre), never shared. Cell data goes to each triangle and vertex from its cell, and
// to each polyline from its cells (segments of cells with different cell data are not joined).
//
// Orientation: the case tables orient triangles toward increasing values for cells with the
// handedness of their reference cell; each crossed 3D cell's handedness is checked (Jacobian
// sign at the centre for hexahedra and voxels, signed volume from the outward-oriented faces for
// the others) and the triangles of mirrored cells (VTK-valid wedges, whose base faces away from
// their top; left-handed structured grids) are reversed, so the convention holds in world space.

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <variant>

#include "contour_internal.hpp"
#include "contour_output.hpp"
#include "isoforge/core/polylines.hpp"
#include "polygon_segments.hpp"
#include "tables.hpp"

namespace isoforge::contour_detail {

namespace {

/// Six times the signed volume of a cell from its faces (outward-oriented in the table's
/// reference cell): positive when the cell has its reference cell's handedness.
double oriented_volume(const CellTopology& topo, const Vec3* corners) {
  Vec3 c{0, 0, 0};
  for (int k = 0; k < topo.corners; ++k) c += corners[k];
  c = c / static_cast<double>(topo.corners);
  double v = 0;
  for (const auto& f : topo.faces) {
    const Vec3 a = corners[f[0]] - c;
    for (std::size_t k = 1; k + 1 < f.size(); ++k) {
      v += dot(a, cross(corners[f[k]] - c, corners[f[k + 1]] - c));
    }
  }
  return v;
}


// ------------------------------------------------------------------------------------------------
// Lists of cells (unstructured grids, polygonal data).

/// Open-addressing hash map from an edge (lo, hi) to an output point id.
class EdgeMap {
 public:
  /// The id stored for (lo, hi), or `fresh` after storing it.
  Index find_or_insert(Index lo, Index hi, Index fresh) {
    if (2 * (size_ + 1) > keys_.size()) grow();
    std::size_t h = hash(lo, hi) & mask_;
    for (;; h = (h + 1) & mask_) {
      auto& k = keys_[h];
      if (k.lo == lo && k.hi == hi) return k.id;
      if (k.lo < 0) {
        k = {lo, hi, fresh};
        ++size_;
        return fresh;
      }
    }
  }

 private:
  struct Slot {
    Index lo = -1, hi = -1, id = -1;
  };
  static std::size_t hash(Index lo, Index hi) {
    std::uint64_t x =
        static_cast<std::uint64_t>(lo) * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint64_t>(hi);
    x ^= x >> 31;
    x *= 0xBF58476D1CE4E5B9ull;
    x ^= x >> 29;
    return static_cast<std::size_t>(x);
  }
  void grow() {
    std::vector<Slot> old = std::move(keys_);
    keys_.assign(std::max<std::size_t>(1024, 2 * old.size()), Slot{});
    mask_ = keys_.size() - 1;
    for (const Slot& s : old) {
      if (s.lo < 0) continue;
      std::size_t h = hash(s.lo, s.hi) & mask_;
      while (keys_[h].lo >= 0) h = (h + 1) & mask_;
      keys_[h] = s;
    }
  }
  std::vector<Slot> keys_;
  std::size_t mask_ = 0, size_ = 0;
};

/// Least-squares gradient of a linear function through points x with values f: M⁺ r with
/// M = Σ dᵢ dᵢᵀ, r = Σ dᵢ (fᵢ − f̄), dᵢ = xᵢ − x̄ (exact for simplices; within the cell's span for
/// planar and linear cells). False when a value is not finite.
bool cell_gradient(std::span<const Vec3> x, std::span<const double> f, Vec3& g) {
  const double n = static_cast<double>(x.size());
  Vec3 xm{0, 0, 0};
  double fm = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(f[i])) return false;
    xm += x[i] / n;
    fm += f[i] / n;
  }
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < x.size(); ++i) {
    const Vec3 d = x[i] - xm;
    const Eigen::Vector3d e(d.x, d.y, d.z);
    m += e * e.transpose();
    r += e * (f[i] - fm);
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(m);
  const Eigen::Vector3d lambda = es.eigenvalues();
  const double tol = 1e-10 * std::max(lambda.cwiseAbs().maxCoeff(), 1e-300);
  Eigen::Vector3d out = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) {
    if (lambda[k] > tol)
      out += es.eigenvectors().col(k) * (es.eigenvectors().col(k).dot(r) / lambda[k]);
  }
  g = {out[0], out[1], out[2]};
  return true;
}

struct CellView {
  CellType type;
  std::span<const Index> ids;
  std::size_t cell;  // input cell id
};

/// Calls f(CellView) for every cell of the runs, in order.
template <class F>
void for_each_cell(std::span<const CellRun> runs, F&& f) {
  for (const CellRun& run : runs) {
    const std::size_t n = run.cells->size();
    for (std::size_t c = 0; c < n; ++c) {
      const auto ids = run.cells->cell(c);
      CellType type = run.types ? (*run.types)[c] : run.kind;
      f(CellView{type, ids, run.first_cell + c});
    }
  }
}

/// Per-point gradients for ContourNormals::Gradient: the mean of the least-squares gradients of
/// the incident cells of the highest dimension at that point (3D cells inside a volume mesh, the
/// polygons of a surface, ...).
std::vector<Vec3> point_gradients(const Points& points, const DataArray& scalars,
                                  std::span<const CellRun> runs) {
  const std::size_t np = points.size();
  std::vector<std::int8_t> dim(np, -1);
  auto cell_dim = [](CellType t) { return t == CellType::Empty ? -1 : cell_dimension(t); };
  for_each_cell(runs, [&](const CellView& c) {
    const int d = cell_dim(c.type);
    for (Index id : c.ids)
      dim[static_cast<std::size_t>(id)] =
          std::max<std::int8_t>(dim[static_cast<std::size_t>(id)], static_cast<std::int8_t>(d));
  });
  std::vector<Vec3> sum(np, Vec3{0, 0, 0});
  std::vector<std::uint32_t> count(np, 0);
  std::vector<Vec3> x;
  std::vector<double> f;
  auto add = [&](std::span<const Index> ids, int d) {
    x.clear();
    f.clear();
    for (Index id : ids) {
      x.push_back(points[static_cast<std::size_t>(id)]);
      f.push_back(scalars.get(static_cast<std::size_t>(id)));
    }
    Vec3 g;
    if (!cell_gradient(x, f, g)) return;
    for (Index id : ids) {
      const auto p = static_cast<std::size_t>(id);
      if (dim[p] != d) continue;
      sum[p] += g;
      ++count[p];
    }
  };
  for_each_cell(runs, [&](const CellView& c) {
    const int d = cell_dim(c.type);
    if (d <= 0) return;
    const std::size_t n = c.ids.size();
    if (c.type == CellType::TriangleStrip) {
      for (std::size_t i = 0; i + 2 < n; ++i) add(c.ids.subspan(i, 3), d);
    } else if (c.type == CellType::PolyLine || c.type == CellType::Line) {
      for (std::size_t i = 0; i + 1 < n; ++i) add(c.ids.subspan(i, 2), d);
    } else {
      add(c.ids, d);
    }
  });
  for (std::size_t p = 0; p < np; ++p) {
    if (count[p]) sum[p] = sum[p] / static_cast<double>(count[p]);
  }
  return sum;
}

template <class T>
class CellContourer {
 public:
  CellContourer(const Points& points, const T* values, double iso, const ContourOptions& options)
      : pts_(points), v_(values), iso_(iso), opt_(options) {}

  [[nodiscard]] double value(Index id) const { return static_cast<double>(v_[id]); }

  /// Contours one cell.
  void cell(const CellView& c) {
    switch (c.type) {
      case CellType::Tetra:
        solid(tetra_table(), c, nullptr);
        break;
      case CellType::Voxel:
        solid(voxel_table(), c, nullptr);
        break;
      case CellType::Hexahedron:
        solid(voxel_table(), c, kHexToVoxel.data());
        break;
      case CellType::Wedge:
        solid(wedge_table(), c, nullptr);
        break;
      case CellType::Pyramid:
        solid(pyramid_table(), c, nullptr);
        break;
      case CellType::Triangle:
      case CellType::Quad:
      case CellType::Polygon:
        polygon(c.ids, c.cell);
        break;
      case CellType::Pixel: {
        const Index ids[4] = {c.ids[0], c.ids[1], c.ids[3], c.ids[2]};
        polygon(ids, c.cell);
        break;
      }
      case CellType::TriangleStrip:
        for (std::size_t i = 0; i + 2 < c.ids.size(); ++i) {
          Index ids[3] = {c.ids[i], c.ids[i + 1], c.ids[i + 2]};
          if (i % 2) std::swap(ids[0], ids[1]);
          polygon(ids, c.cell);
        }
        break;
      case CellType::Line:
      case CellType::PolyLine:
        for (std::size_t i = 0; i + 1 < c.ids.size(); ++i) {
          const Index a = c.ids[i], b = c.ids[i + 1];
          if ((value(a) >= iso_) == (value(b) >= iso_)) continue;
          verts_.push_back(edge_point(a, b));
          vert_cell_.push_back(c.cell);
        }
        break;
      default:
        break;  // vertices, poly-vertices and empty cells have no isolines
    }
  }

  /// Builds the output: points, vertices, polylines (segments joined across points shared by
  /// exactly two segments of cells with equal cell data), triangles, attributes.
  PolyData finish(const Attributes& point_data, const Attributes& cell_data,
                  const std::vector<Vec3>* gradients, ContourStats& stats) {
    const bool cells = opt_.interpolate_attributes && !cell_data.empty();
    const std::size_t np = sources_.size();
    std::function<bool(std::size_t, std::size_t)> joinable;
    if (cells) {
      joinable = [&, same = SameCellData(cell_data)](std::size_t a, std::size_t b) {
        return same(seg_cell_[a], seg_cell_[b]);
      };
    }
    Polylines lines = join_segments(segs_, np, joinable);
    const std::size_t nv = verts_.size(), nl = lines.first.size(), nt = tri_cell_.size();
    PolyData out;
    out.points = Points(np);
    ContourArrays arrays(point_data, cell_data, np, nv + nl + nt, opt_);
    float* xyz = out.points.floats().data();
    // Edge crossings (in parallel: each writes its own point), then centres.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, np, 1024),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t p = r.begin(); p != r.end(); ++p) {
                          const Source& s = sources_[p];
                          if (s.a < 0) continue;
                          const double t = crossing(value(s.a), value(s.b), iso_);
                          const Vec3 a = pts_[static_cast<std::size_t>(s.a)],
                                     b = pts_[static_cast<std::size_t>(s.b)];
                          const Vec3 x = a + (b - a) * t;
                          xyz[3 * p] = static_cast<float>(x.x);
                          xyz[3 * p + 1] = static_cast<float>(x.y);
                          xyz[3 * p + 2] = static_cast<float>(x.z);
                          arrays.attributes.interpolate(p, static_cast<std::size_t>(s.a),
                                             static_cast<std::size_t>(s.b), t);
                          if (arrays.normals) {
                            const Vec3 ga = (*gradients)[static_cast<std::size_t>(s.a)],
                                       gb = (*gradients)[static_cast<std::size_t>(s.b)];
                            store_normal(arrays.normals + 3 * p, ga + (gb - ga) * t, opt_.flip);
                          }
                        }
                      });
    std::vector<AttributeInterpolator::Term> terms;
    for (std::size_t p = 0; p < np; ++p) {
      const Source& s = sources_[p];
      if (s.a >= 0) continue;
      const auto c = static_cast<std::size_t>(-1 - s.a);
      const auto members =
          std::span<const Index>(center_points_)
              .subspan(static_cast<std::size_t>(center_offsets_[c]),
                       static_cast<std::size_t>(center_offsets_[c + 1] - center_offsets_[c]));
      const double w = 1.0 / static_cast<double>(members.size());
      Vec3 x{0, 0, 0}, g{0, 0, 0};
      terms.clear();
      for (Index m : members) {
        const Source& e = sources_[static_cast<std::size_t>(m)];
        const double t = crossing(value(e.a), value(e.b), iso_);
        const Vec3 a = pts_[static_cast<std::size_t>(e.a)], b = pts_[static_cast<std::size_t>(e.b)];
        x += (a + (b - a) * t) * w;
        terms.push_back({static_cast<std::size_t>(e.a), (1 - t) * w});
        terms.push_back({static_cast<std::size_t>(e.b), t * w});
        if (arrays.normals) {
          const Vec3 ga = (*gradients)[static_cast<std::size_t>(e.a)],
                     gb = (*gradients)[static_cast<std::size_t>(e.b)];
          g += (ga + (gb - ga) * t) * w;
        }
      }
      xyz[3 * p] = static_cast<float>(x.x);
      xyz[3 * p + 1] = static_cast<float>(x.y);
      xyz[3 * p + 2] = static_cast<float>(x.z);
      arrays.attributes.combine(p, terms);
      if (arrays.normals) store_normal(arrays.normals + 3 * p, g, opt_.flip);
    }
    // Cells: vertices, polylines, triangles (the PolyData cell order).
    if (cells) {
      for (std::size_t k = 0; k < nv; ++k) arrays.attributes.copy_cell(k, vert_cell_[k]);
      for (std::size_t k = 0; k < nl; ++k) arrays.attributes.copy_cell(nv + k, seg_cell_[lines.first[k]]);
      for (std::size_t k = 0; k < nt; ++k) arrays.attributes.copy_cell(nv + nl + k, tri_cell_[k]);
    }
    out.verts.offsets().resize(nv + 1);
    for (std::size_t k = 0; k <= nv; ++k) out.verts.offsets()[k] = static_cast<Index>(k);
    out.verts.connectivity() = std::move(verts_);
    out.lines = CellArray(std::move(lines.offsets), std::move(lines.connectivity));
    out.polys.offsets().resize(nt + 1);
    for (std::size_t k = 0; k <= nt; ++k) out.polys.offsets()[k] = static_cast<Index>(3 * k);
    out.polys.connectivity() = std::move(tris_);
    arrays.move_into(out);
    stats.points += np;
    stats.cells += nv + segs_.size() / 2 + nt;
    stats.ambiguous_faces += ambiguous_;
    return out;
  }

 private:
  // An output point: the crossing on input edge (a, b), a < b; or centre -1 - a.
  struct Source {
    Index a, b;
  };

  Index edge_point(Index a, Index b) {
    if (a > b) std::swap(a, b);
    const auto fresh = static_cast<Index>(sources_.size());
    const Index id = edges_.find_or_insert(a, b, fresh);
    if (id == fresh) sources_.push_back({a, b});
    return id;
  }

  // A 3D cell through its case table; `corner_map[c]` is the cell point of table corner c.
  void solid(const CaseTable& table, const CellView& c, const int* corner_map) {
    const auto& topo = table.topology();
    Index ids[8];
    double cv[8];
    unsigned cs = 0;
    for (int k = 0; k < topo.corners; ++k) {
      ids[k] = c.ids[static_cast<std::size_t>(corner_map ? corner_map[k] : k)];
      cv[k] = value(ids[k]);
      cs |= static_cast<unsigned>(cv[k] >= iso_) << k;
    }
    if (cs == 0 || cs == (1u << topo.corners) - 1) return;
    const CaseTable::Case& cc = table.at(cs);
    unsigned bits = 0;
    for (unsigned f = 0; f < cc.ambiguous; ++f) {
      const auto& face = topo.faces[cc.faces[f]];
      if (above_connected(cv[face[0]], cv[face[1]], cv[face[2]], cv[face[3]], iso_))
        bits |= 1u << f;
    }
    ambiguous_ += cc.ambiguous;
    const CaseTable::Variant& var = table.variant(cc, bits);
    const std::size_t ne = table.edges();
    Index local[16];  // output point of each table edge (or centre), -1 until used
    std::fill(std::begin(local), std::end(local), Index{-1});
    auto point_of = [&](unsigned e) -> Index {
      if (local[e] >= 0) return local[e];
      if (e < ne) {
        const auto& edge = topo.edges[e];
        return local[e] = edge_point(ids[edge[0]], ids[edge[1]]);
      }
      // A centre: the mean of the crossings on its edges (their points are made first).
      const auto members = table.center_edges(var, static_cast<unsigned>(e - ne));
      for (std::uint8_t m : members) {
        if (local[m] < 0) local[m] = edge_point(ids[topo.edges[m][0]], ids[topo.edges[m][1]]);
        center_points_.push_back(local[m]);
      }
      center_offsets_.push_back(static_cast<Index>(center_points_.size()));
      const auto center = static_cast<Index>(center_offsets_.size() - 2);
      sources_.push_back({-1 - center, 0});
      return local[e] = static_cast<Index>(sources_.size() - 1);
    };
    Vec3 corners[8];
    for (int k = 0; k < topo.corners; ++k) corners[k] = pts_[static_cast<std::size_t>(ids[k])];
    const bool mirrored =
        &table == &voxel_table() ? mirrored_voxel(corners) : oriented_volume(topo, corners) < 0;
    const auto edges = table.triangles(var);
    for (std::size_t e = 0; e < edges.size(); e += 3) {
      Index t[3] = {point_of(edges[e]), point_of(edges[e + 1]), point_of(edges[e + 2])};
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;  // collapsed (degenerate) cell
      if (mirrored) std::swap(t[1], t[2]);
      tris_.insert(tris_.end(), t, t + 3);
      tri_cell_.push_back(c.cell);
    }
  }

  void polygon(std::span<const Index> ids, std::size_t cell) {
    const std::size_t n = ids.size();
    vals_.resize(n);
    for (std::size_t k = 0; k < n; ++k) vals_[k] = value(ids[k]);
    const bool decided = polygon_segments(vals_, iso_, [&](int from, int to) {
      const auto f = static_cast<std::size_t>(from), t = static_cast<std::size_t>(to);
      const Index a = edge_point(ids[f], ids[(f + 1) % n]);
      const Index b = edge_point(ids[t], ids[(t + 1) % n]);
      if (a == b) return;  // a repeated side (degenerate strip triangle)
      segs_.push_back(a);
      segs_.push_back(b);
      seg_cell_.push_back(cell);
    });
    ambiguous_ += decided;
  }

  const Points& pts_;
  const T* v_;
  double iso_;
  const ContourOptions& opt_;
  EdgeMap edges_;
  std::vector<Source> sources_;
  std::vector<Index> center_offsets_{0}, center_points_;
  Buffer<Index> tris_, segs_, verts_;
  std::vector<std::size_t> tri_cell_, seg_cell_, vert_cell_;
  std::vector<double> vals_;
  std::size_t ambiguous_ = 0;
};

}  // namespace

PolyData marching_cells(const Points& points, const Attributes& point_data,
                        const Attributes& cell_data, std::span<const CellRun> runs,
                        const DataArray& scalars, const ContourOptions& options,
                        ContourStats& stats) {
  std::vector<Vec3> gradients;
  if (options.normals == ContourNormals::Gradient)
    gradients = point_gradients(points, scalars, runs);
  std::size_t total = 0;
  for (const CellRun& r : runs) total += r.cells->size();
  return contour_each_value(options, stats, [&](std::size_t v, const ProgressCallback& progress) {
    return scalars.visit([&](const auto& vec) {
      using T = typename std::decay_t<decltype(vec)>::value_type;
      CellContourer<T> c(points, vec.data(), options.values[v], options);
      // Which cells have points on both sides, in parallel; then the crossed cells in order.
      const double iso = options.values[v];
      std::vector<std::uint8_t> crossed(total);
      std::size_t first = 0;
      for (const CellRun& run : runs) {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, run.cells->size(), 4096),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                            for (std::size_t k = r.begin(); k != r.end(); ++k) {
                              const auto ids = run.cells->cell(k);
                              bool any_above = false, any_below = false;
                              for (Index id : ids) {
                                (static_cast<double>(vec[static_cast<std::size_t>(id)]) >= iso
                                     ? any_above
                                     : any_below) = true;
                              }
                              crossed[first + k] = any_above && any_below;
                            }
                          });
        first += run.cells->size();
      }
      std::size_t done = 0;
      for_each_cell(runs, [&](const CellView& cell) {
        if (crossed[done]) c.cell(cell);
        if (++done % 65536 == 0) {
          report_progress(progress, static_cast<double>(done) / static_cast<double>(total),
                          "contour");
        }
      });
      return c.finish(point_data, cell_data,
                      options.normals == ContourNormals::Gradient ? &gradients : nullptr, stats);
    });
  });
}

}  // namespace isoforge::contour_detail
