// Tensor glyphs (filters/tensor_glyph.hpp): Eigen's self-adjoint solver (tridiagonalisation and
// implicit symmetric QR, accurate to a few ulps of the largest eigenvalue) gives each tensor's
// axes E; the unit sphere is mapped by s -> p + E diag(scale |λ|) Eᵀ s, its normals by the
// inverse transpose. Glyphs are written in parallel into slots fixed by their order.

#include "isoforge/filters/tensor_glyph.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "isoforge/core/memory.hpp"
#include "isoforge/core/parallel.hpp"
#include "isoforge/core/subset.hpp"
#include "isoforge/filters/glyph.hpp"

namespace isoforge {
namespace {

/// sgn(x) |x|^e, 0 at 0 (the superquadric's signed power).
double signed_pow(double x, double e) {
  if (x == 0) return 0;
  return std::copysign(std::pow(std::abs(x), e), x);
}

/// Kindlmann's superquadric for semi-axes `axis` (G. Kindlmann, "Superquadric tensor glyphs",
/// VisSym 2004): the Westin metrics cl, cp of the sorted semi-axes choose the symmetry axis (the
/// largest if cl ≥ cp, else the smallest) and the exponents α (around it) and β (along it).
struct Superquadric {
  int sym = 0;              ///< the eigen-axis the source's x axis goes to
  double alpha = 1, beta = 1;

  Superquadric() = default;  // the sphere
  Superquadric(const double axis[3], double gamma) {
    int order[3] = {0, 1, 2};
    std::sort(order, order + 3, [&](int a, int b) { return axis[a] > axis[b]; });
    const double l1 = axis[order[0]], l2 = axis[order[1]], l3 = axis[order[2]];
    const double sum = l1 + l2 + l3;
    if (!(sum > 0)) return;  // collapsed to a point: any shape
    const double cl = (l1 - l2) / sum, cp = 2 * (l2 - l3) / sum;
    if (cl >= cp) {
      sym = order[0];
      alpha = std::pow(1 - cp, gamma);
      beta = std::pow(1 - cl, gamma);
    } else {
      sym = order[2];
      alpha = std::pow(1 - cl, gamma);
      beta = std::pow(1 - cp, gamma);
    }
  }

  /// The point and normal (unnormalised) of unit-sphere point s, in the frame (x along the
  /// symmetry axis): s = (sin η, cos η cos ω, cos η sin ω) goes to
  /// (sin^β η, cos^β η cos^α ω, cos^β η sin^α ω), normal (sin^(2−β) η, cos^(2−β) η cos^(2−α) ω, …).
  void map(const Vec3& s, Vec3& point, Vec3& normal) const {
    const double r = std::sqrt(s.y * s.y + s.z * s.z);
    const double cu = r > 0 ? s.y / r : 0, cv = r > 0 ? s.z / r : 0;
    const double rb = signed_pow(r, beta), rn = signed_pow(r, 2 - beta);
    point = {signed_pow(s.x, beta), rb * signed_pow(cu, alpha), rb * signed_pow(cv, alpha)};
    normal = {signed_pow(s.x, 2 - beta), rn * signed_pow(cu, 2 - alpha),
              rn * signed_pow(cv, 2 - alpha)};
  }
};

/// The tensor of point i as a row-major 3×3 matrix, from 9 or 6 (XX YY ZZ XY YZ XZ) components.
std::array<double, 9> tensor_at(const DataArray& a, std::size_t i) {
  if (a.components() == 9) {
    std::array<double, 9> m{};
    for (int k = 0; k < 9; ++k) m[static_cast<std::size_t>(k)] = a.get(i, k);
    return m;
  }
  const double xx = a.get(i, 0), yy = a.get(i, 1), zz = a.get(i, 2), xy = a.get(i, 3),
               yz = a.get(i, 4), xz = a.get(i, 5);
  return {xx, xy, xz, xy, yy, yz, xz, yz, zz};
}

}  // namespace

SymmetricEigen symmetric_eigen(const std::array<double, 9>& m) {
  for (const double v : m) {
    if (!std::isfinite(v)) throw Error("symmetric_eigen: the matrix has a non-finite entry");
  }
  Eigen::Matrix3d a;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      // The upper triangle, mirrored.
      a(r, c) = m[static_cast<std::size_t>(3 * std::min(r, c) + std::max(r, c))];
    }
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(a);
  SymmetricEigen e;
  for (int k = 0; k < 3; ++k) {  // Eigen sorts increasingly
    const int from = 2 - k;
    e.values[static_cast<std::size_t>(k)] = solver.eigenvalues()(from);
    const auto v = solver.eigenvectors().col(from);
    e.vectors[static_cast<std::size_t>(k)] = {v(0), v(1), v(2)};
  }
  e.vectors[2] = cross(e.vectors[0], e.vectors[1]);
  return e;
}

