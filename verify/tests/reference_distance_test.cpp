// ReferenceDistance, the decimation error of the cases and of `isoforge-verify distance`, on two
// axis-aligned cubes whose distances are known in closed form.

#include "reference_distance.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace isoforge;
using namespace isoforge::verify;

namespace {

// The cube [c - h, c + h]^3 as 12 outward triangles.
PolyData cube(double h, double c = 0.5) {
  PolyData pd;
  for (int i = 0; i < 8; ++i) {
    pd.points.push_back({c + ((i & 1) ? h : -h), c + ((i & 2) ? h : -h), c + ((i & 4) ? h : -h)});
  }
  const Index quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    pd.polys.add({q[0], q[1], q[2]});
    pd.polys.add({q[0], q[2], q[3]});
  }
  return pd;
}

}  // namespace

TEST(ReferenceDistance, SameMeshIsAtZero) {
  const PolyData c = cube(0.5);
  const ReferenceError e = ReferenceDistance(c, 0.05).measure(c);
  EXPECT_LT(e.hausdorff, 1e-12);
  EXPECT_LT(e.rms, 1e-12);
}

TEST(ReferenceDistance, CubeAndScaledCube) {
  // Side 1 against side 1.01, same centre. A point of the small cube is 0.005 from the big one's
  // face above it. A point of the big cube is 0.005 from the small one where its projection falls
  // on a face; toward the big cube's edges and corners it grows to 0.005 sqrt(2) and
  // 0.005 sqrt(3), and the corners are samples, so the Hausdorff distance is exact (up to the
  // float32 storage of the coordinates: 1e-7).
  const PolyData small = cube(0.5), big = cube(0.505);
  const ReferenceDistance ref(small, 0.05);
  const ReferenceError e = ref.measure(big);
  EXPECT_NEAR(e.max_ref_to_mesh, 0.005, 1e-7);
  EXPECT_NEAR(e.max_mesh_to_ref, 0.005 * std::sqrt(3.0), 1e-7);
  EXPECT_DOUBLE_EQ(e.hausdorff, e.max_mesh_to_ref);
  EXPECT_NEAR(e.rms_ref_to_mesh, 0.005, 1e-7);
  EXPECT_GT(e.rms_mesh_to_ref, 0.005);
  EXPECT_LT(e.rms_mesh_to_ref, 0.005 * std::sqrt(2.0));  // only the rim is farther than 0.005
  EXPECT_NEAR(e.relative_hausdorff, e.hausdorff / ref.diagonal(), 1e-15);
  EXPECT_NEAR(ref.diagonal(), std::sqrt(3.0), 1e-7);
}

TEST(ReferenceDistance, SampleBudget) {
  // 12 triangles need at least 84 samples on the grid; with a budget of 50 the reference is
  // sampled at its 8 points and 12 centroids, and the Hausdorff distance still sees the corners.
  const PolyData small = cube(0.5), big = cube(0.505);
  const ReferenceDistance ref(big, 0.05, 50);
  EXPECT_EQ(ref.reference_spacing(), 0.0);
  EXPECT_EQ(ref.reference_samples(), 20u);
  EXPECT_NEAR(ref.measure(small).max_ref_to_mesh, 0.005 * std::sqrt(3.0), 1e-7);
  // A budget the grid fits at a coarser spacing: the spacing grows, never the count.
  const ReferenceDistance coarse(small, 0.01, 2000);
  EXPECT_GT(coarse.reference_spacing(), 0.01);
  EXPECT_LE(coarse.reference_samples(), 2000u);
}
