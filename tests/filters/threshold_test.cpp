#include "isoforge/filters/threshold.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <limits>
#include <set>

#include "isoforge/core/dataset.hpp"
#include "isoforge/io/io.hpp"

using namespace isoforge;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Three unit voxels in a row (4 x 2 x 2 points); point scalar s = x (0, 1, 2, 3), so voxel i
// spans s in [i, i + 1]; cell scalar c = 10 * cell id.
ImageData row_of_voxels() {
  ImageData img;
  img.dims = {4, 2, 2};
  DataArray s("s", ScalarType::Float32, 1, img.num_points());
  for (std::size_t i = 0; i < img.num_points(); ++i) s.set(i, 0, static_cast<double>(i % 4));
  img.point_data.add(std::move(s), AttributeRole::Scalars);
  img.cell_data.add(DataArray::from_vector<std::int32_t>("c", 1, {0, 10, 20}));
  return img;
}

ThresholdOptions range(double lo, double hi) {
  ThresholdOptions o;
  o.lower = lo;
  o.upper = hi;
  return o;
}

}  // namespace

TEST(Threshold, AllPointsAnyPointAndOverlapOnPointData) {
  const ImageData img = row_of_voxels();
  // [0.5, 2.5]: voxel 1 (s 1..2) has every point in; voxels 0 and 2 have some points in.
  ThresholdOptions o = range(0.5, 2.5);
  auto [all, all_stats] = threshold(img, o);
  EXPECT_EQ(all.num_cells(), 1u);
  EXPECT_EQ(all_stats.cells_in, 3u);
  EXPECT_EQ(all_stats.cells_kept, 1u);
  EXPECT_TRUE(all_stats.point_array);
  EXPECT_EQ(all.types[0], CellType::Voxel);  // image data keeps its voxels
  EXPECT_EQ(all.num_points(), 8u);
  EXPECT_EQ(all.cell_data.get("c").get(0), 10.0);
  // The kept points are image points 1, 2, 5, 6, 9, 10, 13, 14 (s = 1 or 2), renumbered in order.
  EXPECT_EQ(all.points[0], (Vec3{1, 0, 0}));
  EXPECT_EQ(all.points[7], (Vec3{2, 1, 1}));
  EXPECT_EQ(all.point_data.get("s").get(7), 2.0);
  EXPECT_EQ(all.point_data.active_name(AttributeRole::Scalars), "s");
  EXPECT_NO_THROW(all.validate());
  o.mode = ThresholdMode::AnyPoint;
  EXPECT_EQ(threshold(img, o).output.num_cells(), 3u);
  // [1.2, 1.8] holds no point value: no cell by points, but voxel 1 spans it (overlap).
  o = range(1.2, 1.8);
  EXPECT_EQ(threshold(img, o).output.num_cells(), 0u);
  o.mode = ThresholdMode::AnyPoint;
  EXPECT_EQ(threshold(img, o).output.num_cells(), 0u);
  o.mode = ThresholdMode::Overlap;
  const auto overlap = threshold(img, o).output;
  ASSERT_EQ(overlap.num_cells(), 1u);
  EXPECT_EQ(overlap.cell_data.get("c").get(0), 10.0);
  // Bounds are inclusive: [3, 3] touches voxel 2 at its right face only.
  o = range(3, 3);
  o.mode = ThresholdMode::AnyPoint;
  EXPECT_EQ(threshold(img, o).output.num_cells(), 1u);
  o.mode = ThresholdMode::AllPoints;
  EXPECT_EQ(threshold(img, o).output.num_cells(), 0u);
}

TEST(Threshold, CellDataUsesEachCellsOwnValue) {
  const ImageData img = row_of_voxels();
  ThresholdOptions o = range(5, 25);
  o.array = "c";
  o.original_ids = true;
  auto [out, stats] = threshold(img, o);
  EXPECT_FALSE(stats.point_array);
  ASSERT_EQ(out.num_cells(), 2u);  // c = 10 and 20
  EXPECT_EQ(out.num_points(), 12u);
  EXPECT_EQ(out.cell_data.get("OriginalCellIds").get(0), 1.0);
  EXPECT_EQ(out.cell_data.get("OriginalCellIds").get(1), 2.0);
  EXPECT_EQ(out.point_data.get("OriginalPointIds").get(0), 1.0);
  EXPECT_EQ(out.cell_data.get("c").get(1), 20.0);
  // A name in both point and cell data: association picks one.
  ImageData both = img;
  both.cell_data.add(DataArray::from_vector<float>("s", 1, {100, 0, 0}));
  o = range(50, 200);
  o.array = "s";
  EXPECT_EQ(threshold(both, o).output.num_cells(), 0u);  // Auto: point s is 0..3
  o.association = ThresholdArrayAssociation::Cells;
  EXPECT_EQ(threshold(both, o).output.num_cells(), 1u);
  o.association = ThresholdArrayAssociation::Points;
  o.array = "c";
  EXPECT_THROW((void)threshold(both, o), Error);  // c is cell data only
}

