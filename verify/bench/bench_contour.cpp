// Marching cubes on dense volumes (the raw fields written by peers/make_fields.py, contoured by
// vtkFlyingEdges3D and vtkMarchingCubes in the same run by peers/vtk_contour.py).
// Set ISOFORGE_BENCH_FIELDS to the directory of the raw fields.

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "isoforge/contour/contour.hpp"

namespace {

using namespace isoforge;

const ImageData& field(const std::string& name, Index n) {
  static std::map<std::string, ImageData> cache;
  const std::string key = name + "_" + std::to_string(n);
  auto it = cache.find(key);
  if (it != cache.end()) return it->second;
  const char* dir = std::getenv("ISOFORGE_BENCH_FIELDS");
  const auto path = std::filesystem::path(dir ? dir : "out/bench/fields") / (key + ".raw");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("bench_contour: missing " + path.string() + " (run peers/make_fields.py)");
  std::vector<float> v(static_cast<std::size_t>(n * n * n));
  in.read(reinterpret_cast<char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(float)));
  ImageData img;
  img.dims = {n, n, n};
  const double h = 1.0 / static_cast<double>(n - 1);
  img.spacing = {h, h, h};
  img.point_data.add(DataArray::from_vector<float>("s", 1, std::move(v)), AttributeRole::Scalars);
  return cache.emplace(key, std::move(img)).first->second;
}

// args: field (0 gyroid, 1 blobs), n, threads (0 = all)
void contour_dense(benchmark::State& state) {
  const std::string name = state.range(0) == 0 ? "gyroid" : "blobs";
  const Index n = state.range(1);
  const int threads = state.range(2) == 0 ? tbb::info::default_concurrency() : static_cast<int>(state.range(2));
  const ImageData& img = field(name, n);
  tbb::global_control c(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  ContourOptions o;
  o.values = {name == "gyroid" ? 0.0 : 0.5};
  o.interpolate_attributes = false;  // like the peers (ComputeScalarsOff)
  ContourStats stats;
  for (auto _ : state) {
    ContourResult r = contour_image(img, o);
    benchmark::DoNotOptimize(r);
    stats = r.stats;
    // Releasing the output is not part of contouring (the VTK peers release theirs outside the
    // timed Update()).
    state.PauseTiming();
    r.output = PolyData{};
    state.ResumeTiming();
  }
  state.counters["threads"] = threads;
  state.counters["triangles"] = static_cast<double>(stats.cells);
  state.counters["Mvoxels_per_s"] =
      benchmark::Counter(static_cast<double>(n * n * n) * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
  state.SetLabel(name + "/" + std::to_string(n) + "/" + std::to_string(threads));
}

long status_kb(const char* key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const std::string k = key;
  while (std::getline(in, line)) {
    if (line.compare(0, k.size(), k) == 0) return std::atol(line.c_str() + k.size());
  }
  return -1;
}

// Peak memory of one contour (all threads) beyond its input, against input + output: the peak
// resident set is reset (/proc/self/clear_refs) after the input is loaded, so the peak above the
// resident set at the call is what the call itself held at once. Run once per process.
// args: field (0 gyroid, 1 blobs), n
void contour_memory(benchmark::State& state) {
  const std::string name = state.range(0) == 0 ? "gyroid" : "blobs";
  const Index n = state.range(1);
  const ImageData& img = field(name, n);
  ContourOptions o;
  o.values = {name == "gyroid" ? 0.0 : 0.5};
  o.interpolate_attributes = false;
  double extra_mb = 0, io_mb = 0;
  for (auto _ : state) {
    { std::ofstream("/proc/self/clear_refs") << "5"; }
    const long base = status_kb("VmRSS:");
    PolyData pd = contour_image(img, o).output;
    const long peak = status_kb("VmHWM:");
    const double output = static_cast<double>(pd.points.size() * 3 * sizeof(float) +
                                              (pd.polys.offsets().size() + pd.polys.connectivity().size()) *
                                                  sizeof(Index));
    const double input = static_cast<double>(n * n * n) * sizeof(float);
    extra_mb = (static_cast<double>(peak - base) * 1024.0 - output) / 1048576.0;
    io_mb = (input + output) / 1048576.0;
    state.counters["output_MB"] = output / 1048576.0;
  }
  state.counters["input_MB"] = static_cast<double>(n * n * n) * sizeof(float) / 1048576.0;
  state.counters["extra_MB"] = extra_mb;
  state.counters["extra_fraction"] = io_mb > 0 ? extra_mb / io_mb : 0;
  state.SetLabel(name + "/" + std::to_string(n));
}

}  // namespace

BENCHMARK(contour_memory)->ArgsProduct({{0, 1}, {256, 512}})->Iterations(1)->Unit(benchmark::kMillisecond);

BENCHMARK(contour_dense)
    ->ArgsProduct({{0, 1}, {256, 512}, {1, 0}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK_MAIN();
