// Fig. 1.30: cones along the surface normals of a face (data/fran_cut.vtk) at 220 randomly
// chosen points (a tenth of the face's), 0.01 long; normals flipped to point out of the face.

#include <fmt/core.h>

#include <algorithm>

#include "figure.hpp"
#include "isoforge/filters/compute_normals.hpp"
#include "isoforge/filters/glyph.hpp"
#include "isoforge/io/io.hpp"

namespace isoforge::cli::figures {

Output fig_1_30(const Context& ctx) {
  const PolyData face = std::get<PolyData>(read(data_file(ctx, "fran_cut.vtk")));
  NormalsOptions no;
  no.flip = true;  // the file's polygons face into the head
  const auto [surface, ns] = compute_normals(face, no);
  GlyphOptions o;
  o.orient = GlyphOrient::Normals;
  o.factor = 0.01;
  o.mask.random = 220;
  o.mask.seed = 1;
  o.progress = ctx.progress;
  const auto [cones, gs] = glyph(surface, GlyphShape::Cone, o);
  // Each cone's axis (apex minus the mean of its base ring) along its point's normal.
  const DataArray& normals = surface.point_data.get("Normals");
  const DataArray& ids = cones.point_data.get("InputPointIds");
  double worst = 1;
  for (std::size_t g = 0; g < gs.glyphs; ++g) {
    const auto id = static_cast<std::size_t>(ids.get(g * 13));
    Vec3 base{0, 0, 0};
    for (std::size_t j = 7; j < 13; ++j) base += cones.points[g * 13 + j];
    const Vec3 axis = cones.points[g * 13] - base / 6.0;
    const Vec3 n{normals.get(id, 0), normals.get(id, 1), normals.get(id, 2)};
    worst = std::min(worst, dot(axis / norm(axis), n));
  }
  Output out;
  out.datasets.emplace_back("face", surface);
  out.datasets.emplace_back("cones", cones);
  out.meshes.push_back({"face", surface, "", Colormap::Rainbow, std::nullopt, {235, 200, 175, 255}});
  out.meshes.push_back({"cones", cones, "", Colormap::Rainbow, std::nullopt, {220, 60, 50, 255}});
  out.counts = fmt::format("{} triangles, {} cones", surface.polys.size(), gs.glyphs);
  out.check = fmt::format("{} surface, {} inconsistent edges, cone axes along normals (cos >= {:.6f})",
                          ns.surfaces, ns.inconsistent_edges, worst);
  out.ok = gs.glyphs == 220 && ns.inconsistent_edges == 0 && worst > 1 - 1e-6;
  return out;
}

}  // namespace isoforge::cli::figures
