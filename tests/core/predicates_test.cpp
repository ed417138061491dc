#include "isoforge/core/predicates.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>

using namespace isoforge;

namespace {

int naive_orient2d(const Vec2& a, const Vec2& b, const Vec2& c) {
  const double det = (a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0]);
  return det > 0 ? 1 : (det < 0 ? -1 : 0);
}

int naive_orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double det = dot(cross(b - a, c - a), d - a);
  return det > 0 ? 1 : (det < 0 ? -1 : 0);
}

using Tri = std::array<Vec3, 3>;

}  // namespace

TEST(predicates_orient, SignConventions) {
  EXPECT_EQ(orient2d({0, 0}, {1, 0}, {0, 1}), 1);   // counterclockwise
  EXPECT_EQ(orient2d({0, 0}, {0, 1}, {1, 0}), -1);  // clockwise
  EXPECT_EQ(orient2d({0, 0}, {1, 1}, {3, 3}), 0);
  EXPECT_EQ(orient3d({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}), 1);  // the documented example
  EXPECT_EQ(orient3d({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, -1}), -1);
  EXPECT_EQ(orient3d({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 7, 0}), 0);
  // orient3d in the plane z = 0 viewed from +z is orient2d.
  EXPECT_EQ(orient3d({0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}), -1);
}

// Shewchuk's perturbed grid: a = (0.5 + i u, 0.5 + j u) with u = 2^-53 (one ulp at 0.5), b =
// (12, 12), c = (24, 24). The exact determinant is 12 (a_y − a_x) = 12 u (j − i), so the sign is
// sign(j − i); plain double evaluation gets many of these wrong.
TEST(predicates_orient, PerturbedGrid2d) {
  const double u = std::ldexp(1.0, -53);
  int naive_wrong = 0;
  for (int i = 0; i < 64; ++i) {
    for (int j = 0; j < 64; ++j) {
      const Vec2 a{0.5 + i * u, 0.5 + j * u}, b{12, 12}, c{24, 24};
      const int expected = (j > i) - (j < i);
      ASSERT_EQ(orient2d(a, b, c), expected) << i << " " << j;
      ASSERT_EQ(orient2d(b, c, a), expected);
      ASSERT_EQ(orient2d(b, a, c), -expected);
      naive_wrong += naive_orient2d(a, b, c) != expected;
    }
  }
  EXPECT_GT(naive_wrong, 100);  // the test exercises the exact path
}

// Points exactly on a line with huge offsets, and one ulp off it.
TEST(predicates_orient, CollinearWithLargeOffsets) {
  const double big = 1e15;
  const Vec2 a{big, big}, b{big + 1, big + 1}, c{big + 3, big + 3};
  EXPECT_EQ(orient2d(a, b, c), 0);
  const Vec2 up{big + 3, std::nextafter(big + 3, 1e300)};
  const Vec2 down{big + 3, std::nextafter(big + 3, -1e300)};
  EXPECT_EQ(orient2d(a, b, up), 1);
  EXPECT_EQ(orient2d(a, b, down), -1);
}

// Points of the plane x + y + z = s: x, y multiples of 2^-10 in [0, 512], s = 1024, so
// z = s − x − y is exact. d is such a point moved one ulp up or down in z. The right-hand normal
// of (a, b, c) is k (1, 1, 1) with k = the xy-orientation of a, b, c (computed exactly in
// integers), so up gives sign(k). The cross product of generic such points needs ~60 bits: the
// plain double evaluation is unreliable.
TEST(predicates_orient, NearPlanarPoints3d) {
  const double s = 1024;
  std::mt19937 rng(7);
  std::uniform_int_distribution<std::int64_t> k(0, std::int64_t{1} << 19);
  int naive_wrong = 0, tested = 0;
  for (int n = 0; n < 4000; ++n) {
    std::int64_t ix[4], iy[4];
    Vec3 p[4];
    for (int i = 0; i < 4; ++i) {
      ix[i] = k(rng), iy[i] = k(rng);
      const double x = std::ldexp(double(ix[i]), -10), y = std::ldexp(double(iy[i]), -10);
      p[i] = {x, y, s - x - y};
    }
    const std::int64_t kz = (ix[1] - ix[0]) * (iy[2] - iy[0]) - (iy[1] - iy[0]) * (ix[2] - ix[0]);
    if (kz == 0) continue;
    ++tested;
    const int up_sign = kz > 0 ? 1 : -1;
    const Vec3 &a = p[0], &b = p[1], &c = p[2], &on = p[3];
    const Vec3 up{on.x, on.y, std::nextafter(on.z, 1e300)};
    const Vec3 down{on.x, on.y, std::nextafter(on.z, -1e300)};
    ASSERT_EQ(orient3d(a, b, c, on), 0);
    ASSERT_EQ(orient3d(a, b, c, up), up_sign);
    ASSERT_EQ(orient3d(a, b, c, down), -up_sign);
    ASSERT_EQ(orient3d(b, a, c, up), -up_sign);
    ASSERT_EQ(orient3d(a, b, up, c), -up_sign);  // d swapped with c
    naive_wrong += (naive_orient3d(a, b, c, on) != 0) + (naive_orient3d(a, b, c, up) != up_sign) +
                   (naive_orient3d(a, b, c, down) != -up_sign);
  }
  EXPECT_GT(tested, 3900);
  EXPECT_GT(naive_wrong, 100);
}

