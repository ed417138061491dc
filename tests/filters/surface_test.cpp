#include "isoforge/filters/surface.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <map>
#include <utility>

#include "isoforge/core/cell.hpp"
#include "isoforge/io/io.hpp"

using namespace isoforge;

namespace {

// Signed volume enclosed by the polygons (fan-triangulated), by the divergence theorem:
// positive when they are oriented outward.
double signed_volume(const PolyData& pd) {
  double v = 0;
  for (std::size_t c = 0; c < pd.polys.size(); ++c) {
    const auto ids = pd.polys.cell(c);
    const Vec3 a = pd.points[static_cast<std::size_t>(ids[0])];
    for (std::size_t i = 1; i + 1 < ids.size(); ++i) {
      const Vec3 b = pd.points[static_cast<std::size_t>(ids[i])];
      const Vec3 d = pd.points[static_cast<std::size_t>(ids[i + 1])];
      v += dot(a, cross(b, d)) / 6;
    }
  }
  return v;
}

// Every directed edge of the polygons used once and its reverse once: closed, manifold at the
// edges, consistently oriented.
bool closed_and_oriented(const PolyData& pd) {
  std::map<std::pair<Index, Index>, int> directed;
  for (std::size_t c = 0; c < pd.polys.size(); ++c) {
    const auto ids = pd.polys.cell(c);
    for (std::size_t i = 0; i < ids.size(); ++i) ++directed[{ids[i], ids[(i + 1) % ids.size()]}];
  }
  for (const auto& [e, n] : directed) {
    if (n != 1) return false;
    const auto r = directed.find({e.second, e.first});
    if (r == directed.end() || r->second != 1) return false;
  }
  return true;
}

UnstructuredGrid single_cell(CellType type) {
  UnstructuredGrid g;
  const auto pp = parametric_points(type);
  std::vector<Index> ids;
  for (const Vec3& p : pp) {
    ids.push_back(static_cast<Index>(g.points.size()));
    // The pyramid's apex (0.5, 0.5, 1), the others as they are: a valid cell of each type.
    g.points.push_back(p);
  }
  g.add_cell(type, ids);
  return g;
}

}  // namespace

TEST(Surface, EachCellTypeGivesItsFacesOrientedOutward) {
  // VTK's valid cells (core/cell.hpp): volumes 1/6 (tetra), 1 (voxel, hexahedron), 1/2 (wedge),
  // 1/3 (pyramid, apex at height 1 over the unit square).
  const std::pair<CellType, double> cases[] = {{CellType::Tetra, 1.0 / 6},
                                               {CellType::Voxel, 1.0},
                                               {CellType::Hexahedron, 1.0},
                                               {CellType::Wedge, 0.5},
                                               {CellType::Pyramid, 1.0 / 3}};
  for (const auto& [type, volume] : cases) {
    UnstructuredGrid g = single_cell(type);
    if (type == CellType::Wedge) {
      // VTK's valid wedge: base (0, 1, 2) ordered with its normal away from the top (3, 4, 5).
      g.cells = CellArray(std::vector<Index>{0, 6}, std::vector<Index>{0, 2, 1, 3, 5, 4});
    }
    auto [s, stats] = extract_surface(g);
    SCOPED_TRACE(std::string(cell_type_name(type)));
    EXPECT_EQ(s.polys.size(), cell_faces(type).size());
    EXPECT_EQ(stats.boundary_faces, cell_faces(type).size());
    EXPECT_EQ(s.num_points(), g.num_points());
    EXPECT_NEAR(signed_volume(s), volume, 1e-12);
    EXPECT_TRUE(closed_and_oriented(s));
  }
}

