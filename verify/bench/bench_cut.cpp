// Timing of cut and clip on in-memory data, the inputs of peers/vtk_cut.py built with the same
// formulas (run by cut.sh). Prints one JSON object: {"case": {"ms": min over repeats, ...}}.
// Usage: bench_cut THREADS REPEATS

#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>

#include "isoforge/filters/clip.hpp"
#include "isoforge/filters/cut.hpp"

using namespace isoforge;

namespace {

float field(double x, double y, double z) {
  return static_cast<float>(std::sin(x * 0.05) + std::cos(y * 0.07) + z * 0.01);
}

ImageData image(Index n) {
  ImageData img;
  img.dims = {n, n, n};
  DataArray s = DataArray::uninitialized("s", ScalarType::Float32, 1, img.num_points());
  auto v = s.values<float>();
  std::size_t i = 0;
  for (Index k = 0; k < n; ++k)
    for (Index j = 0; j < n; ++j)
      for (Index x = 0; x < n; ++x) v[i++] = field(static_cast<double>(x), static_cast<double>(j), static_cast<double>(k));
  img.point_data.add(std::move(s), AttributeRole::Scalars);
  return img;
}

StructuredGrid curvilinear(Index n) {
  StructuredGrid sg;
  sg.dims = {n, n, n};
  sg.points = Points(static_cast<std::size_t>(n * n * n));
  DataArray s = DataArray::uninitialized("s", ScalarType::Float32, 1, sg.points.size());
  auto v = s.values<float>();
  std::size_t i = 0;
  for (Index k = 0; k < n; ++k)
    for (Index j = 0; j < n; ++j)
      for (Index x = 0; x < n; ++x, ++i) {
        const Vec3 p{static_cast<double>(x) + 0.3 * std::sin(static_cast<double>(j) * 0.1),
                     static_cast<double>(j) + 0.3 * std::sin(static_cast<double>(k) * 0.1),
                     static_cast<double>(k)};
        const Vec3 q = sg.points.stored(p);
        sg.points.set(i, q);
        v[i] = field(q.x, q.y, q.z);
      }
  sg.point_data.add(std::move(s), AttributeRole::Scalars);
  return sg;
}

double time_ms(int repeats, const std::function<std::size_t()>& run, std::size_t& size) {
  double best = 1e300;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    size = run();
    const auto t1 = std::chrono::steady_clock::now();
    best = std::min(best, std::chrono::duration<double, std::milli>(t1 - t0).count());
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  const int threads = argc > 1 ? std::atoi(argv[1]) : 2;
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 5;
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  const Vec3 normal{-0.287, 0, 0.9579};
  std::string json = "{";
  auto add = [&](const std::string& name, double ms, std::size_t cells) {
    json += (json.size() > 1 ? ", " : "") + ("\"" + name + "\": {\"ms\": " + std::to_string(ms) +
                                             ", \"cells\": " + std::to_string(cells) + "}");
  };
  std::size_t cells = 0;
  CutOptions triangles;
  triangles.triangulate = true;
  ClipOptions inside;
  inside.inside_out = true;
  for (Index n : {256, 384}) {
    const ImageData img = image(n);
    const double h = static_cast<double>(n - 1) / 2;
    const ImplicitFunction plane = ImplicitFunction::plane({h, h, h}, normal);
    double ms = time_ms(repeats, [&] { return cut(img, plane).output.polys.size(); }, cells);
    add("plane_image/" + std::to_string(n), ms, cells);
    ms = time_ms(repeats, [&] { return cut(img, plane, triangles).output.polys.size(); }, cells);
    add("plane_image_triangles/" + std::to_string(n), ms, cells);
  }
  {
    const StructuredGrid sg = curvilinear(100);
    const ImplicitFunction plane = ImplicitFunction::plane({49.5, 49.5, 49.5}, normal);
    double ms = time_ms(repeats, [&] { return cut(sg, plane).output.polys.size(); }, cells);
    add("plane_curvilinear/100", ms, cells);
    ms = time_ms(repeats, [&] { return cut(sg, plane, triangles).output.polys.size(); }, cells);
    add("plane_curvilinear_triangles/100", ms, cells);
  }
  {
    const Index n = 256;
    const ImageData img = image(n);
    const double h = static_cast<double>(n - 1) / 2;
    const ImplicitFunction sphere = ImplicitFunction::sphere({h, h, h}, 0.4 * (n - 1));
    const double ms = time_ms(repeats, [&] {
      return clip(img, sphere, inside).output.num_cells();
    }, cells);
    add("clip_sphere_image/256", ms, cells);
  }
  json += "}";
  std::puts(json.c_str());
}
