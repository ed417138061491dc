#include "isoforge/core/dataset.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

using namespace isoforge;

TEST(ImageData, CountsBoundsAndPoints) {
  ImageData img;
  img.dims = {3, 4, 5};
  img.origin = {1, 2, 3};
  img.spacing = {0.5, 1, 2};
  EXPECT_EQ(img.num_points(), 60u);
  EXPECT_EQ(img.num_cells(), 2u * 3u * 4u);
  auto b = img.bounds();
  EXPECT_EQ(b.min, (Vec3{1, 2, 3}));
  EXPECT_EQ(b.max, (Vec3{2, 5, 11}));
  EXPECT_EQ(img.point(img.point_id(2, 1, 3)), (Vec3{2, 3, 9}));
  EXPECT_NO_THROW(img.validate());
  img.point_data.add(DataArray("s", ScalarType::Float32, 1, 59));
  EXPECT_THROW(img.validate(), Error);  // 59 tuples for 60 points
}

TEST(ImageData, CellTypesByDimension) {
  ImageData img;
  img.dims = {1, 1, 1};
  EXPECT_EQ(img.num_cells(), 1u);
  EXPECT_EQ(cell_type(Dataset(img), 0), CellType::Vertex);
  img.dims = {4, 1, 1};
  EXPECT_EQ(img.num_cells(), 3u);
  EXPECT_EQ(cell_type(Dataset(img), 0), CellType::Line);
  img.dims = {4, 1, 3};  // a 2D image in the xz plane
  EXPECT_EQ(img.num_cells(), 6u);
  EXPECT_EQ(cell_type(Dataset(img), 0), CellType::Pixel);
  std::vector<Index> ids;
  cell_point_ids(Dataset(img), 4, ids);  // cell (1, 1) of a 3 x 2 cell grid
  // pixel order: (i,k), (i+1,k), (i,k+1), (i+1,k+1); point id = i + 4 * k
  EXPECT_EQ(ids, (std::vector<Index>{5, 6, 9, 10}));
}

TEST(ImageData, VoxelOrderMatchesVtk) {
  ImageData img;
  img.dims = {3, 3, 3};
  std::vector<Index> ids;
  cell_point_ids(Dataset(img), 7, ids);  // cell (1, 1, 1)
  const Index b = 1 + 3 * (1 + 3 * 1);
  EXPECT_EQ(ids, (std::vector<Index>{b, b + 1, b + 3, b + 4, b + 9, b + 10, b + 12, b + 13}));
}

TEST(Dims, OverflowAndNegativeAreErrors) {
  EXPECT_THROW((void)checked_point_count({-1, 2, 2}, "test"), Error);
  EXPECT_THROW((void)checked_point_count({0, 2, 2}, "test"), Error);
  const Index big = Index{1} << 40;
  EXPECT_THROW((void)checked_point_count({big, big, 2}, "test"), Error);
  EXPECT_EQ(checked_point_count({2, 3, 4}, "test"), 24u);
}

