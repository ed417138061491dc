// Accuracy checks (see accuracy.hpp): side check with float-storage tolerances, barycentric-grid
// mesh sampling, area-uniform sphere (Fibonacci lattice) and torus (inverse-CDF grid) samplers,
// distances to analytic surfaces and between meshes, convergence order by least squares,
// border-on-domain-boundary and exact surface identity. No CGAL here: the AABB tree is behind
// MeshDistance (mesh_distance.cpp).

#include "accuracy.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <tuple>
#include <unordered_map>

#include "isoforge/core/mesh_topology.hpp"
#include "mesh_distance.hpp"

namespace isoforge::verify {

namespace {

constexpr double kPi = std::numbers::pi;

Vec3 unit(const Vec3& v) {
  const double n = norm(v);
  if (!(n > 0) || !std::isfinite(n)) throw Error("accuracy: zero or non-finite direction");
  return v / n;
}

// Two unit vectors completing `a` (unit) to a right-handed orthonormal frame.
std::pair<Vec3, Vec3> frame(const Vec3& a) {
  const Vec3 helper = std::abs(a.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 e1 = unit(cross(helper, a));
  return {e1, cross(a, e1)};
}

// Values of f at points, in blocks (one tree walk per block).
std::vector<double> evaluate(const ImplicitFunction& f, std::span<const Vec3> pts) {
  std::vector<double> xyz(3 * pts.size()), v(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    xyz[3 * i] = pts[i].x;
    xyz[3 * i + 1] = pts[i].y;
    xyz[3 * i + 2] = pts[i].z;
  }
  f.evaluate(xyz, v);
  return v;
}

double weighted_rms(std::span<const double> d, std::span<const double> w) {
  double s = 0, ws = 0;
  for (std::size_t i = 0; i < d.size(); ++i) {
    const double wi = w.empty() ? 1.0 : w[i];
    s += wi * d[i] * d[i];
    ws += wi;
  }
  return ws > 0 ? std::sqrt(s / ws) : 0.0;
}

double max_of(std::span<const double> d) {
  double m = 0;
  for (double x : d) m = std::max(m, x);
  return m;
}

}  // namespace

// ---- side -------------------------------------------------------------------------------------

double side_tolerance(const Vec3& p, ScalarType storage, const Vec3& gradient, double ulps,
                      double scale) {
  const double m = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z), std::abs(scale)});
  double ulp = 0;
  if (storage == ScalarType::Float32) {
    const float mf = static_cast<float>(m);
    ulp = static_cast<double>(std::nextafter(mf, std::numeric_limits<float>::infinity()) - mf);
  } else {
    ulp = std::nextafter(m, std::numeric_limits<double>::infinity()) - m;
  }
  return ulps * ulp * norm(gradient);
}

SideReport check_side(const Points& points, const ImplicitFunction& f, Side side, double ulps,
                      double scale) {
  SideReport r;
  r.points = points.size();
  std::vector<Vec3> pts(points.size());
  for (std::size_t i = 0; i < pts.size(); ++i) pts[i] = points[i];
  const std::vector<double> v = evaluate(f, pts);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const double tol = side_tolerance(pts[i], points.type(), f.gradient(pts[i]), ulps, scale);
    const double excess =
        side == Side::Inside ? v[i] : (side == Side::Outside ? -v[i] : std::abs(v[i]));
    // excess / tol, with tol = 0 (a vanishing gradient) meaning "no slack".
    double ratio = 0;
    if (tol > 0) {
      ratio = excess / tol;
    } else {
      ratio = excess > 0 ? std::numeric_limits<double>::infinity() : (excess < 0 ? -1e300 : 0.0);
    }
    const bool bad = excess > tol;
    if (bad) ++r.violations;
    if (!bad && excess > 0) ++r.within_tolerance;
    if (ratio > r.worst_ratio) {
      r.worst_ratio = ratio;
      r.worst_value = v[i];
      r.worst_point = i;
    }
  }
  return r;
}

// ---- sampling -------------------------------------------------------------------------------

