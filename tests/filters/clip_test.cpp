// Tests of filters/clip.hpp: exact volumes on single cells, conservation (a clip and its
// complement add up to the input), crack-free output, exact attributes.

#include "isoforge/filters/clip.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "isoforge/core/cell.hpp"
#include "isoforge/filters/cut.hpp"
#include "support/sample_datasets.hpp"

using namespace isoforge;
using isoforge::test::single_cell;

namespace {

/// Signed volume of a 3D cell by the divergence theorem over its (outward) face table, a quad
/// face split along the diagonal from its smallest point id (`ids`: the cell's point ids) — the
/// clip's convention, exact for planar faces: positive for a valid cell.
double cell_volume(CellType type, const std::vector<Vec3>& p, const std::vector<Index>& ids) {
  double v = 0;
  auto tri = [&](int a, int b, int c) {
    v += dot(p[static_cast<std::size_t>(a)],
             cross(p[static_cast<std::size_t>(b)], p[static_cast<std::size_t>(c)])) /
         6;
  };
  for (const CellFace& f : cell_faces(type)) {
    if (f.size == 4) {
      int m = 0;
      for (int i = 1; i < 4; ++i) {
        if (ids[static_cast<std::size_t>(f.ids[static_cast<std::size_t>(i)])] <
            ids[static_cast<std::size_t>(f.ids[static_cast<std::size_t>(m)])]) {
          m = i;
        }
      }
      const auto at = [&](int k) { return f.ids[static_cast<std::size_t>((m + k) % 4)]; };
      tri(at(0), at(1), at(2));
      tri(at(0), at(2), at(3));
      continue;
    }
    for (int t = 1; t + 1 < f.size; ++t) {
      tri(f.ids[0], f.ids[static_cast<std::size_t>(t)], f.ids[static_cast<std::size_t>(t + 1)]);
    }
  }
  return v;
}

/// Total measure of the cells of a dataset: volume (3D), area (2D) or length (1D); every 3D
/// cell must be positively oriented.
double measure(DatasetRef ds) {
  double total = 0;
  std::vector<Index> ids;
  for (std::size_t c = 0; c < num_cells(ds); ++c) {
    cell_point_ids(ds, static_cast<Index>(c), ids);
    const CellType t = cell_type(ds, static_cast<Index>(c));
    std::vector<Vec3> p;
    for (Index id : ids) p.push_back(point(ds, id));
    if (cell_dimension(t) == 3) {
      const double v = cell_volume(t, p, ids);
      EXPECT_GE(v, -1e-12) << cell_type_name(t) << " cell " << c << " is inverted";
      total += v;
    } else if (cell_dimension(t) == 2) {
      if (t == CellType::Pixel) std::swap(p[2], p[3]);
      Vec3 n{};
      for (std::size_t i = 0; i < p.size(); ++i) n += cross(p[i], p[(i + 1) % p.size()]);
      total += norm(n) / 2;
    } else if (cell_dimension(t) == 1) {
      for (std::size_t i = 0; i + 1 < p.size(); ++i) total += norm(p[i + 1] - p[i]);
    }
  }
  return total;
}

CutOptions triangles() {
  CutOptions o;
  o.triangulate = true;
  return o;
}

CutOptions three_values() {
  CutOptions o;
  o.values = {-0.4, 0.0, 0.4};
  return o;
}

ClipOptions inside_out() {
  ClipOptions o;
  o.inside_out = true;
  return o;
}

ClipOptions at_value(double v) {
  ClipOptions o;
  o.value = v;
  return o;
}

ImageData box_image(Index n) {
  ImageData img;
  img.dims = {n, n + 1, n + 2};
  img.origin = {-1, -1, -1};
  img.spacing = {2.0 / (n - 1), 2.0 / n, 2.0 / (n + 1)};
  DataArray d("density", ScalarType::Float64, 1, img.num_points());
  for (std::size_t i = 0; i < img.num_points(); ++i) {
    const Vec3 p = img.point(static_cast<Index>(i));
    d.set(i, 0, 2 * p.x - p.y + 0.5 * p.z);
  }
  img.point_data.add(std::move(d));
  return img;
}

}  // namespace

