// Tensor glyphs: the eigen-decomposition of random symmetric tensors (residuals, orthonormal
// right-handed axes, known spectra), and ellipsoids that lie exactly on their quadric.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "isoforge/filters/tensor_glyph.hpp"
#include "support/expect_error.hpp"

using namespace isoforge;
using isoforge::test::expect_error;

namespace {

using Mat = std::array<double, 9>;

Vec3 mul(const Mat& m, const Vec3& v) {
  return {m[0] * v.x + m[1] * v.y + m[2] * v.z, m[3] * v.x + m[4] * v.y + m[5] * v.z,
          m[6] * v.x + m[7] * v.y + m[8] * v.z};
}

// R diag(l) Rᵀ for the rotation R whose columns are the unit vectors a, b, a × b.
Mat compose(const Vec3& a, const Vec3& b, const std::array<double, 3>& l) {
  const Vec3 c = cross(a, b);
  const Vec3 e[3] = {a, b, c};
  Mat m{};
  for (int r = 0; r < 3; ++r)
    for (int s = 0; s < 3; ++s)
      for (int k = 0; k < 3; ++k) m[size_t(3 * r + s)] += l[size_t(k)] * e[k][r] * e[k][s];
  return m;
}

// One point with tensor `t` (9 components) as the active tensors.
PolyData one_tensor(const Vec3& p, const Mat& t) {
  PolyData pd;
  pd.points.push_back(p);
  DataArray a("T", ScalarType::Float64, 9, 1);
  for (int k = 0; k < 9; ++k) a.set(0, k, t[size_t(k)]);
  pd.point_data.add(std::move(a), AttributeRole::Tensors);
  return pd;
}

}  // namespace

TEST(SymmetricEigen, RandomTensorsHaveSmallResidualsAndOrthonormalAxes) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-10, 10);
  for (int trial = 0; trial < 2000; ++trial) {
    Mat m{};
    for (int r = 0; r < 3; ++r)
      for (int c = r; c < 3; ++c) m[size_t(3 * r + c)] = m[size_t(3 * c + r)] = u(rng);
    if (trial % 5 == 0) m[1] = m[3] = 0;  // some already partly diagonal
    const SymmetricEigen e = symmetric_eigen(m);
    double scale = 0;
    for (const double v : m) scale = std::max(scale, std::abs(v));
    EXPECT_GE(e.values[0], e.values[1]);
    EXPECT_GE(e.values[1], e.values[2]);
    EXPECT_NEAR(e.values[0] + e.values[1] + e.values[2], m[0] + m[4] + m[8], 1e-12 * scale);
    for (int k = 0; k < 3; ++k) {
      const Vec3& v = e.vectors[size_t(k)];
      EXPECT_NEAR(norm(v), 1, 1e-13);
      EXPECT_LT(norm(mul(m, v) - v * e.values[size_t(k)]), 1e-12 * scale) << trial;
    }
    EXPECT_NEAR(dot(e.vectors[0], e.vectors[1]), 0, 1e-13);
    EXPECT_NEAR(norm(e.vectors[2] - cross(e.vectors[0], e.vectors[1])), 0, 1e-13);
  }
}

TEST(SymmetricEigen, KnownSpectraAndTheUpperTriangle) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n(0, 1);
  for (int trial = 0; trial < 500; ++trial) {
    Vec3 a{n(rng), n(rng), n(rng)}, b{n(rng), n(rng), n(rng)};
    a = a / norm(a);
    b = b - a * dot(a, b);
    b = b / norm(b);
    const std::array<double, 3> l = {5 + n(rng), 1e-3 * n(rng), -4 + n(rng)};  // distinct
    const SymmetricEigen e = symmetric_eigen(compose(a, b, l));
    EXPECT_NEAR(e.values[0], l[0], 1e-12 * 10);
    EXPECT_NEAR(e.values[1], l[1], 1e-12 * 10);
    EXPECT_NEAR(e.values[2], l[2], 1e-12 * 10);
    EXPECT_NEAR(std::abs(dot(e.vectors[0], a)), 1, 1e-12);
  }
  // Only the upper triangle counts (VTK's convention for non-symmetric input).
  const SymmetricEigen e = symmetric_eigen({2, 1, 0, 99, 2, 0, 99, 99, 3});
  EXPECT_NEAR(e.values[0], 3, 1e-14);
  EXPECT_NEAR(e.values[1], 3, 1e-14);
  EXPECT_NEAR(e.values[2], 1, 1e-14);
  expect_error([] { (void)symmetric_eigen({NAN, 0, 0, 0, 1, 0, 0, 0, 1}); }, "non-finite");
}

