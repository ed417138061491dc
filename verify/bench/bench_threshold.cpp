// Threshold and surface extraction benchmark (threshold.sh runs it beside peers/vtk_threshold.py).
//
//   bench_threshold make DIR      writes the inputs: DIR/tets.vtu (a 100^3 hexahedral grid split
//                                 into 5 tetrahedra per hexahedron: 5 000 000 tetrahedra, 1 030 301
//                                 points) and DIR/image.vti (256^3 points), each with the point
//                                 scalar field "s" below
//   bench_threshold time DIR REPS [CASE]  reads them and times each filter on the data in memory, REPS
//                                 times with all threads and REPS times with one; prints one JSON
//                                 object {"case/threads": {"ms": min, "cells": output cells}}
//
// The field s = sin(2 pi x) sin(2 pi y) sin(2 pi z) over [0, 1]^3; the threshold keeps
// s in [-0.2, 0.5] with all points of a cell in the range (vtkThreshold's AllScalars).

#include <fmt/core.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <string>

#include "isoforge/filters/surface.hpp"
#include "isoforge/filters/threshold.hpp"
#include "isoforge/io/io.hpp"

using namespace isoforge;

namespace {

constexpr double kLower = -0.2, kUpper = 0.5;

double field(const Vec3& p) {
  const double w = 2 * std::numbers::pi;
  return std::sin(w * p.x) * std::sin(w * p.y) * std::sin(w * p.z);
}

UnstructuredGrid tets(Index n) {
  const Index m = n + 1;
  UnstructuredGrid g;
  g.points = Points(static_cast<std::size_t>(m * m * m));
  DataArray s("s", ScalarType::Float32, 1, g.points.size());
  const double h = 1.0 / static_cast<double>(n);
  for (Index k = 0; k < m; ++k)
    for (Index j = 0; j < m; ++j)
      for (Index i = 0; i < m; ++i) {
        const auto id = static_cast<std::size_t>(i + m * (j + m * k));
        const Vec3 p{static_cast<double>(i) * h, static_cast<double>(j) * h, static_cast<double>(k) * h};
        g.points.set(id, p);
        s.set(id, 0, field(p));
      }
  g.point_data.add(std::move(s), AttributeRole::Scalars);
  // Corner c of a hexahedron is (c & 1, c >> 1 & 1, c >> 2 & 1). Five tetrahedra: the central one
  // on the corners of one parity and a corner tetrahedron at each corner of the other; the
  // parity alternates with i + j + k, so the face diagonals of neighbours match.
  static constexpr int kEven[5][4] = {{0, 3, 5, 6}, {1, 0, 3, 5}, {2, 0, 6, 3}, {4, 0, 5, 6}, {7, 3, 5, 6}};
  static constexpr int kOdd[5][4] = {{1, 2, 4, 7}, {0, 1, 2, 4}, {3, 1, 2, 7}, {5, 1, 4, 7}, {6, 2, 4, 7}};
  g.types.reserve(static_cast<std::size_t>(5 * n * n * n));
  g.cells.reserve(static_cast<std::size_t>(5 * n * n * n), static_cast<std::size_t>(20 * n * n * n));
  for (Index k = 0; k < n; ++k)
    for (Index j = 0; j < n; ++j)
      for (Index i = 0; i < n; ++i) {
        const auto& table = (i + j + k) % 2 == 0 ? kEven : kOdd;
        for (const auto& t : table) {
          Index ids[4];
          for (int v = 0; v < 4; ++v) {
            const int c = t[v];
            ids[v] = (i + (c & 1)) + m * ((j + (c >> 1 & 1)) + m * (k + (c >> 2 & 1)));
          }
          // Positive orientation (VTK's: the fourth point above the first three).
          const Vec3 a = g.points[static_cast<std::size_t>(ids[0])];
          const double vol = dot(g.points[static_cast<std::size_t>(ids[1])] - a,
                                 cross(g.points[static_cast<std::size_t>(ids[2])] - a,
                                       g.points[static_cast<std::size_t>(ids[3])] - a));
          if (vol < 0) std::swap(ids[1], ids[2]);
          g.add_cell(CellType::Tetra, std::span<const Index>(ids, 4));
        }
      }
  return g;
}

ImageData image(Index n) {
  ImageData img;
  img.dims = {n, n, n};
  const double h = 1.0 / static_cast<double>(n - 1);
  img.spacing = {h, h, h};
  DataArray s("s", ScalarType::Float32, 1, img.num_points());
  for (std::size_t id = 0; id < img.num_points(); ++id) s.set(id, 0, field(img.point(static_cast<Index>(id))));
  img.point_data.add(std::move(s), AttributeRole::Scalars);
  return img;
}

template <class F>
double min_ms(int reps, F&& f) {
  double best = 1e300;
  for (int r = 0; r < reps; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    best = std::min(best, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    fmt::print(stderr, "usage: bench_threshold make DIR | time DIR REPS\n");
    return 2;
  }
  const std::string mode = argv[1], dir = argv[2];
  if (mode == "make") {
    write(tets(100), dir + "/tets.vtu");
    write(image(256), dir + "/image.vti");
    return 0;
  }
  const int reps = argc > 3 ? std::max(1, std::atoi(argv[3])) : 5;
  const std::string only = argc > 4 ? argv[4] : "";  // run only the cases containing this
  const Dataset t = read(dir + "/tets.vtu");
  const Dataset img = read(dir + "/image.vti");
  ThresholdOptions to;
  to.array = "s";
  to.lower = kLower;
  to.upper = kUpper;
  std::string json = "{";
  for (const int threads : {tbb::info::default_concurrency(), 1}) {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    const auto add = [&](const std::string& name, double ms, std::size_t cells) {
      json += fmt::format("{}\"{}/{}\": {{\"ms\": {:.2f}, \"cells\": {}}}", json.size() > 1 ? ", " : "",
                          name, threads, ms, cells);
    };
    for (const auto& input : {std::pair<const char*, const Dataset*>{"tets", &t}, {"image", &img}}) {
      const char* name = input.first;
      const Dataset* ds = input.second;  // not a structured binding: clang 14 lambdas
      std::size_t cells = 0;
      const std::string a = std::string("threshold/") + name, b = std::string("surface/") + name;
      if (a.find(only) != std::string::npos) {
        const double ms = min_ms(reps, [&] { cells = threshold(*ds, to).output.num_cells(); });
        add(a, ms, cells);
      }
      if (b.find(only) != std::string::npos) {
        const double ms = min_ms(reps, [&] { cells = extract_surface(*ds).output.num_cells(); });
        add(b, ms, cells);
      }
    }
  }
  fmt::print("{}}}\n", json);
  return 0;
}