Samples sample_mesh(const PolyData& mesh, double spacing, int min_subdivisions) {
  if (!(spacing > 0)) throw Error("sample_mesh: spacing must be > 0");
  mesh.polys.validate(mesh.points.size(), "polys");
  mesh.strips.validate(mesh.points.size(), "strips");
  const auto tris = triangulate_faces(mesh);
  Samples s;
  for (const auto& t : tris) {
    const Vec3 a = mesh.points[static_cast<std::size_t>(t[0])];
    const Vec3 b = mesh.points[static_cast<std::size_t>(t[1])];
    const Vec3 c = mesh.points[static_cast<std::size_t>(t[2])];
    const double area = 0.5 * norm(cross(b - a, c - a));
    const double longest = std::max({norm(b - a), norm(c - b), norm(a - c)});
    // An even n puts samples on the edge midpoints, where a chord is farthest from a convex arc.
    int n = std::max(min_subdivisions, static_cast<int>(std::ceil(longest / spacing)));
    n += n % 2;
    // Weights of the composite vertex rule: a node stands for a third of each of the n² small
    // triangles around it (a corner touches 1, an edge node 3, an interior node 6), so the
    // weighted sums integrate over the area without favouring corners and edges (which are
    // shared with the neighbours, and where decimated vertices sit).
    const double unit = area / (3.0 * n * n);
    for (int i = 0; i <= n; ++i) {
      for (int j = 0; j <= n - i; ++j) {
        const int k = n - i - j;
        const double inv = 1.0 / n;
        const int zeros = (i == 0) + (j == 0) + (k == 0);
        s.points.push_back(a * (i * inv) + b * (j * inv) + c * (k * inv));
        s.weights.push_back(unit * (zeros >= 2 ? 1 : (zeros == 1 ? 3 : 6)));
      }
    }
    s.points.push_back((a + b + c) / 3.0);  // for the maxima; the grid has the area
    s.weights.push_back(0);
  }
  return s;
}

double mean_edge_length(const PolyData& mesh) {
  const auto tris = triangulate_faces(mesh);
  double sum = 0;
  for (const auto& t : tris) {
    for (int e = 0; e < 3; ++e) {
      sum += norm(mesh.points[static_cast<std::size_t>(t[e])] -
                  mesh.points[static_cast<std::size_t>(t[(e + 1) % 3])]);
    }
  }
  return tris.empty() ? 0.0 : sum / (3.0 * static_cast<double>(tris.size()));
}

AnalyticSurface sphere_surface(const Vec3& center, double radius) {
  if (!(radius > 0)) throw Error("sphere_surface: radius must be > 0");
  const double area = 4 * kPi * radius * radius;
  const double volume = 4.0 / 3.0 * kPi * radius * radius * radius;
  auto sample = [center, radius, area](double spacing) {
    // Fibonacci lattice: N points with z uniform in (-1, 1) (Archimedes: area-uniform) and the
    // azimuth advancing by the golden angle.
    const auto n = static_cast<std::size_t>(std::ceil(area / (spacing * spacing)));
    const double golden = kPi * (3.0 - std::sqrt(5.0));
    std::vector<Vec3> p(std::max<std::size_t>(n, 1));
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double z = 1.0 - (2.0 * static_cast<double>(i) + 1.0) / static_cast<double>(p.size());
      const double rho = std::sqrt(std::max(0.0, 1.0 - z * z));
      const double phi = golden * static_cast<double>(i);
      p[i] = center + Vec3{rho * std::cos(phi), rho * std::sin(phi), z} * radius;
    }
    return p;
  };
  return {"sphere", ImplicitFunction::sphere(center, radius), area, volume, sample};
}

