// The built-in glyph shapes (filters/glyph.hpp): cone, arrow, sphere, cube and line, each about
// one unit long along +x with outward point normals, built from rings about the x axis.

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "isoforge/filters/glyph.hpp"

namespace isoforge {
namespace {

// Builds a closed triangle surface point by point, with a normal per point.
struct Builder {
  PolyData pd;
  std::vector<float> normals;
  Index add(const Vec3& p, const Vec3& n) {
    pd.points.push_back(p);
    const Vec3 u = n / norm(n);
    normals.insert(normals.end(),
                   {static_cast<float>(u.x), static_cast<float>(u.y), static_cast<float>(u.z)});
    return static_cast<Index>(pd.points.size() - 1);
  }
  // A ring of `r` points at abscissa x, radius `radius`, angle 2 pi i / r about +x; normal
  // (nx, cos, sin) scaled so its radial part has length `nr`.
  Index ring(int r, double x, double radius, double nx, double nr) {
    const Index first = static_cast<Index>(pd.points.size());
    for (int i = 0; i < r; ++i) {
      const double t = 2 * std::numbers::pi * i / r;
      add({x, radius * std::cos(t), radius * std::sin(t)}, {nx, nr * std::cos(t), nr * std::sin(t)});
    }
    return first;
  }
  // Quads between two rings of r points (a at smaller x than b when `outward_forward`).
  void band(int r, Index a, Index b) {
    for (int i = 0; i < r; ++i) {
      const Index j = (i + 1) % r;
      pd.polys.add({a + i, a + j, b + j});
      pd.polys.add({a + i, b + j, b + i});
    }
  }
  // A flat disc over ring `a` (r points), facing -x (`back`) or +x.
  void disc(int r, Index a, bool back) {
    for (int i = 1; i + 1 < r; ++i) {
      if (back) {
        pd.polys.add({a, a + i + 1, a + i});
      } else {
        pd.polys.add({a, a + i, a + i + 1});
      }
    }
  }
  // Triangles from ring `a` to the apex.
  void fan(int r, Index a, Index apex) {
    for (int i = 0; i < r; ++i) pd.polys.add({apex, a + i, a + (i + 1) % r});
  }
  PolyData finish() {
    pd.point_data.add(DataArray::from_vector<float>("Normals", 3, normals), AttributeRole::Normals);
    return std::move(pd);
  }
};

}  // namespace

PolyData glyph_source(GlyphShape shape, int resolution) {
  if (resolution < 3) {
    throw Error("glyph source: resolution must be >= 3, got " + std::to_string(resolution));
  }
  const int r = resolution;
  Builder b;
  switch (shape) {
    case GlyphShape::Cone: {
      // Height 1, radius 0.5: the side's outward normal is (0.5, cos, sin) (radial 1, axial 1/2).
      const Index apex = b.add({0.5, 0, 0}, {1, 0, 0});
      const Index side = b.ring(r, -0.5, 0.5, 0.5, 1);
      const Index cap = b.ring(r, -0.5, 0.5, -1, 0);
      b.fan(r, side, apex);
      b.disc(r, cap, true);
      break;
    }
    case GlyphShape::Arrow: {
      constexpr double kShaft = 0.03, kTip = 0.1, kTipStart = 0.65;  // vtkArrowSource's shape
      const Index back = b.ring(r, 0, kShaft, -1, 0);
      const Index s0 = b.ring(r, 0, kShaft, 0, 1);
      const Index s1 = b.ring(r, kTipStart, kShaft, 0, 1);
      const Index inner = b.ring(r, kTipStart, kShaft, -1, 0);
      const Index outer = b.ring(r, kTipStart, kTip, -1, 0);
      const Index tip = b.ring(r, kTipStart, kTip, kTip / (1 - kTipStart), 1);
      const Index apex = b.add({1, 0, 0}, {1, 0, 0});
      b.disc(r, back, true);
      b.band(r, s0, s1);
      b.band(r, inner, outer);  // the annulus faces -x: inner ring first
      b.fan(r, tip, apex);
      break;
    }
    case GlyphShape::Sphere: {
      const int stacks = std::max(2, r / 2);
      const Index south = b.add({-0.5, 0, 0}, {-1, 0, 0});
      Index prev = -1;
      for (int k = 1; k < stacks; ++k) {
        const double phi = std::numbers::pi * k / stacks;  // from -x
        const double x = -0.5 * std::cos(phi), rad = 0.5 * std::sin(phi);
        const Index ring = b.ring(r, x, rad, x, rad);
        if (k == 1) {
          for (int i = 0; i < r; ++i) b.pd.polys.add({south, ring + (i + 1) % r, ring + i});
        } else {
          b.band(r, prev, ring);
        }
        prev = ring;
      }
      const Index north = b.add({0.5, 0, 0}, {1, 0, 0});
      b.fan(r, prev, north);
      break;
    }
    case GlyphShape::Cube: {
      // Each face: 4 points with the face's normal, two triangles counter-clockwise from outside.
      for (int axis = 0; axis < 3; ++axis) {
        for (const double s : {-1.0, 1.0}) {
          Vec3 n{0, 0, 0};
          n[axis] = s;
          const int u = (axis + 1) % 3, v = (axis + 2) % 3;
          const Index first = static_cast<Index>(b.pd.points.size());
          constexpr int kCorners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
          for (const auto& c : kCorners) {
            const int cu = c[0], cv = c[1];
            Vec3 p{0, 0, 0};
            p[axis] = 0.5 * s;
            p[u] = 0.5 * cu;
            p[v] = 0.5 * cv;
            b.add(p, n);
          }
          if (s > 0) {
            b.pd.polys.add({first, first + 1, first + 2});
            b.pd.polys.add({first, first + 2, first + 3});
          } else {
            b.pd.polys.add({first, first + 2, first + 1});
            b.pd.polys.add({first, first + 3, first + 2});
          }
        }
      }
      break;
    }
    case GlyphShape::Line: {
      PolyData line;
      line.points.push_back({0, 0, 0});
      line.points.push_back({1, 0, 0});
      line.lines.add({0, 1});
      return line;
    }
  }
  return b.finish();
}

}  // namespace isoforge
