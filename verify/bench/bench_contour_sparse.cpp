// Marching cubes on sparse OpenVDB level sets: isoforge's contour_vdb against OpenVDB's own
// mesher, openvdb::tools::volumeToMesh (adaptivity 0, a dual method: one point per crossed voxel
// cube, one quad per crossed edge), in the same run on the same grids. The grids are narrow-band
// level sets (half width 3) of the ice cream cone at 512³ and 1024³ effective resolution (the
// longest axis of its natural bounds), sampled once by sample_level_set.

#include <benchmark/benchmark.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <cmath>
#include <map>

#include "isoforge/contour/contour_sparse.hpp"
#include "isoforge/implicit/sample_sparse.hpp"

namespace {

using namespace isoforge;

const openvdb::FloatGrid& cone(Index n) {
  static std::map<Index, openvdb::FloatGrid::Ptr> cache;
  auto it = cache.find(n);
  if (it != cache.end()) return *it->second;
  const double h = 2.1 / static_cast<double>(n - 1);
  GridSpec g;
  g.origin = {-0.1, -0.7, -0.7};
  g.spacing = {h, h, h};
  const auto m = static_cast<Index>(std::floor(1.4 / h)) + 1;
  g.dims = {n, m, m};
  return *cache.emplace(n, sample_level_set(ice_cream_cone(), g).output).first->second;
}

int thread_count(std::int64_t arg) {
  return arg == 0 ? tbb::info::default_concurrency() : static_cast<int>(arg);
}

void set_common_counters(benchmark::State& state, const openvdb::FloatGrid& grid, int threads) {
  state.counters["threads"] = threads;
  state.counters["leaves"] = static_cast<double>(grid.tree().leafCount());
  state.counters["active_voxels"] = static_cast<double>(grid.activeVoxelCount());
}

// args: n (effective resolution), threads (0 = all), attributes (interpolated values)
void contour_vdb_cone(benchmark::State& state) {
  const Index n = state.range(0);
  const int threads = thread_count(state.range(1));
  const openvdb::FloatGrid& grid = cone(n);
  tbb::global_control c(tbb::global_control::max_allowed_parallelism,
                        static_cast<std::size_t>(threads));
  ContourOptions o;
  o.interpolate_attributes = state.range(2) != 0;
  VdbContourStats stats;
  for (auto _ : state) {
    VdbContourResult r = contour_vdb(grid, o);
    benchmark::DoNotOptimize(r);
    stats = r.stats;
  }
  set_common_counters(state, grid, threads);
  state.counters["points"] = static_cast<double>(stats.points);
  state.counters["triangles"] = static_cast<double>(stats.cells);
  state.counters["blocks"] = static_cast<double>(stats.blocks);
  state.SetLabel("isoforge/" + std::to_string(n) + "/" + std::to_string(threads) +
                 (o.interpolate_attributes ? "/values" : ""));
}

// args: n, threads (0 = all)
void volume_to_mesh_cone(benchmark::State& state) {
  const Index n = state.range(0);
  const int threads = thread_count(state.range(1));
  const openvdb::FloatGrid& grid = cone(n);
  tbb::global_control c(tbb::global_control::max_allowed_parallelism,
                        static_cast<std::size_t>(threads));
  std::size_t points = 0, triangles = 0, quads = 0;
  for (auto _ : state) {
    std::vector<openvdb::Vec3s> p;
    std::vector<openvdb::Vec3I> t;
    std::vector<openvdb::Vec4I> q;
    openvdb::tools::volumeToMesh(grid, p, t, q, 0.0, 0.0);
    points = p.size();
    triangles = t.size();
    quads = q.size();
    benchmark::DoNotOptimize(p.data());
  }
  set_common_counters(state, grid, threads);
  state.counters["points"] = static_cast<double>(points);
  state.counters["quads"] = static_cast<double>(quads);
  state.counters["triangles"] = static_cast<double>(triangles + 2 * quads);  // triangle-equivalents
  state.SetLabel("volumeToMesh/" + std::to_string(n) + "/" + std::to_string(threads));
}

}  // namespace

BENCHMARK(contour_vdb_cone)
    ->ArgsProduct({{512, 1024}, {1, 0}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(volume_to_mesh_cone)
    ->ArgsProduct({{512, 1024}, {1, 0}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK_MAIN();
