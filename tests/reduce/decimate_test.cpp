#include "isoforge/reduce/decimate.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <random>

#include "isoforge/contour/contour.hpp"
#include "isoforge/core/mesh_topology.hpp"
#include "isoforge/io/io.hpp"
#include "isoforge/spatial/self_intersections.hpp"
#include "support/expect_error.hpp"
#include "support/meshes.hpp"
#include "support/scratch.hpp"

namespace isoforge {
namespace {

using test::expect_error;

PolyData sphere(int rings, int segments, double r = 1) {
  const double pi = std::numbers::pi;
  return test::polar_surface({0, 0, -r}, {0, 0, r}, rings, segments, [&](int i, int j) {
    const double th = pi * i / rings, ph = 2 * pi * j / segments;
    return Vec3{r * std::sin(th) * std::cos(ph), r * std::sin(th) * std::sin(ph),
                -r * std::cos(th)};
  });
}

// Two shells: the sphere of radius 1 and, `gap` inside it, one facing inward.
PolyData nested_spheres(int rings, int segments, double gap) {
  PolyData shells = sphere(rings, segments, 1.0);
  const PolyData inner = sphere(rings, segments, 1.0 - gap);
  const Index base = Index(shells.num_points());
  for (std::size_t i = 0; i < inner.num_points(); ++i) shells.points.push_back(inner.points[i]);
  for (std::size_t c = 0; c < inner.polys.size(); ++c) {
    const auto f = inner.polys.cell(c);
    shells.polys.add({f[0] + base, f[2] + base, f[1] + base});
  }
  return shells;
}

// The faces crossing the median x of the points: the cut of a partitioned run on a mesh whose
// longest axis is x (docs/algorithms/decimation.md, "Two cores").
std::size_t faces_crossing_median_x(const PolyData& mesh) {
  std::vector<double> xs;
  for (std::size_t i = 0; i < mesh.num_points(); ++i) xs.push_back(mesh.points[i].x);
  std::nth_element(xs.begin(), xs.begin() + xs.size() / 2, xs.end());
  const double cut = xs[xs.size() / 2];
  std::size_t crossing = 0;
  for (std::size_t c = 0; c < mesh.polys.size(); ++c) {
    int below = 0;
    for (Index i : mesh.polys.cell(c)) below += mesh.points[i].x < cut ? 1 : 0;
    crossing += below == 1 || below == 2 ? 1 : 0;
  }
  return crossing;
}

// decimate() with TBB limited to `threads`.
DecimateResult decimate_on(int threads, const PolyData& in, const DecimateOptions& o) {
  tbb::global_control c(tbb::global_control::max_allowed_parallelism,
                        static_cast<std::size_t>(threads));
  return decimate(in, o);
}

// A torus (genus 1) of n × m quads split into triangles, outward oriented.
PolyData torus(int n, int m, double big = 1, double small = 0.3) {
  PolyData pd;
  const double pi = std::numbers::pi;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      const double u = 2 * pi * i / n, v = 2 * pi * j / m;
      pd.points.push_back({(big + small * std::cos(v)) * std::cos(u),
                           (big + small * std::cos(v)) * std::sin(u), small * std::sin(v)});
    }
  }
  auto id = [&](int i, int j) { return Index((i % n) * m + (j % m)); };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      pd.polys.add({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      pd.polys.add({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return pd;
}

// A unit square in z = height(x, y), n × n quads split into triangles (open: one border loop).
PolyData sheet(int n, const std::function<double(double, double)>& height = {}) {
  PolyData pd;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const double x = double(i) / n, y = double(j) / n;
      pd.points.push_back({x, y, height ? height(x, y) : 0.0});
    }
  }
  auto id = [&](int i, int j) { return Index(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      pd.polys.add({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      pd.polys.add({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return pd;
}

void expect_valid(const PolyData& out, bool closed, long genus, std::size_t border_loops) {
  const SurfaceTopology t = analyze_topology(out);
  EXPECT_TRUE(t.manifold());
  EXPECT_TRUE(t.oriented());
  EXPECT_EQ(t.closed(), closed);
  EXPECT_EQ(t.repeated_vertex_faces, 0u);
  ASSERT_EQ(t.components.size(), 1u);
  EXPECT_EQ(t.components[0].genus, genus);
  EXPECT_EQ(t.components[0].border_loops, border_loops);
  EXPECT_EQ(t.vertices, out.num_points());  // points compacted
  EXPECT_TRUE(self_intersections(out).empty());
}

DecimateOptions to_count(std::size_t n, DecimateMethod method = DecimateMethod::Quadric) {
  DecimateOptions o;
  o.method = method;
  o.target_triangles = n;
  return o;
}

TEST(Decimate, QuadricHitsAnEvenTargetExactlyOnAClosedSphere) {
  const PolyData in = sphere(40, 80);
  auto [out, stats] = decimate(in, to_count(500));
  EXPECT_EQ(stats.stop, DecimateStop::Target);
  EXPECT_EQ(stats.output_triangles, 500u);
  EXPECT_EQ(out.polys.size(), 500u);
  EXPECT_EQ(stats.input_triangles, in.polys.size());
  EXPECT_EQ(stats.output_points, out.num_points());
  EXPECT_EQ(out.num_points(), 252u);  // V = F / 2 + 2 on a closed genus-0 surface
  expect_valid(out, true, 0, 0);
  // Every vertex stays close to the unit sphere.
  for (std::size_t i = 0; i < out.num_points(); ++i) {
    EXPECT_NEAR(norm(out.points[i]), 1.0, 0.03);
  }
}

// Signed volume enclosed by a closed, outward-oriented triangle mesh.
double enclosed_volume(const PolyData& mesh) {
  double v = 0;
  for (std::size_t c = 0; c < mesh.polys.size(); ++c) {
    const auto ids = mesh.polys.cell(c);
    v += dot(mesh.points[ids[0]], cross(mesh.points[ids[1]], mesh.points[ids[2]])) / 6;
  }
  return v;
}

TEST(Decimate, PreserveVolumeKeepsTheEnclosedVolume) {
  // Every accepted collapse places its vertex on the plane where the faces around the edge
  // enclose what they did, so a closed surface keeps its volume to rounding (float storage);
  // the quadric's own minimum cuts corners off a convex surface and loses volume.
  for (const long genus : {0, 1}) {
    const PolyData in = genus == 0 ? sphere(40, 80) : torus(60, 24);
    const double before = enclosed_volume(in);
    ASSERT_GT(before, 0);
    DecimateOptions o = to_count(300);
    const auto kept = decimate(in, o);
    EXPECT_EQ(kept.stats.output_triangles, 300u);
    expect_valid(kept.output, true, genus, 0);
    EXPECT_NEAR(enclosed_volume(kept.output) / before, 1.0, 1e-7);
    o.preserve_volume = false;
    const auto free = decimate(in, o);
    EXPECT_LT(enclosed_volume(free.output) / before, 0.99);
  }
}

// The cube [-1, 1]³, each face an n × n grid of quads split into triangles, outward oriented.
PolyData cube(int n) {
  PolyData pd;
  std::map<std::array<int, 3>, Index> ids;
  auto id = [&](std::array<int, 3> c) {
    const auto [it, added] = ids.try_emplace(c, Index(pd.points.size()));
    if (added) pd.points.push_back({2.0 * c[0] / n - 1, 2.0 * c[1] / n - 1, 2.0 * c[2] / n - 1});
    return it->second;
  };
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;  // e_b × e_c = e_a
    for (const int side : {0, n}) {
      for (int u = 0; u < n; ++u) {
        for (int v = 0; v < n; ++v) {
          auto at = [&](int du, int dv) {
            std::array<int, 3> k{};
            k[a] = side;
            k[b] = u + du;
            k[c] = v + dv;
            return id(k);
          };
          const Index p0 = at(0, 0), p1 = at(1, 0), p2 = at(1, 1), p3 = at(0, 1);
          if (side == n) {
            pd.polys.add({p0, p1, p2});
            pd.polys.add({p0, p2, p3});
          } else {
            pd.polys.add({p0, p2, p1});
            pd.polys.add({p0, p3, p2});
          }
        }
      }
    }
  }
  return pd;
}

TEST(Decimate, ACubeWithFeaturesStaysACube) {
  // Volume preservation and the feature planes together: merged vertices stay on the faces
  // (the volume plane of a flat neighbourhood is its face) and on the edges, the corners stay.
  const PolyData in = cube(12);
  ASSERT_NEAR(enclosed_volume(in), 8.0, 1e-12);
  DecimateOptions o = to_count(100);
  o.feature_angle = 40;
  const auto [out, stats] = decimate(in, o);
  EXPECT_EQ(stats.stop, DecimateStop::Target);
  EXPECT_LE(stats.output_triangles, 100u);
  expect_valid(out, true, 0, 0);
  EXPECT_NEAR(enclosed_volume(out), 8.0, 1e-5);
  int corners = 0;
  for (std::size_t i = 0; i < out.num_points(); ++i) {
    const Vec3 p = out.points[i];
    const double ax = std::abs(p.x), ay = std::abs(p.y), az = std::abs(p.z);
    EXPECT_NEAR(std::max({ax, ay, az}), 1.0, 1e-6);  // on the surface
    if (std::min({ax, ay, az}) > 1 - 1e-6) ++corners;
  }
  EXPECT_EQ(corners, 8);
}

TEST(Decimate, EveryMethodKeepsTheGenusOfATorus) {
  const PolyData in = torus(60, 24);
  for (auto method :
       {DecimateMethod::Quadric, DecimateMethod::VertexRemoval, DecimateMethod::CellCollapse}) {
    SCOPED_TRACE(to_string(method));
    auto [out, stats] = decimate(in, to_count(300, method));
    EXPECT_EQ(stats.stop, DecimateStop::Target);
    EXPECT_LE(stats.output_triangles, 300u);
    EXPECT_GE(stats.output_triangles, 296u);
    expect_valid(out, true, 1, 0);
  }
}

TEST(Decimate, EveryMethodReachesSmallCountsOnASphere) {
  const PolyData in = sphere(30, 60);
  for (auto method :
       {DecimateMethod::Quadric, DecimateMethod::VertexRemoval, DecimateMethod::CellCollapse}) {
    SCOPED_TRACE(to_string(method));
    auto [out, stats] = decimate(in, to_count(40, method));
    EXPECT_EQ(stats.stop, DecimateStop::Target);
    EXPECT_LE(stats.output_triangles, 40u);
    expect_valid(out, true, 0, 0);
  }
}

TEST(Decimate, AFlatSheetKeepsItsBorderAndPlane) {
  const PolyData in = sheet(60);
  auto [out, stats] = decimate(in, to_count(50));
  EXPECT_EQ(stats.stop, DecimateStop::Target);
  EXPECT_LE(stats.output_triangles, 50u);
  expect_valid(out, false, 0, 1);
  EXPECT_LT(stats.max_error, 1e-6);  // the border constraint planes amplify rounding
  double area = 0;
  for (std::size_t c = 0; c < out.polys.size(); ++c) {
    const auto ids = out.polys.cell(c);
    const Vec3 a = out.points[ids[0]], b = out.points[ids[1]], d = out.points[ids[2]];
    area += 0.5 * cross(b - a, d - a).z;
  }
  EXPECT_NEAR(area, 1.0, 1e-6);  // border kept (to float32 output precision): covered once
  for (std::size_t i = 0; i < out.num_points(); ++i) EXPECT_NEAR(out.points[i].z, 0.0, 1e-12);
}

TEST(Decimate, MaximumErrorStopsBeforeTheBump) {
  const PolyData in = sheet(40, [](double x, double y) {
    const double r2 = (x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5);
    return 0.2 * std::exp(-r2 / 0.01);
  });
  DecimateOptions o;
  o.max_error = 1e-3;
  auto [out, stats] = decimate(in, o);
  EXPECT_EQ(stats.stop, DecimateStop::MaxError);
  EXPECT_LE(stats.max_error, 1e-3);
  EXPECT_LT(stats.output_triangles, in.polys.size() / 2);
  EXPECT_GT(stats.output_triangles, 40u);  // the bump needs triangles
  expect_valid(out, false, 0, 1);
  // Relative to the diagonal (sqrt(2 + 0.04) here): the same stop.
  o.max_error = 1e-3 / std::sqrt(2.0 + 0.04);
  o.max_error_relative = true;
  auto relative = decimate(in, o);
  EXPECT_NEAR(double(relative.stats.output_triangles), double(stats.output_triangles),
              0.02 * double(stats.output_triangles));
}

TEST(Decimate, CarriesPointArraysAndRenormalisesNormals) {
  PolyData in = sphere(30, 60);
  std::vector<double> xs;
  std::vector<float> ns;
  std::vector<std::int32_t> labels;
  for (std::size_t i = 0; i < in.num_points(); ++i) {
    const Vec3 p = in.points[i];
    xs.push_back(p.x);
    const Vec3 u = p / norm(p);
    ns.insert(ns.end(), {float(u.x), float(u.y), float(u.z)});
    labels.push_back(p.z > 0 ? 7 : 3);
  }
  auto x = DataArray::from_vector("X", 1, xs);
  auto n = DataArray::from_vector("Normals", 3, ns);
  auto label = DataArray::from_vector("Label", 1, labels);
  in.point_data.add(std::move(x), AttributeRole::Scalars);
  in.point_data.add(std::move(n), AttributeRole::Normals);
  in.point_data.add(std::move(label));
  // A merged vertex's values are interpolated at its placement's projection on the collapsed
  // edge; the volume-preserving placement sits farther off the edge (outward) than the quadric's
  // own minimum, so a linear array follows the points less closely.
  for (const bool volume : {false, true}) {
    SCOPED_TRACE(volume ? "preserve_volume" : "free volume");
    DecimateOptions o = to_count(400);
    o.preserve_volume = volume;
    auto [out, stats] = decimate(in, o);
    ASSERT_TRUE(out.point_data.has("X"));
    ASSERT_TRUE(out.point_data.has("Label"));
    EXPECT_EQ(out.point_data.active_name(AttributeRole::Normals), "Normals");
    const DataArray& ox = out.point_data.get("X");
    const DataArray& on = out.point_data.get("Normals");
    const DataArray& ol = out.point_data.get("Label");
    ASSERT_EQ(ox.tuples(), out.num_points());
    for (std::size_t i = 0; i < out.num_points(); ++i) {
      EXPECT_NEAR(ox.get(i), out.points[i].x, volume ? 0.07 : 0.05);  // linear data
      const double l = std::hypot(on.get(i, 0), on.get(i, 1), on.get(i, 2));
      EXPECT_NEAR(l, 1.0, 1e-6);
      const double v = ol.get(i);
      EXPECT_TRUE(v == 7 || v == 3 || (v > 3 && v < 7 && v == std::round(v)));
    }
  }
}

TEST(Decimate, LockedVerticesStayWhereTheyAre) {
  PolyData in = sphere(20, 40);
  std::vector<std::uint8_t> flags;
  std::vector<Vec3> locked;
  for (std::size_t i = 0; i < in.num_points(); ++i) {
    const bool l = in.points[i].z > 0.9;
    flags.push_back(l ? 1 : 0);
    if (l) locked.push_back(in.points[i]);
  }
  auto lock = DataArray::from_vector("Lock", 1, flags);
  in.point_data.add(std::move(lock));
  DecimateOptions o = to_count(100);
  o.lock_array = "Lock";
  auto [out, stats] = decimate(in, o);
  EXPECT_EQ(stats.locked_vertices, locked.size());
  std::size_t found = 0;
  for (const Vec3& p : locked) {
    for (std::size_t i = 0; i < out.num_points(); ++i) found += out.points[i] == p ? 1 : 0;
  }
  EXPECT_EQ(found, locked.size());
  expect_valid(out, true, 0, 0);
}

TEST(Decimate, NonManifoldEdgesAreLockedAndKept) {
  // Three sheets sharing the edge x = 0.5 (a "book" with three pages): its points are locked.
  PolyData in;
  const int n = 20;
  auto add_page = [&](const Vec3& dir) {
    const Index base = Index(in.points.size());
    for (int j = 0; j <= n; ++j) {
      for (int i = 0; i <= n; ++i) {
        in.points.push_back(Vec3{0, double(j) / n, 0} + dir * (double(i) / n));
      }
    }
    auto id = [&](int i, int j) { return base + Index(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        in.polys.add({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        in.polys.add({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    }
    return base;
  };
  add_page({1, 0, 0});
  const Index b2 = add_page({-0.5, 0, 0.8});
  const Index b3 = add_page({-0.5, 0, -0.8});
  // Glue the pages' spines (i = 0) onto the first page's spine: the ids of pages 2 and 3 are
  // replaced by page 1's.
  auto& ids = in.polys.connectivity();
  for (auto& v : ids) {
    for (Index b : {b2, b3}) {
      if (v >= b && v < b + Index((n + 1) * (n + 1)) && (v - b) % (n + 1) == 0) {
        v = (v - b) / (n + 1) * (n + 1);
      }
    }
  }
  ASSERT_EQ(analyze_topology(in).non_manifold_edges, std::size_t(n));
  auto [out, stats] = decimate(in, to_count(200));
  EXPECT_GE(stats.locked_vertices, std::size_t(n + 1));
  const SurfaceTopology t = analyze_topology(out);
  EXPECT_EQ(t.non_manifold_edges, std::size_t(n));  // the spine stays as it was
  EXPECT_TRUE(self_intersections(out).empty());
  EXPECT_LE(out.polys.size(), 200u + 6 * n);
}

TEST(Decimate, AThinSlabNeverSelfIntersects) {
  // Two sheets 0.002 apart, joined at the border: aggressive decimation without the exact test
  // could make the sheets cross; with it, never.
  PolyData top =
      sheet(40, [](double x, double y) { return 0.05 * std::sin(9 * x) * std::cos(7 * y); });
  const std::size_t half = top.num_points();
  PolyData slab = top;
  for (std::size_t i = 0; i < half; ++i) {
    Vec3 p = top.points[i];
    p.z -= 0.002;
    slab.points.push_back(p);
  }
  for (std::size_t c = 0; c < top.polys.size(); ++c) {
    const auto f = top.polys.cell(c);
    slab.polys.add({f[0] + Index(half), f[2] + Index(half), f[1] + Index(half)});
  }
  DecimateOptions o = to_count(200);
  auto [out, stats] = decimate(slab, o);
  EXPECT_TRUE(self_intersections(out).empty());
  EXPECT_EQ(analyze_topology(out).non_manifold_edges, 0u);
}

TEST(Decimate, IntersectionsBetweenSeparateShellsAreFoundAndRedone) {
  // Two nested spheres 0.03 apart: coarse faces of the outer one cut into the inner one. Those
  // merges share no vertex with what they would cut, so only the test of the finished mesh
  // sees them: the run is redone with them tested.
  const PolyData shells = nested_spheres(24, 48, 0.03);
  DecimateOptions unchecked = to_count(120);
  unchecked.check_self_intersections = false;
  EXPECT_FALSE(self_intersections(decimate(shells, unchecked).output).empty());
  for (DecimateMethod m : {DecimateMethod::Quadric, DecimateMethod::CellCollapse}) {
    auto [out, stats] = decimate(shells, to_count(120, m));
    EXPECT_TRUE(self_intersections(out).empty()) << to_string(m);
    EXPECT_GE(stats.intersection_reruns, 1u) << to_string(m);
    EXPECT_GT(stats.refused_intersection, 0u) << to_string(m);
    const SurfaceTopology t = analyze_topology(out);
    EXPECT_TRUE(t.manifold());
    EXPECT_EQ(t.components.size(), 2u);
  }
}

TEST(Decimate, ADeepTargetOnTheHeadsSkinIsRedoneWithTheMergesFoundTestedUntilClean) {
  // The skin of the CT head (78 510 triangles, open where it leaves the volume) to 2 %: the
  // finished mesh of the first run has faces that meet, made by merges whose test was deferred.
  // The redone runs test the merges that made them (and, past the first refused, every merge)
  // and end clean before a run that tests every merge from the start would be needed.
  const Dataset ds = read(test::data_path("headsq/quarter.nhdr"));
  ContourOptions c;
  c.values = {1150};
  c.flip = true;
  const PolyData skin = contour_image(std::get<ImageData>(ds), c).output;
  ASSERT_EQ(skin.polys.size(), 78510u);
  auto [out, stats] = decimate(skin, to_count(1570));
  EXPECT_LE(stats.output_triangles, 1570u);
  EXPECT_GE(stats.output_triangles, 1569u);
  EXPECT_GE(stats.intersection_reruns, 1u);
  EXPECT_LE(stats.intersection_reruns, 2u);
  EXPECT_TRUE(self_intersections(out).empty());
  const SurfaceTopology in_t = analyze_topology(skin), out_t = analyze_topology(out);
  EXPECT_TRUE(out_t.manifold());
  ASSERT_EQ(out_t.components.size(), in_t.components.size());
  const auto sum = [](const SurfaceTopology& t, auto field) {
    long n = 0;
    for (const SurfaceComponent& k : t.components) n += static_cast<long>(k.*field);
    return n;
  };
  EXPECT_EQ(sum(out_t, &SurfaceComponent::genus), sum(in_t, &SurfaceComponent::genus));
  EXPECT_EQ(sum(out_t, &SurfaceComponent::border_loops),
            sum(in_t, &SurfaceComponent::border_loops));
}

TEST(Decimate, TwoCloseShellsDecimatedInHalvesAreRedoneTheSameForAnyThreadCount) {
  // Two spheres 10⁻⁴ apart, 190 000 triangles: decimated in two halves (the target 20 times the
  // faces crossing the cut), whose coarse faces cut the other shell, so the finished mesh is
  // tested and the run redone — each half from its own part of the log, faces keeping the id
  // of the merge that made them across the join.
  const PolyData shells = nested_spheres(200, 240, 1e-4);
  const std::size_t target = 50000;
  ASSERT_GE(shells.polys.size(), 150000u);
  ASSERT_GE(target, 20 * faces_crossing_median_x(shells));
  const PolyData one = decimate_on(1, shells, to_count(target)).output;
  const auto [two, stats] = decimate_on(2, shells, to_count(target));
  EXPECT_EQ(one.points, two.points);
  EXPECT_EQ(one.polys, two.polys);
  EXPECT_GE(stats.intersection_reruns, 1u);
  EXPECT_EQ(stats.output_triangles, target);
  EXPECT_TRUE(self_intersections(two).empty());
  const SurfaceTopology t = analyze_topology(two);
  EXPECT_TRUE(t.manifold());
  EXPECT_EQ(t.components.size(), 2u);
}

TEST(Decimate, OutputDoesNotDependOnTheThreadCount) {
  const PolyData in = torus(80, 30);
  const PolyData one = decimate_on(1, in, to_count(600)).output;
  const PolyData two = decimate_on(2, in, to_count(600)).output;
  EXPECT_EQ(one.points, two.points);
  EXPECT_EQ(one.polys, two.polys);
}

TEST(Decimate, TheTwoHalvesOfALargeMeshGiveTheSameOutputForAnyThreadCount) {
  // 160,000 triangles: above the size where the quadric method decimates two halves at once,
  // cut at the median x (the longest axis, with y); the target at least 20 times the faces
  // crossing the cut, as the partition requires (docs/algorithms/decimation.md, "Two cores").
  const PolyData in = torus(400, 200);
  const std::size_t target = 20000;
  const std::size_t crossing = faces_crossing_median_x(in);
  ASSERT_GT(crossing, 0u);
  ASSERT_GE(target, 20 * crossing);
  const PolyData one = decimate_on(1, in, to_count(target)).output;
  const auto [two, stats] = decimate_on(2, in, to_count(target));
  EXPECT_EQ(one.points, two.points);
  EXPECT_EQ(one.polys, two.polys);
  EXPECT_EQ(stats.output_triangles, target);
  EXPECT_EQ(stats.stop, DecimateStop::Target);
  expect_valid(two, true, 1, 0);
  for (std::size_t i = 0; i < two.num_points(); ++i) {
    const Vec3 p = two.points[i];
    const double ring = std::hypot(p.x, p.y) - 1;
    EXPECT_NEAR(std::hypot(ring, p.z), 0.3, 0.01);  // still on the torus
  }
}

TEST(Decimate, ReportsProgressAndCancels) {
  const PolyData in = sphere(60, 120);
  DecimateOptions o = to_count(100);
  double last = -1;
  bool monotone = true;
  o.progress = [&](double f) {
    monotone = monotone && f >= last;
    last = f;
    return true;
  };
  (void)decimate(in, o);
  EXPECT_TRUE(monotone);
  EXPECT_EQ(last, 1.0);
  o.progress = [](double f) { return f < 0.5; };
  EXPECT_THROW((void)decimate(in, o), Cancelled);
}

TEST(Decimate, BadOptionsAndInputAreErrors) {
  const PolyData in = sphere(8, 16);
  expect_error([&] { (void)decimate(in, DecimateOptions{}); }, "no stop is set");
  DecimateOptions o = to_count(10);
  o.target_reduction = 0.5;
  expect_error([&] { (void)decimate(in, o); }, "contradict");
  o = {};
  o.target_reduction = 1.0;
  expect_error([&] { (void)decimate(in, o); }, "not in [0, 1)");
  o = to_count(10);
  o.feature_angle = std::nan("");
  expect_error([&] { (void)decimate(in, o); }, "feature angle");
  o = to_count(10);
  o.max_error = -1;
  expect_error([&] { (void)decimate(in, o); }, "maximum error");
  o = to_count(10);
  o.lock_array = "Missing";
  expect_error([&] { (void)decimate(in, o); }, "lock array 'Missing'");
  PolyData lines;
  lines.points.push_back({0, 0, 0});
  lines.points.push_back({1, 0, 0});
  lines.lines.add({0, 1});
  expect_error([&] { (void)decimate(lines, to_count(1)); }, "no triangle");
  PolyData bad = sphere(8, 16);
  bad.points.set(3, {std::nan(""), 0, 0});
  expect_error([&] { (void)decimate(bad, to_count(10)); }, "point 3 is not finite");
}

}  // namespace
}  // namespace isoforge
