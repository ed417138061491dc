#include "isoforge/model/attractor.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "isoforge/contour/connectivity.hpp"
#include "isoforge/core/mesh_topology.hpp"
#include "support/expect_error.hpp"

using isoforge::test::expect_error;

using namespace isoforge;

TEST(Attractor, LorenzRightHandSide) {
  const LorenzParameters p;
  const Vec3 d = lorenz(p, {1, 2, 3});
  EXPECT_DOUBLE_EQ(d.x, 10.0);
  EXPECT_DOUBLE_EQ(d.y, 1 * (28 - 3) - 2.0);
  EXPECT_DOUBLE_EQ(d.z, 2 - 8.0);
}

TEST(Attractor, CountsAreDeterministicAndAccounted) {
  TrajectoryOptions o;
  o.steps = 200000;
  o.dims = {64, 64, 64};
  const auto [va, a] = lorenz_density({}, o);
  const auto [vb, b] = lorenz_density({}, o);
  EXPECT_EQ(va, vb);
  EXPECT_EQ(a.end, b.end);
  EXPECT_EQ(a.counted + a.discarded, o.steps);
  EXPECT_EQ(a.discarded, 0u);  // the attractor lies inside x, y in [-30, 30], z in [-10, 60]
  EXPECT_EQ(va.dims, (Dims{64, 64, 64}));
  EXPECT_DOUBLE_EQ(va.origin.z, -10.0);
  EXPECT_DOUBLE_EQ(va.spacing.z, 70.0 / 63);
  EXPECT_EQ(va.point_data.scalars()->type(), ScalarType::UInt32);
  EXPECT_GT(a.max_visits, 50u);
  // The trajectory stays on the attractor.
  EXPECT_LT(std::abs(a.end.x), 25.0);
  EXPECT_GT(a.end.z, 0.0);
}

TEST(Attractor, OutsideTheBoundsIsDiscardedNotAnError) {
  TrajectoryOptions o;
  o.steps = 50000;
  o.dims = {16, 16, 16};
  o.bounds.min = {0, -30, 0};
  o.bounds.max = {30, 30, 60};  // only the x >= 0 wing
  const auto [volume, d] = lorenz_density({}, o);
  EXPECT_GT(d.discarded, 10000u);
  EXPECT_GT(d.counted, 10000u);
  EXPECT_EQ(d.counted + d.discarded, 50000u);
  std::uint64_t total = 0;
  for (std::uint32_t c : volume.point_data.scalars()->values<std::uint32_t>()) total += c;
  EXPECT_EQ(total, d.counted);
}

TEST(Attractor, GenericRightHandSide) {
  TrajectoryOptions o;
  o.steps = 20000;
  o.transient = 100;
  o.dims = {20, 20, 20};
  const LorenzParameters p{10, 28, 8.0 / 3};
  // The generic integrator (a std::function right-hand side) gives the same states as the Lorenz
  // one (its right-hand side inlined).
  const TrajectoryResult a = lorenz_density(p, o);
  const TrajectoryResult b = trajectory_density([&](const Vec3& s) { return lorenz(p, s); }, o);
  EXPECT_EQ(a.output, b.output);
  EXPECT_EQ(a.stats.end, b.stats.end);
  EXPECT_EQ(a.stats.counted, b.stats.counted);
  // A circle in the plane z = 0 visits a ring of samples only.
  TrajectoryOptions ring;
  ring.start = {20, 0, 0};
  ring.step = 0.001;
  ring.steps = 7000;  // a bit more than one turn of 2 pi
  ring.dims = {41, 41, 3};
  ring.bounds.min = {-30, -30, -1};
  ring.bounds.max = {30, 30, 1};
  const TrajectoryResult r = trajectory_density(
      [](const Vec3& s) {
        return Vec3{-s.y, s.x, 0};
      },
      ring);
  const ImageData& v = r.output;
  const auto counts = v.point_data.scalars()->values<std::uint32_t>();
  for (std::size_t i = 0; i < counts.size(); ++i) {
    if (counts[i] == 0) continue;
    const Vec3 x = v.point(Index(i));
    ASSERT_NEAR(std::hypot(x.x, x.y), 20.0, 1.5);  // within a sample of the circle
    ASSERT_EQ(x.z, 0.0);
  }
}

// Fig. 1.25: 10 million RK4 steps into 200^3, contoured at 50 visits.
TEST(Attractor, Figure125SurfaceIsClosedAndManifold) {
  const AttractorResult a = lorenz_attractor();
  EXPECT_EQ(a.stats.trajectory.counted, 10'000'000u);
  EXPECT_EQ(a.stats.trajectory.discarded, 0u);
  EXPECT_EQ(a.stats.contour.cells, a.output.surface.polys.size());
  EXPECT_EQ(a.output.volume.dims, (Dims{200, 200, 200}));
  const PolyData& surface = a.output.surface;
  ASSERT_GT(surface.polys.size(), 10000u);
  const SurfaceTopology t = analyze_topology(surface);
  EXPECT_TRUE(t.closed());
  EXPECT_TRUE(t.manifold());
  EXPECT_TRUE(t.oriented());
  // Oriented outward: the enclosed volume is positive.
  double volume = 0;
  for (const auto& f : triangulate_faces(surface)) {
    volume += dot(surface.points[f[0]], cross(surface.points[f[1]], surface.points[f[2]])) / 6;
  }
  EXPECT_GT(volume, 0);
  // One dominant sheet (plus small blobs where the visit count barely exceeds 50).
  ConnectivityOptions c;
  c.mode = ConnectivityMode::Largest;
  const ConnectivityResult cr = connectivity(surface, c);
  EXPECT_GT(cr.stats.sizes[0], surface.polys.size() / 2);
}

TEST(Attractor, BadInputIsAnErrorNamingTheProblem) {
  TrajectoryOptions o;
  o.steps = 10;
  o.dims = {1, 10, 10};
  expect_error([&] { (void)lorenz_density({}, o); }, "at least 2");
  o.dims = {10, 10, 10};
  o.step = 0;
  expect_error([&] { (void)lorenz_density({}, o); }, "step");
  o.step = 0.01;
  o.steps = 4294967296;  // one voxel could overflow its UInt32 count
  expect_error([&] { (void)lorenz_density({}, o); },
               "4294967296 steps exceed the UInt32 visit counts (at most 4294967295)");
  o.steps = 10;
  o.start = {NAN, 0, 0};
  expect_error([&] { (void)lorenz_density({}, o); }, "start point");
  o.start = {1, 1, 1};
  LorenzParameters p;
  p.rho = INFINITY;
  expect_error([&] { (void)lorenz_density(p, o); }, "parameters");
  o.bounds = Bounds{};
  expect_error([&] { (void)lorenz_density({}, o); }, "empty");
  expect_error([&] { (void)trajectory_density({}, TrajectoryOptions{}); }, "right-hand side");
}