Result<PolyData, TensorGlyphStats> tensor_glyph(DatasetRef input, const TensorGlyphOptions& o) {
  if (!(std::isfinite(o.scale) && o.scale > 0)) {
    throw Error(fmt::format("tensor glyph: scale must be finite and > 0, got {}", o.scale));
  }
  if (!(std::isfinite(o.max_size) && o.max_size >= 0)) {
    throw Error(fmt::format("tensor glyph: max size must be finite and >= 0, got {}", o.max_size));
  }
  if (!(std::isfinite(o.gamma) && o.gamma > 0)) {
    throw Error(fmt::format("tensor glyph: gamma must be finite and > 0, got {}", o.gamma));
  }
  if (o.resolution < 3) {
    throw Error(fmt::format("tensor glyph: resolution must be >= 3, got {}", o.resolution));
  }
  validate(input);
  const Attributes& pd = point_data(input);
  const DataArray* tensors = o.tensors.empty() ? pd.tensors() : pd.find(o.tensors);
  if (!tensors) {
    throw Error(o.tensors.empty()
                    ? fmt::format("tensor glyph: the input has no active point tensors; name one "
                                  "(point arrays: {})", pd.names())
                    : fmt::format("tensor glyph: no point array '{}' (point arrays: {})",
                                  o.tensors, pd.names()));
  }
  if (tensors->components() != 9 && tensors->components() != 6) {
    throw Error(fmt::format("tensor glyph: point array '{}' has {} components: a tensor has 9 "
                            "(3×3) or 6 (symmetric)", tensors->name(), tensors->components()));
  }
  const std::vector<Index> ids = mask_point_ids(input, o.mask);
  const PolyData sphere = glyph_source(GlyphShape::Sphere, o.resolution);
  const std::size_t m = sphere.points.size(), g = ids.size();
  const std::size_t tris = sphere.polys.size();
  require_memory(static_cast<double>(g) * (static_cast<double>(m) * 40.0 + static_cast<double>(tris) * 32.0),
                 fmt::format("tensor glyph: {} ellipsoids of {} points", g, m));

  // Decompose every glyphed tensor first (errors before any output is built).
  std::vector<SymmetricEigen> eig(g);
  parallel_for_range(g, 256, [&](std::size_t b, std::size_t e) {
    for (std::size_t k = b; k < e; ++k) {
      const auto id = static_cast<std::size_t>(ids[k]);
      const std::array<double, 9> t = tensor_at(*tensors, id);
      for (const double v : t) {
        if (!std::isfinite(v)) {
          throw Error(fmt::format("tensor glyph: the tensor of point {} is not finite", id));
        }
      }
      eig[k] = symmetric_eigen(t);
    }
  });
  report_progress(o.progress, 0.2, "tensor glyph");

  TensorGlyphStats stats;
  stats.glyphs = g;
  if (g > 0) {
    stats.min_eigenvalue = INFINITY;
    stats.max_eigenvalue = -INFINITY;
  }
  for (const SymmetricEigen& e : eig) {
    stats.min_eigenvalue = std::min(stats.min_eigenvalue, e.values[2]);
    stats.max_eigenvalue = std::max(stats.max_eigenvalue, e.values[0]);
    if (e.values[0] == 0 || e.values[1] == 0 || e.values[2] == 0) ++stats.degenerate;
  }

  PolyData out;
  out.points = Points(g * m, ScalarType::Float32);
  DataArray normals = DataArray::uninitialized("Normals", ScalarType::Float32, 3, g * m);
  DataArray point_ids = DataArray::uninitialized("InputPointIds", ScalarType::Int64, 1, g * m);
  DataArray color;
  if (o.color != TensorColor::None) {
    color = DataArray::uninitialized("TensorColor", ScalarType::Float32, 1, g * m);
  }
  Attributes carried = empty_like(pd, g * m);
  Buffer<Index> offsets(g * tris + 1), conn(3 * g * tris);
  for (std::size_t t = 0; t <= g * tris; ++t) offsets[t] = static_cast<Index>(3 * t);
  const auto source_normals = sphere.point_data.get("Normals").values<float>();
  float* N = normals.values<float>().data();
  auto* I = point_ids.values<std::int64_t>().data();
  float* C = o.color != TensorColor::None ? color.values<float>().data() : nullptr;
  parallel_for_range(
      g, 64,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t k = b; k < e; ++k) {
          const SymmetricEigen& ev = eig[k];
          const auto id = static_cast<std::size_t>(ids[k]);
          const Vec3 p = point(input, static_cast<Index>(id));
          double axis[3];
          for (int a = 0; a < 3; ++a) axis[a] = o.scale * std::abs(ev.values[static_cast<std::size_t>(a)]);
          const double largest = std::max({axis[0], axis[1], axis[2]});
          if (o.max_size > 0 && largest > o.max_size) {
            for (double& a : axis) a *= o.max_size / largest;
          }
          double value = 0;
          if (o.color == TensorColor::Eigenvalue) {
            value = ev.values[0];
          } else if (o.color == TensorColor::Anisotropy) {
            // Of the ellipsoid's semi-axes |λ|: in [0, 1] for tensors of any signs.
            const double l1 = std::abs(ev.values[0]), l2 = std::abs(ev.values[1]),
                         l3 = std::abs(ev.values[2]);
            const double mean = (l1 + l2 + l3) / 3;
            const double num = (l1 - mean) * (l1 - mean) + (l2 - mean) * (l2 - mean) + (l3 - mean) * (l3 - mean);
            const double den = l1 * l1 + l2 * l2 + l3 * l3;
            value = den > 0 ? std::sqrt(1.5 * num / den) : 0;
          }
          const bool super = o.shape == TensorGlyphShape::Superquadric;
          const Superquadric sq = super ? Superquadric(axis, o.gamma) : Superquadric();
          for (std::size_t j = 0; j < m; ++j) {
            const std::size_t at = k * m + j;
            const Vec3 s = sphere.points[j] * 2.0;  // the unit sphere
            Vec3 q = p, n{0, 0, 0}, flat{0, 0, 0};
            const Vec3 sn{source_normals[3 * j], source_normals[3 * j + 1], source_normals[3 * j + 2]};
            // The shape's coordinates along the eigenvectors: the sphere rotated onto them, or the
            // superquadric with the source's x axis on the symmetry axis (a cyclic, so
            // right-handed, relabelling: x → sym, y → sym + 1, z → sym + 2).
            double local[3], local_n[3];
            if (super) {
              Vec3 lp, ln;
              sq.map(s, lp, ln);
              for (int c = 0; c < 3; ++c) {
                local[(sq.sym + c) % 3] = lp[c];
                local_n[(sq.sym + c) % 3] = ln[c];
              }
            } else {
              for (int a = 0; a < 3; ++a) {
                const Vec3& ea = ev.vectors[static_cast<std::size_t>(a)];
                local[a] = dot(s, ea);
                local_n[a] = dot(sn, ea);
              }
            }
            for (int a = 0; a < 3; ++a) {
              const Vec3& ea = ev.vectors[static_cast<std::size_t>(a)];
              q += ea * (axis[a] * local[a]);
              // Normals by the inverse transpose, diag(1 / axis); along a zero axis (a flat
              // glyph) that term dominates: the normal is the axis, on the source normal's side.
              const double d = local_n[a];
              if (axis[a] > 0) {
                n += ea * (d / axis[a]);
              } else {
                flat += ea * d;
              }
            }
            if (norm2(flat) > 0) n = flat;
            out.points.set(at, q);
            const double ln = norm(n);
            const Vec3 u = ln > 0 && std::isfinite(ln) ? n / ln : sn;
            N[3 * at] = static_cast<float>(u.x);
            N[3 * at + 1] = static_cast<float>(u.y);
            N[3 * at + 2] = static_cast<float>(u.z);
            I[at] = static_cast<std::int64_t>(id);
            if (C) C[at] = static_cast<float>(value);
            copy_tuple(pd, id, carried, at);
          }
          Index* c = conn.data() + 3 * k * tris;
          for (std::size_t t = 0; t < tris; ++t) {
            for (const Index v : sphere.polys.cell(t)) *c++ = static_cast<Index>(k * m) + v;
          }
        }
      },
      progress_range(o.progress, 0.2, 1.0), "tensor glyph");
  out.polys = CellArray(std::move(offsets), std::move(conn));
  out.point_data = std::move(carried);
  out.point_data.remove("Normals");
  out.point_data.add(std::move(normals), AttributeRole::Normals);
  out.point_data.add(std::move(point_ids));
  if (C) out.point_data.add(std::move(color), AttributeRole::Scalars);
  return {std::move(out), stats};
}

}  // namespace isoforge