// One tetrahedron cut by x + y + z = s: the corner tet below has volume s^3 / 6, the rest
// (a wedge) 1/6 − s^3/6.
TEST(Clip, TetrahedronPiecesHaveExactVolumes) {
  const UnstructuredGrid g =
      single_cell(CellType::Tetra, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
  const ImplicitFunction f = ImplicitFunction::plane({0.6, 0, 0}, {1, 1, 1});
  const auto [below, sb] = clip(g, f, inside_out());
  const auto [above, sa] = clip(g, f);
  ASSERT_EQ(below.num_cells(), 1u);
  EXPECT_EQ(below.types[0], CellType::Tetra);
  EXPECT_NEAR(measure(below), 0.216 / 6, 1e-7);
  ASSERT_EQ(above.num_cells(), 1u);
  EXPECT_EQ(above.types[0], CellType::Wedge);
  EXPECT_NEAR(measure(above), (1 - 0.216) / 6, 1e-7);
  EXPECT_EQ(sa.cells_split, 1u);
  // Two points on each side: two wedges.
  const ImplicitFunction g2 = ImplicitFunction::plane({0, 0.25, 0.25}, {0, 1, 1});
  const auto [w1, s1] = clip(g, g2);
  const auto [w2, s2] = clip(g, g2, inside_out());
  EXPECT_EQ(w1.types, std::vector<CellType>{CellType::Wedge});
  EXPECT_EQ(w2.types, std::vector<CellType>{CellType::Wedge});
  EXPECT_NEAR(measure(w1) + measure(w2), 1.0 / 6, 1e-7);
}

// Every 3D cell type: the two sides add up to the cell's volume, every piece positively
// oriented, every new point on the plane.
TEST(Clip, EveryCellTypeConservesVolume) {
  struct Case {
    CellType type;
    std::vector<Vec3> pts;
  };
  const std::vector<Case> cases = {
      {CellType::Tetra, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}},
      {CellType::Hexahedron,
       {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}},
      {CellType::Voxel,
       {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}}},
      {CellType::Wedge, {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}, {0, 1, 1}, {1, 0, 1}}},
      {CellType::Pyramid, {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 1}}},
  };
  const std::vector<ImplicitFunction> planes = {
      ImplicitFunction::plane({0.3, 0.2, 0.25}, {1, 0.4, 0.7}),
      ImplicitFunction::plane({0.5, 0.5, 0.5}, {-0.2, 1, 0.1}),
      ImplicitFunction::plane({0.1, 0.1, 0.1}, {0, 0, 1})};
  for (const Case& c : cases) {
    SCOPED_TRACE(cell_type_name(c.type));
    const UnstructuredGrid g = single_cell(c.type, c.pts);
    const double whole = measure(g);
    EXPECT_GT(whole, 0);
    for (const ImplicitFunction& f : planes) {
      const auto [a, sa] = clip(g, f);
      const auto [b, sb] = clip(g, f, inside_out());
      EXPECT_NEAR(measure(a) + measure(b), whole, 1e-7);
      EXPECT_GT(measure(a), 0);
      EXPECT_GT(measure(b), 0);
      for (std::size_t i = c.pts.size(); i < a.num_points(); ++i) {
        // New points: cut points on the plane, or a cell's centre (F off the plane).
        const double v = f.value(a.points[i]);
        EXPECT_TRUE(std::abs(v) < 1e-7 || v > 0) << v;
      }
    }
  }
}

