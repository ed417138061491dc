// Derivatives of point data (vtkGradientFilter): differences on structured data, averaged cell
// derivatives on polygonal data and unstructured grids.

#include "isoforge/filters/gradient.hpp"

#include <fmt/core.h>

#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "isoforge/core/cell.hpp"
#include "isoforge/core/parallel.hpp"
#include "point_fields.hpp"

namespace isoforge {

namespace {

/// Solves Jᵀ g = d for g, J's columns `col`; false when J is singular.
bool solve_transposed(const std::array<Vec3, 3>& col, const double* d, std::size_t stride,
                      double* g) {
  // Jᵀ's rows are the columns; its inverse's columns are the cross products over the determinant.
  const Vec3 c0 = cross(col[1], col[2]), c1 = cross(col[2], col[0]), c2 = cross(col[0], col[1]);
  const double det = dot(col[0], c0);
  if (!(std::abs(det) > 0) || !std::isfinite(det)) return false;
  const double inv = 1 / det;
  for (int a = 0; a < 3; ++a) {
    g[a] = (c0[a] * d[0] + c1[a] * d[stride] + c2[a] * d[2 * stride]) * inv;
  }
  return true;
}

/// Completes the columns of a structured Jacobian whose axes of one point are missing (a 2D or
/// 1D grid): with the unit normal of the two present ones, or two unit vectors perpendicular to
/// the one present. The field's derivative along a completed column is 0.
void complete(std::array<Vec3, 3>& col, const std::array<bool, 3>& present) {
  int have = 0;
  for (bool p : present) have += p;
  if (have == 3 || have == 0) return;
  if (have == 2) {
    const int m = !present[0] ? 0 : !present[1] ? 1 : 2;
    const Vec3 n = cross(col[(m + 1) % 3], col[(m + 2) % 3]);
    const double len = norm(n);
    col[m] = len > 0 ? n / len : Vec3{};
    return;
  }
  const int a = present[0] ? 0 : present[1] ? 1 : 2;
  const Vec3 t = col[a];
  const Vec3 helper = std::abs(t.x) <= std::abs(t.y) && std::abs(t.x) <= std::abs(t.z) ? Vec3{1, 0, 0}
                      : std::abs(t.y) <= std::abs(t.z)                          ? Vec3{0, 1, 0}
                                                                                : Vec3{0, 0, 1};
  Vec3 u = cross(t, helper);
  const double lu = norm(u);
  u = lu > 0 ? u / lu : Vec3{};
  Vec3 w = cross(t, u);
  const double lw = norm(w);
  w = lw > 0 ? w / lw : Vec3{};
  col[(a + 1) % 3] = u;
  col[(a + 2) % 3] = w;
}

/// Structured data (image data or a structured grid): differences in index space, mapped through
/// the grid's Jacobian at each point. `position(id)` gives a point.
template <class Position>
void structured_gradient(const Dims& dims, const Position& position, const double* f, int nc,
                         double* grad, const ProgressCallback& progress) {
  const std::size_t nx = std::size_t(dims[0]), ny = std::size_t(dims[1]), nz = std::size_t(dims[2]);
  const std::size_t stride[3] = {1, nx, nx * ny};
  const std::size_t n = nx * ny * nz;
  const std::size_t ncs = std::size_t(nc);
  parallel_for_range(
      n, 1 << 12,
      [&](std::size_t b, std::size_t e) {
        std::vector<double> d(3 * ncs);  // d[a * nc + c]: d f_c / d index_a
        for (std::size_t id = b; id < e; ++id) {
          const std::size_t ijk[3] = {id % nx, (id / nx) % ny, id / (nx * ny)};
          std::array<Vec3, 3> col{};
          std::array<bool, 3> present{};
          for (int a = 0; a < 3; ++a) {
            const std::size_t len = a == 0 ? nx : a == 1 ? ny : nz;
            double* da = d.data() + std::size_t(a) * ncs;
            if (len < 2) {
              for (std::size_t c = 0; c < ncs; ++c) da[c] = 0;
              continue;
            }
            present[std::size_t(a)] = true;
            const std::size_t lo = ijk[a] > 0 ? id - stride[a] : id;
            const std::size_t hi = ijk[a] + 1 < len ? id + stride[a] : id;
            const double steps = (hi - lo) / stride[a];
            col[std::size_t(a)] = (position(hi) - position(lo)) / steps;
            for (std::size_t c = 0; c < ncs; ++c) da[c] = (f[hi * ncs + c] - f[lo * ncs + c]) / steps;
          }
          complete(col, present);
          double* g = grad + id * 3 * ncs;
          for (std::size_t c = 0; c < ncs; ++c) {
            if (!solve_transposed(col, d.data() + c, ncs, g + 3 * c)) g[3 * c] = g[3 * c + 1] = g[3 * c + 2] = 0;
          }
        }
      },
      progress, "gradient");
}

/// Polygonal data and unstructured grids: each (sub-)cell's derivative at its centre, averaged
/// at its points. Vertices and degenerate cells (a zero derivative of a field that is not
/// constant over the cell) are left out of the averages.
void cell_gradient(DatasetRef ds, const double* f, int nc, double* grad,
                   const ProgressCallback& progress) {
  const std::size_t ncells = num_cells(ds), np = num_points(ds), ncs = std::size_t(nc);
  // Per cell: its (sub-)cells' gradients, then gathered per point in cell order (deterministic).
  std::vector<std::size_t> first(ncells + 1, 0);
  std::vector<Index> ids;
  for (std::size_t c = 0; c < ncells; ++c) {
    cell_point_ids(ds, Index(c), ids);
    const CellType type = cell_type(ds, Index(c));
    first[c + 1] = first[c] + (is_composite_cell(type) ? std::size_t(num_sub_cells(type, ids.size())) : 1);
  }
  const std::size_t nsub = first[ncells];
  std::vector<double> sub_grad(nsub * 3 * ncs, 0.0);
  std::vector<std::uint8_t> sub_ok(nsub, 0);
  parallel_for_range(
      ncells, 256,
      [&](std::size_t b, std::size_t e) {
        std::vector<Index> cid;
        std::vector<Vec3> pts;
        std::vector<double> vals;
        std::vector<Vec3> g(ncs);
        std::vector<std::uint8_t> nan_component;
        for (std::size_t c = b; c < e; ++c) {
          cell_point_ids(ds, Index(c), cid);
          const CellType type = cell_type(ds, Index(c));
          for (std::size_t s = first[c]; s < first[c + 1]; ++s) {
            CellType t = type;
            pts.clear();
            vals.clear();
            auto take = [&](Index id) {
              pts.push_back(point(ds, id));
              for (std::size_t k = 0; k < ncs; ++k) vals.push_back(f[std::size_t(id) * ncs + k]);
            };
            if (is_composite_cell(type)) {
              const SubCell sc = sub_cell(type, cid.size(), int(s - first[c]));
              t = sc.type;
              for (int local : sc.points()) take(cid[std::size_t(local)]);
            } else {
              for (Index id : cid) take(id);
            }
            if (t == CellType::Vertex || t == CellType::PolyVertex || t == CellType::Empty) continue;
            // A component with a non-finite value in the cell has a NaN gradient there (as on
            // image data, and in VTK): computed with 0 in its place, then replaced.
            nan_component.assign(ncs, 0);
            for (std::size_t q = 0; q < vals.size(); ++q) {
              if (!std::isfinite(vals[q])) {
                nan_component[q % ncs] = 1;
                vals[q] = 0;
              }
            }
            derivatives(t, pts, parametric_center(t), vals, nc, g);
            for (std::size_t k = 0; k < ncs; ++k) {
              constexpr double nan = std::numeric_limits<double>::quiet_NaN();
              if (nan_component[k]) g[k] = Vec3{nan, nan, nan};
            }
            // A degenerate cell gives 0; unless the field is constant there, leave it out.
            bool zero = true, varies = false;
            for (std::size_t k = 0; k < ncs; ++k) zero = zero && g[k] == Vec3{};
            for (std::size_t q = ncs; q < vals.size() && zero && !varies; ++q) varies = vals[q] != vals[q % ncs];
            if (zero && varies) continue;
            for (std::size_t k = 0; k < ncs; ++k) {
              double* out = sub_grad.data() + (s * ncs + k) * 3;
              out[0] = g[k].x;
              out[1] = g[k].y;
              out[2] = g[k].z;
            }
            sub_ok[s] = 1;
          }
        }
      },
      progress_range(progress, 0, 0.9), "gradient");
  std::vector<std::uint32_t> count(np, 0);
  for (std::size_t c = 0; c < ncells; ++c) {
    cell_point_ids(ds, Index(c), ids);
    const CellType type = cell_type(ds, Index(c));
    for (std::size_t s = first[c]; s < first[c + 1]; ++s) {
      if (!sub_ok[s]) continue;
      auto add = [&](Index id) {
        const std::size_t p = std::size_t(id);
        ++count[p];
        for (std::size_t k = 0; k < 3 * ncs; ++k) grad[p * 3 * ncs + k] += sub_grad[s * 3 * ncs + k];
      };
      if (is_composite_cell(type)) {
        // Named: points() views the SubCell, which a temporary in the range would not outlive.
        const SubCell sc = sub_cell(type, ids.size(), int(s - first[c]));
        for (int local : sc.points()) add(ids[std::size_t(local)]);
      } else {
        for (Index id : ids) add(id);
      }
    }
  }
  for (std::size_t p = 0; p < np; ++p) {
    if (count[p] > 1) {
      for (std::size_t k = 0; k < 3 * ncs; ++k) grad[p * 3 * ncs + k] /= count[p];
    }
  }
  report_progress(progress, 1.0, "gradient");
}

}  // namespace

GradientResult gradient(DatasetRef input, const GradientOptions& o) {
  if (!o.compute_gradient && !o.divergence && !o.vorticity) {
    throw Error("gradient: nothing to compute (gradient, divergence and vorticity all off)");
  }
  if (o.compute_gradient && o.gradient_name.empty()) {
    throw Error("gradient: the gradient array needs a name");
  }
  validate(input);
  const DataArray& a = filters_detail::point_field(input, o.array, AttributeRole::Scalars, 0, "gradient");
  const int nc = a.components();
  if ((o.divergence || o.vorticity) && nc != 3) {
    throw Error(fmt::format("gradient: {} needs a 3-component point array; '{}' has {}",
                            o.divergence ? "divergence" : "vorticity", a.name(), nc));
  }
  const std::size_t np = num_points(input), ncs = std::size_t(nc);
  std::vector<double> f(np * ncs);
  for (std::size_t i = 0; i < np; ++i)
    for (std::size_t c = 0; c < ncs; ++c) f[i * ncs + c] = a.get(i, int(c));
  DataArray g(o.compute_gradient ? o.gradient_name : std::string("Gradient"), ScalarType::Float64,
              3 * nc, np);
  double* grad = g.values<double>().data();
  std::fill(grad, grad + np * 3 * ncs, 0.0);
  if (const ImageData* img = input.get_if<ImageData>()) {
    structured_gradient(img->dims, [img](std::size_t id) { return img->point(Index(id)); }, f.data(),
                        nc, grad, o.progress);
  } else if (const StructuredGrid* sg = input.get_if<StructuredGrid>()) {
    structured_gradient(sg->dims, [sg](std::size_t id) { return sg->points[id]; }, f.data(), nc, grad,
                        o.progress);
  } else {
    cell_gradient(input, f.data(), nc, grad, o.progress);
  }
  GradientResult r;
  if (o.divergence) {
    DataArray d("Divergence", ScalarType::Float64, 1, np);
    double* v = d.values<double>().data();
    for (std::size_t i = 0; i < np; ++i) v[i] = grad[i * 9 + 0] + grad[i * 9 + 4] + grad[i * 9 + 8];
    r.divergence = std::move(d);
  }
  if (o.vorticity) {
    DataArray w("Vorticity", ScalarType::Float64, 3, np);
    double* v = w.values<double>().data();
    for (std::size_t i = 0; i < np; ++i) {
      const double* G = grad + i * 9;  // G[3 c + a] = d v_c / d x_a
      v[3 * i + 0] = G[7] - G[5];      // dw/dy − dv/dz
      v[3 * i + 1] = G[2] - G[6];      // du/dz − dw/dx
      v[3 * i + 2] = G[3] - G[1];      // dv/dx − du/dy
    }
    r.vorticity = std::move(w);
  }
  if (o.compute_gradient) r.gradient = std::move(g);
  return r;
}

}  // namespace isoforge
