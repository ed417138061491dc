// Fig. 1.27: boolean operations on the offset solids of a point (a ball of radius 0.5) and a
// line from (-1, 0, 0) to (1, 0, 0) (a capsule of radius 0.25), distances on 61 x 41 x 41
// samples: the originals, their union, intersection and difference, in two rows.

#include <fmt/core.h>

#include "figure.hpp"
#include "isoforge/model/csg.hpp"
#include "isoforge/model/distance.hpp"

namespace isoforge::cli::figures {

Output fig_1_27(const Context&) {
  PolyData point, line;
  point.points.push_back({0, 0, 0});
  point.verts.add({0});
  line.points.push_back({-1, 0, 0});
  line.points.push_back({1, 0, 0});
  line.lines.add({0, 1});
  Bounds b;
  b.min = {-1.5, -1, -1};
  b.max = {1.5, 1, 1};
  const GridSpec g = GridSpec::from_bounds(b, {61, 41, 41});
  DistanceOptions o;
  o.max_distance = 0.75;
  const ImageData ball = offset(distance_image(point, g, o).output, 0.5);
  const ImageData capsule = offset(distance_image(line, g, o).output, 0.25);
  Output out;
  out.datasets.emplace_back("ball", ball);
  out.datasets.emplace_back("capsule", capsule);
  const PolyData ball_s = offset_surfaces(ball, {0.0}).output;
  const PolyData capsule_s = offset_surfaces(capsule, {0.0}).output;
  out.meshes.push_back({"original: ball", translated(ball_s, {-1.7, 0, 1.2}), "", Colormap::Rainbow,
                        std::nullopt, {230, 120, 90, 255}, 0.6});
  out.meshes.push_back({"original: capsule", translated(capsule_s, {-1.7, 0, 1.2}), "",
                        Colormap::Rainbow, std::nullopt, {90, 150, 230, 255}, 0.6});
  const CsgOperation ops[3] = {CsgOperation::Union, CsgOperation::Intersection,
                               CsgOperation::Difference};
  // Two rows: the originals and the union above, the intersection and the difference below.
  const Vec3 kPlace[3] = {{1.7, 0, 1.2}, {-1.7, 0, -1.2}, {1.7, 0, -1.2}};
  const long want_genus[3] = {0, 0, 1};  // a ball on a rod; the rod's middle; a ring
  std::string check;
  bool ok = true;
  std::size_t triangles = 0;
  for (int k = 0; k < 3; ++k) {
    const PolyData s = offset_surfaces(csg(ball, capsule, ops[k]), {0.0}).output;
    const SurfaceTopology t = analyze_topology(s);
    const std::string name(csg_operation_name(ops[k]));
    ok = ok && t.closed() && t.manifold() && t.components.size() == 1 &&
         t.components[0].genus == want_genus[k];
    check += fmt::format("{}{} genus {}", k ? ", " : "", name,
                         t.components.empty() ? -1 : t.components[0].genus);
    triangles += s.polys.size();
    out.datasets.emplace_back(name, s);
    out.meshes.push_back({name, translated(s, kPlace[k]), "", Colormap::Rainbow,
                          std::nullopt, {200, 200, 120, 255}});
  }
  out.counts = fmt::format("61x41x41 samples, {} triangles", triangles);
  out.check = "closed manifold: " + check;
  out.ok = ok;
  return out;
}

}  // namespace isoforge::cli::figures