// The sign of every permutation of four nearly coplanar points follows the permutation's parity
// (naive evaluation breaks this), and an exact scaling changes nothing.
TEST(predicates_orient, PermutationAntisymmetry) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> k(0, 1 << 19);
  std::uniform_int_distribution<int> ulps(-2, 2);
  int zeros = 0, naive_inconsistent = 0;
  for (int n = 0; n < 3000; ++n) {
    // Four points of the plane x + y + z = 1024 (as in NearPlanarPoints3d), each moved a few
    // ulps in z: nearly coplanar, some exactly.
    std::array<Vec3, 4> p;
    for (auto& q : p) {
      const double x = std::ldexp(k(rng), -10), y = std::ldexp(k(rng), -10);
      q = {x, y, 1024 - x - y};
      for (int i = ulps(rng); i != 0; i += i > 0 ? -1 : 1) {
        q.z = std::nextafter(q.z, i > 0 ? 1e300 : -1e300);
      }
    }
    std::array<int, 4> idx{0, 1, 2, 3};
    const int ref = orient3d(p[0], p[1], p[2], p[3]);
    zeros += ref == 0;
    const int naive_ref = naive_orient3d(p[0], p[1], p[2], p[3]);
    do {
      int inversions = 0;
      for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) inversions += idx[i] > idx[j];
      const int parity = inversions % 2 == 0 ? 1 : -1;
      const Vec3 &a = p[idx[0]], &b = p[idx[1]], &c = p[idx[2]], &d = p[idx[3]];
      ASSERT_EQ(orient3d(a, b, c, d), parity * ref);
      naive_inconsistent += naive_orient3d(a, b, c, d) != parity * naive_ref;
      const double t = 0x1p-7;  // scaling by a power of two is exact
      ASSERT_EQ(orient3d(a * t, b * t, c * t, d * t), parity * ref);
    } while (std::next_permutation(idx.begin(), idx.end()));
  }
  EXPECT_GT(naive_inconsistent, 0);
  EXPECT_GT(zeros, 0);  // some quadruples stay exactly coplanar after rounding
}

TEST(predicates_triangles_intersect, CrossingAndSeparate) {
  const Tri p{Vec3{0, 0, 0}, Vec3{2, 0, 0}, Vec3{0, 2, 0}};
  // q pierces p through its interior.
  EXPECT_TRUE(triangles_intersect(p, {Vec3{0.5, 0.5, -1}, Vec3{0.5, 0.5, 1}, Vec3{3, 3, 0.5}}));
  // q above p.
  EXPECT_FALSE(triangles_intersect(p, {Vec3{0, 0, 1}, Vec3{1, 0, 1}, Vec3{0, 1, 2}}));
  // q's plane crosses p's but q misses p (passes beyond the hypotenuse).
  EXPECT_FALSE(triangles_intersect(p, {Vec3{1.5, 1.5, -1}, Vec3{1.5, 1.5, 1}, Vec3{3, 3, 0}}));
  // Symmetric.
  EXPECT_TRUE(triangles_intersect({Vec3{0.5, 0.5, -1}, Vec3{0.5, 0.5, 1}, Vec3{3, 3, 0.5}}, p));
}