AnalyticSurface torus_surface(const Vec3& center, const Vec3& axis, double major, double minor) {
  if (!(major > minor && minor > 0)) throw Error("torus_surface: need major > minor > 0");
  const Vec3 a = unit(axis);
  // Named copies, not a structured binding: clang 14 (make sanitize) cannot capture those.
  const auto basis = frame(a);
  const Vec3 e1 = basis.first, e2 = basis.second;
  auto sample = [=](double spacing) {
    // u around the axis, v around the tube; the area element is r (R + r cos v) du dv, so u is
    // uniform and v follows the CDF (R v + r sin v) / (2 pi R), inverted by Newton's method.
    const auto nu = static_cast<std::size_t>(std::max(3.0, std::ceil(2 * kPi * major / spacing)));
    const auto nv = static_cast<std::size_t>(std::max(3.0, std::ceil(2 * kPi * minor / spacing)));
    const auto invert_cdf = [&](double target) {
      double v = target / major;
      for (int it = 0; it < 50; ++it) {
        const double dv =
            (major * v + minor * std::sin(v) - target) / (major + minor * std::cos(v));
        v -= dv;
        if (std::abs(dv) < 1e-15) break;
      }
      return v;
    };
    std::vector<Vec3> p;
    p.reserve(nu * nv);
    for (std::size_t i = 0; i < nu; ++i) {
      // Rows are staggered by a golden-ratio fraction of a step so samples do not line up in v.
      const double shift = std::fmod(static_cast<double>(i) * 0.6180339887498949, 1.0);
      const double u = 2 * kPi * (static_cast<double>(i) + 0.5) / static_cast<double>(nu);
      const Vec3 radial = e1 * std::cos(u) + e2 * std::sin(u);
      for (std::size_t j = 0; j < nv; ++j) {
        const double v = invert_cdf(2 * kPi * major * (static_cast<double>(j) + shift) /
                                    static_cast<double>(nv));
        p.push_back(center + radial * (major + minor * std::cos(v)) + a * (minor * std::sin(v)));
      }
    }
    return p;
  };
  return {"torus", ImplicitFunction::torus(center, axis, major, minor),
          4 * kPi * kPi * major * minor, 2 * kPi * kPi * major * minor * minor, sample};
}

// ---- distances ------------------------------------------------------------------------------

DistanceReport distance_to_surface(const PolyData& mesh, const AnalyticSurface& surface,
                                   double mesh_spacing, double surface_spacing) {
  DistanceReport r;
  const Samples ms = sample_mesh(mesh, mesh_spacing, 2);
  std::vector<double> d = evaluate(surface.sdf, ms.points);
  for (double& x : d) x = std::abs(x);
  r.samples_a = d.size();
  r.max_a_to_b = max_of(d);
  r.rms_a_to_b = weighted_rms(d, ms.weights);

  const MeshDistance tree(mesh);
  const std::vector<Vec3> sp = surface.sample(surface_spacing);
  const std::vector<double> e = tree.distances(sp);
  r.samples_b = e.size();
  r.max_b_to_a = max_of(e);
  r.rms_b_to_a = weighted_rms(e, {});
  return r;
}

DistanceReport mesh_to_mesh_distance(const PolyData& a, const PolyData& b, double spacing) {
  DistanceReport r;
  const MeshDistance ta(a), tb(b);
  const Samples sa = sample_mesh(a, spacing, 2);
  const std::vector<double> da = tb.distances(sa.points);
  r.samples_a = da.size();
  r.max_a_to_b = max_of(da);
  r.rms_a_to_b = weighted_rms(da, sa.weights);
  const Samples sb = sample_mesh(b, spacing, 2);
  const std::vector<double> db = ta.distances(sb.points);
  r.samples_b = db.size();
  r.max_b_to_a = max_of(db);
  r.rms_b_to_a = weighted_rms(db, sb.weights);
  return r;
}

// ---- errors and convergence -----------------------------------------------------------------

AreaVolume area_and_volume(const PolyData& mesh) {
  AreaVolume r;
  for (const auto& t : triangulate_faces(mesh)) {
    const Vec3 a = mesh.points[static_cast<std::size_t>(t[0])];
    const Vec3 b = mesh.points[static_cast<std::size_t>(t[1])];
    const Vec3 c = mesh.points[static_cast<std::size_t>(t[2])];
    r.area += 0.5 * norm(cross(b - a, c - a));
    r.volume += dot(a, cross(b, c)) / 6.0;
  }
  return r;
}

