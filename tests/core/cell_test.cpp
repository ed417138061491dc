// Tests of the cell machinery (core/cell.hpp): shape functions, derivatives, world <->
// parametric mapping, world-space derivatives, polygons, composite cells and tables.

#include "isoforge/core/cell.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "isoforge/core/error.hpp"

using namespace isoforge;

namespace {

const std::vector<CellType> kFixedTypes = {
    CellType::Vertex, CellType::Line,  CellType::Triangle,   CellType::Pixel, CellType::Quad,
    CellType::Tetra,  CellType::Voxel, CellType::Hexahedron, CellType::Wedge, CellType::Pyramid};

std::string name(CellType t) {
  return std::string(cell_type_name(t));
}

// A 3x3 matrix + translation.
struct Affine {
  std::array<Vec3, 3> rows;
  Vec3 b;
  [[nodiscard]] Vec3 operator()(const Vec3& p) const {
    return Vec3{dot(rows[0], p), dot(rows[1], p), dot(rows[2], p)} + b;
  }
};

double det3(const Affine& a) {
  return dot(a.rows[0], cross(a.rows[1], a.rows[2]));
}

// A random, well-conditioned affine map with positive determinant.
Affine random_affine(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-0.35, 0.35), sc(0.5, 2.0), tr(-10, 10);
  for (;;) {
    Affine a;
    const double s = sc(rng);
    a.rows[0] = Vec3{1 + u(rng), u(rng), u(rng)} * s;
    a.rows[1] = Vec3{u(rng), 1 + u(rng), u(rng)} * s;
    a.rows[2] = Vec3{u(rng), u(rng), 1 + u(rng)} * s;
    a.b = {tr(rng), tr(rng), tr(rng)};
    if (det3(a) > 0.3 * s * s * s) return a;
  }
}

std::vector<Vec3> reference_points(CellType t) {
  const auto p = parametric_points(t);
  return {p.begin(), p.end()};
}

std::vector<Vec3> transformed(const std::vector<Vec3>& pts, const Affine& a) {
  std::vector<Vec3> out;
  for (const Vec3& p : pts) out.push_back(a(p));
  return out;
}

// Moves every point randomly by up to `amount` per coordinate (curves the faces).
std::vector<Vec3> perturbed(std::vector<Vec3> pts, double amount, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-amount, amount);
  for (Vec3& p : pts) p += Vec3{u(rng), u(rng), u(rng)};
  return pts;
}

// A random parametric point inside the domain of `t` (pyramid: t <= tmax).
Vec3 random_pcoords(CellType t, std::mt19937& rng, double tmax = 1.0) {
  std::uniform_real_distribution<double> u(0, 1);
  const int dim = cell_dimension(t);
  for (;;) {
    Vec3 p{u(rng), dim >= 2 ? u(rng) : 0.0, dim >= 3 ? u(rng) : 0.0};
    if (t == CellType::Pyramid && p.z > tmax) continue;
    if (parametric_distance(t, p) == 0) return p;
  }
}

double rel_err(double a, double b) {
  return std::abs(a - b) / std::max(1.0, std::abs(b));
}

// Brute-force closest point on a tetra: project onto the affine hull of every subset of its
// vertices, keep projections with non-negative barycentric coordinates (independent of the
// library's face-based search).
double tetra_dist2_bruteforce(const std::array<Vec3, 4>& v, const Vec3& x) {
  double best = std::numeric_limits<double>::infinity();
  for (int mask = 1; mask < 16; ++mask) {
    std::vector<Vec3> s;
    for (int i = 0; i < 4; ++i) {
      if (mask & (1 << i)) s.push_back(v[i]);
    }
    const std::size_t k = s.size() - 1;
    // Gram system G lambda = b for x ~ s0 + sum lambda_j (s_j - s0), solved by elimination.
    std::vector<std::vector<double>> g(k, std::vector<double>(k + 1));
    for (std::size_t i = 0; i < k; ++i) {
      for (std::size_t j = 0; j < k; ++j) g[i][j] = dot(s[i + 1] - s[0], s[j + 1] - s[0]);
      g[i][k] = dot(x - s[0], s[i + 1] - s[0]);
    }
    bool ok = true;
    for (std::size_t c = 0; c < k && ok; ++c) {
      std::size_t piv = c;
      for (std::size_t r = c + 1; r < k; ++r) {
        if (std::abs(g[r][c]) > std::abs(g[piv][c])) piv = r;
      }
      if (std::abs(g[piv][c]) < 1e-14) ok = false;
      if (!ok) break;
      std::swap(g[c], g[piv]);
      for (std::size_t r = 0; r < k; ++r) {
        if (r == c) continue;
        const double f = g[r][c] / g[c][c];
        for (std::size_t cc = c; cc <= k; ++cc) g[r][cc] -= f * g[c][cc];
      }
    }
    if (!ok) continue;
    Vec3 p = s[0];
    double sum = 0;
    bool inside = true;
    for (std::size_t i = 0; i < k; ++i) {
      const double l = g[i][k] / g[i][i];
      if (l < -1e-12) inside = false;
      sum += l;
      p += l * (s[i + 1] - s[0]);
    }
    if (sum > 1 + 1e-12) inside = false;
    if (inside) best = std::min(best, norm2(x - p));
  }
  return best;
}

double tets_dist2(const std::vector<Vec3>& p, const std::vector<std::array<int, 4>>& tets,
                  const Vec3& x) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : tets) {
    best = std::min(best, tetra_dist2_bruteforce({p[t[0]], p[t[1]], p[t[2]], p[t[3]]}, x));
  }
  return best;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Shape functions
// ---------------------------------------------------------------------------------------------

TEST(CellShape, PartitionOfUnityAndKroneckerDelta) {
  std::mt19937 rng(1);
  for (CellType t : kFixedTypes) {
    SCOPED_TRACE(name(t));
    const auto pc = parametric_points(t);
    ASSERT_EQ(pc.size(), static_cast<std::size_t>(cell_fixed_size(t)));
    for (int k = 0; k < 50; ++k) {
      const CellWeights w = interpolation_weights(t, random_pcoords(t, rng));
      double sum = 0;
      for (double v : w) sum += v;
      EXPECT_NEAR(sum, 1.0, 1e-14);
    }
    for (std::size_t j = 0; j < pc.size(); ++j) {
      const CellWeights w = interpolation_weights(t, pc[j]);
      for (std::size_t i = 0; i < pc.size(); ++i) {
        EXPECT_NEAR(w[i], i == j ? 1.0 : 0.0, 1e-15) << "point " << j << " weight " << i;
      }
    }
  }
}