TEST(Threshold, NaNNeverPasses) {
  ImageData img = row_of_voxels();
  img.point_data.get("s").set(1, 0, kNaN);  // a corner of voxels 0 and 1
  ThresholdOptions o;  // (-inf, inf): every finite value passes
  EXPECT_EQ(threshold(img, o).output.num_cells(), 1u);  // only voxel 2 has no NaN corner
  o.mode = ThresholdMode::AnyPoint;
  EXPECT_EQ(threshold(img, o).output.num_cells(), 3u);  // the other corners pass
  o.mode = ThresholdMode::Overlap;
  EXPECT_EQ(threshold(img, o).output.num_cells(), 1u);  // a NaN corner: no range
  img.cell_data.add(DataArray::from_vector<float>("f", 1, {0, 10, static_cast<float>(kNaN)}));
  o.array = "f";
  EXPECT_EQ(threshold(img, o).output.num_cells(), 2u);
}

TEST(Threshold, ComponentsAndMagnitude) {
  ImageData img;
  img.dims = {3, 1, 1};  // two line cells
  img.point_data.add(DataArray::from_vector<double>("v", 3, {3, 4, 0, 0, 0, 1, 0, -2, 0}));
  ThresholdOptions o = range(4.5, 5.5);
  o.array = "v";
  o.component = -1;  // |v| = 5, 1, 2
  o.mode = ThresholdMode::AnyPoint;
  auto out = threshold(img, o).output;
  ASSERT_EQ(out.num_cells(), 1u);
  EXPECT_EQ(out.types[0], CellType::Line);
  EXPECT_EQ(out.num_points(), 2u);
  o = range(-2, -1);
  o.array = "v";
  o.component = 1;  // y: 4, 0, -2
  EXPECT_EQ(threshold(img, o).output.num_cells(), 0u);
  o.mode = ThresholdMode::AnyPoint;
  out = threshold(img, o).output;
  ASSERT_EQ(out.num_cells(), 1u);
  EXPECT_EQ(out.point_data.get("v").get(1, 1), -2.0);
}