double relative_error(double measured, double truth) {
  return std::abs(measured - truth) / std::abs(truth);
}

double convergence_order(std::span<const double> h, std::span<const double> error) {
  if (h.size() != error.size() || h.size() < 2) {
    throw Error("convergence_order: need at least two (h, error) pairs of equal count");
  }
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const auto n = static_cast<double>(h.size());
  for (std::size_t i = 0; i < h.size(); ++i) {
    if (!(h[i] > 0) || !(error[i] > 0)) throw Error("convergence_order: values must be > 0");
    const double x = std::log(h[i]), y = std::log(error[i]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  const double den = n * sxx - sx * sx;
  if (!(std::abs(den) > 0)) throw Error("convergence_order: all h are equal");
  return (n * sxy - sx * sy) / den;
}

// ---- borders and identity ---------------------------------------------------------------------

BorderReport check_borders(const PolyData& mesh, const Bounds& domain, double tol) {
  const auto tris = triangulate_faces(mesh);
  std::unordered_map<std::uint64_t, int> uses;
  const auto key = [](Index a, Index b) {
    if (a > b) std::swap(a, b);
    return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint64_t>(b);
  };
  if (mesh.points.size() >= (std::size_t{1} << 32)) throw Error("check_borders: too many points");
  uses.reserve(tris.size() * 2);
  for (const auto& t : tris) {
    for (int e = 0; e < 3; ++e) ++uses[key(t[e], t[(e + 1) % 3])];
  }
  BorderReport r;
  for (const auto& [k, n] : uses) {
    if (n != 1) continue;
    ++r.border_edges;
    const Vec3 p = mesh.points[static_cast<std::size_t>(k >> 32)];
    const Vec3 q = mesh.points[static_cast<std::size_t>(k & 0xffffffffu)];
    bool on_face = false;
    for (int axis = 0; axis < 3 && !on_face; ++axis) {
      for (double plane : {domain.min[axis], domain.max[axis]}) {
        if (std::abs(p[axis] - plane) <= tol && std::abs(q[axis] - plane) <= tol) on_face = true;
      }
    }
    if (!on_face) ++r.off_boundary;
  }
  return r;
}

namespace {

using Coords = std::array<double, 3>;

Coords coords_of(const PolyData& pd, Index id) {
  const Vec3 p = pd.points[static_cast<std::size_t>(id)];
  return {p.x, p.y, p.z};
}

struct SurfaceRecords {
  std::vector<Coords> points;
  std::vector<std::array<Coords, 3>> triangles;
};

SurfaceRecords records(const PolyData& pd) {
  SurfaceRecords r;
  const auto tris = triangulate_faces(pd);
  std::vector<bool> used(pd.points.size(), false);
  for (const auto& t : tris) {
    std::array<Coords, 3> c = {coords_of(pd, t[0]), coords_of(pd, t[1]), coords_of(pd, t[2])};
    std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
    r.triangles.push_back(c);
    for (Index id : t) used[static_cast<std::size_t>(id)] = true;
  }
  for (std::size_t i = 0; i < used.size(); ++i) {
    if (used[i]) r.points.push_back(coords_of(pd, static_cast<Index>(i)));
  }
  std::sort(r.points.begin(), r.points.end());
  std::sort(r.triangles.begin(), r.triangles.end());
  return r;
}

}  // namespace

SurfaceComparison compare_surfaces(const PolyData& a, const PolyData& b) {
  const SurfaceRecords ra = records(a), rb = records(b);
  SurfaceComparison c;
  c.points_a = ra.points.size();
  c.points_b = rb.points.size();
  c.triangles_a = ra.triangles.size();
  c.triangles_b = rb.triangles.size();
  c.same_points = ra.points == rb.points;
  c.same_triangles = ra.triangles == rb.triangles;
  return c;
}

}  // namespace isoforge::verify
