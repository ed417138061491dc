// Points, segments and triangles over one vertex array (spatial/primitives.hpp).

#include "isoforge/spatial/primitives.hpp"

#include <fmt/format.h>

#include <cmath>

#include "isoforge/core/mesh_topology.hpp"

namespace isoforge {

PrimitiveSet::PrimitiveSet(std::vector<Vec3> vertices, std::vector<Id> points,
                           std::vector<std::array<Id, 2>> segments,
                           std::vector<std::array<Id, 3>> triangles)
    : vertices_(std::move(vertices)),
      points_(std::move(points)),
      segments_(std::move(segments)),
      triangles_(std::move(triangles)) {
  if (vertices_.size() >= kNone) throw Error("primitives: more than 2^32 - 2 vertices");
  for (std::size_t i = 0; i < vertices_.size(); ++i) {
    if (!is_finite(vertices_[i]))
      throw Error(fmt::format("primitives: vertex {} is not finite", i));
  }
  const auto check = [&](Id v) {
    if (v >= vertices_.size()) {
      throw Error(fmt::format("primitives: vertex id {} is out of range ({} vertices)", v,
                              vertices_.size()));
    }
  };
  for (Id v : points_) check(v);
  for (const auto& s : segments_)
    for (Id v : s) check(v);
  for (const auto& t : triangles_)
    for (Id v : t) check(v);
  const std::size_t total = points_.size() + segments_.size() + triangles_.size();
  if (total >= kNone) throw Error("primitives: more than 2^32 - 2 primitives");
  segment_begin_ = static_cast<Id>(points_.size());
  triangle_begin_ = static_cast<Id>(points_.size() + segments_.size());
  size_ = static_cast<Id>(total);
}

void PrimitiveSet::set_radii(std::vector<double> radii) {
  if (radii.size() != points_.size()) {
    throw Error(fmt::format("primitives: {} radii for {} points", radii.size(), points_.size()));
  }
  for (std::size_t i = 0; i < radii.size(); ++i) {
    if (!(radii[i] >= 0) || !std::isfinite(radii[i])) {
      throw Error(fmt::format("primitives: radius of point {} is {:g}, must be finite and >= 0",
                              points_[i], radii[i]));
    }
  }
  radii_ = std::move(radii);
}

Bounds PrimitiveSet::bounds(Id id) const {
  Bounds b;
  for_each_vertex(id, [&](const Vec3& v) { b.extend(v); });
  return b;
}

PrimitiveSet primitives_of(const PolyData& in, std::string_view what) {
  in.validate();
  if (in.num_cells() == 0 || in.points.empty()) {
    throw Error(fmt::format("{}: the input is empty (no vertices, lines or polygons)", what));
  }
  const std::size_t bad = in.points.first_non_finite();
  if (bad < in.points.size()) throw Error(fmt::format("{}: point {} is not finite", what, bad));
  if (in.points.size() >= PrimitiveSet::kNone) {
    throw Error(fmt::format("{}: more than 2^32 - 2 points", what));
  }
  using Id = PrimitiveSet::Id;
  std::vector<Vec3> vertices(in.points.size());
  for (std::size_t i = 0; i < in.points.size(); ++i) vertices[i] = in.points[i];
  std::vector<Id> points;
  for (std::size_t c = 0; c < in.verts.size(); ++c) {
    for (Index id : in.verts.cell(c)) points.push_back(static_cast<Id>(id));
  }
  std::vector<std::array<Id, 2>> segments;
  for (std::size_t c = 0; c < in.lines.size(); ++c) {
    const auto ids = in.lines.cell(c);
    for (std::size_t k = 0; k + 1 < ids.size(); ++k) {
      segments.push_back({static_cast<Id>(ids[k]), static_cast<Id>(ids[k + 1])});
    }
  }
  std::vector<std::array<Id, 3>> triangles;
  for (const auto& t : triangulate_faces(in)) {
    triangles.push_back({static_cast<Id>(t[0]), static_cast<Id>(t[1]), static_cast<Id>(t[2])});
  }
  const std::size_t total = points.size() + segments.size() + triangles.size();
  if (total >= PrimitiveSet::kNone)
    throw Error(fmt::format("{}: more than 2^32 - 2 primitives", what));
  if (total == 0)
    throw Error(fmt::format("{}: the input is empty (its cells have no primitives)", what));
  return PrimitiveSet(std::move(vertices), std::move(points), std::move(segments),
                      std::move(triangles));
}

}  // namespace isoforge