// A sphere clipping image data: conservation (to rounding), whole cells kept unchanged,
// crack-free output (every face of a piece is shared by two cells, or lies on the domain's
// boundary or on the sphere), exact linear attributes at the new points.
TEST(Clip, ImageBySphereIsCrackFreeAndConservative) {
  const ImageData img = box_image(9);
  const ImplicitFunction f = ImplicitFunction::sphere({0.1, -0.05, 0.2}, 0.7);
  const auto [out, stats] = clip(img, f, inside_out());
  const auto [rest, rs] = clip(img, f);
  const double volume = 8.0;
  EXPECT_NEAR(measure(out) + measure(rest), volume, 1e-9);
  EXPECT_NEAR(measure(out), 4.0 / 3.0 * M_PI * 0.343, 0.05);
  // Whole cells: those with every point inside, counted independently.
  std::size_t inside = 0, outside = 0;
  std::vector<Index> ids;
  for (std::size_t c = 0; c < img.num_cells(); ++c) {
    cell_point_ids(img, static_cast<Index>(c), ids);
    std::size_t in = 0;
    for (Index id : ids) in += f.value(img.point(id)) < 0;
    inside += in == 8;
    outside += in == 0;
  }
  EXPECT_EQ(stats.cells_kept, inside);
  EXPECT_EQ(rs.cells_kept, outside);
  EXPECT_EQ(stats.cells_split, img.num_cells() - inside - outside);
  std::size_t voxels = 0;
  for (CellType t : out.types) voxels += t == CellType::Voxel;
  EXPECT_EQ(voxels, inside);
  // Faces, each triangulated along the diagonal from its smallest id.
  std::map<std::array<Index, 3>, int> faces;
  for (std::size_t c = 0; c < out.num_cells(); ++c) {
    const auto cell = out.cells.cell(c);
    for (const CellFace& face : cell_faces(out.types[c])) {
      std::vector<Index> q;
      for (int i = 0; i < face.size; ++i) q.push_back(cell[static_cast<std::size_t>(face.ids[static_cast<std::size_t>(i)])]);
      std::vector<std::array<Index, 3>> tris;
      if (q.size() == 3) {
        tris.push_back({q[0], q[1], q[2]});
      } else {
        const auto m = static_cast<std::size_t>(std::min_element(q.begin(), q.end()) - q.begin());
        tris.push_back({q[m], q[(m + 1) % 4], q[(m + 2) % 4]});
        tris.push_back({q[m], q[(m + 2) % 4], q[(m + 3) % 4]});
      }
      for (auto t : tris) {
        std::sort(t.begin(), t.end());
        ++faces[t];
      }
    }
  }
  for (const auto& [t, uses] : faces) {
    ASSERT_LE(uses, 2);
    if (uses == 2) continue;
    bool on_sphere = true;
    for (Index id : t) on_sphere &= std::abs(f.value(out.points[static_cast<std::size_t>(id)])) < 1e-6;
    EXPECT_TRUE(on_sphere) << "a face used once lies on the cut surface (the sphere is inside the box)";
  }
  const DataArray& d = out.point_data.get("density");
  for (std::size_t i = 0; i < out.num_points(); ++i) {
    const Vec3 p = out.points[i];
    EXPECT_NEAR(d.get(i), 2 * p.x - p.y + 0.5 * p.z, 1e-5);
  }
}

// Polygonal data stays polygonal: triangles and quads of a surface clipped by a plane keep the
// area; lines keep their length.
TEST(Clip, PolyDataAreasAndLengthsAreKept) {
  const auto [surface, s0] =
      cut(box_image(12), ImplicitFunction::sphere({0, 0, 0}, 0.8), triangles());
  const ImplicitFunction f = ImplicitFunction::plane({0, 0, 0.1}, {0.3, 0.2, 1});
  const auto [a, sa] = clip_polydata(surface, f);
  const auto [b, sb] = clip_polydata(surface, f, inside_out());
  EXPECT_NEAR(measure(a) + measure(b), measure(surface), 1e-6);
  EXPECT_GT(a.polys.size(), 0u);
  EXPECT_EQ(a.lines.size(), 0u);
  // Lines: the cut loops of the surface by z = c, clipped by x = 0.
  const auto [loops, s1] = cut(surface, ImplicitFunction::plane({0, 0, 0}, {0, 0, 1}),
                               three_values());
  const ImplicitFunction xf = ImplicitFunction::plane({0, 0, 0}, {1, 0, 0});
  const auto [la, s2] = clip_polydata(loops, xf);
  const auto [lb, s3] = clip_polydata(loops, xf, inside_out());
  EXPECT_NEAR(measure(la) + measure(lb), measure(loops), 1e-6);
  for (std::size_t i = 0; i < la.points.size(); ++i) EXPECT_GE(la.points[i].x, -1e-7);
}

