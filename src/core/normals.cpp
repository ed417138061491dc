// Point normals of polygonal surfaces (core/normals.hpp).

#include "isoforge/core/normals.hpp"

#include <vector>

namespace isoforge {

DataArray point_normals(const PolyData& surface) {
  const std::size_t np = surface.points.size();
  std::vector<double> acc(3 * np, 0.0);
  const CellArray& polys = surface.polys;
  for (std::size_t c = 0; c < polys.size(); ++c) {
    const auto ids = polys.cell(c);
    for (std::size_t k = 1; k + 1 < ids.size(); ++k) {
      const Vec3 a = surface.points[static_cast<std::size_t>(ids[0])];
      const Vec3 b = surface.points[static_cast<std::size_t>(ids[k])];
      const Vec3 d = surface.points[static_cast<std::size_t>(ids[k + 1])];
      const Vec3 n = cross(b - a, d - a);  // twice the area, along the normal
      for (const Index id : {ids[0], ids[k], ids[k + 1]}) {
        for (int i = 0; i < 3; ++i)
          acc[3 * static_cast<std::size_t>(id) + static_cast<std::size_t>(i)] += n[i];
      }
    }
  }
  DataArray normals("Normals", ScalarType::Float32, 3, np);
  float* out = normals.values<float>().data();
  for (std::size_t i = 0; i < np; ++i) {
    const Vec3 n{acc[3 * i], acc[3 * i + 1], acc[3 * i + 2]};
    const double len = norm(n);
    const Vec3 u = len > 0 ? n / len : Vec3{0, 0, 0};
    out[3 * i] = static_cast<float>(u.x);
    out[3 * i + 1] = static_cast<float>(u.y);
    out[3 * i + 2] = static_cast<float>(u.z);
  }
  return normals;
}

}  // namespace isoforge