TEST(Threshold, BadArgumentsAreErrorsNamingTheProblem) {
  const ImageData img = row_of_voxels();
  const auto message = [&](ThresholdOptions o) {
    try {
      (void)threshold(img, o);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message(range(2, 1)), "threshold: lower bound 2 exceeds upper bound 1");
  EXPECT_NE(message(range(kNaN, 1)).find("NaN"), std::string::npos);
  ThresholdOptions o;
  o.array = "nope";
  EXPECT_EQ(message(o), "threshold: no array 'nope' (point arrays: 's'; cell arrays: 'c')");
  o.array = "s";
  o.component = 1;
  EXPECT_NE(message(o).find("component 1 of 's', which has 1 component"), std::string::npos);
  o.component = -2;
  EXPECT_NE(message(o).find("component -2"), std::string::npos);
  ImageData bare;
  bare.dims = {2, 2, 2};
  EXPECT_THROW((void)threshold(bare, {}), Error);  // no active scalars
}

TEST(Threshold, WholeRangeIsTheInputAndComplementaryRangesPartitionTheCells) {
  // post.vtk: 8750 tetrahedra, every point used, point scalars "Pressure" 0.355..1.641.
  const Dataset ds = read(std::string(ISOFORGE_DATA_DIR) + "/post.vtk");
  const auto& ug = std::get<UnstructuredGrid>(ds);
  ThresholdOptions o;
  o.array = "Pressure";
  const UnstructuredGrid whole = threshold(ug, o).output;
  EXPECT_EQ(whole, ug);  // same points, cells, arrays, in the same order
  // A cell array that splits the cells: [lo, t] and (t, hi] partition them.
  UnstructuredGrid g = ug;
  DataArray cv("cv", ScalarType::Float64, 1, g.num_cells());
  for (std::size_t c = 0; c < g.num_cells(); ++c) cv.set(c, 0, std::sin(0.37 * static_cast<double>(c)));
  g.cell_data.add(std::move(cv));
  o.array = "cv";
  o.original_ids = true;
  o.upper = 0.1;
  const auto low = threshold(g, o).output;
  o.lower = std::nextafter(0.1, 1.0);
  o.upper = std::numeric_limits<double>::infinity();
  const auto high = threshold(g, o).output;
  EXPECT_EQ(low.num_cells() + high.num_cells(), g.num_cells());
  std::set<double> ids;
  for (const auto* part : {&low, &high})
    for (std::size_t c = 0; c < part->num_cells(); ++c)
      ids.insert(part->cell_data.get("OriginalCellIds").get(c));
  EXPECT_EQ(ids.size(), g.num_cells());
  EXPECT_GT(low.num_cells(), 1000u);
  EXPECT_GT(high.num_cells(), 1000u);
  // The point overlap and the AllPoints/AnyPoint split of a point array: all <= overlap <= any.
  o = range(0.8, 1.0);
  o.array = "Pressure";
  const std::size_t n_all = threshold(ug, o).output.num_cells();
  o.mode = ThresholdMode::Overlap;
  const std::size_t n_overlap = threshold(ug, o).output.num_cells();
  o.mode = ThresholdMode::AnyPoint;
  const std::size_t n_any = threshold(ug, o).output.num_cells();
  EXPECT_LT(0u, n_all);
  EXPECT_LE(n_all, n_overlap);
  EXPECT_LE(n_any, n_overlap);  // overlap also keeps cells spanning the range with no point in it
  EXPECT_LT(n_all, n_any);
}

TEST(Threshold, PolyDataAndStructuredGridCellTypes) {
  PolyData pd;
  for (int i = 0; i < 5; ++i) pd.points.push_back({static_cast<double>(i), 0, 0});
  pd.verts.add({4});
  pd.lines.add({0, 1, 2});
  pd.polys.add({1, 2, 3, 4});
  pd.point_data.add(DataArray::from_vector<float>("s", 1, {0, 1, 2, 3, 4}), AttributeRole::Scalars);
  ThresholdOptions o = range(1, 4);
  const auto out = threshold(pd, o).output;
  ASSERT_EQ(out.num_cells(), 2u);
  EXPECT_EQ(out.types[0], CellType::Vertex);
  EXPECT_EQ(out.types[1], CellType::Quad);
  EXPECT_EQ(out.num_points(), 4u);
  StructuredGrid sg;
  sg.dims = {2, 2, 2};
  sg.points = Points(8);
  for (std::size_t i = 0; i < 8; ++i)
    sg.points.set(i, {static_cast<double>(i & 1), static_cast<double>(i >> 1 & 1), static_cast<double>(i >> 2)});
  sg.cell_data.add(DataArray::from_vector<float>("c", 1, {1}), AttributeRole::Scalars);
  const auto hex = threshold(sg, o).output;
  ASSERT_EQ(hex.num_cells(), 1u);
  EXPECT_EQ(hex.types[0], CellType::Hexahedron);
  EXPECT_EQ(to_unstructured(sg).cells, hex.cells);
}

TEST(Threshold, SameOutputForAnyThreadCount) {
  ImageData img;
  img.dims = {41, 37, 33};  // 50 688 voxels: several blocks
  DataArray s("s", ScalarType::Float32, 1, img.num_points());
  for (std::size_t i = 0; i < img.num_points(); ++i) {
    const Vec3 p = img.point(static_cast<Index>(i));
    s.set(i, 0, std::sin(0.3 * p.x) * std::cos(0.2 * p.y) + 0.01 * p.z);
  }
  img.point_data.add(std::move(s), AttributeRole::Scalars);
  ThresholdOptions o = range(-0.2, 0.5);
  o.original_ids = true;
  const auto many = threshold(img, o).output;
  UnstructuredGrid one;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = threshold(img, o).output;
  }
  EXPECT_GT(many.num_cells(), 1000u);
  EXPECT_EQ(many, one);
  // And the same as a serial reference: the cells whose 8 corners all lie in the range.
  std::size_t expected = 0;
  std::vector<Index> ids;
  for (std::size_t c = 0; c < img.num_cells(); ++c) {
    cell_point_ids(img, static_cast<Index>(c), ids);
    bool all = true;
    for (Index id : ids) {
      const double v = img.point_data.get("s").get(static_cast<std::size_t>(id));
      all = all && v >= -0.2 && v <= 0.5;
    }
    expected += all;
  }
  EXPECT_EQ(many.num_cells(), expected);
}
