// isoforge's exact self-intersection test (spatial/self_intersections.hpp, on core/predicates.hpp)
// against the CGAL check of the verification suite (check_mesh): the same number of pairs on
// the bunny, random triangle soups sharing vertices, and meshes with folds (coplanar and not);
// and the predicates themselves against CGAL's on nearly degenerate inputs.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

#include "isoforge/core/mesh_topology.hpp"
#include "isoforge/core/predicates.hpp"
#include "isoforge/io/ply.hpp"
#include "isoforge/spatial/self_intersections.hpp"
#include "mesh_checks.hpp"
#include "support/meshes.hpp"

using namespace isoforge;

namespace {

std::size_t cgal_count(const PolyData& m) {
  return verify::check_mesh(m).self_intersections;
}

// An n × n grid of the unit square split into triangles (alternating diagonals), z = f(x, y).
template <class F>
PolyData grid(int n, F&& height) {
  return test::grid_surface(
      n,
      [&](int i, int j) {
        const double x = double(i) / n, y = double(j) / n;
        return Vec3{x, y, height(x, y)};
      },
      [](int i, int j) { return (i + j) % 2 == 0; });
}

// Moves a fraction of the points by up to `amount` along the axes in `axes` (x, y, z flags).
void perturb(PolyData& m, double fraction, double amount, std::array<bool, 3> axes, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1), d(-amount, amount);
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    if (u(rng) >= fraction) continue;
    Vec3 p = m.points[i];
    for (int k = 0; k < 3; ++k) {
      if (axes[static_cast<std::size_t>(k)]) p[k] += d(rng);
    }
    m.points.set(i, p);
  }
}

}  // namespace

TEST(self_intersections_vs_cgal, Bunny) {
  const PolyData bunny = read_ply(ISOFORGE_DATA_DIR "/bunny.ply");
  EXPECT_EQ(self_intersections(bunny).size(), cgal_count(bunny));
}

TEST(self_intersections_vs_cgal, BunnyWithDisplacedVertices) {
  PolyData bunny = read_ply(ISOFORGE_DATA_DIR "/bunny.ply");
  // 2% of the vertices moved by up to ~3 mean edge lengths (the bunny is ~0.15 wide, edges
  // ~1.5e-3): folds and crossings all over.
  perturb(bunny, 0.02, 0.005, {true, true, true}, 4);
  const std::size_t ours = self_intersections(bunny).size();
  EXPECT_GT(ours, 100u);
  EXPECT_EQ(ours, cgal_count(bunny));
}

TEST(self_intersections_vs_cgal, RandomSoupsWithSharedVertices) {
  for (unsigned seed = 1; seed <= 6; ++seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 4), d(-0.7, 0.7);
    PolyData m;
    for (int i = 0; i < 200; ++i) m.points.push_back({u(rng), u(rng), u(rng)});
    std::uniform_int_distribution<Index> pool(0, 199);
    for (int n = 0; n < 600; ++n) {
      const Index a = pool(rng);
      const Vec3 p = m.points[std::size_t(a)];
      m.points.push_back(p + Vec3{d(rng), d(rng), d(rng)});
      const Index c = Index(m.points.size() - 1);
      // A third of the triangles use two pool vertices (so edges get shared too), the rest
      // one pool vertex and two new points near it.
      Index b;
      if (n % 3 == 0) {
        b = pool(rng);
      } else {
        m.points.push_back(p + Vec3{d(rng), d(rng), d(rng)});
        b = Index(m.points.size() - 1);
      }
      m.polys.add({a, b, c});
      if (n % 5 == 0) m.polys.add({b, a, pool(rng)});  // a neighbour across edge a-b
    }
    const std::size_t ours = self_intersections(m).size();
    EXPECT_GT(ours, 0u) << seed;
    EXPECT_EQ(ours, cgal_count(m)) << "seed " << seed;
  }
}

// Triangles on a 4 × 4 × 4 integer lattice: touching at corners, along edges and in shared
// planes everywhere, collinear (skipped) faces, and distinct ids at equal positions (points 64
// and up repeat the lattice) — the exact cases where a tolerance would decide.
TEST(self_intersections_vs_cgal, LatticeSoups) {
  for (unsigned seed = 1; seed <= 12; ++seed) {
    std::mt19937 rng(seed);
    PolyData m;
    for (int copy = 0; copy < 2; ++copy) {
      for (int k = 0; k < 4; ++k) {
        for (int j = 0; j < 4; ++j) {
          for (int i = 0; i < 4; ++i) m.points.push_back({double(i), double(j), double(k)});
        }
      }
    }
    const Index pool = seed % 2 ? 127 : 40;  // all points, or a few: more shared ids
    std::uniform_int_distribution<Index> id(0, pool);
    for (int n = 0; n < 150; ++n) m.polys.add({id(rng), id(rng), id(rng)});
    const std::size_t ours = self_intersections(m).size();
    EXPECT_GT(ours, 100u) << seed;
    EXPECT_EQ(ours, cgal_count(m)) << "seed " << seed;
  }
}

