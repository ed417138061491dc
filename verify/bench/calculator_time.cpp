// Timing of the array calculator (verify/bench/calculator.sh): an N³ image (16.7M points at
// N = 256) with a float vector array V and a float scalar P, the expression
// `mag(V) * 2 + P / 3` (and a vector one, `cross(V, [0, 0, 1]) * P`); the peer
// (peers/vtk_calculator.py) builds the same arrays with numpy and runs vtkArrayCalculator.
// One JSON line per case and thread count, minimum of --repeat runs.
//
//   calculator_time [--n N] [--repeat R]

#include <fmt/core.h>
#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <cstring>

#include "isoforge/filters/calculator.hpp"

using namespace isoforge;

int main(int argc, char** argv) {
  Index n = 256;
  int repeat = 3;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--n") && i + 1 < argc) n = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc) repeat = std::max(1, std::atoi(argv[++i]));
    else {
      fmt::print(stderr, "usage: calculator_time [--n N] [--repeat R]\n");
      return 2;
    }
  }
  ImageData img;
  img.dims = {n, n, n};
  const std::size_t np = img.num_points();
  DataArray v = DataArray::uninitialized("V", ScalarType::Float32, 3, np);
  DataArray p = DataArray::uninitialized("P", ScalarType::Float32, 1, np);
  float* vp = v.values<float>().data();
  float* pp = p.values<float>().data();
  for (std::size_t i = 0; i < np; ++i) {  // the same formulas as the peer's numpy arrays
    const double t = double(i) * 1e-6;
    vp[3 * i] = float(std::sin(t));
    vp[3 * i + 1] = float(std::cos(t));
    vp[3 * i + 2] = float(t);
    pp[i] = float(1 + t);
  }
  img.point_data.add(std::move(v));
  img.point_data.add(std::move(p));
  for (const auto& [name, expression] :
       {std::pair{"scalar", "mag(V) * 2 + P / 3"}, std::pair{"vector", "cross(V, [0, 0, 1]) * P"}}) {
    for (const int threads : {1, 2}) {
      tbb::global_control gc(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
      double best = 1e300, check = 0;
      for (int r = 0; r < repeat; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        const DataArray out = calculate(img, "r", expression);
        best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        check = out.get(np / 2, 0);
      }
      fmt::print("{{\"case\": \"{}/{}\", \"peer\": \"isoforge\", \"threads\": {}, \"seconds\": {:.4f}, "
                 "\"value_at_middle\": {:.9g}}}\n", name, np, threads, best, check);
    }
  }
}