TEST(CellShape, DerivativesMatchFiniteDifferences) {
  std::mt19937 rng(2);
  const double h = 1e-6;
  for (CellType t : kFixedTypes) {
    SCOPED_TRACE(name(t));
    const std::size_t n = static_cast<std::size_t>(cell_fixed_size(t));
    std::vector<double> d(3 * n), wp(n), wm(n);
    for (int k = 0; k < 20; ++k) {
      const Vec3 p = random_pcoords(t, rng, 0.95);
      interpolation_derivatives(t, p, d);
      for (int dir = 0; dir < 3; ++dir) {
        Vec3 pp = p, pm = p;
        pp[dir] += h;
        pm[dir] -= h;
        interpolation_weights(t, pp, wp);
        interpolation_weights(t, pm, wm);
        for (std::size_t i = 0; i < n; ++i) {
          const double fd = dir < cell_dimension(t) ? (wp[i] - wm[i]) / (2 * h) : 0.0;
          EXPECT_NEAR(d[dir * n + i], fd, 1e-8) << "dir " << dir << " point " << i;
        }
      }
    }
  }
}

TEST(CellShape, ParametricCenterMapsToCentroidOfAffineCells) {
  std::mt19937 rng(3);
  for (CellType t : kFixedTypes) {
    SCOPED_TRACE(name(t));
    const auto pts = transformed(reference_points(t), random_affine(rng));
    Vec3 c{};
    for (const Vec3& p : pts) c += p;
    c = c / static_cast<double>(pts.size());
    const Vec3 x = evaluate_location(t, pts, parametric_center(t));
    EXPECT_NEAR(norm(x - c), 0.0, 1e-12);
    EXPECT_EQ(parametric_distance(t, parametric_center(t)), 0.0);
  }
}

TEST(CellShape, ParametricDistance) {
  EXPECT_EQ(parametric_distance(CellType::Tetra, {0.2, 0.2, 0.2}), 0.0);
  EXPECT_NEAR(parametric_distance(CellType::Tetra, {0.5, 0.5, 0.5}), 0.5, 1e-15);
  EXPECT_NEAR(parametric_distance(CellType::Hexahedron, {-0.25, 0.5, 1.1}), 0.25, 1e-15);
  EXPECT_NEAR(parametric_distance(CellType::Wedge, {0.6, 0.6, 0.5}), 0.2, 1e-15);
  EXPECT_EQ(parametric_distance(CellType::Line, {0.5, 7, 7}), 0.0);  // unused coords ignored
  EXPECT_NEAR(parametric_distance(CellType::TriangleStrip, {-0.1, 0.2, 0}), 0.1, 1e-15);
}

// ---------------------------------------------------------------------------------------------
// Exactness on linear fields
// ---------------------------------------------------------------------------------------------

TEST(CellLinear, InterpolationReproducesLinearFieldsOnDistortedSimplices) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-3, 3);
  for (CellType t : {CellType::Line, CellType::Triangle, CellType::Tetra}) {
    SCOPED_TRACE(name(t));
    for (int trial = 0; trial < 20; ++trial) {
      const auto pts = transformed(reference_points(t), random_affine(rng));
      const Vec3 a{u(rng), u(rng), u(rng)};
      const double b = u(rng);
      auto f = [&](const Vec3& x) { return dot(a, x) + b; };
      for (int k = 0; k < 20; ++k) {
        std::uniform_real_distribution<double> q(0, 1);
        // Random pcoords, also outside the cell: simplices are affine, so exactness holds.
        const Vec3 pc{q(rng) * 1.5 - 0.25, cell_dimension(t) > 1 ? q(rng) : 0.0,
                      cell_dimension(t) > 2 ? q(rng) * 0.5 : 0.0};
        const CellWeights w = interpolation_weights(t, pc);
        double fi = 0;
        for (std::size_t i = 0; i < pts.size(); ++i) fi += w[i] * f(pts[i]);
        // Independent world point: the affine image of pc.
        Vec3 xw = pts[0];
        for (int d = 0; d < cell_dimension(t); ++d) xw += pc[d] * (pts[d + 1] - pts[0]);
        EXPECT_LE(rel_err(fi, f(xw)), 1e-12);
        EXPECT_LE(norm(evaluate_location(t, pts, pc) - xw), 1e-12 * (1 + norm(xw)));
      }
    }
  }
}

TEST(CellLinear, IsoparametricInterpolationReproducesLinearFieldsOnCurvedCells) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-3, 3);
  for (CellType t : kFixedTypes) {
    SCOPED_TRACE(name(t));
    const auto pts = perturbed(transformed(reference_points(t), random_affine(rng)), 0.1, rng);
    const Vec3 a{u(rng), u(rng), u(rng)};
    const double b = u(rng);
    for (int k = 0; k < 20; ++k) {
      const Vec3 pc = random_pcoords(t, rng);
      const CellWeights w = interpolation_weights(t, pc);
      double fi = 0;
      for (std::size_t i = 0; i < pts.size(); ++i) fi += w[i] * (dot(a, pts[i]) + b);
      EXPECT_LE(rel_err(fi, dot(a, evaluate_location(t, pts, pc)) + b), 1e-12);
    }
  }
}

// Expected world gradient of f = a.x on a cell: a itself for 3D cells, its tangential part for
// 2D cells, its component along the line for 1D cells.
Vec3 expected_gradient(CellType t, const std::vector<Vec3>& pts, const Vec3& pc, const Vec3& a) {
  const int dim = cell_dimension(t);
  if (dim == 3) return a;
  const std::size_t n = pts.size();
  std::vector<double> d(3 * n);
  interpolation_derivatives(t, pc, d);
  Vec3 c0{}, c1{};
  for (std::size_t i = 0; i < n; ++i) {
    c0 += d[i] * pts[i];
    c1 += d[n + i] * pts[i];
  }
  if (dim == 1) return c0 * (dot(a, c0) / norm2(c0));
  Vec3 nn = cross(c0, c1);
  nn = nn / norm(nn);
  return a - dot(a, nn) * nn;
}

