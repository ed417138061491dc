// The C++ example from README.md, compiled and run by the consumer_package test so the README
// cannot drift from the API. Keep the two in sync.
#include <isoforge/io/io.hpp>
#include <cstdio>

int main() {
  isoforge::Dataset ds = isoforge::read("data/combxyz.bin",            // PLOT3D grid ...
                                        {.plot3d_q = "data/combq.bin"});  // ... and its solution
  const auto& grid = std::get<isoforge::StructuredGrid>(ds);
  auto [lo, hi] = grid.point_data.get("Density").range();
  std::printf("%zu points, density %g..%g\n", grid.num_points(), lo, hi);
  isoforge::write(ds, "combustor.vts");  // opens in ParaView; written atomically
}