TEST(StructuredGrid, HexOrderAndValidation) {
  StructuredGrid sg;
  sg.dims = {2, 2, 2};
  sg.points = Points(8);
  for (std::size_t i = 0; i < 8; ++i) {
    sg.points.set(i, {double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
  }
  EXPECT_NO_THROW(sg.validate());
  std::vector<Index> ids;
  cell_point_ids(Dataset(sg), 0, ids);
  EXPECT_EQ(ids, (std::vector<Index>{0, 1, 3, 2, 4, 5, 7, 6}));
  EXPECT_EQ(cell_type(Dataset(sg), 0), CellType::Hexahedron);
  sg.points.resize(7);
  EXPECT_THROW(sg.validate(), Error);
}

TEST(PolyData, CellOrderAndValidation) {
  PolyData pd;
  for (int i = 0; i < 5; ++i) pd.points.push_back({double(i), 0, 0});
  pd.verts.add({0});
  pd.lines.add({0, 1, 2});
  pd.polys.add({0, 1, 2});
  pd.polys.add({0, 1, 2, 3});
  pd.polys.add({0, 1, 2, 3, 4});
  EXPECT_EQ(pd.num_cells(), 5u);
  Dataset ds = pd;
  EXPECT_EQ(cell_type(ds, 0), CellType::Vertex);
  EXPECT_EQ(cell_type(ds, 1), CellType::PolyLine);
  EXPECT_EQ(cell_type(ds, 2), CellType::Triangle);
  EXPECT_EQ(cell_type(ds, 3), CellType::Quad);
  EXPECT_EQ(cell_type(ds, 4), CellType::Polygon);
  EXPECT_NO_THROW(pd.validate());
  pd.polys.add({0, 1, 5});  // id 5 is out of range
  EXPECT_THROW(pd.validate(), Error);
}

TEST(UnstructuredGrid, ValidatesTypesAndSizes) {
  UnstructuredGrid ug;
  for (int i = 0; i < 4; ++i) ug.points.push_back({double(i == 1), double(i == 2), double(i == 3)});
  ug.add_cell(CellType::Tetra, {0, 1, 2, 3});
  EXPECT_NO_THROW(ug.validate());
  ug.add_cell(CellType::Hexahedron, {0, 1, 2, 3});  // a hexahedron needs 8 points
  EXPECT_THROW(ug.validate(), Error);
}

TEST(Dataset, ToUnstructuredKeepsCellsAndData) {
  ImageData img;
  img.dims = {3, 2, 2};
  img.point_data.add(DataArray("s", ScalarType::Float32, 1, 12), AttributeRole::Scalars);
  img.cell_data.add(DataArray("c", ScalarType::Int32, 1, 2));
  UnstructuredGrid ug = to_unstructured(img);
  EXPECT_EQ(ug.num_points(), 12u);
  EXPECT_EQ(ug.num_cells(), 2u);
  EXPECT_EQ(ug.types[1], CellType::Voxel);
  EXPECT_EQ(ug.point_data.scalars()->name(), "s");
  EXPECT_NO_THROW(ug.validate());
  EXPECT_EQ(ug.points[11], (Vec3{2, 1, 1}));
}

TEST(Points, Float64AndNonFinite) {
  Points p(2, ScalarType::Float64);
  p.set(0, {1e-300, 2, 3});
  p.set(1, {std::numeric_limits<double>::quiet_NaN(), 0, 0});
  EXPECT_EQ(p[0].x, 1e-300);
  EXPECT_EQ(p.first_non_finite(), 1u);
  EXPECT_THROW(Points(2, ScalarType::Int32), Error);
}

TEST(CellArray, ValidateNamesTheFirstBadCellOfALargeArray) {
  // 300 000 cells over several of the check's parallel ranges, every tenth one empty: the error
  // names the lowest bad cell (found from its position by the sorted offsets), for any thread
  // count.
  const std::size_t cells = 300'000;
  std::vector<Index> offsets{0}, connectivity;
  for (std::size_t c = 0; c < cells; ++c) {
    if (c % 10 != 3) {
      for (Index k = 0; k < 3; ++k) connectivity.push_back(static_cast<Index>((c + k) % 1000));
    }
    offsets.push_back(static_cast<Index>(connectivity.size()));
  }
  const auto error_of = [](const CellArray& a) {
    try {
      a.validate(1000, "polys");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error_of(CellArray(offsets, connectivity)), "");
  // Bad ids in cells 250 000, 120 001 and (negative) 270 000: cell 120 001 is named.
  std::vector<Index> bad = connectivity;
  const auto first_of = [&](std::size_t c) { return static_cast<std::size_t>(offsets[c]); };
  bad[first_of(250'000) + 1] = 1000;
  bad[first_of(120'001) + 2] = 5000;
  bad[first_of(270'000)] = -4;
  EXPECT_EQ(error_of(CellArray(offsets, bad)),
            "polys: cell 120001 refers to point 5000, outside [0, 1000)");
  bad[first_of(120'001) + 2] = 1;
  EXPECT_EQ(error_of(CellArray(offsets, bad)),
            "polys: cell 250000 refers to point 1000, outside [0, 1000)");
  // Decreasing offsets, named by the first cell whose end comes before its start.
  std::vector<Index> down = offsets;
  down[200'001] = down[200'000] - 1;
  down[100'002] = down[100'001] - 1;
  try {
    CellArray a(down, connectivity);
    ADD_FAILURE() << "decreasing offsets accepted";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "CellArray: offsets decrease at cell 100001");
  }
}

/// The message of `d.validate()`, or "" when it passes.
template <class D>
std::string validate_error(const D& d) {
  try {
    d.validate();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(PolyData, ValidateNamesTheFirstShortCellOfALargeArray) {
  // 300 000 triangles over several parallel ranges; short cells at 210 000 and 140 001 (a
  // two-point polygon) and an empty vertex: the lowest of each list is named.
  PolyData pd;
  for (int i = 0; i < 10; ++i) pd.points.push_back({double(i), 0, 0});
  const auto triangles = [&](std::size_t short_a, std::size_t short_b) {
    CellArray a;
    for (std::size_t c = 0; c < 300'000; ++c) {
      if (c == short_a || c == short_b) {
        a.add({1, 2});
      } else {
        a.add({0, 1, 2});
      }
    }
    return a;
  };
  pd.polys = triangles(1'000'000, 1'000'000);
  EXPECT_NO_THROW(pd.validate());
  pd.polys = triangles(210'000, 140'001);
  EXPECT_EQ(validate_error(pd), "polys: cell 140001 has fewer than 3 points");
  EXPECT_EQ(pd.polys.first_smaller_than(3), 140'001u);
  EXPECT_EQ(pd.polys.first_smaller_than(2), pd.polys.size());
  pd.strips = triangles(250'000, 1'000'000);
  pd.polys = triangles(1'000'000, 1'000'000);
  EXPECT_THROW(pd.validate(), Error);
  pd.strips = CellArray();
  pd.verts = CellArray(std::vector<Index>{0, 1, 1}, std::vector<Index>{5});  // cell 1 empty
  EXPECT_EQ(validate_error(pd), "verts: cell 1 is empty");
}

TEST(UnstructuredGrid, ValidateNamesTheFirstBadCellOfALargeGrid) {
  // 200 000 tetrahedra; a hexahedron of 4 points at 150 000 and an unknown type at 90 000: the
  // lowest is named, with its problem.
  UnstructuredGrid ug;
  for (int i = 0; i < 4; ++i) ug.points.push_back({double(i == 1), double(i == 2), double(i == 3)});
  for (std::size_t c = 0; c < 200'000; ++c) {
    ug.add_cell(c == 150'000 ? CellType::Hexahedron : CellType::Tetra, {0, 1, 2, 3});
  }
  EXPECT_EQ(validate_error(ug), "unstructured grid: cell 150000 (hexahedron) has 4 points");
  ug.types[90'000] = static_cast<CellType>(200);
  EXPECT_EQ(validate_error(ug), "unstructured grid: cell 90000 has unknown type 200");
}

TEST(Points, FirstNonFiniteOfALargeSetIsTheLowest) {
  Points p(500'000, ScalarType::Float32);
  for (std::size_t i = 0; i < p.size(); ++i) p.set(i, {double(i), 1, 2});
  EXPECT_EQ(p.first_non_finite(), p.size());
  p.set(420'000, {0, std::numeric_limits<double>::infinity(), 0});
  p.set(333'333, {0, 0, std::numeric_limits<double>::quiet_NaN()});
  EXPECT_EQ(p.first_non_finite(), 333'333u);
}
