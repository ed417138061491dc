// Timing of streamlines (verify/bench/streamline.sh): the ABC flow on an N³ image (float
// vectors), 10k seeds on a low-discrepancy sequence, RK4 with 0.5-cell steps and RK45, both
// directions, 500 steps at most; the peer (peers/vtk_streamline.py) builds the same field and
// seeds with numpy. With --write DIR, also the same flow (scaled to the unit cube) on the probe
// benchmark's warped 100³ grid and 44³-cube tetrahedral mesh (511 104 tetrahedra), written to
// DIR for the peer, 10 000 seeds (--file-seeds), RK4. One JSON line per case and thread count: the minimum of
// --repeat runs.
//
//   streamline_time [--n N] [--seeds S] [--repeat R] [--write DIR [--file-seeds K]]

#include <fmt/core.h>
#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <string>
#include <numbers>

#include "isoforge/filters/streamline.hpp"
#include "isoforge/io/io.hpp"
#include "peers/probe_inputs.hpp"

using namespace isoforge;

namespace {

// ABC flow with A = √3, B = √2, C = 1 over [0, 2π]³.
ImageData abc_field(Index n) {
  ImageData img;
  img.dims = {n, n, n};
  const double h = 2 * std::numbers::pi / double(n - 1);
  img.spacing = {h, h, h};
  const std::size_t np = img.num_points();
  DataArray v = DataArray::uninitialized("V", ScalarType::Float32, 3, np);
  float* p = v.values<float>().data();
  const double a = std::sqrt(3.0), b = std::sqrt(2.0), c = 1.0;
  for (Index k = 0; k < n; ++k)
    for (Index j = 0; j < n; ++j)
      for (Index i = 0; i < n; ++i) {
        const double x = double(i) * h, y = double(j) * h, z = double(k) * h;
        const std::size_t id = std::size_t(img.point_id(i, j, k));
        p[3 * id] = float(a * std::sin(z) + c * std::cos(y));
        p[3 * id + 1] = float(b * std::sin(x) + a * std::cos(z));
        p[3 * id + 2] = float(c * std::sin(y) + b * std::cos(x));
      }
  img.point_data.add(std::move(v), AttributeRole::Vectors);
  return img;
}

// The ABC flow over [0, 1]³ (one period of [0, 2π]³) at the points of `ds`, as "V".
template <class D>
void add_abc(D& ds) {
  const std::size_t np = num_points(ds);
  DataArray v = DataArray::uninitialized("V", ScalarType::Float32, 3, np);
  const double a = std::sqrt(3.0), b = std::sqrt(2.0), c = 1.0, k = 2 * std::numbers::pi;
  for (std::size_t i = 0; i < np; ++i) {
    const Vec3 p = point(ds, Index(i)) * k;
    v.set(i, 0, a * std::sin(p.z) + c * std::cos(p.y));
    v.set(i, 1, b * std::sin(p.x) + a * std::cos(p.z));
    v.set(i, 2, c * std::sin(p.y) + b * std::cos(p.x));
  }
  ds.point_data.add(std::move(v), AttributeRole::Vectors);
}

// Seeds i = 1..s: the R3 sequence (fractional parts of i α), scaled into [0.05, 0.95] of the box
// [0, L]³.
PolyData seeds(std::size_t s, double L = 2 * std::numbers::pi) {
  PolyData out;
  const double a[3] = {0.8191725133961645, 0.6710436067037893, 0.5497004779019703};
  for (std::size_t i = 1; i <= s; ++i) {
    Vec3 p;
    for (int d = 0; d < 3; ++d) {
      const double f = std::fmod(0.5 + double(i) * a[d], 1.0);
      p[d] = L * (0.05 + 0.9 * f);
    }
    out.points.push_back(p);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  Index n = 256;
  std::size_t nseeds = 10000;
  int repeat = 3;
  std::size_t file_seeds = 10000;
  std::string dir;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--n") && i + 1 < argc) n = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--seeds") && i + 1 < argc) nseeds = std::size_t(std::atol(argv[++i]));
    else if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc) repeat = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--write") && i + 1 < argc) dir = argv[++i];
    else if (!std::strcmp(argv[i], "--file-seeds") && i + 1 < argc) file_seeds = std::size_t(std::atol(argv[++i]));
    else {
      fmt::print(stderr, "usage: streamline_time [--n N] [--seeds S] [--repeat R] [--write DIR [--file-seeds K]]\n");
      return 2;
    }
  }
  if (!dir.empty()) {
    // Curvilinear grid and tetrahedra, RK4, seeds in the unit cube.
    StructuredGrid grid = bench::warped_grid(100);
    add_abc(grid);
    UnstructuredGrid tets = bench::tet_mesh(44);
    add_abc(tets);
    write(grid, dir + "/stream_grid.vts");
    write(tets, dir + "/stream_tets.vtu");
    const PolyData unit_seeds = seeds(file_seeds, 1.0);
    // VTK's step unit is each cell's bounding-box diagonal: a tetrahedron of the cube split has
    // the cube's, while the mean cell length of 6 tetrahedra per cube is the cube's / cbrt(6).
    // The same world step on both sides: 0.5 cbrt(6) of ours on the tetrahedra.
    auto time_it = [&](const char* name, DatasetRef ds, double step) {
      for (const int threads : {1, 2}) {
        tbb::global_control gc(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        StreamlineOptions o;
        o.integrator = StreamIntegrator::RK4;
        o.step = step;
        o.max_steps = 500;
        double best = 1e300;
        StreamlineStats stats;
        for (int r = 0; r < repeat; ++r) {
          const auto t0 = std::chrono::steady_clock::now();
          auto result = streamlines(ds, unit_seeds, o);
          best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
          stats = result.stats;
        }
        fmt::print("{{\"case\": \"{}\", \"peer\": \"isoforge\", \"threads\": {}, \"seconds\": {:.4f}, "
                   "\"lines\": {}, \"points\": {}}}\n",
                   name, threads, best, stats.lines, stats.points);
      }
    };
    time_it("rk4/curvilinear100", grid, 0.5);
    time_it("rk4/tets44", tets, 0.5 * std::cbrt(6.0));
  }
  const ImageData field = abc_field(n);
  const PolyData s = seeds(nseeds);
  for (const auto& [name, integrator] :
       {std::pair{"rk4", StreamIntegrator::RK4}, std::pair{"rk45", StreamIntegrator::RK45}}) {
    for (const int threads : {1, 2}) {
      tbb::global_control gc(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
      StreamlineOptions o;
      o.integrator = integrator;
      o.step = 0.5;
      o.max_steps = 500;
      o.max_error = 1e-4;
      double best = 1e300;
      StreamlineStats stats;
      for (int r = 0; r < repeat; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        auto result = streamlines(field, s, o);
        best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        stats = result.stats;
      }
      fmt::print("{{\"case\": \"{}/{}\", \"peer\": \"isoforge\", \"threads\": {}, \"seconds\": {:.4f}, "
                 "\"lines\": {}, \"points\": {}}}\n",
                 name, n, threads, best, stats.lines, stats.points);
    }
  }
}
