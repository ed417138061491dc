// Timing of tensor glyphs (verify/bench/tensor_glyph.sh): 100 000 points on a 47³ image with the
// stress tensor of a point load on a half-space (Boussinesq), ellipsoids of 12 × 7 (62 points,
// 120 triangles); the peer (peers/vtk_tensor_glyph.py) builds the same field with numpy and runs
// vtkTensorGlyph with a vtkSphereSource of the same size. One JSON line per thread count,
// minimum of --repeat runs.
//
//   tensor_glyph_time [--repeat R]

#include <fmt/core.h>
#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <numbers>

#include "isoforge/filters/tensor_glyph.hpp"

using namespace isoforge;

int main(int argc, char** argv) {
  int repeat = 3;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc) repeat = std::max(1, std::atoi(argv[++i]));
    else {
      fmt::print(stderr, "usage: tensor_glyph_time [--repeat R]\n");
      return 2;
    }
  }
  // Boussinesq: unit load P at the origin on the half-space z < 0, Poisson ratio ν = 0.3
  // (the stress field of VTK's pointLoad source), sampled on [-1, 1]² × [-2, -0.1].
  ImageData img;
  img.dims = {47, 47, 47};
  img.origin = {-1, -1, -2};
  img.spacing = {2.0 / 46, 2.0 / 46, 1.9 / 46};
  const std::size_t n = img.num_points();
  DataArray t("stress", ScalarType::Float32, 9, n);
  const double P = 1, nu = 0.3;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 p = img.point(Index(i));
    const double x = p.x, y = p.y, z = -p.z;  // depth
    const double rho = std::sqrt(x * x + y * y + z * z), rho2 = rho * rho, rho3 = rho2 * rho,
                 rho5 = rho3 * rho2, rz = rho + z, rz2 = rz * rz;
    const double k = P / (2 * std::numbers::pi);
    const double sxx = k * (3 * x * x * z / rho5 + (1 - 2 * nu) * (z / rho3 - 1 / (rho * rz) + x * x * (2 * rho + z) / (rho3 * rz2)));
    const double syy = k * (3 * y * y * z / rho5 + (1 - 2 * nu) * (z / rho3 - 1 / (rho * rz) + y * y * (2 * rho + z) / (rho3 * rz2)));
    const double szz = k * 3 * z * z * z / rho5;
    const double sxy = k * (3 * x * y * z / rho5 - (1 - 2 * nu) * x * y * (2 * rho + z) / (rho3 * rz2));
    const double syz = k * 3 * y * z * z / rho5, sxz = k * 3 * x * z * z / rho5;
    const double m[9] = {sxx, sxy, sxz, sxy, syy, syz, sxz, syz, szz};
    for (int c = 0; c < 9; ++c) t.set(i, c, m[c]);
  }
  img.point_data.add(std::move(t), AttributeRole::Tensors);
  for (const int threads : {1, 2}) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    TensorGlyphOptions o;
    o.scale = 0.05;
    o.resolution = 12;
    double best = 1e300;
    std::size_t tris = 0;
    for (int r = 0; r < repeat; ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      const auto result = tensor_glyph(img, o);
      best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      tris = result.output.polys.size();
    }
    fmt::print("{{\"case\": \"boussinesq/{}\", \"peer\": \"isoforge\", \"threads\": {}, \"seconds\": {:.4f}, "
               "\"triangles\": {}}}\n", n, threads, best, tris);
  }
}