TEST(CellLinear, DerivativesOfLinearFieldsAreExact) {
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> u(-3, 3);
  for (CellType t : kFixedTypes) {
    if (t == CellType::Vertex) continue;
    SCOPED_TRACE(name(t));
    for (int trial = 0; trial < 10; ++trial) {
      // Simplices: any affine image. Others: parallelepiped shapes (affine images).
      const auto pts = transformed(reference_points(t), random_affine(rng));
      const Vec3 a{u(rng), u(rng), u(rng)};
      const double b = u(rng);
      std::vector<double> values;
      for (const Vec3& p : pts) values.push_back(dot(a, p) + b);
      for (int k = 0; k < 10; ++k) {
        const Vec3 pc = random_pcoords(t, rng);
        const auto g = derivatives(t, pts, pc, values, 1);
        ASSERT_EQ(g.size(), 1u);
        const Vec3 e = expected_gradient(t, pts, pc, a);
        EXPECT_LE(norm(g[0] - e), 1e-12 * (1 + norm(a)))
            << "pc " << pc.x << " " << pc.y << " " << pc.z;
      }
    }
  }
}

TEST(CellLinear, DerivativesOfLinearFieldsOnCurvedCellsAndMultipleComponents) {
  // The isoparametric map makes a linear field's gradient exact on any non-degenerate cell.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-3, 3);
  for (CellType t : {CellType::Hexahedron, CellType::Wedge, CellType::Pyramid, CellType::Quad}) {
    SCOPED_TRACE(name(t));
    const auto pts = perturbed(transformed(reference_points(t), random_affine(rng)), 0.1, rng);
    const Vec3 a0{u(rng), u(rng), u(rng)}, a1{u(rng), u(rng), u(rng)};
    std::vector<double> values;
    for (const Vec3& p : pts) {
      values.push_back(dot(a0, p) + 1);
      values.push_back(dot(a1, p) - 2);
    }
    for (int k = 0; k < 10; ++k) {
      const Vec3 pc = random_pcoords(t, rng, 0.9);
      const auto g = derivatives(t, pts, pc, values, 2);
      EXPECT_LE(norm(g[0] - expected_gradient(t, pts, pc, a0)), 1e-10);
      EXPECT_LE(norm(g[1] - expected_gradient(t, pts, pc, a1)), 1e-10);
    }
  }
}

TEST(CellLinear, PyramidApexAndVoxelDerivatives) {
  const Vec3 a{1.5, -2, 0.25};
  std::mt19937 rng(8);
  const auto pyr = transformed(reference_points(CellType::Pyramid), random_affine(rng));
  std::vector<double> values;
  for (const Vec3& p : pyr) values.push_back(dot(a, p));
  const auto g = derivatives(CellType::Pyramid, pyr, {0.5, 0.5, 1.0}, values, 1);
  EXPECT_LE(norm(g[0] - a), 1e-8);

  // An image-data voxel with anisotropic spacing.
  std::vector<Vec3> vox;
  for (const Vec3& p : parametric_points(CellType::Voxel)) {
    vox.push_back(Vec3{2 + 0.5 * p.x, -1 + 2 * p.y, 3 + 0.1 * p.z});
  }
  values.clear();
  for (const Vec3& p : vox) values.push_back(dot(a, p) + 4);
  const auto gv = derivatives(CellType::Voxel, vox, {0.3, 0.6, 0.9}, values, 1);
  EXPECT_LE(norm(gv[0] - a), 1e-12);
}

// ---------------------------------------------------------------------------------------------
// locate_in_cell
// ---------------------------------------------------------------------------------------------

TEST(CellLocate, RoundTripOnCurvedCells) {
  std::mt19937 rng(9);
  for (CellType t : {CellType::Hexahedron, CellType::Wedge, CellType::Pyramid, CellType::Quad,
                     CellType::Tetra, CellType::Triangle, CellType::Line}) {
    SCOPED_TRACE(name(t));
    for (int trial = 0; trial < 20; ++trial) {
      auto pts = transformed(reference_points(t), random_affine(rng));
      if (cell_dimension(t) > 1 && t != CellType::Tetra && t != CellType::Triangle) {
        pts = perturbed(pts, 0.12, rng);
      }
      for (int k = 0; k < 20; ++k) {
        const Vec3 pc = random_pcoords(t, rng, 0.9);
        const Vec3 x = evaluate_location(t, pts, pc);
        const CellPosition pos = locate_in_cell(t, pts, x);
        EXPECT_TRUE(pos.converged);
        EXPECT_TRUE(pos.inside);
        EXPECT_LE(norm(pos.pcoords - pc), 1e-9);
        EXPECT_LE(pos.dist2, 1e-20);
        EXPECT_LE(norm(pos.closest_point - x), 1e-9);
        const CellWeights w = interpolation_weights(t, pc);
        ASSERT_EQ(pos.weights.size(), w.size());
        for (std::size_t i = 0; i < w.size(); ++i) EXPECT_NEAR(pos.weights[i], w[i], 1e-9);
      }
    }
  }
}

TEST(CellLocate, NonPlanarQuadProjectsAlongTheNormal) {
  // A saddle quad: the orthogonal projection of X(pc) + h n(pc) is X(pc) for small h.
  const std::vector<Vec3> q = {{0, 0, 0.2}, {1.1, 0, -0.2}, {1, 0.9, 0.25}, {-0.1, 1, -0.15}};
  std::mt19937 rng(10);
  for (int k = 0; k < 50; ++k) {
    const Vec3 pc = random_pcoords(CellType::Quad, rng);
    const Vec3 x0 = evaluate_location(CellType::Quad, q, pc);
    std::vector<double> d(12);
    interpolation_derivatives(CellType::Quad, pc, d);
    Vec3 c0{}, c1{};
    for (int i = 0; i < 4; ++i) {
      c0 += d[i] * q[i];
      c1 += d[4 + i] * q[i];
    }
    Vec3 n = cross(c0, c1);
    n = n / norm(n);
    const double h = k % 2 ? 0.01 : -0.02;
    const CellPosition pos = locate_in_cell(CellType::Quad, q, x0 + h * n);
    EXPECT_TRUE(pos.inside);
    EXPECT_LE(norm(pos.pcoords - pc), 1e-9);
    EXPECT_NEAR(pos.dist2, h * h, 1e-12);
    EXPECT_LE(norm(pos.closest_point - x0), 1e-9);
  }
}

