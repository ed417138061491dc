#pragma once
// Test surfaces built in code.

#include <functional>

#include "isoforge/core/dataset.hpp"

namespace isoforge::test {

/// A closed, outward-oriented surface around the z axis: the poles `south` and `north` and
/// rings 1 .. rings-1 of `segments` points each, ring_point(i, j) for ring i and segment j,
/// rings ordered from south to north and segments counterclockwise seen from +z.
inline PolyData polar_surface(const Vec3& south, const Vec3& north, int rings, int segments,
                              const std::function<Vec3(int, int)>& ring_point) {
  PolyData pd;
  pd.points.push_back(south);
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segments; ++j) pd.points.push_back(ring_point(i, j));
  pd.points.push_back(north);
  const auto ring = [&](int i, int j) { return Index(1 + (i - 1) * segments + (j % segments)); };
  const Index top = Index(pd.points.size() - 1);
  for (int j = 0; j < segments; ++j) pd.polys.add({0, ring(1, j + 1), ring(1, j)});
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      pd.polys.add({ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)});
      pd.polys.add({ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)});
    }
  for (int j = 0; j < segments; ++j) pd.polys.add({ring(rings - 1, j), ring(rings - 1, j + 1), top});
  return pd;
}

/// An n × n grid of quads, point(i, j) at node (i, j) for 0 ≤ i, j ≤ n, each quad split into two
/// triangles along (i, j)–(i+1, j+1) when up(i, j), else along (i+1, j)–(i, j+1); oriented
/// counterclockwise seen from +z when point(i, j) follows (i, j) in the plane.
inline PolyData grid_surface(int n, const std::function<Vec3(int, int)>& point,
                             const std::function<bool(int, int)>& up) {
  PolyData pd;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) pd.points.push_back(point(i, j));
  const auto id = [n](int i, int j) { return Index(i + (n + 1) * j); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if (up(i, j)) {
        pd.polys.add({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        pd.polys.add({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      } else {
        pd.polys.add({id(i, j), id(i + 1, j), id(i, j + 1)});
        pd.polys.add({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    }
  return pd;
}

}  // namespace isoforge::test
