// Each mesh check on meshes built to pass it and meshes built to fail it.

#include "mesh_checks.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace isoforge;
using namespace isoforge::verify;

namespace {

PolyData tetra() {
  PolyData pd;
  pd.points.push_back({0, 0, 0});
  pd.points.push_back({1, 0, 0});
  pd.points.push_back({0, 1, 0});
  pd.points.push_back({0, 0, 1});
  // Outward: counter-clockwise seen from outside.
  pd.polys.add({0, 2, 1});
  pd.polys.add({0, 1, 3});
  pd.polys.add({0, 3, 2});
  pd.polys.add({1, 2, 3});
  return pd;
}

PolyData flipped(const PolyData& in) {
  PolyData pd;
  pd.points = in.points;
  for (std::size_t c = 0; c < in.polys.size(); ++c) {
    auto ids = in.polys.cell(c);
    std::vector<Index> r(ids.rbegin(), ids.rend());
    pd.polys.add(r);
  }
  return pd;
}

// Torus of n x m quads (split into triangles), radii R = 2, r = 0.5, outward.
PolyData torus(int n, int m) {
  PolyData pd;
  const double pi = std::acos(-1.0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      double u = 2 * pi * i / n, v = 2 * pi * j / m;
      pd.points.push_back({(2 + 0.5 * std::cos(v)) * std::cos(u),
                           (2 + 0.5 * std::cos(v)) * std::sin(u), 0.5 * std::sin(v)});
    }
  auto id = [&](int i, int j) { return Index((i % n) * m + (j % m)); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      pd.polys.add({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      pd.polys.add({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return pd;
}

}  // namespace

TEST(MeshChecks, ClosedOutwardTetrahedron) {
  const MeshReport r = check_mesh(tetra());
  EXPECT_EQ(r.vertices, 4u);
  EXPECT_EQ(r.edges, 6u);
  EXPECT_EQ(r.faces, 4u);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.manifold);
  EXPECT_TRUE(r.oriented);
  EXPECT_TRUE(r.outward);
  EXPECT_EQ(r.self_intersections, 0u);
  EXPECT_TRUE(r.valid_closed_surface());
  ASSERT_EQ(r.components.size(), 1u);
  EXPECT_EQ(r.components[0].euler, 2);
  EXPECT_EQ(r.components[0].genus, 0);
  EXPECT_NEAR(r.volume, 1.0 / 6.0, 1e-15);
}

TEST(MeshChecks, InwardTetrahedronIsNotOutward) {
  const MeshReport r = check_mesh(flipped(tetra()));
  EXPECT_TRUE(r.oriented);
  EXPECT_FALSE(r.outward);
  EXPECT_NEAR(r.volume, -1.0 / 6.0, 1e-15);
}

TEST(MeshChecks, OneFlippedFaceBreaksOrientation) {
  PolyData pd = tetra();
  std::swap(pd.polys.cell(3)[1], pd.polys.cell(3)[2]);  // (1,3,2)
  const MeshReport r = check_mesh(pd);
  EXPECT_EQ(r.inconsistent_edges, 3u);  // the three edges of the flipped face
  EXPECT_FALSE(r.oriented);
  EXPECT_FALSE(r.valid_closed_surface());
}

TEST(MeshChecks, OpenSurfaceHasBorderLoop) {
  PolyData pd = tetra();
  PolyData open;
  open.points = pd.points;
  for (std::size_t c = 0; c < 3; ++c) open.polys.add(pd.polys.cell(c));
  const MeshReport r = check_mesh(open);
  EXPECT_FALSE(r.closed);
  EXPECT_EQ(r.border_edges, 3u);
  ASSERT_EQ(r.components.size(), 1u);
  EXPECT_EQ(r.components[0].border_loops, 1u);
  EXPECT_EQ(r.components[0].genus, 0);  // a disk: V - E + F = 1 = 2 - 0 - 1
}

TEST(MeshChecks, NonManifoldEdge) {
  PolyData pd;
  pd.points.push_back({0, 0, 0});
  pd.points.push_back({1, 0, 0});
  pd.points.push_back({0, 1, 0});
  pd.points.push_back({0, -1, 0});
  pd.points.push_back({0, 0, 1});
  pd.polys.add({0, 1, 2});
  pd.polys.add({1, 0, 3});
  pd.polys.add({0, 1, 4});
  const MeshReport r = check_mesh(pd);
  EXPECT_EQ(r.non_manifold_edges, 1u);
  EXPECT_FALSE(r.manifold);
}

namespace {

/// `tetra()` and a second, outward-oriented tetrahedron (3, 4, 5, 6) above it that shares only
/// point 3, its apex: closed, every edge manifold, one non-manifold vertex.
PolyData two_tetrahedra_touching() {
  PolyData pd = tetra();
  pd.points.push_back({0, 0, 2});
  pd.points.push_back({1, 0, 2});
  pd.points.push_back({0, 1, 2});
  pd.polys.add({3, 4, 6});
  pd.polys.add({3, 5, 4});
  pd.polys.add({3, 6, 5});
  pd.polys.add({4, 5, 6});
  return pd;
}

}  // namespace

TEST(MeshChecks, NonManifoldVertexWhereTwoTetrahedraTouch) {
  const MeshReport r = check_mesh(two_tetrahedra_touching());
  EXPECT_EQ(r.non_manifold_edges, 0u);
  EXPECT_EQ(r.non_manifold_vertices, 1u);
  EXPECT_FALSE(r.manifold);
  EXPECT_TRUE(r.closed);
}

TEST(MeshChecks, DegenerateAndDuplicatePoints) {
  PolyData pd = tetra();
  pd.points.push_back({0.5, 0, 0});  // 4: on edge 0-1 -> collinear with 0 and 1
  pd.points.push_back({0, 0, 1});    // 5: same coordinates as 3
  pd.polys.add({0, 4, 1});
  pd.polys.add({2, 2, 5});
  const MeshReport r = check_mesh(pd);
  EXPECT_EQ(r.degenerate_faces, 2u);
  EXPECT_EQ(r.duplicate_points, 1u);
}

TEST(MeshChecks, CrossingTrianglesSelfIntersect) {
  PolyData pd;
  pd.points.push_back({0, 0, 0});
  pd.points.push_back({2, 0, 0});
  pd.points.push_back({1, 2, 0});
  pd.points.push_back({1, 1, -1});
  pd.points.push_back({1, 1, 1});
  pd.points.push_back({1, 3, 0.5});
  pd.polys.add({0, 1, 2});
  pd.polys.add({3, 4, 5});
  const MeshReport r = check_mesh(pd);
  EXPECT_TRUE(r.self_intersection_checked);
  EXPECT_EQ(r.self_intersections, 1u);
  EXPECT_EQ(r.components.size(), 2u);
}

TEST(MeshChecks, TorusHasGenusOne) {
  const MeshReport r = check_mesh(torus(24, 12));
  EXPECT_TRUE(r.valid_closed_surface());
  EXPECT_TRUE(r.outward);
  ASSERT_EQ(r.components.size(), 1u);
  EXPECT_EQ(r.components[0].euler, 0);
  EXPECT_EQ(r.components[0].genus, 1);
  // The inscribed polyhedral torus encloses a little less than 2 pi^2 R r^2 = pi^2: about
  // sinc(2 pi / 24) * sinc(2 pi / 12) = 0.944 of it.
  const double pi2 = std::acos(-1.0) * std::acos(-1.0);
  EXPECT_GT(r.volume, 0.93 * pi2);
  EXPECT_LT(r.volume, pi2);
}

TEST(MeshChecks, NoFacesIsAnError) {
  PolyData pd;
  pd.points.push_back({0, 0, 0});
  EXPECT_THROW((void)check_mesh(pd), Error);
  pd.polys.add({0, 1, 2});  // ids out of range
  EXPECT_THROW((void)check_mesh(pd), Error);
}

namespace {

// Tetrahedron scaled by s about (0.1, 0.1, 0.1) and shifted by d, outward unless `inward`.
void add_tetra(PolyData& pd, double s, const Vec3& d, bool inward) {
  const PolyData t = tetra();
  const Index base = static_cast<Index>(pd.points.size());
  for (std::size_t i = 0; i < t.points.size(); ++i) {
    pd.points.push_back((t.points[i] - Vec3{0.1, 0.1, 0.1}) * s + Vec3{0.1, 0.1, 0.1} + d);
  }
  for (std::size_t c = 0; c < t.polys.size(); ++c) {
    auto ids = t.polys.cell(c);
    if (inward) {
      pd.polys.add({base + ids[0], base + ids[2], base + ids[1]});
    } else {
      pd.polys.add({base + ids[0], base + ids[1], base + ids[2]});
    }
  }
}

}  // namespace

TEST(MeshChecks, OutwardAccountsForNesting) {
  // A hollow tetrahedron: the cavity's surface must face inward (into the cavity).
  PolyData hollow;
  add_tetra(hollow, 1.0, {0, 0, 0}, false);
  add_tetra(hollow, 0.3, {0, 0, 0}, true);
  MeshReport r = check_mesh(hollow);
  EXPECT_TRUE(r.valid_closed_surface());
  EXPECT_TRUE(r.outward);
  EXPECT_EQ(r.inward_components, 0u);
  // The cavity facing outward is wrong although every component alone looks outward.
  PolyData wrong;
  add_tetra(wrong, 1.0, {0, 0, 0}, false);
  add_tetra(wrong, 0.3, {0, 0, 0}, false);
  r = check_mesh(wrong);
  EXPECT_FALSE(r.outward);
  EXPECT_EQ(r.inward_components, 1u);
  // Two separate solids, both outward; then one of them flipped.
  PolyData two;
  add_tetra(two, 1.0, {0, 0, 0}, false);
  add_tetra(two, 1.0, {3, 0, 0}, false);
  r = check_mesh(two);
  EXPECT_TRUE(r.outward);
  PolyData one_flipped;
  add_tetra(one_flipped, 1.0, {0, 0, 0}, false);
  add_tetra(one_flipped, 1.0, {3, 0, 0}, true);
  r = check_mesh(one_flipped);
  EXPECT_FALSE(r.outward);
  EXPECT_EQ(r.inward_components, 1u);
}

TEST(MeshChecks, OutwardNeedsAValidClosedSurface) {
  // An open surface is never "outward", whatever its faces do.
  PolyData open;
  const PolyData t = tetra();
  open.points = t.points;
  for (std::size_t c = 0; c < 3; ++c) open.polys.add(t.polys.cell(c));
  EXPECT_FALSE(check_mesh(open).outward);
}

// ---- self-intersections of faces that share corners or edges (manifold or not) ----

namespace {

PolyData triangles(std::vector<Vec3> points, std::vector<std::vector<Index>> faces) {
  PolyData pd;
  for (const Vec3& p : points) pd.points.push_back(p);
  for (const auto& f : faces) pd.polys.add(f);
  return pd;
}

}  // namespace

TEST(MeshChecks, ThreeTrianglesOnOneEdgeDoNotIntersect) {
  // A non-manifold "book" of three pages on the edge (0,0,0)-(1,0,0): two pages in the plane
  // z = 0 on opposite sides of the edge, one standing up. They meet only along the edge.
  const PolyData pd = triangles({{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}, {0.5, 0, 1}},
                                {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
  const MeshReport r = check_mesh(pd);
  EXPECT_EQ(r.non_manifold_edges, 1u);
  EXPECT_TRUE(r.self_intersection_checked);
  EXPECT_EQ(r.self_intersections, 0u);
}

TEST(MeshChecks, CoplanarPagesOnTheSameSideOfAnEdgeOverlap) {
  // The same book with the third page folded flat onto the first: those two overlap (1 pair);
  // the page on the other side touches both only along the edge.
  const PolyData pd = triangles({{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}, {0.2, 0.5, 0}},
                                {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
  EXPECT_EQ(check_mesh(pd).self_intersections, 1u);
}

TEST(MeshChecks, TwoTetrahedraTouchingAtOneCornerDoNotIntersect) {
  // Non-manifold vertex: the faces around the shared apex meet only there.
  const MeshReport r = check_mesh(two_tetrahedra_touching());
  EXPECT_EQ(r.non_manifold_vertices, 1u);
  EXPECT_TRUE(r.self_intersection_checked);
  EXPECT_EQ(r.self_intersections, 0u);
}

TEST(MeshChecks, FacesSharingOneCornerIntersectOnlyBeyondIt) {
  // Two triangles sharing corner 0: crossed like a bow tie out of plane (they meet only at the
  // corner), then with the second one piercing the first (the opposite edge 3-4 passes through).
  const PolyData apart =
      triangles({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 1}, {-1, 1, 1}}, {{0, 1, 2}, {0, 3, 4}});
  EXPECT_EQ(check_mesh(apart).self_intersections, 0u);
  const PolyData pierced = triangles(
      {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {1.5, 0.5, -1}, {1.5, 0.5, 1}}, {{0, 1, 2}, {0, 3, 4}});
  EXPECT_EQ(check_mesh(pierced).self_intersections, 1u);
}

TEST(MeshChecks, RequirementsNameWhatFailed) {
  const MeshReport ok = check_mesh(tetra());
  EXPECT_TRUE(failed_requirements(ok, mesh_requirement_names()).empty());

  PolyData open;
  const PolyData t = tetra();
  open.points = t.points;
  for (std::size_t c = 0; c < 3; ++c) open.polys.add(t.polys.cell(c));
  const auto failed = failed_requirements(check_mesh(open), {"closed", "manifold"});
  ASSERT_EQ(failed.size(), 1u);
  EXPECT_EQ(failed[0], "closed (3 border edges)");

  const PolyData crossing =
      triangles({{0, 0, 0}, {2, 0, 0}, {1, 2, 0}, {1, 1, -1}, {1, 1, 1}, {1, 3, 0.5}},
                {{0, 1, 2}, {3, 4, 5}});
  const auto si = failed_requirements(check_mesh(crossing), {"no-self-intersections"});
  ASSERT_EQ(si.size(), 1u);
  EXPECT_EQ(si[0], "no-self-intersections (1 intersecting face pairs)");
  MeshCheckOptions skip;
  skip.self_intersections = false;
  EXPECT_EQ(failed_requirements(check_mesh(crossing, skip), {"no-self-intersections"}).at(0),
            "no-self-intersections (not checked)");

  EXPECT_THROW((void)failed_requirements(ok, {"watertight"}), Error);
}