TEST(CellLocate, PixelAndVoxelClosedForm) {
  std::vector<Vec3> vox;
  for (const Vec3& p : parametric_points(CellType::Voxel)) {
    vox.push_back(Vec3{1 + 2 * p.x, 2 + 0.5 * p.y, -1 + p.z});
  }
  auto pos = locate_in_cell(CellType::Voxel, vox, {2, 2.25, -0.75});
  EXPECT_TRUE(pos.inside);
  EXPECT_LE(norm(pos.pcoords - Vec3{0.5, 0.5, 0.25}), 1e-15);
  EXPECT_EQ(pos.dist2, 0.0);
  pos = locate_in_cell(CellType::Voxel, vox, {4, 2.25, -0.75});  // 1 beyond x = 3
  EXPECT_FALSE(pos.inside);
  EXPECT_NEAR(pos.dist2, 1.0, 1e-15);
  EXPECT_NEAR(pos.pcoords.x, 1.5, 1e-15);

  // A pixel in the xz plane at y = 5.
  const std::vector<Vec3> pix = {{0, 5, 0}, {2, 5, 0}, {0, 5, 1}, {2, 5, 1}};
  pos = locate_in_cell(CellType::Pixel, pix, {0.5, 7, 0.5});
  EXPECT_TRUE(pos.inside);
  EXPECT_LE(norm(pos.pcoords - Vec3{0.25, 0.5, 0}), 1e-15);
  EXPECT_NEAR(pos.dist2, 4.0, 1e-15);
  EXPECT_LE(norm(pos.closest_point - Vec3{0.5, 5, 0.5}), 1e-15);
  pos = locate_in_cell(CellType::Pixel, pix, {3, 6, 2});
  EXPECT_FALSE(pos.inside);
  EXPECT_NEAR(pos.dist2, 3.0, 1e-14);
}

TEST(CellLocate, OutsideDistanceToUnitCube) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-2, 3);
  std::vector<Vec3> voxel;
  for (const Vec3& p : parametric_points(CellType::Voxel)) voxel.push_back(p);
  const auto hex = reference_points(CellType::Hexahedron);
  for (int k = 0; k < 300; ++k) {
    const Vec3 x{u(rng), u(rng), u(rng)};
    const Vec3 c{std::clamp(x.x, 0.0, 1.0), std::clamp(x.y, 0.0, 1.0), std::clamp(x.z, 0.0, 1.0)};
    const double expect = norm2(x - c);
    const bool in = expect == 0;
    for (CellType t : {CellType::Hexahedron, CellType::Voxel}) {
      SCOPED_TRACE(name(t));
      const CellPosition pos = locate_in_cell(t, t == CellType::Voxel ? voxel : hex, x);
      EXPECT_EQ(pos.inside, in);
      EXPECT_NEAR(pos.dist2, expect, 1e-12 * (1 + expect));
      EXPECT_LE(norm(pos.closest_point - (in ? x : c)), 1e-9);
      EXPECT_LE(norm(pos.pcoords - x), 1e-9);  // unit cube: pcoords = x, unclamped
    }
  }
}

TEST(CellLocate, OutsideDistanceToTetraWedgePyramidMatchesBruteForce) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(-1.5, 2.5);
  // Tetra: the unit tetra and distorted ones.
  for (int trial = 0; trial < 5; ++trial) {
    const auto tet = trial == 0
                         ? reference_points(CellType::Tetra)
                         : transformed(reference_points(CellType::Tetra), random_affine(rng));
    for (int k = 0; k < 200; ++k) {
      Vec3 x{u(rng), u(rng), u(rng)};
      if (trial > 0) x = tet[0] + 2.0 * x;
      const double expect = tetra_dist2_bruteforce({tet[0], tet[1], tet[2], tet[3]}, x);
      const CellPosition pos = locate_in_cell(CellType::Tetra, tet, x);
      EXPECT_EQ(pos.inside, expect <= 1e-20) << expect;
      EXPECT_NEAR(pos.dist2, expect, 1e-11 * (1 + expect));
    }
  }
  // Planar-faced wedge and pyramid (affine images), against their tetra decompositions.
  // The wedge is mirrored so that it is valid by VTK's convention.
  const std::vector<std::array<int, 4>> wedge_tets = {{0, 1, 2, 3}, {1, 2, 3, 4}, {2, 3, 4, 5}};
  const std::vector<std::array<int, 4>> pyr_tets = {{0, 1, 2, 4}, {0, 2, 3, 4}};
  for (int trial = 0; trial < 5; ++trial) {
    const Affine a = random_affine(rng);
    auto wedge = transformed(reference_points(CellType::Wedge), a);
    const auto pyr = transformed(reference_points(CellType::Pyramid), a);
    for (int k = 0; k < 200; ++k) {
      const Vec3 x = a(Vec3{u(rng), u(rng), u(rng)});
      double expect = tets_dist2(wedge, wedge_tets, x);
      CellPosition pos = locate_in_cell(CellType::Wedge, wedge, x);
      EXPECT_EQ(pos.inside, expect <= 1e-20) << expect;
      EXPECT_NEAR(pos.dist2, expect, 1e-10 * (1 + expect));
      expect = tets_dist2(pyr, pyr_tets, x);
      pos = locate_in_cell(CellType::Pyramid, pyr, x);
      EXPECT_EQ(pos.inside, expect <= 1e-20) << expect;
      EXPECT_NEAR(pos.dist2, expect, 1e-10 * (1 + expect));
    }
  }
}

TEST(CellLocate, OutsideDistanceToCurvedCellsIsTheMinimumOverTheirBoundary) {
  std::mt19937 rng(13);
  for (CellType t : {CellType::Hexahedron, CellType::Wedge, CellType::Pyramid}) {
    SCOPED_TRACE(name(t));
    for (int trial = 0; trial < 3; ++trial) {
      const auto cell = perturbed(transformed(reference_points(t), random_affine(rng)), 0.15, rng);
      // Dense samples of the boundary (bilinear quads and flat triangles).
      std::vector<Vec3> samples;
      const int m = 100;
      for (const CellFace& f : cell_faces(t)) {
        std::vector<Vec3> q;
        for (int id : f.points()) q.push_back(cell[id]);
        const CellType ft = f.size == 4 ? CellType::Quad : CellType::Triangle;
        for (int i = 0; i <= m; ++i) {
          for (int j = 0; j <= m; ++j) {
            if (ft == CellType::Triangle && i + j > m) continue;
            samples.push_back(evaluate_location(ft, q, {double(i) / m, double(j) / m, 0}));
          }
        }
      }
      std::uniform_real_distribution<double> u(-1.5, 1.5);
      Vec3 c{};
      for (const Vec3& p : cell) c += p / static_cast<double>(cell.size());
      int outside = 0;
      for (int k = 0; k < 40; ++k) {
        const Vec3 x = c + Vec3{u(rng), u(rng), u(rng)} * 2.0;
        const CellPosition pos = locate_in_cell(t, cell, x);
        if (pos.inside) continue;
        ++outside;
        double sampled = std::numeric_limits<double>::infinity();
        for (const Vec3& s : samples) sampled = std::min(sampled, norm(x - s));
        const double d = std::sqrt(pos.dist2);
        EXPECT_LE(d, sampled + 1e-9);  // never worse than any boundary sample
        EXPECT_GE(d, sampled - 0.03);  // and within the sampling resolution
        EXPECT_NEAR(norm(x - pos.closest_point), d, 1e-12);
      }
      EXPECT_GT(outside, 20);
    }
  }
}

