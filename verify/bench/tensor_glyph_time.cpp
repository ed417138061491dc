// Timing of tensor glyphs (verify/bench/tensor_glyph.sh): 100 000 points on a 47³ image with the
// stress tensor of a point load on a half-space (Boussinesq, model/point_load.hpp), ellipsoids of
// 12 × 7 (62 points, 120 triangles); the peer (peers/vtk_tensor_glyph.py) samples the same field
// with vtkPointLoad and runs vtkTensorGlyph with a vtkSphereSource of the same size. One JSON
// line per thread count, minimum of --repeat runs.
//
//   tensor_glyph_time [--repeat R]

#include <fmt/core.h>
#include <tbb/global_control.h>

#include <chrono>
#include <cstring>

#include "isoforge/filters/tensor_glyph.hpp"
#include "isoforge/model/point_load.hpp"

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
  // Boussinesq: unit load at the centre of the top face of [-1, 1]³, Poisson ratio 0.3, 47³
  // samples: the field of VTK's vtkPointLoad with the same settings.
  PointLoadOptions field;
  field.dims = {47, 47, 47};
  field.scalars = "";
  const ImageData img = point_load(field).output;
  const std::size_t n = img.num_points();
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