TEST(self_intersections_vs_cgal, FlatGridWithCoplanarFolds) {
  // A flat grid with points moved in the plane by up to 1.5 cells: triangles flip and overlap
  // their neighbours — every contact is coplanar, the hardest case for the predicates.
  for (unsigned seed = 1; seed <= 4; ++seed) {
    PolyData m = grid(24, [](double, double) { return 0.0; });
    perturb(m, 0.15, 1.5 / 24, {true, true, false}, seed);
    const std::size_t ours = self_intersections(m).size();
    EXPECT_GT(ours, 10u) << seed;
    EXPECT_EQ(ours, cgal_count(m)) << "seed " << seed;
  }
  // A tilted plane (z = x/2 + y/4: exact in float for these coordinates only before the
  // perturbation; after it the points leave the plane by rounding — near-coplanar folds).
  for (unsigned seed = 1; seed <= 3; ++seed) {
    PolyData m = grid(24, [](double x, double y) { return 0.5 * x + 0.25 * y; });
    perturb(m, 0.15, 1.5 / 24, {true, true, false}, seed + 10);
    for (std::size_t i = 0; i < m.points.size(); ++i) {
      Vec3 p = m.points[i];
      p.z = 0.5 * p.x + 0.25 * p.y;
      m.points.set(i, p);
    }
    EXPECT_EQ(self_intersections(m).size(), cgal_count(m)) << "tilted seed " << seed;
  }
}

TEST(self_intersections_vs_cgal, WavyGridWithFolds) {
  for (unsigned seed = 1; seed <= 4; ++seed) {
    PolyData m =
        grid(30, [](double x, double y) { return 0.1 * std::sin(6 * x) * std::cos(5 * y); });
    perturb(m, 0.1, 2.0 / 30, {true, true, true}, seed + 20);
    const std::size_t ours = self_intersections(m).size();
    EXPECT_GT(ours, 10u) << seed;
    EXPECT_EQ(ours, cgal_count(m)) << "seed " << seed;
  }
}

// ---------------------------------------------------------------------------------------------
// The predicates themselves against CGAL's exact ones, on inputs where rounding decides.

namespace {

// Four points near one plane: kind 0 on a random plane, rounded to float (as stored data), then
// moved by 0–2 ulps per coordinate; kind 1 the same near a line; kind 2 far from the origin;
// kind 3 on the plane x + y + z = 1024 exactly (x, y multiples of 2^-10) with z moved by at
// most one ulp, so that many quadruples are exactly coplanar.
std::array<Vec3, 4> near_degenerate(std::mt19937& rng, int kind) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> ulps(-2, 2);
  std::array<Vec3, 4> p;
  if (kind == 3) {
    std::uniform_int_distribution<int> k(0, 1 << 19);
    for (auto& q : p) {
      const double x = std::ldexp(k(rng), -10), y = std::ldexp(k(rng), -10);
      q = {x, y, 1024 - x - y};
      const int i = ulps(rng);
      if (i == 1 || i == -1) q.z = std::nextafter(q.z, i > 0 ? 1e300 : -1e300);
    }
    return p;
  }
  const Vec3 o{u(rng), u(rng), u(rng)}, e1{u(rng), u(rng), u(rng)}, e2{u(rng), u(rng), u(rng)};
  const double offset = kind == 2 ? 1e6 : 0;
  for (auto& q : p) {
    const double s = u(rng), t = kind == 1 ? 0 : u(rng);
    q = o + e1 * s + e2 * t + Vec3{offset, offset, offset};
    q = {float(q.x), float(q.y), float(q.z)};
    for (int k = 0; k < 3; ++k) {
      for (int i = ulps(rng); i != 0; i += i > 0 ? -1 : 1) {
        q[k] = std::nextafter(q[k], i > 0 ? 1e300 : -1e300);
      }
    }
  }
  return p;
}

}  // namespace

TEST(predicates_vs_cgal, Orient3dOnNearDegenerateInputs) {
  std::mt19937 rng(17);
  std::size_t zeros = 0;
  for (int n = 0; n < 300000; ++n) {
    const auto p = near_degenerate(rng, n % 4);
    const int expected = verify::exact_orientation(p[0], p[1], p[2], p[3]);
    ASSERT_EQ(orient3d(p[0], p[1], p[2], p[3]), expected) << n;
    zeros += expected == 0;
  }
  EXPECT_GT(zeros, 5000u);
}

TEST(predicates_vs_cgal, TrianglesIntersectOnNearDegenerateInputs) {
  std::mt19937 rng(19);
  std::size_t hits = 0, tested = 0;
  for (int n = 0; n < 100000; ++n) {
    // Two triangles from points near one plane: coplanar and nearly coplanar contacts.
    const int kind = n % 2 == 0 ? 0 : 3;
    const auto a = near_degenerate(rng, kind), b = near_degenerate(rng, kind);
    std::array<Vec3, 3> p{a[0], a[1], a[2]}, q{a[3], b[0], b[1]};
    if (n % 2 == 1) q = {b[0], b[1], b[2]};
    // CGAL's test needs non-degenerate triangles.
    if (triangle_degenerate(q[0], q[1], q[2]) || triangle_degenerate(p[0], p[1], p[2])) continue;
    ++tested;
    const bool expected = verify::exact_triangles_intersect(p, q);
    ASSERT_EQ(triangles_intersect(p, q), expected) << n;
    hits += expected;
  }
  EXPECT_GT(tested, 90000u);
  EXPECT_GT(hits, 3000u);
}
