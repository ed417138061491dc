// Verification cases for implicit modeling (section 1.5.3) and the Lorenz attractor (1.5.2.3):
// - distances against independent oracles: CGAL's AABB tree for triangles (bunny.ply), a
//   brute-force long-double closest point for points and segments (the dense rows);
// - the surfaces of the chapter's figures checked with CGAL's exact predicates: HELLO thickened
//   (Fig. 1.28: five closed letters, the O a torus), the booleans of a ball and a capsule
//   (Fig. 1.27), the attractor's surface (Fig. 1.25);
// - the sparse modeller against the dense one on the band (same bits).
// This is the one translation unit of verify/ that includes OpenVDB (via the model headers).

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "case_support.hpp"
#include "isoforge/io/io.hpp"
#include "isoforge/model/attractor.hpp"
#include "isoforge/model/csg_sparse.hpp"
#include "isoforge/model/distance_sparse.hpp"
#include "isoforge/model/implicit_modeller_sparse.hpp"
#include "mesh_distance.hpp"

namespace isoforge::verify {

namespace {

Bounds box(const Vec3& lo, const Vec3& hi) {
  Bounds b;
  b.extend(lo);
  b.extend(hi);
  return b;
}

template <class T>
std::vector<T> scalars(const ImageData& img) {
  const auto v = img.point_data.scalars()->values<T>();
  return {v.begin(), v.end()};
}

// Distance from p to the segment [a, b] in long double, by the projection written out (not the
// library's kernel).
long double segment_distance_ld(const Vec3& p, const Vec3& a, const Vec3& b) {
  const long double ux = static_cast<long double>(b.x) - a.x, uy = static_cast<long double>(b.y) - a.y,
                    uz = static_cast<long double>(b.z) - a.z;
  const long double wx = static_cast<long double>(p.x) - a.x, wy = static_cast<long double>(p.y) - a.y,
                    wz = static_cast<long double>(p.z) - a.z;
  const long double uu = ux * ux + uy * uy + uz * uz;
  long double t = uu > 0 ? (wx * ux + wy * uy + wz * uz) / uu : 0;
  t = std::clamp(t, 0.0L, 1.0L);
  const long double dx = wx - t * ux, dy = wy - t * uy, dz = wz - t * uz;
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

// Records the band of a dense distance field against reference distances `ref` of its samples:
// values within `tol` inside the band, the band holding exactly the samples closer than maxd
// (ties within tol excepted), and the far value elsewhere.
void record_band(CaseResult& r, const std::vector<double>& v, const std::vector<double>& ref,
                 double maxd, double far, double tol) {
  double worst = 0;
  std::size_t in_band = 0, wrong_band = 0, wrong_far = 0;
  for (std::size_t id = 0; id < v.size(); ++id) {
    if (std::abs(ref[id] - maxd) <= tol) continue;  // a tie with the band's edge
    if (ref[id] < maxd) {
      ++in_band;
      if (v[id] == far) ++wrong_band;
      worst = std::max(worst, std::abs(v[id] - ref[id]));
    } else if (v[id] != far) {
      ++wrong_far;
    }
  }
  r.note("band samples", fmt::format("{} of {}", in_band, v.size()));
  r.at_least("band samples", static_cast<double>(in_band), static_cast<double>(v.size()) / 20);
  r.equal("samples within the maximum distance left out of the band", wrong_band, std::size_t{0});
  r.equal("samples beyond the maximum distance given a value", wrong_far, std::size_t{0});
  r.at_most("max |distance - reference| in the band", worst, tol);
}

void distance_bunny(CaseResult& r) {
  const PolyData bunny = std::get<PolyData>(read(ISOFORGE_DATA_DIR "/bunny.ply"));
  const Bounds b = bunny.bounds();
  const GridSpec g = GridSpec::from_bounds(
      box(b.min - b.size() * 0.1, b.max + b.size() * 0.1), {40, 40, 34});
  DistanceOptions o;
  o.max_distance = 0.1 * b.diagonal();
  o.type = ScalarType::Float64;
  const auto [img, stats] = distance_image(bunny, g, o);
  std::vector<Vec3> pts(img.num_points());
  for (std::size_t id = 0; id < pts.size(); ++id) pts[id] = img.point(static_cast<Index>(id));
  const MeshDistance oracle(bunny);
  const std::vector<double> ref = oracle.distances(pts);
  r.note("input", fmt::format("bunny.ply, {} triangles; {} x {} x {} samples, maximum distance "
                              "0.1 x diagonal; strategy {}",
                              oracle.triangles(), g.dims[0], g.dims[1], g.dims[2],
                              stats.strategy == DistanceStrategy::Gather ? "Gather" : "Scatter"));
  record_band(r, scalars<double>(img), ref, o.max_distance, o.max_distance, 1e-5 * b.diagonal());
  // The other strategy gives the same bits.
  o.strategy = stats.strategy == DistanceStrategy::Gather ? DistanceStrategy::Scatter
                                                          : DistanceStrategy::Gather;
  r.is_true("Scatter and Gather give identical values",
            scalars<double>(distance_image(bunny, g, o).output) ==
                scalars<double>(img));
}

void distance_segments(CaseResult& r) {
  // Random segments, a polyline and points: the dense rows (distance_rows.cpp).
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> u(0, 1);
  PolyData pd;
  const auto random_point = [&] { return Vec3{u(rng), u(rng), u(rng)}; };
  for (int s = 0; s < 60; ++s) {
    const Index i = static_cast<Index>(pd.points.size());
    pd.points.push_back(random_point());
    pd.points.push_back(random_point());
    pd.lines.add({i, i + 1});
  }
  std::vector<Index> line;
  for (int k = 0; k < 40; ++k) {
    const double t = k / 39.0;
    line.push_back(static_cast<Index>(pd.points.size()));
    pd.points.push_back({0.5 + 0.3 * std::cos(9 * t), 0.5 + 0.3 * std::sin(9 * t), t});
  }
  pd.lines.add(line);
  std::vector<Index> verts;
  for (int k = 0; k < 20; ++k) {
    verts.push_back(static_cast<Index>(pd.points.size()));
    pd.points.push_back(random_point());
  }
  pd.verts.add(verts);
  const GridSpec g = GridSpec::from_bounds(box({-0.1, -0.1, -0.1}, {1.1, 1.1, 1.1}), {61, 57, 53});
  DistanceOptions o;
  o.max_distance = 0.08;
  o.type = ScalarType::Float64;
  const auto [img, stats] = distance_image(pd, g, o);
  std::vector<double> ref(img.num_points());
  for (std::size_t id = 0; id < ref.size(); ++id) {
    const Vec3 p = img.point(static_cast<Index>(id));
    long double best = INFINITY;
    for (std::size_t c = 0; c < pd.lines.size(); ++c) {
      const auto ids = pd.lines.cell(c);
      for (std::size_t k = 0; k + 1 < ids.size(); ++k) {
        best = std::min(best, segment_distance_ld(p, pd.points[ids[k]], pd.points[ids[k + 1]]));
      }
    }
    for (Index v : verts) best = std::min(best, segment_distance_ld(p, pd.points[v], pd.points[v]));
    ref[id] = static_cast<double>(best);
  }
  r.note("input", fmt::format("60 random segments, a 39-segment helix, 20 points; {} x {} x {} "
                              "samples, maximum distance 0.08; {} kernel calls on {} z-planes",
                              g.dims[0], g.dims[1], g.dims[2], stats.evaluations, stats.blocks));
  record_band(r, scalars<double>(img), ref, o.max_distance, o.max_distance, 1e-12);
  o.strategy = DistanceStrategy::Gather;
  r.is_true("the rows equal Gather (the block engine) bit for bit",
            scalars<double>(distance_image(pd, g, o).output) ==
                scalars<double>(img));
}

PolyData hello() { return std::get<PolyData>(read(ISOFORGE_DATA_DIR "/hello.vtk")); }

ImplicitModellerOptions hello_options() {
  ImplicitModellerOptions o;  // VTK's Hello example
  o.sample_dimensions = {110, 40, 20};
  o.model_bounds = box({-1, -1, -1}, {10, 3, 1});
  o.maximum_distance = 0.25;
  return o;
}

void hello_offset(CaseResult& r) {
  const PolyData surface =
      offset_surfaces(implicit_modeller(hello(), hello_options()).output, {0.25}).output;
  const MeshReport m = check_mesh(surface);
  note_mesh(r, m);
  record_closed_surface(r, m);
  // H, E, L, L, O: each letter's strokes touch, letters are 1 unit apart (> 2 x 0.25).
  r.equal("components (the five letters)", m.components.size(), std::size_t{5});
  std::vector<long> genera;
  for (const auto& c : m.components) genera.push_back(c.genus);
  std::sort(genera.begin(), genera.end());
  r.is_true("genera 0, 0, 0, 0, 1 (the O is a torus)", genera == std::vector<long>{0, 0, 0, 0, 1});
}

void hello_sparse_vs_dense(CaseResult& r) {
  // The sparse modeller needs cubic voxels: a box around HELLO with sides 12 x 5 x 3 on
  // 121 x 51 x 31 samples (spacing 0.1 on every axis), the Hello example's reach of 2.75.
  ImplicitModellerOptions o = hello_options();
  o.model_bounds = box({-1.5, -1.5, -1.5}, {10.5, 3.5, 1.5});
  o.adjust_bounds = false;
  o.sample_dimensions = {121, 51, 31};
  o.maximum_distance = 2.75 / 12;
  o.capping = false;  // the sparse modeller does not cap
  const ImageData dense = implicit_modeller(hello(), o).output;
  const auto grid = implicit_modeller_vdb(hello(), o).output;
  const auto v = scalars<float>(dense);
  auto acc = grid->getConstAccessor();
  std::size_t active = 0, differ = 0;
  for (auto it = grid->cbeginValueOn(); it; ++it) {
    const openvdb::Coord c = it.getCoord();
    ++active;
    differ += *it != v[static_cast<std::size_t>(dense.point_id(c.x(), c.y(), c.z()))];
  }
  r.note("grid", fmt::format("121 x 51 x 31 cubic voxels; {} active voxels in the sparse band",
                             active));
  r.at_least("active voxels", static_cast<double>(active), 1000);
  r.equal("active voxels whose value differs from the dense one", differ, std::size_t{0});
}

void booleans(CaseResult& r) {
  // Fig. 1.27: a ball of radius 0.5 about a point and a capsule of radius 0.25 about a line,
  // as offsets of their unsigned distance fields, combined by OpenVDB's level-set CSG.
  PolyData point, line;
  point.points.push_back({0, 0, 0});
  point.verts.add({0});
  line.points.push_back({-1, 0, 0});
  line.points.push_back({1, 0, 0});
  line.lines.add({0, 1});
  const GridSpec g = cubic_grid(box({-1.5, -1, -1}, {1.5, 1, 1}), Index{121});
  DistanceOptions o;
  o.max_distance = 0.75;
  const auto ball = offset(*distance_grid(point, g, o).output, 0.5);
  const auto capsule = offset(*distance_grid(line, g, o).output, 0.25);
  const struct {
    CsgOperation op;
    long genus;
  } expected[] = {{CsgOperation::Union, 0}, {CsgOperation::Intersection, 0},
                  {CsgOperation::Difference, 1}};
  for (const auto& e : expected) {
    const std::string name(csg_operation_name(e.op));
    const PolyData s = offset_surfaces(*csg(*ball, *capsule, e.op), {0.0}).output;
    const MeshReport m = check_mesh(s);
    note_mesh(r, m, name + ": ");
    r.is_true(name + ": valid closed surface (closed, manifold, oriented, no degenerate faces, "
                     "no self-intersections; exact)",
              m.valid_closed_surface());
    r.is_true(name + ": outward oriented (exact)", m.outward);
    r.equal(name + ": components", m.components.size(), std::size_t{1});
    r.equal(name + ": genus", m.components.empty() ? -1L : m.components[0].genus, e.genus);
  }
}

void attractor(CaseResult& r) {
  const AttractorResult a = lorenz_attractor();  // Fig. 1.25's defaults
  const TrajectoryStats& t = a.stats.trajectory;
  r.note("trajectory", fmt::format("{} states counted, {} discarded, largest count {}", t.counted,
                                   t.discarded, t.max_visits));
  r.equal("states discarded (the default box holds the attractor)", t.discarded, std::size_t{0});
  const MeshReport m = check_mesh(a.output.surface);
  note_mesh(r, m);
  record_closed_surface(r, m);
}

}  // namespace

void add_model_cases(std::vector<Case>& cases) {
  cases.push_back({"model/distance_bunny",
                   "exact distance to bunny.ply's 69k triangles vs CGAL's AABB tree, band and "
                   "far values; Scatter = Gather",
                   true, distance_bunny});
  cases.push_back({"model/distance_segments",
                   "dense rows of segments, a polyline and points vs long-double brute force; "
                   "rows = block engine",
                   true, distance_segments});
  cases.push_back({"model/hello_offset",
                   "Fig. 1.28: HELLO thickened by 0.25 on 110 x 40 x 20: five closed letters, "
                   "the O a torus (exact checks)",
                   true, hello_offset});
  cases.push_back({"model/hello_sparse_vs_dense",
                   "HELLO on cubic voxels: the OpenVDB modeller's band equals the dense volume", true,
                   hello_sparse_vs_dense});
  cases.push_back({"model/booleans",
                   "Fig. 1.27: union / intersection / difference of a ball and a capsule via "
                   "OpenVDB CSG: closed, no self-intersections; the difference is a ring",
                   true, booleans});
  cases.push_back({"model/attractor",
                   "Fig. 1.25: Lorenz attractor, 10M RK4 steps into 200^3, surface at 50 visits: "
                   "closed, manifold, no self-intersections (exact)",
                   true, attractor});
}

}  // namespace isoforge::verify
