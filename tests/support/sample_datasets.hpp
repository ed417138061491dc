#pragma once
// Small datasets of every type, built in code, with attributes of several types and roles.
// Shared by io round-trip tests.

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "isoforge/core/dataset.hpp"

namespace isoforge::test {

/// 4 x 3 x 2 image, origin (1, 2, 3), spacing (0.5, 0.25, 2); point scalars (float32, active),
/// point vectors (float64, active), cell ids (int32).
inline ImageData sample_image() {
  ImageData img;
  img.dims = {4, 3, 2};
  img.origin = {1, 2, 3};
  img.spacing = {0.5, 0.25, 2};
  const std::size_t np = img.num_points();
  DataArray s("temperature", ScalarType::Float32, 1, np);
  DataArray v("velocity", ScalarType::Float64, 3, np);
  for (std::size_t i = 0; i < np; ++i) {
    s.set(i, 0, 0.1 * static_cast<double>(i) - 1.0);
    v.set(i, 0, std::sin(static_cast<double>(i)));
    v.set(i, 1, std::cos(static_cast<double>(i)));
    v.set(i, 2, static_cast<double>(i) / 7.0);
  }
  img.point_data.add(std::move(s), AttributeRole::Scalars);
  img.point_data.add(std::move(v), AttributeRole::Vectors);
  DataArray c("cell_id", ScalarType::Int32, 1, img.num_cells());
  for (std::size_t i = 0; i < img.num_cells(); ++i) c.set(i, 0, static_cast<double>(i));
  img.cell_data.add(std::move(c));
  return img;
}

/// A 3 x 2 x 2 curvilinear grid (a sheared box) with point density and cell uint8 flags.
inline StructuredGrid sample_structured() {
  StructuredGrid sg;
  sg.dims = {3, 2, 2};
  for (Index k = 0; k < 2; ++k)
    for (Index j = 0; j < 2; ++j)
      for (Index i = 0; i < 3; ++i)
        sg.points.push_back({i + 0.25 * static_cast<double>(j), j + 0.5 * static_cast<double>(k),
                             static_cast<double>(k) * 1.5});
  DataArray d("density", ScalarType::Float32, 1, sg.num_points());
  for (std::size_t i = 0; i < sg.num_points(); ++i) d.set(i, 0, 1.0 + 0.125 * static_cast<double>(i));
  sg.point_data.add(std::move(d), AttributeRole::Scalars);
  DataArray f("flag", ScalarType::UInt8, 1, sg.num_cells());
  f.set(1, 0, 1);
  sg.cell_data.add(std::move(f));
  return sg;
}

/// A unit square pyramid surface: 5 points, 4 triangles + 1 quad, one line and one vertex;
/// point normals (active), int64 point ids, cell scalars; field data.
inline PolyData sample_poly(bool surface_only = false) {
  PolyData pd;
  pd.points.push_back({0, 0, 0});
  pd.points.push_back({1, 0, 0});
  pd.points.push_back({1, 1, 0});
  pd.points.push_back({0, 1, 0});
  pd.points.push_back({0.5, 0.5, 1});
  pd.polys.add({0, 3, 2, 1});
  pd.polys.add({0, 1, 4});
  pd.polys.add({1, 2, 4});
  pd.polys.add({2, 3, 4});
  pd.polys.add({3, 0, 4});
  if (!surface_only) {
    pd.verts.add({4});
    pd.lines.add({0, 2});
  }
  DataArray n("Normals", ScalarType::Float32, 3, 5);
  for (std::size_t i = 0; i < 5; ++i) {
    auto p = pd.points[i] - Vec3{0.5, 0.5, 0.3};
    p = p / norm(p);
    for (int c = 0; c < 3; ++c) n.set(i, c, p[c]);
  }
  pd.point_data.add(std::move(n), AttributeRole::Normals);
  DataArray ids("point_ids", ScalarType::Int64, 1, 5);
  for (std::size_t i = 0; i < 5; ++i) ids.set(i, 0, static_cast<double>(i) * 1000000007.0);
  pd.point_data.add(std::move(ids));
  if (!surface_only) {
    DataArray cs("area_class", ScalarType::Float64, 1, pd.num_cells());
    for (std::size_t i = 0; i < pd.num_cells(); ++i) cs.set(i, 0, 1.0 / (1.0 + static_cast<double>(i)));
    pd.cell_data.add(std::move(cs), AttributeRole::Scalars);
    pd.field_data.add(DataArray::from_vector<double>("time", 1, {0.25}));
  }
  return pd;
}

/// One cell of each 3D type plus a triangle and a line, sharing points; float64 points.
inline UnstructuredGrid sample_unstructured() {
  UnstructuredGrid ug;
  ug.points = Points(0, ScalarType::Float64);
  // A unit cube's 8 corners (hexahedron order), then an apex above it and a point beside it.
  const double c[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                          {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  for (auto& p : c) ug.points.push_back({p[0], p[1], p[2]});
  ug.points.push_back({0.5, 0.5, 2});      // 8: pyramid apex on top face
  ug.points.push_back({2, 0.5, 0.5});      // 9
  ug.points.push_back({1.0 / 3, 1e-17, 5});  // 10: awkward doubles
  ug.add_cell(CellType::Hexahedron, {0, 1, 2, 3, 4, 5, 6, 7});
  ug.add_cell(CellType::Pyramid, {4, 5, 6, 7, 8});
  ug.add_cell(CellType::Tetra, {1, 2, 5, 9});
  ug.add_cell(CellType::Wedge, {1, 5, 9, 2, 6, 10});
  ug.add_cell(CellType::Triangle, {8, 9, 10});
  ug.add_cell(CellType::Line, {0, 10});
  ug.add_cell(CellType::Quad, {0, 1, 5, 4});
  ug.add_cell(CellType::Polygon, {0, 1, 9, 2, 3});
  ug.add_cell(CellType::Vertex, {10});
  DataArray p("pressure", ScalarType::Float64, 1, ug.num_points());
  for (std::size_t i = 0; i < ug.num_points(); ++i) p.set(i, 0, std::sqrt(static_cast<double>(i)));
  ug.point_data.add(std::move(p), AttributeRole::Scalars);
  DataArray t("stress", ScalarType::Float32, 9, ug.num_points());
  for (std::size_t i = 0; i < ug.num_points(); ++i)
    for (int k = 0; k < 9; ++k) t.set(i, k, static_cast<double>(k) - static_cast<double>(i));
  ug.point_data.add(std::move(t), AttributeRole::Tensors);
  DataArray m("material", ScalarType::Int16, 1, ug.num_cells());
  for (std::size_t i = 0; i < ug.num_cells(); ++i) m.set(i, 0, -static_cast<double>(i));
  ug.cell_data.add(std::move(m));
  return ug;
}

/// A signed distance field of a sphere (centre (0.8, 2.1, 3.7), radius 1.3) sampled on a
/// 24 x 20 x 18 image with origin (-1.5, 0.25, 2) and spacing 0.2: Float32 scalars `name`.
inline ImageData sphere_distance_image(const std::string& name = "distance") {
  ImageData img;
  img.dims = {24, 20, 18};
  img.origin = {-1.5, 0.25, 2.0};
  img.spacing = {0.2, 0.2, 0.2};
  const Vec3 c{0.8, 2.1, 3.7};
  std::vector<float> v;
  for (Index k = 0; k < img.dims[2]; ++k) {
    for (Index j = 0; j < img.dims[1]; ++j) {
      for (Index i = 0; i < img.dims[0]; ++i) {
        v.push_back(static_cast<float>(norm(img.point(i, j, k) - c) - 1.3));
      }
    }
  }
  img.point_data.add(DataArray::from_vector(name, 1, std::move(v)), AttributeRole::Scalars);
  return img;
}

/// One cell of `type` over the points `pts`, in order.
inline UnstructuredGrid single_cell(CellType type, const std::vector<Vec3>& pts) {
  UnstructuredGrid g;
  std::vector<Index> ids;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    g.points.push_back(pts[i]);
    ids.push_back(static_cast<Index>(i));
  }
  g.add_cell(type, ids);
  return g;
}

}  // namespace isoforge::test