TEST(Surface, SharedFacesAreDropped) {
  // Two tetrahedra sharing the face (1, 2, 3), plus a triangle, a line and a vertex.
  UnstructuredGrid g;
  for (const Vec3& p : {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}, Vec3{1, 1, 1},
                        Vec3{5, 5, 5}, Vec3{6, 5, 5}, Vec3{5, 6, 5}, Vec3{9, 9, 9}})
    g.points.push_back(p);
  g.add_cell(CellType::Vertex, {8});
  g.add_cell(CellType::Tetra, {0, 1, 2, 3});
  g.add_cell(CellType::Triangle, {5, 6, 7});
  g.add_cell(CellType::Tetra, {1, 4, 2, 3});  // 1,2,3 seen from 4: opposite to the first
  g.add_cell(CellType::Line, {5, 6});
  g.point_data.add(DataArray::from_vector<float>("p", 1, {0, 1, 2, 3, 4, 5, 6, 7, 8}));
  g.cell_data.add(DataArray::from_vector<std::int32_t>("c", 1, {100, 101, 102, 103, 104}));
  SurfaceOptions o;
  o.original_point_ids = true;
  auto [s, stats] = extract_surface(g, o);
  EXPECT_EQ(stats.boundary_faces, 6u);  // 8 faces, the shared one twice
  EXPECT_EQ(stats.passed_cells, 3u);
  ASSERT_EQ(s.verts.size(), 1u);
  ASSERT_EQ(s.lines.size(), 1u);
  ASSERT_EQ(s.polys.size(), 7u);  // 3 + 1 + 3 in owner order
  EXPECT_EQ(s.num_points(), 9u);
  // Cell data follows the owners: verts, lines, then polys by owner (cell 1 x3, 2, 3 x3).
  const DataArray& owner = s.cell_data.get("OriginalCellIds");
  const std::vector<double> expected = {0, 4, 1, 1, 1, 2, 3, 3, 3};
  ASSERT_EQ(owner.tuples(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(owner.get(i), expected[i]);
    EXPECT_EQ(s.cell_data.get("c").get(i), 100 + expected[i]);
  }
  EXPECT_EQ(s.point_data.get("OriginalPointIds").get(8), 8.0);
  // The two tets' surface without the loose cells encloses both volumes.
  PolyData tets = s;
  tets.polys = CellArray();
  for (std::size_t c = 0; c < s.polys.size(); ++c)
    if (owner.get(s.verts.size() + s.lines.size() + c) != 2) tets.polys.add(s.polys.cell(c));
  EXPECT_NEAR(signed_volume(tets), 1.0 / 6 + 1.0 / 3, 1e-12);  // [1,4,2,3]: 1/3 (|det| = 2)
  EXPECT_TRUE(closed_and_oriented(tets));
  EXPECT_NO_THROW(s.validate());
}

TEST(Surface, StructuredFastPathEqualsTheGeneralPath) {
  ImageData img;
  img.dims = {4, 3, 5};
  img.origin = {1, 2, 3};
  img.spacing = {0.5, 1, 2};
  DataArray p("p", ScalarType::Float64, 1, img.num_points());
  for (std::size_t i = 0; i < img.num_points(); ++i) p.set(i, 0, static_cast<double>(i));
  img.point_data.add(std::move(p), AttributeRole::Scalars);
  DataArray c("c", ScalarType::Int16, 1, img.num_cells());
  for (std::size_t i = 0; i < img.num_cells(); ++i) c.set(i, 0, static_cast<double>(i));
  img.cell_data.add(std::move(c));
  SurfaceOptions o;
  o.original_point_ids = true;
  auto [fast, fast_stats] = extract_surface(img, o);
  auto [general, general_stats] = extract_surface(to_unstructured(img), o);
  // 2 (3*2 + 3*4 + 2*4) = 52 faces; 60 points minus the 2*1*3 interior ones.
  EXPECT_EQ(fast.polys.size(), 52u);
  EXPECT_EQ(fast.num_points(), 54u);
  EXPECT_EQ(fast, general);
  EXPECT_EQ(fast_stats.boundary_faces, general_stats.boundary_faces);
  EXPECT_NEAR(signed_volume(fast), 1.5 * 2 * 8, 1e-9);
  EXPECT_TRUE(closed_and_oriented(fast));
  // The same for a (curvilinear) structured grid of hexahedra, with a thin axis (2 points).
  StructuredGrid sg;
  sg.dims = {2, 3, 4};
  sg.points = Points(24, ScalarType::Float64);
  for (Index k = 0; k < 4; ++k)
    for (Index j = 0; j < 3; ++j)
      for (Index i = 0; i < 2; ++i)
        sg.points.set(static_cast<std::size_t>(sg.point_id(i, j, k)),
                      {static_cast<double>(i) + 0.1 * static_cast<double>(j * k),
                       static_cast<double>(j), static_cast<double>(k)});
  const PolyData sfast = extract_surface(sg).output;
  EXPECT_EQ(sfast, extract_surface(to_unstructured(sg)).output);
  EXPECT_EQ(sfast.points.type(), ScalarType::Float64);
  EXPECT_EQ(sfast.polys.size(), 2u * (1 * 2 + 1 * 3 + 2 * 3));
  EXPECT_NEAR(signed_volume(sfast), 6.0, 1e-9);  // shear keeps the volume
  EXPECT_TRUE(closed_and_oriented(sfast));
}

