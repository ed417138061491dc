// Peer of `isoforge decimate`: meshoptimizer's meshopt_simplify (Debian libmeshoptimizer-dev
// 0.18), single-threaded, to an exact target triangle count.
// Usage: meshopt_decimate IN OUT TARGET [--lock-border]
//   IN, OUT: any mesh file isoforge reads / writes (.ply .vtp .vtk .off); TARGET: triangles.
// target_error is 1 (the whole extent of the mesh, relative as meshopt measures it), so only the
// count stops the simplifier; it may still stop above TARGET when no collapse is allowed.
// Without --lock-border the options are 0 (meshopt's default: border vertices may slide along
// the border); --lock-border passes meshopt_SimplifyLockBorder. Prints one JSON line:
// {"peer", "input", "target", "output_triangles", "seconds" (meshopt_simplify alone),
//  "total_seconds" (read + simplify + compaction + write), "result_error" (meshopt's, relative)}.

#include <meshoptimizer.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "isoforge/core/mesh_topology.hpp"
#include "isoforge/io/io.hpp"

using Clock = std::chrono::steady_clock;

namespace {

double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4 || argc > 5 || (argc == 5 && std::strcmp(argv[4], "--lock-border") != 0)) {
    std::fprintf(stderr, "usage: meshopt_decimate IN OUT TARGET [--lock-border]\n");
    return 2;
  }
  const bool lock_border = argc == 5;
  const std::size_t target = std::stoull(argv[3]);
  try {
    const auto start = Clock::now();
    const isoforge::Dataset ds = isoforge::read(argv[1]);
    const auto* in = std::get_if<isoforge::PolyData>(&ds);
    if (!in) throw isoforge::Error(std::string(argv[1]) + ": not a polygonal mesh");
    const auto tris = isoforge::triangulate_faces(*in);
    std::vector<float> xyz(3 * in->points.size());
    for (std::size_t i = 0; i < in->points.size(); ++i) {
      const isoforge::Vec3 p = in->points[i];
      xyz[3 * i] = static_cast<float>(p.x);
      xyz[3 * i + 1] = static_cast<float>(p.y);
      xyz[3 * i + 2] = static_cast<float>(p.z);
    }
    std::vector<unsigned> indices(3 * tris.size());
    for (std::size_t f = 0; f < tris.size(); ++f) {
      for (std::size_t k = 0; k < 3; ++k) indices[3 * f + k] = static_cast<unsigned>(tris[f][k]);
    }
    std::vector<unsigned> out(indices.size());
    float error = 0;
    const auto t0 = Clock::now();
    const std::size_t count = meshopt_simplify(
        out.data(), indices.data(), indices.size(), xyz.data(), in->points.size(),
        3 * sizeof(float), 3 * target, 1.0f, lock_border ? meshopt_SimplifyLockBorder : 0, &error);
    const double seconds = since(t0);
    out.resize(count);

    // Keep the points the triangles use, in first-use order.
    std::vector<isoforge::Index> remap(in->points.size(), -1);
    isoforge::PolyData result;
    result.polys.reserve(count / 3, count);
    for (std::size_t f = 0; f < count / 3; ++f) {
      isoforge::Index ids[3];
      for (std::size_t k = 0; k < 3; ++k) {
        const unsigned v = out[3 * f + k];
        if (remap[v] < 0) {
          remap[v] = static_cast<isoforge::Index>(result.points.size());
          result.points.push_back(in->points[v]);
        }
        ids[k] = remap[v];
      }
      result.polys.add({ids[0], ids[1], ids[2]});
    }
    isoforge::write(result, argv[2]);
    std::printf(
        "{\"peer\": \"%s\", \"input\": \"%s\", \"target\": %zu, \"output_triangles\": %zu, "
        "\"seconds\": %.6f, \"total_seconds\": %.6f, \"result_error\": %.6g}\n",
        lock_border ? "meshopt-lockborder" : "meshopt", argv[1], target, count / 3, seconds,
        since(start), static_cast<double>(error));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "meshopt_decimate: %s\n", e.what());
    return 1;
  }
}