TEST(TensorGlyph, EllipsoidsLieOnTheirQuadric) {
  const Vec3 a = Vec3{1, 1, 0} / std::sqrt(2.0), b{0, 0, 1};
  const Vec3 p{1, 2, 3};
  const PolyData pd = one_tensor(p, compose(a, b, {3, -2, 1}));  // |λ| are the semi-axes
  TensorGlyphOptions o;
  o.scale = 0.5;
  const auto [out, stats] = tensor_glyph(pd, o);
  EXPECT_EQ(stats.glyphs, 1u);
  EXPECT_EQ(stats.degenerate, 0u);
  EXPECT_DOUBLE_EQ(stats.max_eigenvalue, 3);
  EXPECT_NEAR(stats.min_eigenvalue, -2, 1e-14);
  const Vec3 c = cross(a, b);
  const DataArray& normals = out.point_data.get("Normals");
  const DataArray& color = out.point_data.get("TensorColor");
  ASSERT_GT(out.points.size(), 50u);
  for (std::size_t i = 0; i < out.points.size(); ++i) {
    const Vec3 d = out.points[i] - p;
    const double x = dot(d, a) / 1.5, y = dot(d, b) / 1.0, z = dot(d, c) / 0.5;
    EXPECT_NEAR(x * x + y * y + z * z, 1, 1e-5);  // float points
    // The normal is the quadric's gradient direction.
    const Vec3 g = a * (x / 1.5) + b * (y / 1.0) + c * (z / 0.5);
    const Vec3 nn{normals.get(i, 0), normals.get(i, 1), normals.get(i, 2)};
    EXPECT_NEAR(dot(nn, g / norm(g)), 1, 1e-5);
    EXPECT_EQ(color.get(i), 3.0);  // the largest eigenvalue
  }
  // Triangles face outward: the normal of each along the points' normals.
  for (std::size_t t = 0; t < out.polys.size(); ++t) {
    const auto v = out.polys.cell(t);
    const Vec3 q0 = out.points[size_t(v[0])], q1 = out.points[size_t(v[1])], q2 = out.points[size_t(v[2])];
    EXPECT_GT(dot(cross(q1 - q0, q2 - q0), (q0 + q1 + q2) / 3.0 - p), 0);
  }
}

TEST(TensorGlyph, SixComponentsMaskClampAnisotropyAndFlatGlyphs) {
  PolyData pd;
  DataArray t("S", ScalarType::Float32, 6, 4);  // XX YY ZZ XY YZ XZ
  const double rows[4][6] = {{2, 2, 2, 0, 0, 0}, {1, 0, 0, 0, 0, 0}, {4, 1, 1, 0, 0, 0},
                             {1, 1, 0, 0, 0, 0}};
  for (std::size_t i = 0; i < 4; ++i) {
    pd.points.push_back({double(i) * 10, 0, 0});
    for (int k = 0; k < 6; ++k) t.set(i, k, rows[i][k]);
  }
  pd.point_data.add(std::move(t));
  TensorGlyphOptions o;
  o.tensors = "S";
  o.color = TensorColor::Anisotropy;
  o.max_size = 3;
  const auto [out, stats] = tensor_glyph(pd, o);
  EXPECT_EQ(stats.glyphs, 4u);
  EXPECT_EQ(stats.degenerate, 2u);  // the line and the disc
  const std::size_t m = out.points.size() / 4;
  const DataArray& fa = out.point_data.get("TensorColor");
  EXPECT_NEAR(fa.get(0), 0, 1e-7);      // isotropic
  EXPECT_NEAR(fa.get(m), 1, 1e-7);      // a line
  EXPECT_NEAR(fa.get(3 * m), std::sqrt(0.5), 1e-6);  // a disc
  // Glyph 2 (semi-axes 4, 1, 1) is shrunk uniformly to max_size 3.
  double reach = 0;
  for (std::size_t j = 0; j < m; ++j) reach = std::max(reach, norm(out.points[2 * m + j] - Vec3{20, 0, 0}));
  EXPECT_NEAR(reach, 3, 1e-5);
  // The disc (λ = 1, 1, 0) is flat in z, its normals along ±z, except on its rim (the source
  // sphere's equator), where they lie in the plane.
  const DataArray& n = out.point_data.get("Normals");
  std::size_t rim = 0;
  for (std::size_t j = 0; j < m; ++j) {
    const Vec3 q = out.points[3 * m + j] - Vec3{30, 0, 0};
    EXPECT_NEAR(q.z, 0, 1e-12);
    if (std::abs(n.get(3 * m + j, 2)) < 1e-6) {
      ++rim;
      EXPECT_NEAR(norm(q), 1, 1e-6);
    } else {
      EXPECT_NEAR(std::abs(n.get(3 * m + j, 2)), 1, 1e-6);
    }
  }
  EXPECT_LE(rim, 12u);  // one ring of the default 12 slices
  o.mask.every = 2;
  EXPECT_EQ(tensor_glyph(pd, o).stats.glyphs, 2u);
}

