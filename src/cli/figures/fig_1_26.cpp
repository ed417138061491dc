// Fig. 1.26: distance functions to a point, a line and a triangle (the implicit modeller on 61^3
// samples over [-1.2, 1.2]^3), each shown by its offset surface at distance 0.3 around the
// generator.

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "figure.hpp"
#include "isoforge/core/closest_point.hpp"
#include "isoforge/model/csg.hpp"
#include "isoforge/model/implicit_modeller.hpp"

namespace isoforge::cli::figures {

Output fig_1_26(const Context&) {
  PolyData point, line, tri;
  point.points.push_back({0, 0, 0});
  point.verts.add({0});
  line.points.push_back({-0.5, 0, 0});
  line.points.push_back({0.5, 0, 0});
  line.lines.add({0, 1});
  for (const Vec3& p : {Vec3{-0.5, -0.4, 0}, Vec3{0.5, -0.4, 0}, Vec3{0, 0.5, 0}}) {
    tri.points.push_back(p);
  }
  tri.polys.add({0, 1, 2});
  const double d = 0.3;
  Bounds box;
  box.min = {-1.2, -1.2, -1.2};
  box.max = {1.2, 1.2, 1.2};
  Output out;
  double worst = 0;  // largest |distance - d| over the surfaces' points, in units of h
  bool ok = true;
  std::size_t triangles = 0;
  const char* names[3] = {"point", "line", "triangle"};
  const Rgba8 colors[3] = {{230, 90, 80, 255}, {90, 180, 90, 255}, {80, 130, 230, 255}};
  int k = 0;
  for (const PolyData* gen : {&point, &line, &tri}) {
    ImplicitModellerOptions o;
    o.sample_dimensions = {61, 61, 61};
    o.model_bounds = box;
    o.maximum_distance = 0.25;  // 0.6 world units, beyond the offset
    const ImageData img = implicit_modeller(*gen, o).output;
    const PolyData surface = offset_surfaces(img, {d}).output;
    const double h = img.spacing.x;
    for (std::size_t i = 0; i < surface.num_points(); ++i) {
      const Vec3 p = surface.points[i];
      const double e = k == 0   ? norm(p)
                       : k == 1 ? std::sqrt(segment_distance2(p, line.points[0], line.points[1]))
                                : std::sqrt(triangle_distance2(p, tri.points[0], tri.points[1],
                                                               tri.points[2]));
      worst = std::max(worst, std::abs(e - d) / h);
    }
    const SurfaceTopology t = analyze_topology(surface);
    ok = ok && t.closed() && t.manifold() && t.components.size() == 1;
    triangles += surface.polys.size();
    const Vec3 shift{2.0 * (k - 1), 0, 0};
    out.datasets.emplace_back(fmt::format("distance_to_{}", names[k]), img);
    out.datasets.emplace_back(fmt::format("offset_{}", names[k]), surface);
    out.meshes.push_back({fmt::format("{} generator", names[k]), translated(*gen, shift), "",
                          Colormap::Rainbow, std::nullopt, {250, 250, 250, 255}});
    out.meshes.push_back({fmt::format("distance {} to the {}", d, names[k]),
                          translated(surface, shift), "", Colormap::Rainbow, std::nullopt,
                          colors[k], 0.55});
    ++k;
  }
  out.counts = fmt::format("3 x 61^3 samples, {} triangles", triangles);
  out.check = fmt::format("3 closed manifold surfaces, distance error max {:.2g} h", worst);
  out.ok = ok && worst < 0.1;
  return out;
}

}  // namespace isoforge::cli::figures