TEST(CellLocate, PyramidApex) {
  std::mt19937 rng(16);
  const auto pyr =
      perturbed(transformed(reference_points(CellType::Pyramid), random_affine(rng)), 0.1, rng);
  for (double t : {0.99, 0.999999, 1.0}) {
    const Vec3 x = evaluate_location(CellType::Pyramid, pyr, {0.3, 0.6, t});
    const CellPosition pos = locate_in_cell(CellType::Pyramid, pyr, x);
    EXPECT_TRUE(pos.inside) << t;
    EXPECT_EQ(pos.dist2, 0.0);
    EXPECT_NEAR(pos.pcoords.z, t, 1e-6);
    EXPECT_LE(norm(evaluate_location(CellType::Pyramid, pyr, pos.pcoords) - x), 1e-9);
    EXPECT_NEAR(pos.weights[4], t, 1e-6);
  }
}

TEST(CellLocate, ToleranceWidensInside) {
  const auto tet = reference_points(CellType::Tetra);
  const Vec3 x{-1e-4, 0.2, 0.2};
  EXPECT_FALSE(locate_in_cell(CellType::Tetra, tet, x).inside);
  const CellPosition pos = locate_in_cell(CellType::Tetra, tet, x, 1e-3);
  EXPECT_TRUE(pos.inside);
  EXPECT_EQ(pos.dist2, 0.0);
  EXPECT_NEAR(pos.pcoords.x, -1e-4, 1e-15);
}

TEST(CellLocate, DegenerateCellsReturnQuickly) {
  const Vec3 x{0.3, 0.4, 0.5};
  auto timed = [&](CellType t, const std::vector<Vec3>& pts) {
    const auto start = std::chrono::steady_clock::now();
    const CellPosition pos = locate_in_cell(t, pts, x);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    EXPECT_LT(ms, 50.0) << name(t);
    EXPECT_TRUE(std::isfinite(pos.dist2)) << name(t);
    EXPECT_TRUE(is_finite(pos.pcoords)) << name(t);
    EXPECT_TRUE(is_finite(pos.closest_point)) << name(t);
    for (double w : pos.weights) EXPECT_TRUE(std::isfinite(w)) << name(t);
    return pos;
  };
  // Everything collapsed to one point.
  for (CellType t : kFixedTypes) {
    if (t == CellType::Vertex) continue;
    const std::vector<Vec3> pts(static_cast<std::size_t>(cell_fixed_size(t)), Vec3{1, 1, 1});
    const CellPosition pos = timed(t, pts);
    EXPECT_FALSE(pos.inside) << name(t);
    EXPECT_FALSE(pos.converged) << name(t);
    EXPECT_NEAR(pos.dist2, norm2(x - Vec3{1, 1, 1}), 1e-12) << name(t);
  }
  // Flattened 3D cells (all z = 0.5, x lies on them): distance 0, never inside.
  for (CellType t : {CellType::Hexahedron, CellType::Wedge, CellType::Pyramid, CellType::Tetra,
                     CellType::Voxel}) {
    auto pts = reference_points(t);
    for (Vec3& p : pts) p.z = 0.5;
    const CellPosition pos = timed(t, pts);
    EXPECT_FALSE(pos.converged) << name(t);
    EXPECT_NEAR(pos.dist2, 0.0, 1e-20) << name(t);
  }
  // Collinear 2D cells.
  const std::vector<Vec3> line_tri = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  EXPECT_NEAR(timed(CellType::Triangle, line_tri).dist2, 0.16 + 0.25, 1e-12);
  const std::vector<Vec3> line_quad = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  EXPECT_NEAR(timed(CellType::Quad, line_quad).dist2, 0.16 + 0.25, 1e-12);
  const std::vector<Vec3> line_poly = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  EXPECT_NEAR(timed(CellType::Polygon, line_poly).dist2, 0.16 + 0.25, 1e-12);
  // A "bow-tie" hexahedron (top face twisted by 180 degrees): inverted, must still return.
  std::vector<Vec3> twisted = reference_points(CellType::Hexahedron);
  std::swap(twisted[4], twisted[6]);
  std::swap(twisted[5], twisted[7]);
  timed(CellType::Hexahedron, twisted);
  // Degenerate cells give zero gradients instead of garbage.
  const std::vector<Vec3> flat_hex(8, Vec3{0, 0, 0});
  const std::vector<double> vals = {0, 1, 2, 3, 4, 5, 6, 7};
  const auto g = derivatives(CellType::Hexahedron, flat_hex, {0.5, 0.5, 0.5}, vals, 1);
  EXPECT_EQ(g[0], (Vec3{0, 0, 0}));
}

TEST(CellLocate, VertexAndLineIn3D) {
  const std::vector<Vec3> v = {{1, 2, 3}};
  EXPECT_TRUE(locate_in_cell(CellType::Vertex, v, {1, 2, 3}).inside);
  const CellPosition pv = locate_in_cell(CellType::Vertex, v, {1, 2, 5});
  EXPECT_FALSE(pv.inside);
  EXPECT_EQ(pv.dist2, 4.0);
  const std::vector<Vec3> l = {{0, 0, 0}, {2, 0, 0}};
  CellPosition pos = locate_in_cell(CellType::Line, l, {0.5, 3, 4});
  EXPECT_TRUE(pos.inside);
  EXPECT_NEAR(pos.pcoords.x, 0.25, 1e-15);
  EXPECT_NEAR(pos.dist2, 25.0, 1e-12);
  pos = locate_in_cell(CellType::Line, l, {5, 0, 4});
  EXPECT_FALSE(pos.inside);
  EXPECT_NEAR(pos.pcoords.x, 2.5, 1e-15);
  EXPECT_NEAR(pos.dist2, 9.0 + 16.0, 1e-12);
  EXPECT_EQ(pos.closest_point, (Vec3{2, 0, 0}));
}