TEST(TensorGlyph, RejectsBadInput) {
  PolyData pd = one_tensor({0, 0, 0}, {1, 0, 0, 0, 1, 0, 0, 0, 1});
  TensorGlyphOptions o;
  o.scale = 0;
  expect_error([&] { (void)tensor_glyph(pd, o); }, "scale must be finite and > 0");
  o.scale = 1;
  o.max_size = -1;
  expect_error([&] { (void)tensor_glyph(pd, o); }, "max size must be finite and >= 0");
  o.max_size = 0;
  o.resolution = 2;
  expect_error([&] { (void)tensor_glyph(pd, o); }, "resolution must be >= 3");
  o.resolution = 8;
  o.tensors = "nope";
  expect_error([&] { (void)tensor_glyph(pd, o); }, "no point array 'nope' (point arrays: 'T')");
  PolyData none;
  none.points.push_back({0, 0, 0});
  expect_error([&] { (void)tensor_glyph(none, {}); }, "the input has no active point tensors");
  PolyData wrong = none;
  wrong.point_data.add(DataArray("W", ScalarType::Float32, 4, 1), AttributeRole::Tensors);
  expect_error([&] { (void)tensor_glyph(wrong, {}); }, "has 4 components: a tensor has 9");
  PolyData bad = one_tensor({0, 0, 0}, {1, 0, 0, 0, INFINITY, 0, 0, 0, 1});
  expect_error([&] { (void)tensor_glyph(bad, {}); }, "the tensor of point 0 is not finite");
}

namespace {

// Checks glyph 0 of `out` (centre p, eigenvectors a, b, a × b with semi-axes `axes`) against
// Kindlmann's superquadric with symmetry axis `sym` and exponents α, β: every point satisfies
// (|Y|^(2/α) + |Z|^(2/α))^(α/β) + |X|^(2/β) = 1 in coordinates normalised by the semi-axes, X
// along the symmetry axis; every normal is along the implicit function's gradient; triangles
// face outward.
void expect_superquadric(const PolyData& out, const Vec3& p, const Vec3 (&e)[3],
                         const double (&axes)[3], int sym, double alpha, double beta) {
  const DataArray& normals = out.point_data.get("Normals");
  const int ia = sym, ib = (sym + 1) % 3, ic = (sym + 2) % 3;
  ASSERT_GT(out.points.size(), 50u);
  for (std::size_t i = 0; i < out.points.size(); ++i) {
    const Vec3 d = out.points[i] - p;
    const double X = dot(d, e[ia]) / axes[ia], Y = dot(d, e[ib]) / axes[ib],
                 Z = dot(d, e[ic]) / axes[ic];
    const double ay = std::pow(std::abs(Y), 2 / alpha), az = std::pow(std::abs(Z), 2 / alpha);
    const double S = ay + az;
    EXPECT_NEAR(std::pow(S, alpha / beta) + std::pow(std::abs(X), 2 / beta), 1, 2e-4) << i;
    // The gradient, in world coordinates (chain rule through the normalisation).
    const double gx = (2 / beta) * std::copysign(std::pow(std::abs(X), 2 / beta - 1), X);
    const double f = S > 0 ? (2 / beta) * std::pow(S, alpha / beta - 1) : 0;
    const double gy = Y == 0 ? 0 : f * std::copysign(std::pow(std::abs(Y), 2 / alpha - 1), Y);
    const double gz = Z == 0 ? 0 : f * std::copysign(std::pow(std::abs(Z), 2 / alpha - 1), Z);
    const Vec3 g = e[ia] * (gx / axes[ia]) + e[ib] * (gy / axes[ib]) + e[ic] * (gz / axes[ic]);
    const Vec3 nn{normals.get(i, 0), normals.get(i, 1), normals.get(i, 2)};
    EXPECT_NEAR(norm(nn), 1, 1e-6);
    if (norm(g) > 0) {
      EXPECT_GT(dot(nn, g / norm(g)), 0.999) << i;
    }
  }
  for (std::size_t t = 0; t < out.polys.size(); ++t) {
    const auto v = out.polys.cell(t);
    const Vec3 q0 = out.points[size_t(v[0])], q1 = out.points[size_t(v[1])],
               q2 = out.points[size_t(v[2])];
    const Vec3 area = cross(q1 - q0, q2 - q0);
    if (norm(area) > 1e-9) {
      EXPECT_GT(dot(area, (q0 + q1 + q2) / 3.0 - p), 0) << t;
    }
  }
}

}  // namespace

