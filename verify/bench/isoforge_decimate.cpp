// isoforge's row of the decimation benchmark (decimate.sh), timed like the peers: reads a mesh,
// runs isoforge::decimate (quadric method, defaults) to a target triangle count and writes the
// result. Usage: isoforge_decimate IN OUT TARGET [THREADS]  (THREADS: default 1).
// Prints one JSON line: {"peer", "input", "target", "output_triangles", "seconds" (decimate
// alone), "total_seconds" (read + decimate + write), "stop", "refused_*"}.

#include <tbb/global_control.h>

#include <chrono>
#include <cstdio>
#include <string>

#include "isoforge/io/io.hpp"
#include "isoforge/reduce/decimate.hpp"

using Clock = std::chrono::steady_clock;

int main(int argc, char** argv) {
  if (argc < 4 || argc > 5) {
    std::fprintf(stderr, "usage: isoforge_decimate IN OUT TARGET [THREADS]\n");
    return 2;
  }
  try {
    const auto since = [](Clock::time_point t) {
      return std::chrono::duration<double>(Clock::now() - t).count();
    };
    const std::size_t threads = argc == 5 ? std::stoull(argv[4]) : 1;
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    const auto start = Clock::now();
    const isoforge::Dataset ds = isoforge::read(argv[1]);
    const auto* in = std::get_if<isoforge::PolyData>(&ds);
    if (!in) throw isoforge::Error(std::string(argv[1]) + ": not a polygonal mesh");
    isoforge::DecimateOptions o;
    o.target_triangles = std::stoull(argv[3]);
    const auto t0 = Clock::now();
    const auto [mesh, stats] = isoforge::decimate(*in, o);
    const double seconds = since(t0);
    isoforge::write(mesh, argv[2]);
    std::printf(
        "{\"peer\": \"isoforge-lib\", \"input\": \"%s\", \"target\": %zu, \"output_triangles\": "
        "%zu, \"seconds\": %.6f, \"total_seconds\": %.6f, \"threads\": %zu, \"stop\": \"%s\", "
        "\"refused_topology\": %zu, \"refused_flip\": %zu, \"refused_intersection\": %zu}\n",
        argv[1], o.target_triangles, stats.output_triangles, seconds, since(start), threads,
        isoforge::to_string(stats.stop), stats.refused_topology, stats.refused_flip,
        stats.refused_intersection);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "isoforge_decimate: %s\n", e.what());
    return 1;
  }
}