TEST(CellLocate, TriangleOutsideDistanceIsToTheClosestEdge) {
  const std::vector<Vec3> tri = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  CellPosition pos = locate_in_cell(CellType::Triangle, tri, {0.25, 0.25, 2});
  EXPECT_TRUE(pos.inside);
  EXPECT_NEAR(pos.dist2, 4.0, 1e-15);
  pos = locate_in_cell(CellType::Triangle, tri, {1, 1, 1});
  EXPECT_FALSE(pos.inside);
  EXPECT_NEAR(pos.dist2, 0.5 + 1.0, 1e-14);  // to (0.5, 0.5, 0)
  EXPECT_LE(norm(pos.closest_point - Vec3{0.5, 0.5, 0}), 1e-15);
  pos = locate_in_cell(CellType::Triangle, tri, {-1, -2, 0});
  EXPECT_NEAR(pos.dist2, 5.0, 1e-14);  // to vertex 0
}

// ---------------------------------------------------------------------------------------------
// Polygon
// ---------------------------------------------------------------------------------------------

namespace {

// An L-shaped (non-convex) hexagon in the plane z = 0, then rotated and translated.
std::vector<Vec3> l_polygon_2d() {
  return {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
}
Affine rigid() {
  const double c = std::cos(0.7), s = std::sin(0.7);
  Affine a;
  // Rotation about x by 0.7 then about z by 0.7.
  const std::array<Vec3, 3> rx = {Vec3{1, 0, 0}, Vec3{0, c, -s}, Vec3{0, s, c}};
  const std::array<Vec3, 3> rz = {Vec3{c, -s, 0}, Vec3{s, c, 0}, Vec3{0, 0, 1}};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      a.rows[i][j] = rz[i][0] * rx[0][j] + rz[i][1] * rx[1][j] + rz[i][2] * rx[2][j];
    }
  }
  a.b = {3, -1, 2};
  return a;
}

}  // namespace

TEST(CellPolygon, MeanValueCoordinatesOnANonConvexPolygon) {
  const Affine a = rigid();
  const auto poly = transformed(l_polygon_2d(), a);
  const Vec3 n = cross(a(Vec3{1, 0, 0}) - a.b, a(Vec3{0, 1, 0}) - a.b);  // unit normal
  const Vec3 grad{0.3, -1.2, 2.0};
  std::mt19937 rng(14);
  std::uniform_real_distribution<double> u(0, 2);
  int inside = 0;
  for (int k = 0; k < 300; ++k) {
    const Vec3 p2{u(rng), u(rng), 0};
    const bool in = !(p2.x > 1 && p2.y > 1);
    const double h = k % 3 == 0 ? 0.5 : 0.0;
    const Vec3 x = a(p2) + h * n;
    const CellPosition pos = locate_in_cell(CellType::Polygon, poly, x);
    EXPECT_EQ(pos.inside, in);
    ASSERT_EQ(pos.weights.size(), poly.size());
    double sum = 0;
    Vec3 rep{};
    double f = 0;
    for (std::size_t i = 0; i < poly.size(); ++i) {
      sum += pos.weights[i];
      rep += pos.weights[i] * poly[i];
      f += pos.weights[i] * dot(grad, poly[i]);
    }
    EXPECT_NEAR(sum, 1.0, 1e-12);
    EXPECT_LE(norm(rep - a(p2)), 1e-10);  // linear precision
    EXPECT_NEAR(f, dot(grad, a(p2)), 1e-10);
    if (in) {
      ++inside;
      for (double w : pos.weights) EXPECT_GT(w, -1e-12 - (in ? 1.0 : 0.0));
      EXPECT_NEAR(pos.dist2, h * h, 1e-12);
      EXPECT_LE(norm(evaluate_location(CellType::Polygon, poly, pos.pcoords) - a(p2)), 1e-10);
      CellWeights w2;
      evaluate_weights(CellType::Polygon, poly, pos.pcoords, 0, w2);
      for (std::size_t i = 0; i < poly.size(); ++i) EXPECT_NEAR(w2[i], pos.weights[i], 1e-10);
    } else {
      // In the notch [1,2]^2: the distance is to the corner (1,1) or an edge of the notch.
      const double dx = p2.x - 1, dy = p2.y - 1;
      const double in_plane = std::min(dx, dy);
      EXPECT_NEAR(pos.dist2, in_plane * in_plane + h * h, 1e-10);
    }
  }
  EXPECT_GT(inside, 150);
  // Kronecker delta at the vertices, linear along the edges.
  CellWeights w;
  polygon_weights(poly, poly[3], w);
  for (std::size_t i = 0; i < poly.size(); ++i) EXPECT_NEAR(w[i], i == 3 ? 1 : 0, 1e-12);
  polygon_weights(poly, 0.25 * poly[1] + 0.75 * poly[2], w);
  for (std::size_t i = 0; i < poly.size(); ++i) {
    EXPECT_NEAR(w[i], i == 1 ? 0.25 : i == 2 ? 0.75 : 0.0, 1e-12);
  }
  // Derivatives of a linear field: the tangential part, exactly.
  std::vector<double> values;
  for (const Vec3& p : poly) values.push_back(dot(grad, p) + 7);
  const auto g = derivatives(CellType::Polygon, poly, {0.3, 0.3, 0}, values, 1);
  EXPECT_LE(norm(g[0] - (grad - dot(grad, n) * n)), 1e-12);
}

TEST(CellPolygon, ConvexPolygonWeightsArePositive) {
  std::vector<Vec3> hexagon;
  for (int i = 0; i < 6; ++i) {
    const double t = i * std::numbers::pi / 3;
    hexagon.push_back({std::cos(t), std::sin(t), 1});
  }
  CellWeights w;
  polygon_weights(hexagon, {0.2, -0.3, 1}, w);
  for (double v : w) EXPECT_GT(v, 0);
  ASSERT_EQ(w.size(), 6u);
  // Many points: weights live on the heap.
  std::vector<Vec3> circle;
  for (int i = 0; i < 40; ++i) {
    const double t = 2 * std::numbers::pi * i / 40;
    circle.push_back({std::cos(t), std::sin(t), 0});
  }
  const CellPosition pos = locate_in_cell(CellType::Polygon, circle, {0.1, 0.2, 0});
  ASSERT_EQ(pos.weights.size(), 40u);
  Vec3 rep{};
  for (std::size_t i = 0; i < 40; ++i) rep += pos.weights[i] * circle[i];
  EXPECT_LE(norm(rep - Vec3{0.1, 0.2, 0}), 1e-12);
}

// ---------------------------------------------------------------------------------------------
// Composite cells
// ---------------------------------------------------------------------------------------------

