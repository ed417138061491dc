// The filter times of the glyph benchmark (glyph.sh), the counterpart of peers/vtk_glyph.py:
// the same inputs in memory (built by the same formulas, or read from the same files before the
// clock starts), each filter run REPEAT times, the fastest run printed as one JSON line.
//
// Usage: glyph_time CASE [ARGS...]
//   glyph N SOURCE.vtp REPEAT      N points, cones (SOURCE) oriented and scaled by the vectors
//   hedgehog N REPEAT              N points, one line each
//   normals MESH REPEAT            compute_normals (split at 30 degrees, consistent, outward)
//   tube LINES RADIUS SIDES REPEAT tubes with caps
//   source OUT.vtp                 writes the cone both programs glyph (6 sides, with normals)

#include <fmt/core.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <string>

#include "isoforge/filters/compute_normals.hpp"
#include "isoforge/filters/glyph.hpp"
#include "isoforge/filters/tube.hpp"
#include "isoforge/io/io.hpp"

using namespace isoforge;

namespace {

// n points on a jittered lattice with a swirling vector field; vtk_glyph.py builds the same.
PolyData point_cloud(std::size_t n) {
  const auto side = static_cast<std::size_t>(std::ceil(std::cbrt(static_cast<double>(n))));
  PolyData pd;
  pd.points = Points(n);
  DataArray v("V", ScalarType::Float32, 3, n);
  float* p = pd.points.floats().data();
  float* w = v.values<float>().data();
  for (std::size_t i = 0; i < n; ++i) {
    const double x = static_cast<double>(i % side), y = static_cast<double>((i / side) % side),
                 z = static_cast<double>(i / (side * side));
    p[3 * i] = static_cast<float>(x + 0.25 * std::sin(1.3 * static_cast<double>(i)));
    p[3 * i + 1] = static_cast<float>(y);
    p[3 * i + 2] = static_cast<float>(z);
    w[3 * i] = static_cast<float>(std::sin(0.1 * y) + 0.2);
    w[3 * i + 1] = static_cast<float>(std::cos(0.1 * z));
    w[3 * i + 2] = static_cast<float>(std::sin(0.1 * x));
  }
  pd.point_data.add(std::move(v), AttributeRole::Vectors);
  return pd;
}

double best_of(int repeat, const std::function<std::size_t()>& run, std::size_t& size) {
  double best = INFINITY;
  for (int r = 0; r < repeat; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    size = run();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    fmt::print(stderr, "usage: glyph_time glyph|hedgehog|normals|tube ARGS... (see the source)\n");
    return 2;
  }
  const std::string what = argv[1];
  std::size_t points = 0;
  double seconds = 0;
  if (what == "glyph" && argc == 5) {
    const PolyData input = point_cloud(std::strtoull(argv[2], nullptr, 10));
    const auto source = std::get<PolyData>(read(argv[3]));
    GlyphOptions o;
    o.orient = GlyphOrient::Vectors;
    o.scale = GlyphScale::Vector;
    o.factor = 0.5;
    o.carry_point_data = false;  // vtkGlyph3D does not copy the vectors either
    seconds = best_of(std::atoi(argv[4]), [&] { return glyph(input, source, o).output.num_points(); }, points);
  } else if (what == "source" && argc == 3) {
    write(glyph_source(GlyphShape::Cone, 6), argv[2]);
    return 0;
  } else if (what == "hedgehog" && argc == 4) {
    const PolyData input = point_cloud(std::strtoull(argv[2], nullptr, 10));
    GlyphOptions o;
    o.scale = GlyphScale::Vector;
    o.factor = 0.5;
    o.carry_point_data = false;
    o.point_ids = false;  // vtkHedgeHog makes none
    seconds = best_of(std::atoi(argv[3]), [&] { return glyph(input, GlyphShape::Line, o).output.num_points(); }, points);
  } else if (what == "normals" && argc == 4) {
    const auto mesh = std::get<PolyData>(read(argv[2]));
    seconds = best_of(std::atoi(argv[3]), [&] { return compute_normals(mesh).output.num_points(); }, points);
  } else if (what == "tube" && argc == 6) {
    const auto lines = std::get<PolyData>(read(argv[2]));
    TubeOptions o;
    o.radius = std::atof(argv[3]);
    o.sides = std::atoi(argv[4]);
    seconds = best_of(std::atoi(argv[5]), [&] { return tube(lines, o).output.num_points(); }, points);
  } else {
    fmt::print(stderr, "glyph_time: bad arguments for '{}'\n", what);
    return 2;
  }
  fmt::print("{{\"case\": \"{}\", \"peer\": \"isoforge\", \"seconds\": {:.6f}, \"output_points\": {}}}\n",
             what, seconds, points);
  return 0;
}