TEST(Surface, LowerDimensionalCellsPassThrough) {
  ImageData img;
  img.dims = {3, 1, 3};  // 4 pixels in the xz plane
  const PolyData s = extract_surface(img).output;
  ASSERT_EQ(s.polys.size(), 4u);
  // Pixel (0, 1, 3, 4) in voxel order becomes the loop (0, 1, 4, 3).
  const auto q = s.polys.cell(0);
  EXPECT_EQ(std::vector<Index>(q.begin(), q.end()), (std::vector<Index>{0, 1, 4, 3}));
  ImageData line;
  line.dims = {1, 4, 1};
  const PolyData l = extract_surface(line).output;
  EXPECT_EQ(l.lines.size(), 3u);
  // blow.vtk: 1057 shell cells (928 triangles + 129 quads) and their 687 points.
  const Dataset blow = read(std::string(ISOFORGE_DATA_DIR) + "/blow.vtk");
  auto [b, stats] = extract_surface(blow);
  EXPECT_EQ(b.polys.size(), 1057u);
  EXPECT_EQ(stats.boundary_faces, 0u);
  EXPECT_EQ(stats.passed_cells, 1057u);
  EXPECT_EQ(b.point_data.size(), point_data(blow).size());
}

TEST(Surface, TetrahedralMeshGivesAClosedOutwardSurface) {
  // post.vtk: 8750 tetrahedra.
  const Dataset ds = read(std::string(ISOFORGE_DATA_DIR) + "/post.vtk");
  const auto& ug = std::get<UnstructuredGrid>(ds);
  auto [s, stats] = extract_surface(ug);
  EXPECT_GT(s.polys.size(), 100u);
  EXPECT_TRUE(closed_and_oriented(s));
  // The enclosed volume is the sum of the tetrahedra's volumes.
  double volume = 0;
  for (std::size_t c = 0; c < ug.num_cells(); ++c) {
    const auto ids = ug.cells.cell(c);
    const Vec3 a = ug.points[static_cast<std::size_t>(ids[0])];
    volume += dot(ug.points[static_cast<std::size_t>(ids[1])] - a,
                  cross(ug.points[static_cast<std::size_t>(ids[2])] - a,
                        ug.points[static_cast<std::size_t>(ids[3])] - a)) / 6;
  }
  EXPECT_GT(volume, 0);
  EXPECT_NEAR(signed_volume(s), volume, 1e-9 * std::abs(volume) + 1e-9);
  EXPECT_TRUE(s.point_data.has("Pressure"));
  // Same output with one thread.
  PolyData one;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = extract_surface(ug).output;
  }
  EXPECT_EQ(one, s);
}