TEST(CellComposite, PolyLine) {
  const std::vector<Vec3> pl = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {2, 1, 0}};
  EXPECT_EQ(num_sub_cells(CellType::PolyLine, pl.size()), 3);
  CellPosition pos = locate_in_cell(CellType::PolyLine, pl, {1.2, 0.4, 0});
  EXPECT_EQ(pos.sub_id, 1);
  EXPECT_TRUE(pos.inside);
  EXPECT_NEAR(pos.pcoords.x, 0.4, 1e-15);
  EXPECT_NEAR(pos.dist2, 0.04, 1e-15);
  EXPECT_NEAR(pos.weights[0], 0, 0);
  EXPECT_NEAR(pos.weights[1], 0.6, 1e-15);
  EXPECT_NEAR(pos.weights[2], 0.4, 1e-15);
  EXPECT_NEAR(pos.weights[3], 0, 0);
  EXPECT_LE(
      norm(evaluate_location(CellType::PolyLine, pl, pos.pcoords, pos.sub_id) - Vec3{1, 0.4, 0}),
      1e-15);
  pos = locate_in_cell(CellType::PolyLine, pl, {3, 1, 0});
  EXPECT_EQ(pos.sub_id, 2);
  EXPECT_FALSE(pos.inside);
  EXPECT_NEAR(pos.dist2, 1.0, 1e-15);
  // Gradient along the sub-line.
  const std::vector<double> vals = {0, 1, 3, 3};
  const auto g = derivatives(CellType::PolyLine, pl, {0.5, 0, 0}, vals, 1, 1);
  EXPECT_LE(norm(g[0] - Vec3{0, 2, 0}), 1e-15);
}

TEST(CellComposite, TriangleStrip) {
  // Points zig-zag: 0 (0,0) 1 (0,1) 2 (1,0) 3 (1,1) 4 (2,0) 5 (2,1), at z = 1.
  const std::vector<Vec3> st = {{0, 0, 1}, {0, 1, 1}, {1, 0, 1}, {1, 1, 1}, {2, 0, 1}, {2, 1, 1}};
  ASSERT_EQ(num_sub_cells(CellType::TriangleStrip, st.size()), 4);
  // Sub-triangles are consistently oriented.
  Vec3 n0{};
  for (int i = 0; i < 4; ++i) {
    const SubCell sc = sub_cell(CellType::TriangleStrip, st.size(), i);
    EXPECT_EQ(sc.type, CellType::Triangle);
    const Vec3 n = cross(st[sc.ids[1]] - st[sc.ids[0]], st[sc.ids[2]] - st[sc.ids[0]]);
    if (i == 0) n0 = n;
    EXPECT_GT(dot(n, n0), 0) << i;
  }
  std::mt19937 rng(15);
  std::uniform_real_distribution<double> u(0.01, 0.99), v(0.01, 1.99);
  for (int k = 0; k < 100; ++k) {
    const Vec3 x{v(rng), u(rng), 1.5};
    const CellPosition pos = locate_in_cell(CellType::TriangleStrip, st, x);
    EXPECT_TRUE(pos.inside);
    EXPECT_NEAR(pos.dist2, 0.25, 1e-14);
    const Vec3 back = evaluate_location(CellType::TriangleStrip, st, pos.pcoords, pos.sub_id);
    EXPECT_LE(norm(back - Vec3{x.x, x.y, 1}), 1e-14);
    Vec3 rep{};
    for (std::size_t i = 0; i < st.size(); ++i) rep += pos.weights[i] * st[i];
    EXPECT_LE(norm(rep - Vec3{x.x, x.y, 1}), 1e-14);
    // The chosen sub-triangle really contains x.
    const int expect_sub = x.x < 1 ? (x.x + x.y < 1 ? 0 : 1) : (x.x - 1 + x.y < 1 ? 2 : 3);
    EXPECT_EQ(pos.sub_id, expect_sub) << x.x << " " << x.y;
  }
  CellWeights w;
  evaluate_weights(CellType::TriangleStrip, st, {0.2, 0.3, 0}, 3, w);
  EXPECT_EQ(w[0] + w[1] + w[2], 0.0);
  EXPECT_NEAR(w[3] + w[4] + w[5], 1.0, 1e-15);
}

TEST(CellComposite, PolyVertex) {
  const std::vector<Vec3> pv = {{0, 0, 0}, {1, 0, 0}, {5, 5, 5}};
  CellPosition pos = locate_in_cell(CellType::PolyVertex, pv, {4, 5, 5});
  EXPECT_EQ(pos.sub_id, 2);
  EXPECT_FALSE(pos.inside);
  EXPECT_EQ(pos.dist2, 1.0);
  EXPECT_EQ(pos.weights[2], 1.0);
  pos = locate_in_cell(CellType::PolyVertex, pv, {1, 0, 0});
  EXPECT_EQ(pos.sub_id, 1);
  EXPECT_TRUE(pos.inside);
  EXPECT_EQ(evaluate_location(CellType::PolyVertex, pv, {}, 2), (Vec3{5, 5, 5}));
}

// ---------------------------------------------------------------------------------------------
// Tables
// ---------------------------------------------------------------------------------------------

TEST(CellTables, EdgeAndFaceCountsMatchVtk) {
  const std::map<CellType, std::pair<std::size_t, std::size_t>> expect = {
      {CellType::Vertex, {0, 0}}, {CellType::Line, {0, 0}},        {CellType::Triangle, {3, 0}},
      {CellType::Pixel, {4, 0}},  {CellType::Quad, {4, 0}},        {CellType::Tetra, {6, 4}},
      {CellType::Voxel, {12, 6}}, {CellType::Hexahedron, {12, 6}}, {CellType::Wedge, {9, 5}},
      {CellType::Pyramid, {8, 5}}};
  for (const auto& [t, counts] : expect) {
    EXPECT_EQ(cell_edges(t).size(), counts.first) << name(t);
    EXPECT_EQ(cell_faces(t).size(), counts.second) << name(t);
  }
  EXPECT_EQ(cell_edges(CellType::Hexahedron)[2], (CellEdge{3, 2}));  // VTK's hex edge 2
  EXPECT_EQ(cell_edges(CellType::Quad)[2], (CellEdge{3, 2}));
  EXPECT_EQ(cell_edges(CellType::Pixel)[1], (CellEdge{1, 3}));
  EXPECT_EQ(polygon_edge(5, 4), (CellEdge{4, 0}));
}

