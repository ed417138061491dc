// Fig. 1.4c (section 1.4; VTK's TensorEllipsoids): the stress of a point load of 100 on a
// half-space (Boussinesq, model/point_load.hpp) sampled on 6³ points of [−10, 10]³, drawn as
// ellipsoids coloured by the largest eigenvalue; a cone marks the load, an outline the box.

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "figure.hpp"
#include "isoforge/filters/glyph.hpp"
#include "isoforge/filters/tensor_glyph.hpp"
#include "isoforge/model/point_load.hpp"

namespace isoforge::cli::figures {

Output fig_1_4c(const Context& ctx) {
  PointLoadOptions po;
  po.bounds = {{-10, -10, -10}, {10, 10, 10}};
  po.dims = {6, 6, 6};
  po.load = 100;
  const auto [field, ps] = point_load(po);
  TensorGlyphOptions to;
  to.scale = 6;
  to.max_size = 1.9;  // half the spacing (4) minus a little: the ellipsoids never touch
  to.resolution = 20;
  to.progress = ctx.progress;
  const auto [ellipsoids, ts] = tensor_glyph(field, to);
  // The sampled tensors against the closed form's trace, −(1 + ν) P d / (π ρ³).
  const DataArray& t = field.point_data.get("stress");
  double worst = 0;
  for (std::size_t p = 0; p < field.num_points(); ++p) {
    const Vec3 q = field.point(Index(p));
    const double d = 10 - q.z, rho = std::sqrt(q.x * q.x + q.y * q.y + d * d);
    const double trace = -(1 + po.poisson_ratio) * po.load * d / (std::numbers::pi * rho * rho * rho);
    const double got = t.get(p, 0) + t.get(p, 4) + t.get(p, 8);
    worst = std::max(worst, std::abs(got - trace) / std::max(std::abs(trace), 1e-3));
  }
  double reach = 0;
  const DataArray& ids = ellipsoids.point_data.get("InputPointIds");
  for (std::size_t i = 0; i < ellipsoids.points.size(); ++i) {
    reach = std::max(reach, norm(ellipsoids.points[i] - field.point(Index(ids.get(i)))));
  }
  // The load: a cone above the top face's centre, pointing down.
  PolyData at;
  at.points.push_back({0, 0, 11.2});
  DataArray down("down", ScalarType::Float32, 3, 1);
  down.set(0, 2, -1);
  at.point_data.add(std::move(down), AttributeRole::Vectors);
  GlyphOptions go;
  go.factor = 2.4;
  const PolyData cone = glyph(at, glyph_source(GlyphShape::Cone, 24), go).output;
  Output out;
  out.datasets.emplace_back("point_load", field);
  out.datasets.emplace_back("ellipsoids", ellipsoids);
  out.meshes.push_back({"ellipsoids", ellipsoids, "TensorColor", Colormap::Rainbow, std::nullopt});
  out.meshes.push_back({"load", cone, "", Colormap::Rainbow, std::nullopt, {200, 40, 40, 255}});
  out.meshes.push_back({"outline", box_outline(po.bounds), "", Colormap::Rainbow, std::nullopt,
                        {60, 60, 60, 255}});
  out.counts = fmt::format("{} ellipsoids, {} triangles", ts.glyphs, ellipsoids.polys.size());
  out.check = fmt::format(
      "{} flat (the free surface), largest semi-axis {:.3f} <= 1.9; stress trace within {:.1e} "
      "of -(1+nu) P d / (pi rho^3)",
      ts.degenerate, reach, worst);
  out.ok = ts.glyphs == 216 && ts.degenerate == 36 && ps.singular == 0 && reach <= 1.9 + 1e-5 &&
           worst < 1e-5;
  return out;
}

}  // namespace isoforge::cli::figures