TEST(Clip, ValueIsChecked) {
  const UnstructuredGrid g =
      single_cell(CellType::Tetra, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
  EXPECT_THROW((void)clip(g, ImplicitFunction::sphere({0, 0, 0}, 1), at_value(NAN)), Error);
}

// ---- The structured pass (image data, structured grids) against the generic one ----

namespace {

/// 7 × 6 × 5 points at multiples of 0.5 (exact in float), so the same grid as an unstructured
/// grid has the same coordinates; a linear point array and the cell index as a cell array.
ImageData half_grid() {
  ImageData img;
  img.dims = {7, 6, 5};
  img.origin = {-1.5, -1, -1};
  img.spacing = {0.5, 0.5, 0.5};
  DataArray d("d", ScalarType::Float64, 1, img.num_points());
  for (std::size_t i = 0; i < img.num_points(); ++i) {
    const Vec3 p = img.point(static_cast<Index>(i));
    d.set(i, 0, p.x - 2 * p.y + 3 * p.z);
  }
  img.point_data.add(std::move(d));
  DataArray cell("cell", ScalarType::Int32, 1, img.num_cells());
  for (std::size_t c = 0; c < img.num_cells(); ++c) cell.set(c, 0, static_cast<double>(c));
  img.cell_data.add(std::move(cell));
  return img;
}

/// The same points sheared into a curvilinear grid (offsets of 1/8, exact in float).
StructuredGrid sheared_grid() {
  const ImageData img = half_grid();
  StructuredGrid sg;
  sg.dims = img.dims;
  sg.points = Points(img.num_points());
  for (std::size_t i = 0; i < img.num_points(); ++i) {
    const Vec3 p = img.point(static_cast<Index>(i));
    sg.points.set(i, {p.x + 0.125 * p.z, p.y - 0.125 * p.x, p.z});
  }
  sg.point_data = img.point_data;
  sg.cell_data = img.cell_data;
  return sg;
}

}  // namespace

// The structured pass (kept sides by rows, cut points numbered by edge) gives exactly what the
// generic pass gives for the same cells as an unstructured grid — including functions that are
// exactly c at grid points (a sphere through grid points, a plane through a layer of them).
TEST(Clip, StructuredPassEqualsTheGenericPass) {
  const ImageData img = half_grid();
  const StructuredGrid sg = sheared_grid();
  const std::vector<ImplicitFunction> functions = {
      ImplicitFunction::sphere({0, 0, 0}, 1.0),            // through (±1, 0, 0), (0, ±1, 0), ...
      ImplicitFunction::sphere({0.1, -0.2, 0.05}, 1.1),    // no grid point on it
      ImplicitFunction::plane({0, 0, 0}, {1, 0, 0}),       // through the layer x = 0
      ImplicitFunction::plane({0.2, 0, 0}, {0.3, -1, 0.6})};
  for (std::size_t fi = 0; fi < functions.size(); ++fi) {
    for (const bool inside : {false, true}) {
      ClipOptions o;
      o.inside_out = inside;
      // (A general plane is evaluated on image data from its exact coordinates, on float points
      // with another order of the sums, so that plane is compared on the structured grid only.)
      if (fi != 3) {
        const auto a = clip(img, functions[fi], o);
        const auto b = clip(to_unstructured(img), functions[fi], o);
        EXPECT_TRUE(a.output == b.output) << "image, function " << fi << ", inside_out " << inside;
        EXPECT_EQ(a.stats.points, b.stats.points);
        EXPECT_EQ(a.stats.cells_kept, b.stats.cells_kept);
        EXPECT_EQ(a.stats.cells_split, b.stats.cells_split);
        EXPECT_GT(a.stats.cells_split, 0u);
      }
      const auto c = clip(sg, functions[fi], o);
      const auto d = clip(to_unstructured(sg), functions[fi], o);
      EXPECT_TRUE(c.output == d.output) << "structured grid, function " << fi << ", inside_out "
                                        << inside;
      EXPECT_EQ(c.stats.points, d.stats.points);
      EXPECT_EQ(c.stats.cells_split, d.stats.cells_split);
    }
  }
}

TEST(Clip, StructuredPassIsDeterministicForAnyThreadCount) {
  ImageData img = box_image(40);
  const ImplicitFunction f = ImplicitFunction::sphere({0.1, -0.05, 0.2}, 0.7);
  UnstructuredGrid one, two;
  {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
    one = clip(img, f, inside_out()).output;
  }
  {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 2);
    two = clip(img, f, inside_out()).output;
  }
  EXPECT_GT(one.num_cells(), 0u);
  EXPECT_TRUE(one == two);
}

