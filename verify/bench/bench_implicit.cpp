// Sampling implicit functions: dense (vs vtkSampleFunction, timed by peers/vtk_sample.py in the
// same run) and sparse narrow band into OpenVDB (time, tree memory and active voxels).

#include <benchmark/benchmark.h>
#include <sys/resource.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include "isoforge/implicit/sample.hpp"
#include "isoforge/implicit/sample_sparse.hpp"

namespace {

using namespace isoforge;

Bounds ice_bounds() {
  Bounds b;
  b.extend({-0.1, -0.7, -0.7});
  b.extend({2.0, 0.7, 0.7});
  return b;
}

// args: resolution, threads (0 = all)
void dense_icecream(benchmark::State& state) {
  const Index n = state.range(0);
  const int threads = state.range(1) == 0 ? tbb::info::default_concurrency() : static_cast<int>(state.range(1));
  tbb::global_control c(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  const ImplicitFunction f = ice_cream_cone();
  const GridSpec g = GridSpec::from_bounds(ice_bounds(), {n, n, n});
  for (auto _ : state) {
    ImageData img = sample_image(f, g);
    benchmark::DoNotOptimize(img);
  }
  const double evals = static_cast<double>(n * n * n);
  state.counters["threads"] = threads;
  state.counters["Mevals_per_s"] = benchmark::Counter(evals * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["Mevals_per_s_per_core"] =
      benchmark::Counter(evals * 1e-6 / threads, benchmark::Counter::kIsIterationInvariantRate);
}

long peak_rss_kb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

void sparse_icecream(benchmark::State& state) {
  const Index n = state.range(0);
  const ImplicitFunction f = ice_cream_cone();
  const Bounds b = ice_bounds();
  const double h = (b.max.x - b.min.x) / static_cast<double>(n - 1);
  GridSpec g;
  g.origin = b.min;
  g.spacing = {h, h, h};
  g.dims = {n, static_cast<Index>(1.4 / h) + 1, static_cast<Index>(1.4 / h) + 1};
  SparseSampleStats stats;
  for (auto _ : state) {
    SparseSampleResult r = sample_level_set(f, g);
    benchmark::DoNotOptimize(r);
    stats = r.stats;
  }
  state.counters["active_voxels"] = static_cast<double>(stats.active_voxels);
  state.counters["tree_MB"] = static_cast<double>(stats.memory_bytes) / 1e6;
  state.counters["dense_MB"] = static_cast<double>(g.dims[0]) * static_cast<double>(g.dims[1]) *
                               static_cast<double>(g.dims[2]) * 4 / 1e6;
  state.counters["peak_rss_MB"] = static_cast<double>(peak_rss_kb()) / 1e3;
  state.counters["evaluated_fraction"] =
      static_cast<double>(stats.evaluated_voxels) /
      (static_cast<double>(g.dims[0]) * static_cast<double>(g.dims[1]) * static_cast<double>(g.dims[2]));
}

}  // namespace

BENCHMARK(dense_icecream)->Args({256, 1})->Args({256, 0})->Args({512, 1})->Args({512, 0})
    ->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(sparse_icecream)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(sparse_icecream)->Arg(4096)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

BENCHMARK_MAIN();
