#include "reduce/quadric.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <numbers>

#include "isoforge/core/parallel.hpp"

namespace isoforge::reduce {

Vec3 minimize(const Quadric& q, const Vec3& anchor, double relative_cutoff) {
  // Well-conditioned systems (the common case on curved surfaces) by Cramer's rule: the
  // smallest eigenvalue is det / (λmax λmid) ≥ det / I2 (I2 = the sum of the principal 2×2
  // minors = λ1λ2 + λ1λ3 + λ2λ3) and λmax ≤ trace, so det > cutoff × trace × I2 means every
  // eigenvalue is above cutoff × λmax and the pseudo-inverse below equals the inverse.
  {
    const double c00 = q.a11 * q.a22 - q.a12 * q.a12;
    const double c01 = q.a02 * q.a12 - q.a01 * q.a22;
    const double c02 = q.a01 * q.a12 - q.a02 * q.a11;
    const double det = q.a00 * c00 + q.a01 * c01 + q.a02 * c02;
    const double trace = q.a00 + q.a11 + q.a22;
    const double c11 = q.a00 * q.a22 - q.a02 * q.a02;
    const double c22 = q.a00 * q.a11 - q.a01 * q.a01;
    const double minors = c00 + c11 + c22;
    if (trace > 0 && minors > 0 && det > 2 * relative_cutoff * trace * minors) {
      const double c12 = q.a01 * q.a02 - q.a00 * q.a12;
      const double inv = 1 / det;
      const Vec3 p{-(c00 * q.b0 + c01 * q.b1 + c02 * q.b2) * inv,
                   -(c01 * q.b0 + c11 * q.b1 + c12 * q.b2) * inv,
                   -(c02 * q.b0 + c12 * q.b1 + c22 * q.b2) * inv};
      if (is_finite(p)) return p;
    }
  }
  Eigen::Matrix3d a;
  a << q.a00, q.a01, q.a02, q.a01, q.a11, q.a12, q.a02, q.a12, q.a22;
  const double scale = a.cwiseAbs().maxCoeff();
  if (!(scale > 0) || !std::isfinite(scale)) return anchor;
  // Solve on the scaled matrix so the eigen solver works near 1.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(a / scale);
  const Eigen::Vector3d m(anchor.x, anchor.y, anchor.z);
  const Eigen::Vector3d r = -(a * m + Eigen::Vector3d(q.b0, q.b1, q.b2)) / scale;
  const auto& values = eig.eigenvalues();
  const auto& vectors = eig.eigenvectors();
  const double largest = values.cwiseAbs().maxCoeff();
  Eigen::Vector3d step = Eigen::Vector3d::Zero();
  for (int i = 0; i < 3; ++i) {
    if (values[i] > relative_cutoff * largest) {
      step += vectors.col(i) * (vectors.col(i).dot(r) / values[i]);
    }
  }
  const Eigen::Vector3d p = m + step;
  if (!p.allFinite()) return anchor;
  return {p.x(), p.y(), p.z()};
}

void vertex_quadrics(const EditMesh& mesh, const DecimateOptions& options,
                     std::vector<Quadric>& quadrics, std::vector<PointQuadric>& points,
                     std::vector<double>& areas, const ProgressCallback& progress) {
  const std::size_t nv = mesh.vertex_count();
  quadrics.assign(nv, Quadric{});
  areas.assign(nv, 0.0);
  points.assign(nv, PointQuadric{});
  const bool border = options.preserve_boundary && options.boundary_weight > 0;
  const bool features = options.feature_angle < 180;
  const double cos_feature = std::cos(options.feature_angle * std::numbers::pi / 180);
  auto normal_of = [&](Fid f) {
    const Tri& t = mesh.face(f);
    return cross(mesh.position(t[1]) - mesh.position(t[0]),
                 mesh.position(t[2]) - mesh.position(t[0]));
  };
  parallel_for_range(
      nv, 1024,
      [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
          const Vid v = static_cast<Vid>(i);
          Quadric q;
          double area = 0;
          const Vec3& pv = mesh.position(v);
          for (Fid f : mesh.faces_of(v)) {
            const Vec3 n = normal_of(f);
            const double len = norm(n);
            if (!(len > 0)) continue;
            const Vec3 u = n / len;
            const double a = 0.5 * len;
            q += Quadric::plane(u, -dot(u, mesh.position(mesh.face(f)[0])), a);
            area += a;
            if (!border && !features) continue;
            // Constraint planes through this face's edges at v that are borders or features.
            const Tri& t = mesh.face(f);
            for (int k = 0; k < 3; ++k) {
              const Vid a0 = t[k], a1 = t[(k + 1) % 3];
              if (a0 != v && a1 != v) continue;
              const Vid w = a0 == v ? a1 : a0;
              bool constrain = false;
              if (border && mesh.edge_faces(v, w) == 1) constrain = true;
              if (!constrain && features) {
                for (Fid g : mesh.faces_of(v)) {
                  if (g == f) continue;
                  const Tri& s = mesh.face(g);
                  if (s[0] != w && s[1] != w && s[2] != w) continue;
                  const Vec3 m = normal_of(g);
                  const double lm = norm(m);
                  if (lm > 0 && dot(u, m / lm) < cos_feature) constrain = true;
                }
              }
              if (!constrain) continue;
              const Vec3 e = mesh.position(w) - pv;
              const double le2 = norm2(e);
              const Vec3 c = cross(e, u);
              const double lc = norm(c);
              if (!(lc > 0)) continue;
              const Vec3 cn = c / lc;
              q += Quadric::plane(cn, -dot(cn, pv), options.boundary_weight * le2);
            }
          }
          quadrics[v] = q;
          points[v] = PointQuadric::at(pv, kPointQuadricWeight * area);
          areas[v] = area;
        }
      },
      progress, "decimate");
}

}  // namespace isoforge::reduce