TEST(CellTables, EdgesAreUniqueAndFacesCloseTheSurface) {
  for (CellType t : kFixedTypes) {
    SCOPED_TRACE(name(t));
    std::set<std::pair<int, int>> edges;
    for (const CellEdge& e : cell_edges(t)) {
      EXPECT_NE(e[0], e[1]);
      EXPECT_TRUE(edges.insert({std::min(e[0], e[1]), std::max(e[0], e[1])}).second);
    }
    if (cell_dimension(t) == 2) {
      // The edges of a 2D cell are its boundary: every point is on exactly two edges.
      std::map<int, int> deg;
      for (const CellEdge& e : cell_edges(t)) {
        ++deg[e[0]];
        ++deg[e[1]];
      }
      for (int i = 0; i < cell_fixed_size(t); ++i) EXPECT_EQ(deg[i], 2) << i;
    }
    if (cell_dimension(t) != 3) continue;
    // Every face edge is a cell edge, and every cell edge borders exactly two faces.
    std::map<std::pair<int, int>, int> uses;
    for (const CellFace& f : cell_faces(t)) {
      for (int i = 0; i < f.size; ++i) {
        const int a = f.ids[i], b = f.ids[(i + 1) % f.size];
        const std::pair<int, int> key{std::min(a, b), std::max(a, b)};
        EXPECT_TRUE(edges.count(key)) << a << "-" << b;
        ++uses[key];
      }
    }
    for (const auto& e : edges) EXPECT_EQ(uses[e], 2) << e.first << "-" << e.second;
  }
}

TEST(CellTables, FaceNormalsPointOutOfValidCells) {
  for (CellType t : {CellType::Tetra, CellType::Voxel, CellType::Hexahedron, CellType::Wedge,
                     CellType::Pyramid}) {
    SCOPED_TRACE(name(t));
    auto pts = reference_points(t);
    // VTK's valid wedge has its base ordered clockwise seen from the top: mirror the reference.
    if (t == CellType::Wedge) {
      for (Vec3& p : pts) p.y = -p.y;
    }
    Vec3 c{};
    for (const Vec3& p : pts) c += p / static_cast<double>(pts.size());
    for (const CellFace& f : cell_faces(t)) {
      Vec3 n{}, fc{};
      for (int i = 0; i < f.size; ++i) {
        n += cross(pts[f.ids[i]], pts[f.ids[(i + 1) % f.size]]);
        fc += pts[f.ids[i]] / f.size;
      }
      EXPECT_GT(dot(n, fc - c), 0);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Errors
// ---------------------------------------------------------------------------------------------

template <class F>
void expect_error(F&& f, const std::string& substring) {
  try {
    f();
    ADD_FAILURE() << "no Error thrown, expected one containing '" << substring << "'";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(substring), std::string::npos)
        << "message: " << e.what() << "\nexpected to contain: " << substring;
  }
}

TEST(CellErrors, BadInputThrowsWithAClearMessage) {
  const auto hex = reference_points(CellType::Hexahedron);
  const std::vector<Vec3> seven(hex.begin(), hex.begin() + 7);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  expect_error([&] { (void)locate_in_cell(CellType::Hexahedron, seven, {}); },
               "hexahedron needs 8 points, got 7");
  expect_error([&] { (void)evaluate_location(CellType::Tetra, seven, {}); },
               "tetra needs 4 points");
  auto bad = hex;
  bad[3].y = nan;
  expect_error([&] { (void)locate_in_cell(CellType::Hexahedron, bad, {}); },
               "point 3 of the hexahedron is not finite");
  expect_error(
      [&] {
        (void)locate_in_cell(CellType::Hexahedron, hex, {nan, 0, 0});
      },
      "x is not finite");
  expect_error([&] { (void)locate_in_cell(CellType::Hexahedron, hex, {}, -1); }, "tolerance");
  expect_error([&] { (void)locate_in_cell(CellType::Hexahedron, hex, {}, nan); }, "tolerance");
  expect_error(
      [&] {
        (void)evaluate_location(CellType::Hexahedron, hex, {0, nan, 0});
      },
      "pcoords is not finite");
  expect_error([&] { (void)interpolation_weights(CellType::Polygon, {}); },
               "no fixed parametric points");
  expect_error([&] { (void)parametric_points(CellType::Empty); }, "empty cell type");
  expect_error([&] { (void)locate_in_cell(CellType::Empty, hex, {}); }, "empty cell type");
  std::vector<double> w(3);
  expect_error([&] { interpolation_weights(CellType::Quad, {}, w); }, "has 4 weights");
  std::vector<double> d(8);
  expect_error([&] { interpolation_derivatives(CellType::Quad, {}, d); }, "12 derivatives");
  const std::vector<Vec3> two = {{0, 0, 0}, {1, 0, 0}};
  expect_error([&] { (void)locate_in_cell(CellType::Polygon, two, {}); },
               "polygon needs at least 3 points, got 2");
  expect_error([&] { (void)evaluate_location(CellType::PolyLine, two, {}, 1); },
               "sub_id 1 is out of range");
  expect_error([&] { (void)evaluate_location(CellType::Hexahedron, hex, {}, 1); }, "sub_id 1");
  const std::vector<double> vals(7, 1.0);
  expect_error([&] { (void)derivatives(CellType::Hexahedron, hex, {}, vals, 1); },
               "expected 8 values");
  std::vector<double> nan_vals(8, 1.0);
  nan_vals[5] = nan;
  expect_error([&] { (void)derivatives(CellType::Hexahedron, hex, {}, nan_vals, 1); },
               "value 0 of point 5 is not finite");
  expect_error([&] { (void)derivatives(CellType::Hexahedron, hex, {}, nan_vals, 0); },
               "components must be >= 1");
  expect_error([&] { (void)sub_cell(CellType::Quad, 4, 0); }, "not a composite cell");
  expect_error([&] { (void)sub_cell(CellType::TriangleStrip, 5, 3); }, "out of range");
  expect_error([&] { (void)cell_edges(CellType::Polygon); }, "polygon");
  expect_error([&] { (void)polygon_edge(4, 4); }, "edge 4 is out of range");
  expect_error([&] { (void)parametric_distance(CellType::Tetra, {nan, 0, 0}); }, "not finite");
}

TEST(CellWeightsType, InlineAndHeapStorage) {
  CellWeights w(3);
  EXPECT_EQ(w.size(), 3u);
  w[2] = 5;
  CellWeights copy = w;
  EXPECT_EQ(copy[2], 5);
  w.resize(20);
  EXPECT_EQ(w.size(), 20u);
  for (double v : w) EXPECT_EQ(v, 0);
  w[19] = 1;
  CellWeights big = w;
  EXPECT_EQ(big[19], 1);
  big.resize(2);
  EXPECT_EQ(big.span().size(), 2u);
  EXPECT_EQ(big[0], 0);
}
