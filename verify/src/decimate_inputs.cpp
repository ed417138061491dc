// Inputs of the decimation cases and benchmark (see decimate_inputs.hpp).

#include "decimate_inputs.hpp"

#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "isoforge/contour/contour.hpp"
#include "isoforge/core/mesh_topology.hpp"
#include "isoforge/io/io.hpp"

namespace isoforge::verify {

namespace {

using Tri = std::array<Index, 3>;

PolyData from_triangles(const std::vector<Vec3>& points, const std::vector<Tri>& tris) {
  PolyData pd;
  pd.points.reserve(points.size());
  for (const auto& p : points) pd.points.push_back(p);
  pd.polys.reserve(tris.size(), 3 * tris.size());
  for (const auto& t : tris) pd.polys.add({t[0], t[1], t[2]});
  return pd;
}

// Unit icosphere: points on the unit sphere, outward triangles.
std::pair<std::vector<Vec3>, std::vector<Tri>> unit_icosphere(int subdivisions) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> p = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (auto& v : p) v = v / norm(v);
  std::vector<Tri> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                        {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                        {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                        {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<Index, Index>, Index> midpoint;
    const auto mid = [&](Index a, Index b) {
      const auto key = std::minmax(a, b);
      const auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      const Vec3 m = p[static_cast<std::size_t>(a)] + p[static_cast<std::size_t>(b)];
      p.push_back(m / norm(m));
      const auto id = static_cast<Index>(p.size() - 1);
      midpoint.emplace(key, id);
      return id;
    };
    std::vector<Tri> next;
    next.reserve(4 * f.size());
    for (const auto& [a, b, c] : f) {
      const Index ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      next.push_back({a, ab, ca});
      next.push_back({b, bc, ab});
      next.push_back({c, ca, bc});
      next.push_back({ab, bc, ca});
    }
    f = std::move(next);
  }
  return {std::move(p), std::move(f)};
}

}  // namespace

PolyData icosphere(int subdivisions, double radius, const Vec3& center) {
  auto [p, f] = unit_icosphere(subdivisions);
  for (auto& v : p) v = center + v * radius;
  return from_triangles(p, f);
}

PolyData noisy_sphere(int subdivisions, double amplitude, unsigned seed, double radius) {
  auto [p, f] = unit_icosphere(subdivisions);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  for (auto& v : p) v = v * (radius * (1.0 + u(rng)));
  return from_triangles(p, f);
}

PolyData cut_by_plane(const PolyData& mesh, const Vec3& origin, const Vec3& normal) {
  const auto tris = triangulate_faces(mesh);
  std::vector<Index> remap(mesh.points.size(), -1);
  std::vector<Vec3> points;
  std::vector<Tri> kept;
  for (const auto& t : tris) {
    const Vec3 c =
        (mesh.points[static_cast<std::size_t>(t[0])] + mesh.points[static_cast<std::size_t>(t[1])] +
         mesh.points[static_cast<std::size_t>(t[2])]) /
        3.0;
    if (!(dot(c - origin, normal) < 0)) continue;
    Tri out{};
    for (std::size_t k = 0; k < 3; ++k) {
      auto& id = remap[static_cast<std::size_t>(t[k])];
      if (id < 0) {
        id = static_cast<Index>(points.size());
        points.push_back(mesh.points[static_cast<std::size_t>(t[k])]);
      }
      out[k] = id;
    }
    kept.push_back(out);
  }
  return from_triangles(points, kept);
}

PolyData spheres_glued_on_edge(int subdivisions) {
  auto [p, f] = unit_icosphere(subdivisions);
  // The edge: the first one of the first triangle. Every other vertex of the convex polyhedron
  // is farther from the edge's midpoint direction than the edge's ends, so the polyhedron lies
  // on one side of the mirror plane and touches it along the edge only.
  const Index u = f[0][0], v = f[0][1];
  const Vec3 pu = p[static_cast<std::size_t>(u)], pv = p[static_cast<std::size_t>(v)];
  const Vec3 n = (pu + pv) / norm(pu + pv);
  const double d = dot(n, pu);
  std::vector<Index> image(p.size());
  for (std::size_t i = 0; i < image.size(); ++i) {
    const auto id = static_cast<Index>(i);
    if (id == u || id == v) {
      image[i] = id;
    } else {
      image[i] = static_cast<Index>(p.size());
      p.push_back(p[i] - n * (2 * (dot(n, p[i]) - d)));
    }
  }
  const std::size_t faces = f.size();
  for (std::size_t k = 0; k < faces; ++k) {
    const Tri t = f[k];
    // A mirror image reverses orientation: swap two corners to face outward again.
    f.push_back({image[static_cast<std::size_t>(t[0])], image[static_cast<std::size_t>(t[2])],
                 image[static_cast<std::size_t>(t[1])]});
  }
  return from_triangles(p, f);
}

PolyData headsq_surface(const std::string& data_dir, double isovalue) {
  const Dataset ds = read(std::filesystem::path(data_dir) / "headsq/quarter.nhdr");
  const auto* img = std::get_if<ImageData>(&ds);
  if (!img) throw Error("headsq/quarter.nhdr: not image data");
  ContourOptions o;
  o.values = {isovalue};
  o.flip = true;
  return contour_image(*img, o).output;
}

const std::vector<std::string>& decimation_input_kinds() {
  static const std::vector<std::string> kinds = {"bunny", "headsq", "noisy-sphere", "open-bunny",
                                                 "glued-spheres"};
  return kinds;
}

PolyData decimation_input(const std::string& kind) {
  const auto bunny = [] {
    Dataset ds = read(ISOFORGE_DATA_DIR "/bunny.ply");
    return std::get<PolyData>(std::move(ds));
  };
  if (kind == "bunny") return bunny();
  if (kind == "headsq") return headsq_surface(ISOFORGE_DATA_DIR, 1150);
  // Radial noise of +-0.5 % of the radius: about a third of an edge.
  if (kind == "noisy-sphere") return noisy_sphere(6, 0.005, 1);
  if (kind == "open-bunny") {
    const PolyData b = bunny();
    const Bounds box = b.bounds();
    return cut_by_plane(b, (box.min + box.max) * 0.5, {1, 0, 0});
  }
  if (kind == "glued-spheres") return spheres_glued_on_edge(5);
  throw Error("decimation input: unknown kind '" + kind + "'");
}

}  // namespace isoforge::verify