TEST(TensorGlyph, SuperquadricsOfLinearPlanarAndIsotropicTensors) {
  const Vec3 a = Vec3{1, 1, 0} / std::sqrt(2.0), b{0, 0, 1};
  const Vec3 e[3] = {a, b, cross(a, b)};
  const Vec3 p{1, 2, 3};
  TensorGlyphOptions o;
  o.shape = TensorGlyphShape::Superquadric;
  o.resolution = 16;
  o.scale = 0.5;
  {
    // Linear (λ 3, −1, 0.5: cl = 4/9 ≥ cp = 2/9): symmetric about the largest axis,
    // α = (1 − cp)^γ, β = (1 − cl)^γ; a rounded cylinder.
    const PolyData pd = one_tensor(p, compose(a, b, {3, -1, 0.5}));
    const auto [out, stats] = tensor_glyph(pd, o);
    EXPECT_EQ(stats.glyphs, 1u);
    const double cl = 4.0 / 9, cp = 2.0 / 9;
    expect_superquadric(out, p, e, {1.5, 0.5, 0.25}, 0, std::pow(1 - cp, 3), std::pow(1 - cl, 3));
  }
  {
    // Planar (λ 3, 2.5, −0.5: cl = 1/12 < cp = 2/3): symmetric about the smallest axis,
    // α = (1 − cl)^γ, β = (1 − cp)^γ; a rounded disc. γ = 2 this time.
    o.gamma = 2;
    const PolyData pd = one_tensor(p, compose(a, b, {3, 2.5, -0.5}));
    const auto [out, stats] = tensor_glyph(pd, o);
    const double cl = 1.0 / 12, cp = 2.0 / 3;
    expect_superquadric(out, p, e, {1.5, 1.25, 0.25}, 2, std::pow(1 - cl, 2), std::pow(1 - cp, 2));
  }
  {
    // Isotropic: α = β = 1, the sphere, with as many points as the ellipsoid.
    const PolyData pd = one_tensor(p, compose(a, b, {2, 2, 2}));
    const auto sq = tensor_glyph(pd, o).output;
    expect_superquadric(sq, p, e, {1, 1, 1}, 0, 1, 1);
    o.shape = TensorGlyphShape::Ellipsoid;
    const auto el = tensor_glyph(pd, o).output;
    EXPECT_EQ(sq.points.size(), el.points.size());
    EXPECT_EQ(sq.polys.size(), el.polys.size());
  }
  o.shape = TensorGlyphShape::Superquadric;
  for (const double g : {0.0, -1.0, double(NAN), double(INFINITY)}) {
    o.gamma = g;
    expect_error([&] { (void)tensor_glyph(one_tensor(p, compose(a, b, {1, 1, 1})), o); },
                 "gamma must be finite and > 0");
  }
}