// Faces conform as they are, quads as quads: every face of a piece is the face of one other
// cell with the same points, or lies on the cut surface or the input's boundary — so a boundary
// extraction of the clip finds no inner face. (A cut cell with a quad face wholly kept next to a
// cell kept whole used to split that quad into two triangles.) Image data, a sheared structured
// grid and the same grid as an unstructured grid, by a sphere and oblique planes, both sides.
TEST(Clip, FacesConformQuadsAsQuads) {
  const ImageData img = half_grid();
  const StructuredGrid sg = sheared_grid();
  const std::vector<Dataset> inputs = {img, sg, to_unstructured(sg)};
  const std::vector<ImplicitFunction> functions = {
      ImplicitFunction::sphere({0.1, -0.2, 0.05}, 1.1),
      ImplicitFunction::plane({0.6, 0.6, 0.6}, {1, 1, 1}),
      ImplicitFunction::plane({0.2, 0, 0}, {0.3, -1, 0.6})};
  const Bounds box = img.bounds();
  // The sheared grid's points back in the image's frame (sheared_grid's map inverted).
  const auto unshear = [](const Vec3& p) {
    const double x = p.x - 0.125 * p.z;
    return Vec3{x, p.y + 0.125 * x, p.z};
  };
  for (std::size_t di = 0; di < inputs.size(); ++di) {
    for (std::size_t fi = 0; fi < functions.size(); ++fi) {
      for (const bool inside : {false, true}) {
        SCOPED_TRACE("input " + std::to_string(di) + ", function " + std::to_string(fi) +
                     (inside ? ", inside out" : ""));
        ClipOptions o;
        o.inside_out = inside;
        const auto [out, stats] = clip(inputs[di], functions[fi], o);
        ASSERT_GT(stats.cells_split, 0u);
        std::map<std::vector<Index>, int> faces;
        for (std::size_t c = 0; c < out.num_cells(); ++c) {
          const auto cell = out.cells.cell(c);
          for (const CellFace& face : cell_faces(out.types[c])) {
            std::vector<Index> q;
            for (int i = 0; i < face.size; ++i) {
              q.push_back(cell[static_cast<std::size_t>(face.ids[static_cast<std::size_t>(i)])]);
            }
            std::sort(q.begin(), q.end());
            ++faces[q];
          }
        }
        std::size_t inner_once = 0;
        for (const auto& [q, uses] : faces) {
          ASSERT_LE(uses, 2);
          if (uses == 2) continue;
          bool on_cut = true;
          for (Index id : q) {
            on_cut &=
                std::abs(functions[fi].value(out.points[static_cast<std::size_t>(id)])) < 1e-6;
          }
          bool on_boundary = false;
          for (int a = 0; a < 3 && !on_boundary; ++a) {
            for (const double side : {box.min[a], box.max[a]}) {
              bool all = true;
              for (Index id : q) {
                const Vec3 p = out.points[static_cast<std::size_t>(id)];
                all &= std::abs((di == 0 ? p : unshear(p))[a] - side) < 1e-6;
              }
              on_boundary |= all;
            }
          }
          inner_once += on_cut || on_boundary ? 0 : 1;
        }
        EXPECT_EQ(inner_once, 0u);
      }
    }
  }
}
