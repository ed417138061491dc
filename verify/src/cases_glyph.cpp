// Verification cases for glyphs, surface normals and tubes: glyph counts exact and every glyph
// a closed, outward copy of its source (exact orientation, no self-intersections once the
// glyphs' coincident crease points are welded); compute_normals turns a closed surface with
// reversed triangles into an outward one (exact) with point normals agreeing with their faces;
// capped tubes are closed and outward with the prism volume; Fig. 1.30's cones lie along the
// face's normals.

#include <fmt/core.h>

#include <cmath>
#include <map>
#include <numbers>
#include <tuple>

#include "case_support.hpp"
#include "isoforge/contour/contour.hpp"
#include "isoforge/filters/compute_normals.hpp"
#include "isoforge/filters/glyph.hpp"
#include "isoforge/filters/tube.hpp"
#include "isoforge/io/io.hpp"

namespace isoforge::verify {

namespace {

// The polygons of `pd` on points merged by exact position (glyphs and tubes duplicate the
// points along their creases, each copy with its own normal).
PolyData welded(const PolyData& pd) {
  std::map<std::tuple<double, double, double>, Index> ids;
  std::vector<Index> map(pd.num_points());
  PolyData m;
  for (std::size_t i = 0; i < pd.num_points(); ++i) {
    const Vec3 p = pd.points[i];
    const auto [it, fresh] = ids.emplace(std::make_tuple(p.x, p.y, p.z), static_cast<Index>(m.num_points()));
    if (fresh) m.points.push_back(p);
    map[i] = it->second;
  }
  std::vector<Index> cell;
  for (std::size_t c = 0; c < pd.polys.size(); ++c) {
    cell.clear();
    for (const Index id : pd.polys.cell(c)) cell.push_back(map[static_cast<std::size_t>(id)]);
    m.polys.add(cell);
  }
  return m;
}

double polygon_area(int r, double R) { return 0.5 * r * R * R * std::sin(2 * std::numbers::pi / r); }

void glyph_case(CaseResult& r, GlyphShape shape, const char* name, std::size_t points_each,
                std::size_t triangles_each, double source_volume) {
  // 8^3 lattice points 1 apart with a swirling vector field; 100 of them at random get a glyph
  // of size 0.2 .. 0.45 (the vector's length times 0.3): glyphs never touch.
  ImageData img;
  img.dims = {8, 8, 8};
  DataArray v("V", ScalarType::Float64, 3, img.num_points());
  for (std::size_t i = 0; i < img.num_points(); ++i) {
    const Vec3 p = img.point(static_cast<Index>(i));
    const Vec3 d{std::sin(p.y + 0.3), std::cos(p.z * 0.7), std::sin(p.x * 1.3 + 1)};
    const Vec3 u = d / norm(d);
    const double len = 0.2 / 0.3 + (0.25 / 0.3) * (0.5 + 0.5 * std::sin(static_cast<double>(i)));
    for (int c = 0; c < 3; ++c) v.set(i, c, u[c] * len);
  }
  img.point_data.add(std::move(v), AttributeRole::Vectors);
  GlyphOptions o;
  o.scale = GlyphScale::Vector;
  o.factor = 0.3;
  o.mask.random = 100;
  o.mask.seed = 2026;
  const auto [out, stats] = glyph(img, shape, o, 8);
  r.equal("glyphs", stats.glyphs, std::size_t{100});
  r.equal(fmt::format("points (100 x {})", points_each), out.num_points(), 100 * points_each);
  r.equal(fmt::format("triangles (100 x {})", triangles_each), out.polys.size(), 100 * triangles_each);
  const PolyData w = welded(out);
  const MeshReport m = check_mesh(w);
  note_mesh(r, m, "welded: ");
  record_closed_surface(r, m);
  r.equal("components (one per glyph)", m.components.size(), std::size_t{100});
  // Volume: each glyph is the source scaled by its size; the sizes are known per glyph.
  double expected = 0;
  const auto ids = mask_point_ids(img, o.mask);
  for (const Index id : ids) {
    const DataArray& a = img.point_data.get("V");
    const double s = 0.3 * norm(Vec3{a.get(static_cast<std::size_t>(id), 0), a.get(static_cast<std::size_t>(id), 1),
                                     a.get(static_cast<std::size_t>(id), 2)});
    expected += s * s * s * source_volume;
  }
  r.within(std::string(name) + " volume / sum of size^3 x source volume", m.volume / expected,
           1 - 1e-5, 1 + 1e-5);
}

void normals_case(CaseResult& r) {
  // A torus contoured from a 64-sample grid, a third of its triangles reversed.
  const ImplicitFunction f = ImplicitFunction::torus({0.02, 0.01, -0.03}, {0, 1, 1}, 0.55, 0.25);
  Bounds box;
  box.extend({-1, -1, -1});
  box.extend({1, 1, 1});
  PolyData s = contour_image(sample_image(f, verify::cubic_grid(box, Index{64}))).output;
  std::size_t reversed = 0;
  for (std::size_t c = 0; c < s.polys.size(); c += 3) {
    auto ids = s.polys.cell(c);
    std::reverse(ids.begin() + 1, ids.end());
    ++reversed;
  }
  NormalsOptions o;
  o.split = false;
  const auto [smooth, st] = compute_normals(s, o);
  r.note("input", fmt::format("{} triangles, {} reversed", s.polys.size(), reversed));
  r.equal("reversed triangles put back", st.flipped_polygons, reversed);
  r.equal("surfaces (closed)", st.closed_surfaces, std::size_t{1});
  const MeshReport m = check_mesh(smooth);
  record_closed_surface(r, m);
  r.at_least("volume > 0", m.volume, 1e-9);
  // Split at 30 degrees, welded back: the same outward surface; every corner's point normal
  // within 90 degrees of its triangle's normal.
  const auto [split, ss] = compute_normals(s);
  r.note("points added by splitting at 30 degrees", fmt::format("{}", ss.split_points));
  const MeshReport ms = check_mesh(welded(split));
  r.is_true("split surface, welded: outward (exact)", ms.outward);
  std::size_t against = 0;
  const DataArray& n = split.point_data.get("Normals");
  for (std::size_t c = 0; c < split.polys.size(); ++c) {
    const auto ids = split.polys.cell(c);
    const Vec3 a = split.points[static_cast<std::size_t>(ids[0])];
    const Vec3 fn = cross(split.points[static_cast<std::size_t>(ids[1])] - a,
                          split.points[static_cast<std::size_t>(ids[2])] - a);
    for (const Index id : ids) {
      const auto i = static_cast<std::size_t>(id);
      against += dot(fn, Vec3{n.get(i, 0), n.get(i, 1), n.get(i, 2)}) <= 0 ? 1 : 0;
    }
  }
  r.equal("corners whose point normal is 90 degrees or more from the face", against, std::size_t{0});
}

void tube_case(CaseResult& r) {
  // A helix of radius 1 and pitch 0.6 (2 turns, 121 points), tube radius 0.1, 10 sides, capped.
  PolyData line;
  std::vector<Index> ids;
  double length = 0;
  for (int i = 0; i <= 120; ++i) {
    const double t = 4 * std::numbers::pi * i / 120;
    line.points.push_back({std::cos(t), std::sin(t), 0.6 * t / (2 * std::numbers::pi)});
    ids.push_back(i);
    if (i > 0) length += norm(line.points[static_cast<std::size_t>(i)] - line.points[static_cast<std::size_t>(i - 1)]);
  }
  line.lines.add(ids);
  TubeOptions o;
  o.radius = 0.1;
  o.sides = 10;
  const auto [out, stats] = tube(line, o);
  r.equal("points (121 rings + 2 caps of 10)", out.num_points(), std::size_t{1230});
  r.equal("triangles (120 x 20 + 2 x 8)", out.polys.size(), std::size_t{2416});
  const MeshReport m = check_mesh(welded(out));
  record_closed_surface(r, m);
  // The rings are normal to the mean tangent, so the volume is the polygon's area times the
  // length to within the bend (1 - cos of half the turn per segment, here ~1e-3).
  r.within("volume / (decagon area x line length)", m.volume / (polygon_area(10, 0.1) * length),
           0.99, 1.01);
}

void figure_130_case(CaseResult& r) {
  const auto face = std::get<PolyData>(read(ISOFORGE_DATA_DIR "/fran_cut.vtk"));
  NormalsOptions no;
  no.flip = true;  // the file's triangles face into the head (the textbook flips them too)
  const auto [surface, ns] = compute_normals(face, no);
  GlyphOptions o;
  o.orient = GlyphOrient::Normals;
  o.factor = 0.01;
  o.mask.random = 220;
  o.mask.seed = 1;
  const auto [cones, gs] = glyph(surface, GlyphShape::Cone, o);
  r.equal("cones", gs.glyphs, std::size_t{220});
  r.equal("points", cones.num_points(), std::size_t{220 * 13});
  r.equal("triangles", cones.polys.size(), std::size_t{2200});
  const DataArray& n = surface.point_data.get("Normals");
  const DataArray& ids = cones.point_data.get("InputPointIds");
  double worst = 0;
  for (std::size_t g = 0; g < 220; ++g) {
    const auto id = static_cast<std::size_t>(ids.get(g * 13));
    Vec3 base{0, 0, 0};
    for (std::size_t j = 7; j < 13; ++j) base += cones.points[g * 13 + j];
    const Vec3 axis = cones.points[g * 13] - base / 6.0;
    // The angle by atan2(|a x n|, a . n): exact near 0, where acos of a rounded cosine is not.
    const Vec3 nn{n.get(id, 0), n.get(id, 1), n.get(id, 2)};
    const double angle = std::atan2(norm(cross(axis, nn)), dot(axis, nn));
    worst = std::max(worst, angle * 180 / std::numbers::pi);
  }
  // The cones' points are floats of magnitude <= 0.25 (ulp 3e-8) 0.01 from each other: the axis
  // may turn by a few 1e-6 rad (1e-4 degrees).
  r.at_most("largest angle between a cone's axis and its point's normal (degrees)", worst, 1e-3);
  const MeshReport m = check_mesh(welded(cones), {false});
  r.equal("welded cones: border edges", m.border_edges, std::size_t{0});
  r.equal("welded cones: inconsistent edges", m.inconsistent_edges, std::size_t{0});
}

}  // namespace

void add_glyph_cases(std::vector<Case>& cases) {
  cases.push_back({"glyph/cones", "100 cones (8 sides) at random lattice points: counts, closed, outward, volume",
                   true, [](CaseResult& r) {
                     glyph_case(r, GlyphShape::Cone, "cone", 17, 14, polygon_area(8, 0.5) / 3);
                   }});
  cases.push_back({"glyph/arrows", "100 arrows (8 sides): counts, closed, outward, volume", false,
                   [](CaseResult& r) {
                     glyph_case(r, GlyphShape::Arrow, "arrow", 49, 46,
                                polygon_area(8, 0.03) * 0.65 + polygon_area(8, 0.1) * 0.35 / 3);
                   }});
  cases.push_back({"glyph/cubes", "100 cubes: counts, closed, outward, volume", false,
                   [](CaseResult& r) { glyph_case(r, GlyphShape::Cube, "cube", 24, 12, 1.0); }});
  cases.push_back({"glyph/figure-1.30", "cones along the normals of fran_cut (Fig. 1.30)", true,
                   [](CaseResult& r) { figure_130_case(r); }});
  cases.push_back({"normals/torus-reversed", "compute_normals on a torus with a third of its triangles reversed: outward (exact)",
                   false, [](CaseResult& r) { normals_case(r); }});
  cases.push_back({"tube/helix-capped", "capped tube around a helix: closed, outward, prism volume",
                   false, [](CaseResult& r) { tube_case(r); }});
}

}  // namespace isoforge::verify
