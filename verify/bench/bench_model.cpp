// Implicit modeling and the Lorenz attractor:
// - implicit_modeller vs vtkImplicitModeller (timed by peers/vtk_model.py in the same run) on the
//   HELLO strokes (110 x 40 x 20), 500 random segments (200^3) and bunny.ply (64^3, 128^3, maximum
//   distance 0.1 of the diagonal);
// - narrow-band distance of a 1.1M-triangle mesh (bunny.ply subdivided twice) at 512^3 and 1024^3
//   effective resolution vs openvdb::tools::meshToVolume (unsigned, same voxel size and band):
//   time, active voxels, tree memory and peak memory (run one case per process: see run.sh);
// - the Lorenz attractor: 10M RK4 steps + 200^3 marching cubes, one thread.
// With ISOFORGE_BENCH_OUT set, the dense modeller results are written there as .vti so that the
// peer compares VTK's values with ours.

#include <benchmark/benchmark.h>
#include <sys/resource.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <unistd.h>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>

#include "isoforge/io/io.hpp"
#include "isoforge/model/attractor.hpp"
#include "isoforge/model/distance_sparse.hpp"
#include "isoforge/model/implicit_modeller.hpp"

namespace {

using namespace isoforge;

// splitmix64: the same sequence in peers/vtk_model.py.
struct SplitMix {
  std::uint64_t s;
  std::uint64_t next() {
    std::uint64_t z = (s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
};

PolyData random_segments(int n) {
  SplitMix rng{12345};
  PolyData pd;
  for (int i = 0; i < 2 * n; ++i) {
    const double x = rng.uniform(), y = rng.uniform(), z = rng.uniform();
    pd.points.push_back({x, y, z});
  }
  for (int i = 0; i < n; ++i) pd.lines.add({2 * i, 2 * i + 1});
  return pd;
}

const PolyData& input(const std::string& name) {
  static std::map<std::string, PolyData> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return it->second;
  PolyData pd;
  if (name == "hello") {
    pd = std::get<PolyData>(read(ISOFORGE_DATA_DIR "/hello.vtk"));
  } else if (name == "bunny") {
    pd = std::get<PolyData>(read(ISOFORGE_DATA_DIR "/bunny.ply"));
  } else {
    pd = random_segments(500);
  }
  return cache.emplace(name, std::move(pd)).first->second;
}

// bunny.ply with every triangle split into four (midpoints shared by edge), twice: 1,111,216
// triangles on the same surface.
PolyData subdivided_bunny() {
  PolyData pd = std::get<PolyData>(read(ISOFORGE_DATA_DIR "/bunny.ply"));
  for (int level = 0; level < 2; ++level) {
    std::map<std::pair<Index, Index>, Index> mid;
    PolyData out;
    out.points = pd.points;
    const auto midpoint = [&](Index a, Index b) {
      const auto key = std::minmax(a, b);
      auto [it, added] = mid.try_emplace({key.first, key.second}, Index(out.points.size()));
      if (added)
        out.points.push_back((pd.points[std::size_t(a)] + pd.points[std::size_t(b)]) * 0.5);
      return it->second;
    };
    out.polys.reserve(pd.polys.size() * 4, pd.polys.size() * 12);
    for (std::size_t c = 0; c < pd.polys.size(); ++c) {
      const auto t = pd.polys.cell(c);
      const Index ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
      out.polys.add({t[0], ab, ca});
      out.polys.add({ab, t[1], bc});
      out.polys.add({ca, bc, t[2]});
      out.polys.add({ab, bc, ca});
    }
    pd = std::move(out);
  }
  return pd;
}

long peak_rss_kb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

long current_rss_kb() {
  long pages = 0, resident = 0;
  if (FILE* f = std::fopen("/proc/self/statm", "r")) {
    if (std::fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = 0;
    std::fclose(f);
  }
  return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

ImplicitModellerOptions modeller_options(const std::string& name, Index n) {
  ImplicitModellerOptions o;
  if (name == "hello") {  // VTK's Hello example
    o.sample_dimensions = {110, 40, 20};
    o.model_bounds.min = {-1, -1, -1};
    o.model_bounds.max = {10, 3, 1};
    o.maximum_distance = 0.25;
  } else if (name == "bunny") {  // maximum distance 0.1 of the diagonal
    const Bounds b = input("bunny").bounds();
    const Vec3 s = b.size();
    o.sample_dimensions = {n, n, n};
    o.maximum_distance = 0.1 * b.diagonal() / std::max({s.x, s.y, s.z});
  } else {  // VTK's defaults
    o.sample_dimensions = {n, n, n};
  }
  return o;
}

// args: input (0 hello, 1 segments, 2 bunny), n, threads (0 = all)
void modeller(benchmark::State& state) {
  static const char* names[] = {"hello", "segments500", "bunny"};
  const std::string name = names[state.range(0)];
  const Index n = state.range(1);
  const int threads = state.range(2) == 0 ? tbb::info::default_concurrency() : int(state.range(2));
  tbb::global_control c(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
  const PolyData& in = input(name);
  const ImplicitModellerOptions o = modeller_options(name, n);
  ImplicitModellerResult r;
  for (auto _ : state) {
    r = implicit_modeller(in, o);
    benchmark::DoNotOptimize(r);
  }
  const ImageData& img = r.output;
  const DistanceStats& stats = r.stats;
  if (const char* dir = std::getenv("ISOFORGE_BENCH_OUT"); dir && state.range(2) == 0) {
    write(img, std::filesystem::path(dir) / (name + "_" + std::to_string(n) + ".vti"));
    if (name == "hello") {  // VTK's other output scalar types, for the peer to compare
      const struct {
        ScalarType type;
        bool scaled;
        const char* tag;
      } variants[] = {{ScalarType::UInt8, true, "uint8s"},
                      {ScalarType::Int16, false, "int16"},
                      {ScalarType::UInt16, true, "uint16s"},
                      {ScalarType::Float64, false, "float64"}};
      for (const auto& v : variants) {
        ImplicitModellerOptions ov = o;
        ov.output_type = v.type;
        ov.scale_to_maximum_distance = v.scaled;
        write(implicit_modeller(in, ov).output,
              std::filesystem::path(dir) / (name + "_" + v.tag + "_" + std::to_string(n) + ".vti"));
      }
    }
  }
  state.SetLabel(name + "/" + std::to_string(n));
  state.counters["threads"] = threads;
  state.counters["primitives"] = double(stats.points + stats.segments + stats.triangles);
  state.counters["samples"] = double(img.num_points());
  state.counters["band_samples"] = double(stats.active_voxels);
  state.counters["gather"] = stats.strategy == DistanceStrategy::Gather;
  state.counters["kernel_calls"] = double(stats.evaluations);
}

// args: effective resolution (voxels along the largest side), 0 = ours, 1 = meshToVolume
void narrowband(benchmark::State& state) {
  static PolyData mesh = subdivided_bunny();
  const Index n = state.range(0);
  const Bounds b = mesh.bounds();
  const Vec3 s = b.size();
  const double h = std::max({s.x, s.y, s.z}) / double(n);
  const double half_width = 3;
  const GridSpec g = cubic_grid(b, h, (half_width + 1) * h);
  const long before = current_rss_kb();
  std::size_t active = 0, tree = 0;
  for (auto _ : state) {
    openvdb::FloatGrid::Ptr grid;
    if (state.range(1) == 0) {
      DistanceOptions o;
      o.max_distance = half_width * h;
      DistanceGridResult r = distance_grid(mesh, g, o);
      grid = std::move(r.output);
      state.counters["gather"] = r.stats.strategy == DistanceStrategy::Gather;
    } else {
      grid = openvdb_mesh_to_volume(mesh, g, half_width, false);
    }
    active = std::size_t(grid->activeVoxelCount());
    tree = std::size_t(grid->memUsage());
    benchmark::DoNotOptimize(grid);
  }
  state.SetLabel(std::string(state.range(1) == 0 ? "isoforge" : "meshToVolume") + "/" +
                 std::to_string(n));
  state.counters["triangles"] = double(mesh.polys.size());
  state.counters["active_voxels"] = double(active);
  state.counters["tree_MB"] = double(tree) / 1e6;
  state.counters["peak_rss_MB"] = double(peak_rss_kb()) / 1e3;
  state.counters["rss_before_MB"] = double(before) / 1e3;
  state.counters["peak_extra_MB"] = double(peak_rss_kb() - before) / 1e3;
  state.counters["threads"] = tbb::info::default_concurrency();
}

// A helix of n segments (8 turns, radius 0.35) in the unit cube, distance field on 128³ with
// maximum distance 0.1: how Scatter (the dense rows) and Gather compare as the segments' reach
// volumes overlap more (shorter segments, same band): the data behind Auto's choice.
// args: n, strategy (0 Scatter, 1 Gather)
void crossover(benchmark::State& state) {
  const int n = int(state.range(0));
  PolyData pd;
  std::vector<Index> ids;
  for (int i = 0; i <= n; ++i) {
    const double t = double(i) / n, a = 16 * 3.141592653589793 * t;
    pd.points.push_back({0.5 + 0.35 * std::cos(a), 0.5 + 0.35 * std::sin(a), 0.1 + 0.8 * t});
    ids.push_back(i);
  }
  pd.lines.add(ids);
  Bounds b;
  b.extend({0, 0, 0});
  b.extend({1, 1, 1});
  const GridSpec g = GridSpec::from_bounds(b, {128, 128, 128});
  DistanceOptions o;
  o.max_distance = 0.1;
  o.strategy = state.range(1) == 0 ? DistanceStrategy::Scatter : DistanceStrategy::Gather;
  DistanceStats stats;
  for (auto _ : state) {
    DistanceImageResult r = distance_image(pd, g, o);
    benchmark::DoNotOptimize(r);
    stats = r.stats;
  }
  state.SetLabel(std::string(state.range(1) == 0 ? "scatter" : "gather") + "/" + std::to_string(n));
  state.counters["segments"] = n;
  state.counters["band_samples"] = double(stats.active_voxels);
  state.counters["kernel_calls"] = double(stats.evaluations);
  state.counters["scatter_estimate"] = stats.scatter_estimate;
}

void attractor(benchmark::State& state) {
  tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
  AttractorResult r;
  for (auto _ : state) {
    r = lorenz_attractor();
    benchmark::DoNotOptimize(r);
  }
  state.counters["steps"] = double(r.stats.trajectory.counted + r.stats.trajectory.discarded);
  state.counters["discarded"] = double(r.stats.trajectory.discarded);
  state.counters["triangles"] = double(r.output.surface.polys.size());
  state.counters["threads"] = 1;
}

}  // namespace

BENCHMARK(modeller)
    ->Args({0, 0, 1})
    ->Args({0, 0, 0})
    ->Args({1, 200, 1})
    ->Args({1, 200, 0})
    ->Args({2, 64, 1})
    ->Args({2, 64, 0})
    ->Args({2, 128, 1})
    ->Args({2, 128, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(narrowband)
    ->Args({512, 0})
    ->Args({512, 1})
    ->Args({1024, 0})
    ->Args({1024, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);
BENCHMARK(crossover)
    ->ArgsProduct({{1000, 10000, 100000, 1000000}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(attractor)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
