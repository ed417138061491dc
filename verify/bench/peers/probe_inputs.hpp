#pragma once
// The deterministic inputs of the probe benchmark (verify/bench/probe.sh), made in memory by
// probe_time and written to files for the VTK peer and the CLI runs.

#include <cmath>
#include <numbers>

#include "isoforge/core/dataset.hpp"

namespace isoforge::bench {

/// The field every input carries: smooth, not linear (so interpolation does real work).
inline double probe_field(const Vec3& p) { return p.x * p.y + std::sin(3 * p.z) + p.x; }

/// A warped n³-point grid over about [0, 1]³: each coordinate shifted by 0.03 sin(2π ·) of
/// another, so the hexahedra are curved but valid (the warp's slope 0.19 is below 1).
inline StructuredGrid warped_grid(Index n) {
  StructuredGrid g;
  g.dims = {n, n, n};
  g.points = Points(std::size_t(n * n * n), ScalarType::Float32);
  DataArray f("f", ScalarType::Float32, 1, g.points.size());
  const double h = 1.0 / double(n - 1), a = 0.03, w = 2 * std::numbers::pi;
  for (Index k = 0; k < n; ++k)
    for (Index j = 0; j < n; ++j)
      for (Index i = 0; i < n; ++i) {
        const double u = double(i) * h, v = double(j) * h, t = double(k) * h;
        const Vec3 p{u + a * std::sin(w * v), v + a * std::sin(w * t), t + a * std::sin(w * u)};
        const auto id = std::size_t(g.point_id(i, j, k));
        g.points.set(id, p);
        f.set(id, 0, probe_field(g.points[id]));
      }
  g.point_data.add(std::move(f), AttributeRole::Scalars);
  return g;
}

/// An n³-cube grid over [0, 1]³ split into 6 tetrahedra per cube (around the main diagonal:
/// conforming without parity), 6 n³ tetrahedra.
inline UnstructuredGrid tet_mesh(Index n) {
  UnstructuredGrid ug;
  const Index m = n + 1;
  ug.points = Points(std::size_t(m * m * m), ScalarType::Float32);
  DataArray f("f", ScalarType::Float32, 1, ug.points.size());
  for (Index k = 0; k < m; ++k)
    for (Index j = 0; j < m; ++j)
      for (Index i = 0; i < m; ++i) {
        const auto id = std::size_t(i + m * (j + m * k));
        ug.points.set(id, Vec3{double(i), double(j), double(k)} * (1.0 / double(n)));
        f.set(id, 0, probe_field(ug.points[id]));
      }
  ug.point_data.add(std::move(f), AttributeRole::Scalars);
  // The six paths from corner 0 to corner 7 along the cube's edges (bits: x 1, y 2, z 4).
  const int paths[6][2] = {{1, 3}, {1, 5}, {2, 3}, {2, 6}, {4, 5}, {4, 6}};
  ug.types.reserve(std::size_t(6 * n * n * n));
  for (Index k = 0; k < n; ++k)
    for (Index j = 0; j < n; ++j)
      for (Index i = 0; i < n; ++i) {
        auto corner = [&](int c) {
          return (i + (c & 1)) + m * ((j + ((c >> 1) & 1)) + m * (k + ((c >> 2) & 1)));
        };
        for (const auto& p : paths) {
          ug.add_cell(CellType::Tetra, {corner(0), corner(p[0]), corner(p[1]), corner(7)});
        }
      }
  return ug;
}

}  // namespace isoforge::bench