TEST(predicates_triangles_intersect, TouchingExactly) {
  const Tri p{Vec3{0, 0, 0}, Vec3{2, 0, 0}, Vec3{0, 2, 0}};
  // A corner of q on p's interior, the rest above.
  EXPECT_TRUE(triangles_intersect(p, {Vec3{0.5, 0.5, 0}, Vec3{1, 0, 1}, Vec3{0, 1, 1}}));
  // ... one ulp above: no contact.
  const double up = std::nextafter(0.0, 1.0);
  EXPECT_FALSE(triangles_intersect(p, {Vec3{0.5, 0.5, up}, Vec3{1, 0, 1}, Vec3{0, 1, 1}}));
  // A corner of q on the hypotenuse of p (x + y = 2).
  EXPECT_TRUE(triangles_intersect(p, {Vec3{1.25, 0.75, 0}, Vec3{3, 3, 1}, Vec3{3, 3, -1}}));
  // ... a hair outside the hypotenuse.
  EXPECT_FALSE(triangles_intersect(
      p, {Vec3{1.25, std::nextafter(0.75, 1.0), 0}, Vec3{3, 3, 1}, Vec3{3, 3, -1}}));
  // Edges crossing in a point (q's edge crosses p's edge x = 0 at (0, 1, 0)).
  EXPECT_TRUE(triangles_intersect(p, {Vec3{-1, 1, 0}, Vec3{1, 1, 0}, Vec3{0, 1, 5}}));
  // Sharing a corner position only.
  EXPECT_TRUE(triangles_intersect(p, {Vec3{2, 0, 0}, Vec3{3, 0, 0}, Vec3{3, 1, 1}}));
}

TEST(predicates_triangles_intersect, Coplanar) {
  const Tri p{Vec3{0, 0, 0}, Vec3{2, 0, 0}, Vec3{0, 2, 0}};
  // Overlapping.
  EXPECT_TRUE(triangles_intersect(p, {Vec3{1, 1, 0}, Vec3{-1, 1, 0}, Vec3{1, -1, 0}}));
  // Contained.
  EXPECT_TRUE(triangles_intersect(p, {Vec3{0.1, 0.1, 0}, Vec3{0.5, 0.1, 0}, Vec3{0.1, 0.5, 0}}));
  EXPECT_TRUE(triangles_intersect({Vec3{0.1, 0.1, 0}, Vec3{0.5, 0.1, 0}, Vec3{0.1, 0.5, 0}}, p));
  // Disjoint although the boxes overlap (beyond the hypotenuse).
  EXPECT_FALSE(triangles_intersect(p, {Vec3{2, 2, 0}, Vec3{1.5, 2, 0}, Vec3{2, 1.5, 0}}));
  // Sharing part of an edge, on opposite sides.
  EXPECT_TRUE(triangles_intersect(p, {Vec3{0.5, 0, 0}, Vec3{1.5, 0, 0}, Vec3{1, -1, 0}}));
  // Tilted plane: the same configuration rotated off the axes (exact in doubles: a shear).
  const auto shear = [](const Vec3& v) { return Vec3{v.x, v.y, 0.5 * v.x + 0.25 * v.y}; };
  EXPECT_TRUE(triangles_intersect({shear(p[0]), shear(p[1]), shear(p[2])},
                                  {shear({1, 1, 0}), shear({-1, 1, 0}), shear({1, -1, 0})}));
  EXPECT_FALSE(triangles_intersect({shear(p[0]), shear(p[1]), shear(p[2])},
                                   {shear({2, 2, 0}), shear({1.5, 2, 0}), shear({2, 1.5, 0})}));
}

TEST(predicates_triangles_intersect, Degenerate) {
  const Tri p{Vec3{0, 0, 0}, Vec3{2, 0, 0}, Vec3{0, 2, 0}};
  // A segment-shaped triangle piercing p.
  EXPECT_TRUE(triangles_intersect(p, {Vec3{0.5, 0.5, -1}, Vec3{0.5, 0.5, 1}, Vec3{0.5, 0.5, 0.3}}));
  // ... and missing it.
  EXPECT_FALSE(triangles_intersect(p, {Vec3{1.5, 1.5, -1}, Vec3{1.5, 1.5, 1}, Vec3{1.5, 1.5, 0}}));
  // A point-shaped triangle inside p, and outside.
  EXPECT_TRUE(triangles_intersect(p, {Vec3{0.5, 0.5, 0}, Vec3{0.5, 0.5, 0}, Vec3{0.5, 0.5, 0}}));
  EXPECT_FALSE(triangles_intersect(p, {Vec3{0.5, 0.5, 1}, Vec3{0.5, 0.5, 1}, Vec3{0.5, 0.5, 1}}));
  // Two collinear segments, overlapping and not.
  const Tri s{Vec3{0, 0, 5}, Vec3{1, 1, 5}, Vec3{2, 2, 5}};
  EXPECT_TRUE(triangles_intersect(s, {Vec3{1.5, 1.5, 5}, Vec3{3, 3, 5}, Vec3{4, 4, 5}}));
  EXPECT_FALSE(triangles_intersect(s, {Vec3{2.5, 2.5, 5}, Vec3{3, 3, 5}, Vec3{4, 4, 5}}));
  // Two crossing segments in a plane, and skew ones.
  EXPECT_TRUE(triangles_intersect(s, {Vec3{0, 2, 5}, Vec3{2, 0, 5}, Vec3{2, 0, 5}}));
  EXPECT_FALSE(triangles_intersect(s, {Vec3{0, 2, 5.5}, Vec3{2, 0, 4.75}, Vec3{2, 0, 4.75}}));
}

