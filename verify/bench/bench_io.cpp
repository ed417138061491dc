// Reading the real files in data/: isoforge's readers. The same files are read by VTK's readers
// in the same run by peers/vtk_io.py (see run.sh), which reports the ratio.

#include <benchmark/benchmark.h>

#include <filesystem>

#include "isoforge/io/io.hpp"

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

}  // namespace

BENCHMARK_CAPTURE(read_file, bunny_ply_ascii, "bunny.ply", "")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_file, torso_vtp_zlib, "Torso.vtp", "")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_file, fran_cut_vtk_ascii, "fran_cut.vtk", "")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_file, post_vtk_binary, "post.vtk", "")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_file, ironprot_vtk_binary, "ironProt.vtk", "")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_file, combustor_plot3d, "combxyz.bin", "combq.bin")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_file, headsq_nrrd, "headsq/quarter.nhdr", "")->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
