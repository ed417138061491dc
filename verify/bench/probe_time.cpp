// Timing of the probe filter on in-memory inputs (verify/bench/probe.sh): the two cases of the
// issue's table, each the minimum of --repeat runs. Prints one JSON line per case; with
// --write DIR it first writes the inputs (grid.vts, tets.vtu) for the VTK peer and the CLI runs.
//
//   probe_time [--write DIR] [--repeat N] [--case curvilinear|tets]

#include <fmt/core.h>

#include <chrono>
#include <ctime>
#include <cstring>
#include <string>

#include "isoforge/filters/probe.hpp"
#include "isoforge/io/io.hpp"
#include "peers/probe_inputs.hpp"

using namespace isoforge;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Minimum over `repeat` runs of: building the prober (its locator) and probing.
template <class Input>
void run(const char* name, const Input& input, const ImageData& probe_ds, int repeat) {
  double best = 1e300, best_build = 0, best_cpu = 1e300;
  std::size_t found = 0;
  double checksum = 0;
  for (int r = 0; r < repeat; ++r) {
    const std::clock_t c0 = std::clock();  // CPU time of all threads: robust on a busy machine
    const auto t0 = std::chrono::steady_clock::now();
    const Prober prober(input);
    const double build = seconds_since(t0);
    const auto [out, stats] = prober.probe(probe_ds);
    const double total = seconds_since(t0);
    best_cpu = std::min(best_cpu, double(std::clock() - c0) / CLOCKS_PER_SEC);
    if (total < best) {
      best = total;
      best_build = build;
    }
    found = stats.found;
    const DataArray& f = point_data(out).get("f");
    checksum = 0;
    for (std::size_t i = 0; i < f.tuples(); i += 997) {
      if (!std::isnan(f.get(i))) checksum += f.get(i);
    }
  }
  fmt::print(
      "{{\"case\": \"{}\", \"peer\": \"isoforge\", \"seconds\": {:.4f}, \"cpu_seconds\": {:.4f}, "
      "\"locator_seconds\": {:.4f}, \"cells\": {}, \"probe_points\": {}, \"found\": {}, "
      "\"checksum\": {:.6f}}}\n",
      name, best, best_cpu, best_build, num_cells(input), probe_ds.num_points(), found, checksum);
}

}  // namespace

int main(int argc, char** argv) {
  std::string dir, only;
  int repeat = 3;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--write") && i + 1 < argc) dir = argv[++i];
    else if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc) repeat = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--case") && i + 1 < argc) only = argv[++i];
    else {
      fmt::print(stderr, "usage: probe_time [--write DIR] [--repeat N] [--case NAME]\n");
      return 2;
    }
  }
  if (only.empty() || only == "curvilinear") {
    const StructuredGrid grid = bench::warped_grid(100);
    if (!dir.empty()) write(grid, dir + "/grid.vts");
    run("curvilinear", grid, probe_volume(grid.bounds(), {200, 200, 200}), repeat);
  }
  if (only.empty() || only == "tets") {
    const UnstructuredGrid tets = bench::tet_mesh(44);
    if (!dir.empty()) write(tets, dir + "/tets.vtu");
    run("tets", tets, probe_volume(tets.bounds(), {100, 100, 100}), repeat);
  }
  return 0;
}