// A random check against a brute-force contact test on small integer triangles: contact iff some
// point of a fine common lattice lies in both — not exact in general, so only the "true" answers
// of our predicate on integer coordinates are checked for symmetry and the false ones against
// separation by the triangles' bounding boxes or planes.
TEST(predicates_triangles_intersect, SymmetricOnRandomIntegerTriangles) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> c(0, 3);
  int hits = 0;
  for (int n = 0; n < 20000; ++n) {
    Tri p, q;
    for (auto& v : p) v = {double(c(rng)), double(c(rng)), double(c(rng))};
    for (auto& v : q) v = {double(c(rng)), double(c(rng)), double(c(rng))};
    const bool r = triangles_intersect(p, q);
    hits += r;
    ASSERT_EQ(r, triangles_intersect(q, p));
    ASSERT_EQ(r, triangles_intersect({p[1], p[2], p[0]}, {q[2], q[1], q[0]}));
    // Sharing a corner position implies contact.
    bool share = false;
    for (const auto& a : p) {
      for (const auto& b : q) share = share || a == b;
    }
    if (share) {
      ASSERT_TRUE(r);
    }
  }
  EXPECT_GT(hits, 1000);
  EXPECT_LT(hits, 19000);
}

TEST(predicates_faces_intersect, NoSharedVertex) {
  const Tri p{Vec3{0, 0, 0}, Vec3{2, 0, 0}, Vec3{0, 2, 0}};
  // Touching at a point counts when nothing is shared.
  EXPECT_TRUE(
      faces_intersect(p, {0, 1, 2}, {Vec3{2, 0, 0}, Vec3{3, 0, 0}, Vec3{3, 1, 1}}, {3, 4, 5}));
  EXPECT_FALSE(
      faces_intersect(p, {0, 1, 2}, {Vec3{2.5, 0, 0}, Vec3{3, 0, 0}, Vec3{3, 1, 1}}, {3, 4, 5}));
}

TEST(predicates_faces_intersect, SharedVertex) {
  const Tri p{Vec3{0, 0, 0}, Vec3{2, 0, 0}, Vec3{0, 2, 0}};
  // Fan neighbours around vertex 0 (a bent fan): only the shared vertex in common.
  EXPECT_FALSE(
      faces_intersect(p, {0, 1, 2}, {Vec3{0, 0, 0}, Vec3{-1, 0, 1}, Vec3{0, -1, 1}}, {0, 3, 4}));
  // q starts at the shared vertex and dives through p.
  EXPECT_TRUE(
      faces_intersect(p, {0, 1, 2}, {Vec3{0, 0, 0}, Vec3{1, 0.5, -1}, Vec3{0.5, 1, 1}}, {0, 3, 4}));
  // Coplanar: q overlaps p near the shared vertex.
  EXPECT_TRUE(
      faces_intersect(p, {0, 1, 2}, {Vec3{0, 0, 0}, Vec3{1, 1, 0}, Vec3{-1, 1, 0}}, {0, 3, 4}));
  // Coplanar: q on the other side, touching p only at the shared vertex.
  EXPECT_FALSE(
      faces_intersect(p, {0, 1, 2}, {Vec3{0, 0, 0}, Vec3{-1, 0, 0}, Vec3{-1, -1, 0}}, {0, 3, 4}));
  // Coplanar: q touches p along p's edge (0,1) beyond the shared vertex — a common segment.
  EXPECT_TRUE(
      faces_intersect(p, {0, 1, 2}, {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{1, -1, 0}}, {0, 3, 4}));
  // Non-coplanar: q's far corner touches p's opposite edge exactly.
  EXPECT_TRUE(
      faces_intersect(p, {0, 1, 2}, {Vec3{0, 0, 0}, Vec3{1, 1, 0}, Vec3{0, 0, 3}}, {0, 3, 4}));
  // ... and a hair short of it.
  EXPECT_TRUE(faces_intersect(p, {0, 1, 2}, {Vec3{0, 0, 0}, Vec3{0.9, 0.9, 0}, Vec3{0, 0, 3}},
                              {0, 3, 4}));  // still on p's interior: the edge 0-3 lies in p
  EXPECT_FALSE(faces_intersect(
      p, {0, 1, 2}, {Vec3{0, 0, 0}, Vec3{0.9, 0.9, std::nextafter(0.0, 1.0)}, Vec3{0, 0, 3}},
      {0, 3, 4}));  // lifted by the smallest double: only vertex 0
  // The shared vertex at different corners of the two faces.
  EXPECT_TRUE(
      faces_intersect(p, {0, 1, 2}, {Vec3{1, 0.5, -1}, Vec3{0.5, 1, 1}, Vec3{0, 0, 0}}, {3, 4, 0}));
}

