// Reading the real files in data/: isoforge's readers. The same files are read by VTK's readers
// in the same run by peers/vtk_io.py (see run.sh), which reports the ratio.
// Writing VTK XML from a dataset in memory (the writer alone, without the reading that a whole
// `convert` also pays; xml_io.sh times whole commands against VTK): the 256^3 float32 distance
// field and the 1.46M-triangle isosurface of xml_io.sh, uncompressed, zlib and LZ4, into the
// page cache; bytes processed are those of the uncompressed file.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include "isoforge/contour/contour.hpp"
#include "isoforge/io/io.hpp"
#include "isoforge/io/vtk_xml.hpp"

namespace {

void read_file(benchmark::State& state, const char* file, const char* q) {
  const auto path = std::filesystem::path(ISOFORGE_DATA_DIR) / file;
  isoforge::ReadOptions ro;
  if (*q) ro.plot3d_q = std::filesystem::path(ISOFORGE_DATA_DIR) / q;
  std::size_t bytes = std::filesystem::file_size(path);
  if (*q) bytes += std::filesystem::file_size(ro.plot3d_q);
  for (auto _ : state) {
    isoforge::Dataset ds = isoforge::read(path, ro);
    benchmark::DoNotOptimize(ds);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes));
}

// A 256^3 Float32 distance field on [-1, 1]^3 of `shape`: 0 the union of a torus (R 0.6, r 0.2)
// and a sphere (centre (0.3, 0.2, 0.1), r 0.5), as xml_io.sh samples; 1 the distance to the origin.
isoforge::ImageData distance_volume(int shape) {
  constexpr int n = 256;
  isoforge::ImageData img;
  img.dims = {n, n, n};
  img.origin = {-1, -1, -1};
  img.spacing = {2.0 / (n - 1), 2.0 / (n - 1), 2.0 / (n - 1)};
  std::vector<float> f(std::size_t{n} * n * n);
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        const isoforge::Vec3 p = img.point(i, j, k);
        double d = std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
        if (shape == 0) {
          const double q = std::hypot(std::hypot(p.x, p.y) - 0.6, p.z) - 0.2;
          const double s = std::sqrt((p.x - 0.3) * (p.x - 0.3) + (p.y - 0.2) * (p.y - 0.2) +
                                     (p.z - 0.1) * (p.z - 0.1)) -
                           0.5;
          d = std::min(q, s);
        }
        f[static_cast<std::size_t>(img.point_id(i, j, k))] = static_cast<float>(d);
      }
    }
  }
  img.point_data.add(isoforge::DataArray::from_vector<float>("F", 1, f),
                     isoforge::AttributeRole::Scalars);
  return img;
}

const isoforge::Dataset& bench_dataset(bool surface) {
  static const isoforge::Dataset volume{distance_volume(0)};
  static const isoforge::Dataset spheres = [] {
    isoforge::ContourOptions o;
    o.values = {0.2, 0.35, 0.5, 0.65, 0.8, 0.95};
    return isoforge::Dataset{isoforge::contour(distance_volume(1), o).output};
  }();
  return surface ? spheres : volume;
}

void write_xml(benchmark::State& state, bool surface, const char* compressor) {
  const isoforge::Dataset& ds = bench_dataset(surface);
  isoforge::VtkXmlWriteOptions o;
  o.compress = std::string(compressor) != "none";
  if (std::string(compressor) == "lz4") o.compressor = isoforge::VtkXmlCompressor::Lz4;
  const auto dir = std::filesystem::temp_directory_path() / "isoforge_bench_io";
  std::filesystem::create_directories(dir);
  const auto path = dir / (surface ? "surface.vtp" : "volume.vti");
  // Throughput is counted in bytes of the uncompressed file, as xml_io.sh counts it.
  isoforge::write_vtk_xml(ds, path, isoforge::VtkXmlWriteOptions{.compress = false});
  const std::size_t bytes = std::filesystem::file_size(path);
  std::filesystem::remove(path);
  for (auto _ : state) {
    isoforge::write_vtk_xml(ds, path, o);
    state.PauseTiming();
    std::filesystem::remove(path);  // a fresh file each time, as a user's
    state.ResumeTiming();
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes));
}

}  // namespace

BENCHMARK_CAPTURE(read_file, bunny_ply_ascii, "bunny.ply", "")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_file, torso_vtp_zlib, "Torso.vtp", "")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_file, fran_cut_vtk_ascii, "fran_cut.vtk", "")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_file, post_vtk_binary, "post.vtk", "")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_file, ironprot_vtk_binary, "ironProt.vtk", "")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_file, combustor_plot3d, "combxyz.bin", "combq.bin")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_file, headsq_nrrd, "headsq/quarter.nhdr", "")->Unit(benchmark::kMillisecond);

// The writer's threads: wall-clock time, not the main thread's CPU time.
#define ISOFORGE_WRITE_XML(name, surface, compressor)     \
  BENCHMARK_CAPTURE(write_xml, name, surface, compressor) \
      ->Unit(benchmark::kMillisecond)                     \
      ->UseRealTime()
ISOFORGE_WRITE_XML(volume_none, false, "none");
ISOFORGE_WRITE_XML(volume_zlib, false, "zlib");
ISOFORGE_WRITE_XML(volume_lz4, false, "lz4");
ISOFORGE_WRITE_XML(surface_none, true, "none");
ISOFORGE_WRITE_XML(surface_zlib, true, "zlib");
ISOFORGE_WRITE_XML(surface_lz4, true, "lz4");

BENCHMARK_MAIN();
