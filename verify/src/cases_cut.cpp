// Verification cases of cutting and clipping (filters/cut.hpp, filters/clip.hpp): every cut
// point on F = c within the tolerance of its float storage, the cut of a closed volume made of
// closed polygons (no dangling edges), and a clip plus its complement (inside_out) adding up to
// the input's volume.

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "case_support.hpp"
#include "isoforge/core/cell.hpp"
#include "isoforge/filters/clip.hpp"
#include "isoforge/filters/cut.hpp"

namespace isoforge::verify {

namespace {

using F = ImplicitFunction;

ImageData grid(Index n) {
  ImageData img;
  img.dims = {n, n + 3, n + 5};
  img.origin = {-1.1, -1.2, -1.3};
  img.spacing = {2.2 / static_cast<double>(n - 1), 2.4 / static_cast<double>(n + 2),
                 2.6 / static_cast<double>(n + 4)};
  return img;
}

StructuredGrid bent(Index n) {
  StructuredGrid sg;
  sg.dims = {n, n, n};
  for (Index k = 0; k < n; ++k)
    for (Index j = 0; j < n; ++j)
      for (Index i = 0; i < n; ++i) {
        const double x = -1.2 + 2.4 * static_cast<double>(i) / static_cast<double>(n - 1);
        const double y = -1.2 + 2.4 * static_cast<double>(j) / static_cast<double>(n - 1);
        const double z = -1.2 + 2.4 * static_cast<double>(k) / static_cast<double>(n - 1);
        sg.points.push_back({x + 0.05 * std::sin(3 * y), y + 0.05 * std::sin(2 * z), z});
      }
  return sg;
}

/// |F(p) − c| against 4 ulp (float) of the input's coordinates, for every point of a cut.
void on_surface(CaseResult& r, const PolyData& pd, const F& f, const std::vector<double>& values,
                double scale) {
  const auto vi = pd.point_data.get("CutValueIndex").values<std::int32_t>();
  std::size_t bad = 0;
  double worst = 0;
  for (std::size_t i = 0; i < pd.points.size(); ++i) {
    const Vec3 p = pd.points[i];
    const double tol = side_tolerance(p, pd.points.type(), f.gradient(p), 4, scale);
    const double ratio = std::abs(f.value(p) - values[static_cast<std::size_t>(vi[i])]) / tol;
    worst = std::max(worst, ratio);
    bad += ratio > 1;
  }
  r.note("cut", fmt::format("{} points, {} polygons, {} lines", pd.points.size(), pd.polys.size(),
                            pd.lines.size()));
  r.at_least("points", static_cast<double>(pd.points.size()), 1);
  r.equal("points off F = c (|F - c| > 4 ulp(float) |grad F|)", bad, std::size_t{0});
  r.at_most("worst point: |F - c| / tol", worst, 1.0);
}

/// Edges of the polygons and how many polygons use each.
std::map<std::pair<Index, Index>, int> edge_uses(const PolyData& pd) {
  std::map<std::pair<Index, Index>, int> uses;
  for (std::size_t c = 0; c < pd.polys.size(); ++c) {
    const auto ids = pd.polys.cell(c);
    for (std::size_t i = 0; i < ids.size(); ++i) {
      const Index a = ids[i], b = ids[(i + 1) % ids.size()];
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  }
  return uses;
}

/// Signed volume of a cell by the divergence theorem over its outward face table, a quad face
/// split along the diagonal from its smallest point id (the clip's convention; exact for planar
/// faces, and what makes a clip and its complement add up where a piece's top is not planar).
double cell_volume(DatasetRef ds, std::size_t cell, std::vector<Index>& ids) {
  cell_point_ids(ds, static_cast<Index>(cell), ids);
  double v = 0;
  auto tri = [&](int a, int b, int c) {
    v += dot(point(ds, ids[static_cast<std::size_t>(a)]),
             cross(point(ds, ids[static_cast<std::size_t>(b)]),
                   point(ds, ids[static_cast<std::size_t>(c)]))) /
         6;
  };
  for (const CellFace& face : cell_faces(cell_type(ds, static_cast<Index>(cell)))) {
    int m = 0;
    if (face.size == 4) {
      for (int i = 1; i < 4; ++i) {
        if (ids[static_cast<std::size_t>(face.ids[static_cast<std::size_t>(i)])] <
            ids[static_cast<std::size_t>(face.ids[static_cast<std::size_t>(m)])]) {
          m = i;
        }
      }
    }
    const auto at = [&](int k) { return face.ids[static_cast<std::size_t>((m + k) % face.size)]; };
    for (int t = 1; t + 1 < face.size; ++t) tri(at(0), at(t), at(t + 1));
  }
  return v;
}

void conservation(CaseResult& r, const F& f) {
  const ImageData img = grid(30);
  ClipOptions inside_out;
  inside_out.inside_out = true;
  const auto [in, si] = clip(img, f, inside_out);
  const auto [out, so] = clip(img, f);
  std::vector<Index> ids;
  double vin = 0, vout = 0, most_negative = 0;
  for (std::size_t c = 0; c < in.num_cells(); ++c) {
    const double v = cell_volume(in, c, ids);
    vin += v, most_negative = std::min(most_negative, v);
  }
  for (std::size_t c = 0; c < out.num_cells(); ++c) {
    const double v = cell_volume(out, c, ids);
    vout += v, most_negative = std::min(most_negative, v);
  }
  const double total = 2.2 * 2.4 * 2.6;
  r.note("clip", fmt::format("inside: {} cells ({} kept whole), outside: {} cells ({} kept whole); "
                             "volumes {:.9g} + {:.9g}",
                             in.num_cells(), si.cells_kept, out.num_cells(), so.cells_kept, vin, vout));
  r.at_most("|V(clip) + V(inside-out clip) - V(input)| / V(input)", std::abs(vin + vout - total) / total,
            1e-6);
  // A piece cut next to a grid point can be flat to rounding (volume ~1e-19): allowed down to
  // -1e-12 of the input's volume; an inverted cell would be a sizeable fraction of a voxel.
  r.at_least("most negative cell volume / V(input) (an inverted cell would be << 0)",
             most_negative / total, -1e-12);
  r.equal("input cells kept whole or split", si.cells_kept + so.cells_kept + si.cells_split,
          img.num_cells());
}

}  // namespace

void add_cut_cases(std::vector<Case>& cases) {
  cases.push_back({"cut/plane-image-on-plane",
                   "cut of a 40^3 image by an oblique plane at 5 values (fast path): every point "
                   "on F = c",
                   true, [](CaseResult& r) {
                     const ImageData img = grid(40);
                     const F f = F::plane({0.1, -0.2, 0.05}, {-0.287, 0.4, 0.9579});
                     const std::vector<double> values = generate_values(5, -0.8, 0.8);
                     CutOptions o;
                     o.values = values;
                     const auto [pd, stats] = cut(img, f, o);
                     r.is_true("fast path taken", stats.fast_path);
                     on_surface(r, pd, f, values, 1.3);
                   }});
  cases.push_back({"cut/sphere-curvilinear-on-surface",
                   "cut of a curvilinear 40^3 grid by a sphere (points refined onto F = 0)", false,
                   [](CaseResult& r) {
                     const StructuredGrid sg = bent(40);
                     const F f = F::sphere({0.05, -0.1, 0.02}, 0.8);
                     const auto [pd, stats] = cut(sg, f);
                     on_surface(r, pd, f, {0.0}, 1.3);
                     std::size_t not_two = 0;
                     for (const auto& [e, n] : edge_uses(pd)) not_two += n != 2;
                     r.equal("edges not shared by exactly two polygons (a closed surface)", not_two,
                             std::size_t{0});
                   }});
  cases.push_back({"cut/plane-closed-polygons",
                   "cut of a closed volume (a 40^3 image) by a plane: no dangling edges", false,
                   [](CaseResult& r) {
                     const ImageData img = grid(40);
                     const F f = F::plane({0.1, 0.1, 0.1}, {0.3, -0.5, 0.8});
                     const auto [pd, stats] = cut(img, f);
                     std::map<Index, int> border;
                     std::size_t over = 0;
                     for (const auto& [e, n] : edge_uses(pd)) {
                       over += n > 2;
                       if (n == 1) ++border[e.first], ++border[e.second];
                     }
                     std::size_t dangling = 0, inside = 0;
                     const Bounds b = img.bounds();
                     for (const auto& [p, d] : border) {
                       dangling += d != 2;
                       const Vec3 q = pd.points[static_cast<std::size_t>(p)];
                       const double gap = std::min({q.x - b.min.x, b.max.x - q.x, q.y - b.min.y,
                                                    b.max.y - q.y, q.z - b.min.z, b.max.z - q.z});
                       inside += gap > 1e-6;
                     }
                     r.note("cut", fmt::format("{} polygons, {} border points", pd.polys.size(), border.size()));
                     r.equal("edges used by more than two polygons", over, std::size_t{0});
                     r.equal("border points not on exactly two border edges (open loops)", dangling,
                             std::size_t{0});
                     r.equal("border points inside the domain (a hole in the cut)", inside,
                             std::size_t{0});
                   }});
  cases.push_back({"clip/sphere-volume", "clip of an image by a sphere: clip + complement = input volume",
                   true, [](CaseResult& r) { conservation(r, F::sphere({0.1, -0.05, 0.2}, 0.8)); }});
  cases.push_back({"clip/union-volume",
                   "clip of an image by a union of a torus and a box: clip + complement = input volume",
                   false, [](CaseResult& r) {
                     conservation(r, F::torus({0, 0, 0}, {0, 1, 1}, 0.6, 0.25) |
                                         F::box({-0.2, -0.9, -0.3}, {0.4, 0.1, 0.2}));
                   }});
}

}  // namespace isoforge::verify