TEST(predicates_faces_intersect, SharedEdge) {
  const Tri p{Vec3{0, 0, 0}, Vec3{2, 0, 0}, Vec3{0, 2, 0}};
  // A flat neighbour across edge (1, 2): no overlap.
  EXPECT_FALSE(
      faces_intersect(p, {0, 1, 2}, {Vec3{2, 0, 0}, Vec3{2, 2, 0}, Vec3{0, 2, 0}}, {1, 3, 2}));
  // A bent neighbour: no overlap.
  EXPECT_FALSE(
      faces_intersect(p, {0, 1, 2}, {Vec3{2, 0, 0}, Vec3{2, 2, 1}, Vec3{0, 2, 0}}, {1, 3, 2}));
  // Folded onto p (coplanar, same side of the edge): overlap.
  EXPECT_TRUE(
      faces_intersect(p, {0, 1, 2}, {Vec3{2, 0, 0}, Vec3{0.5, 0.5, 0}, Vec3{0, 2, 0}}, {1, 3, 2}));
  // Folded, with the opposite corner outside p but on the same side of the edge line.
  EXPECT_TRUE(
      faces_intersect(p, {0, 1, 2}, {Vec3{2, 0, 0}, Vec3{-1, -1, 0}, Vec3{0, 2, 0}}, {1, 3, 2}));
  // Almost folded (one ulp off the plane): they meet only along the edge.
  EXPECT_FALSE(faces_intersect(
      p, {0, 1, 2}, {Vec3{2, 0, 0}, Vec3{0.5, 0.5, std::nextafter(0.0, 1.0)}, Vec3{0, 2, 0}},
      {1, 3, 2}));
  // Duplicate faces, in either orientation.
  EXPECT_TRUE(faces_intersect(p, {0, 1, 2}, p, {0, 1, 2}));
  EXPECT_TRUE(faces_intersect(p, {0, 1, 2}, {p[2], p[1], p[0]}, {2, 1, 0}));
}

TEST(predicates_faces_intersect, DegenerateFaces) {
  const Tri p{Vec3{0, 0, 0}, Vec3{2, 0, 0}, Vec3{0, 2, 0}};
  // A flat (collinear) face sharing edge (0, 1) and lying on it: nothing beyond the edge.
  EXPECT_FALSE(
      faces_intersect(p, {0, 1, 2}, {Vec3{0, 0, 0}, Vec3{2, 0, 0}, Vec3{1, 0, 0}}, {0, 1, 3}));
  // ... sticking out along the edge line: still only the edge inside p.
  EXPECT_FALSE(
      faces_intersect(p, {0, 1, 2}, {Vec3{0, 0, 0}, Vec3{2, 0, 0}, Vec3{3, 0, 0}}, {0, 1, 3}));
  // Two flat faces on one line sharing edge (0, 1), both sticking out past 1: overlap.
  EXPECT_TRUE(faces_intersect({Vec3{0, 0, 0}, Vec3{2, 0, 0}, Vec3{4, 0, 0}}, {0, 1, 2},
                              {Vec3{0, 0, 0}, Vec3{2, 0, 0}, Vec3{3, 0, 0}}, {0, 1, 3}));
  // ... sticking out on opposite ends: only the edge in common.
  EXPECT_FALSE(faces_intersect({Vec3{0, 0, 0}, Vec3{2, 0, 0}, Vec3{4, 0, 0}}, {0, 1, 2},
                               {Vec3{0, 0, 0}, Vec3{2, 0, 0}, Vec3{-1, 0, 0}}, {0, 1, 3}));
  // A flat face through shared vertex 0 with v between its ends, crossing p's interior.
  EXPECT_TRUE(
      faces_intersect(p, {0, 1, 2}, {Vec3{0, 0, 0}, Vec3{-1, -1, 0}, Vec3{1, 1, 0}}, {0, 3, 4}));
  // ... pointing away from p on both sides (along the line x = −y): only vertex 0.
  EXPECT_FALSE(
      faces_intersect(p, {0, 1, 2}, {Vec3{0, 0, 0}, Vec3{-1, 1, 0}, Vec3{1, -1, 0}}, {0, 3, 4}));
}
