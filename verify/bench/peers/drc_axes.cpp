// drc_axes INPUT FLATTEN REL...: Draco quantizes positions on one cubic grid sized by the largest
// extent (draco issue #506). Does per-axis handling give smaller files at the same error budget?
// For INPUT with z scaled by FLATTEN (a flat mesh is where the cube wastes most levels) and each
// budget REL (fraction of the diagonal), two encodings with the same guarantee on the Euclidean
// error e of every point:
//   cube:    isoforge's grid (one step for all axes, sized to e);
//   stretch: every axis stretched to the largest extent (each axis then spans the whole grid,
//            as a per-axis range would), a grid fine enough that the error mapped back to the
//            original axes stays within e; measured after decoding and unstretching.
// Prints one JSON line per budget: bytes and measured error of each.

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <variant>

#include "isoforge/io/draco.hpp"
#include "isoforge/io/io.hpp"

using namespace isoforge;

namespace {

double max_error(const PolyData& a, const PolyData& b, const std::array<double, 3>& unscale,
                 const Vec3& origin) {
  // Sequential coding keeps ids: compare point by point.
  double worst = 0;
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    const Vec3 q = b.points[i];
    Vec3 back;
    for (int c = 0; c < 3; ++c) back[c] = origin[c] + (q[c] - origin[c]) * unscale[c];
    worst = std::max(worst, norm(back - a.points[i]));
  }
  return worst;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: drc_axes INPUT FLATTEN REL...\n");
    return 2;
  }
  try {
    PolyData m = std::get<PolyData>(read(argv[1]));
    m.point_data.clear();
    const double flatten = std::atof(argv[2]);
    for (std::size_t i = 0; i < m.points.size(); ++i) {
      Vec3 p = m.points[i];
      p[2] *= flatten;
      m.points.set(i, p);
    }
    const Bounds b = m.bounds();
    double big = 0;
    for (int c = 0; c < 3; ++c) big = std::max(big, b.max[c] - b.min[c]);
    std::array<double, 3> k{}, unscale{};
    for (int c = 0; c < 3; ++c) {
      k[c] = big / (b.max[c] - b.min[c]);
      unscale[c] = 1 / k[c];
    }
    PolyData s = m;
    for (std::size_t i = 0; i < s.points.size(); ++i) {
      Vec3 p = s.points[i];
      for (int c = 0; c < 3; ++c) p[c] = b.min[c] + (p[c] - b.min[c]) * k[c];
      s.points.set(i, p);
    }
    for (int a = 3; a < argc; ++a) {
      const double e = std::atof(argv[a]) * b.diagonal();
      DracoWriteOptions o;
      o.method = DracoMethod::Sequential;  // ids kept for the measurement; same for both
      o.max_position_error = e;
      auto cube = encode_draco(m, o);
      // Stretched: per-axis error d_c/k_c in original units; a grid of step h in the stretched
      // space moves a point by at most (h/2)·sqrt(Σ 1/k_c²) there, so h = 2e/sqrt(Σ 1/k_c²),
      // which the budget e' = h·√3/2 of the stretched encoding guarantees.
      double s2 = 0;
      for (int c = 0; c < 3; ++c) s2 += unscale[c] * unscale[c];
      DracoWriteOptions os = o;
      os.max_position_error = 2 * e / std::sqrt(s2) * std::sqrt(3.0) / 2;
      auto stretch = encode_draco(s, os);
      const auto bytes_of = [](const std::vector<std::uint8_t>& v) {
        return std::span<const std::byte>(reinterpret_cast<const std::byte*>(v.data()), v.size());
      };
      const PolyData dc = read_draco(bytes_of(cube.output), "cube");
      const PolyData ds = read_draco(bytes_of(stretch.output), "stretch");
      // Edgebreaker sizes too (same grids), for the default method.
      o.method = os.method = DracoMethod::Edgebreaker;
      const auto cube_eb = encode_draco(m, o);
      const auto stretch_eb = encode_draco(s, os);
      std::printf("{\"flatten\": %g, \"rel\": %g, \"budget\": %.6g, \"cube_bytes\": %zu, "
                  "\"cube_error\": %.6g, \"stretch_bytes\": %zu, \"stretch_error\": %.6g, "
                  "\"cube_eb_bytes\": %zu, \"stretch_eb_bytes\": %zu}\n",
                  flatten, std::atof(argv[a]), e, cube.output.size(),
                  max_error(m, dc, {1, 1, 1}, b.min), stretch.output.size(),
                  max_error(m, ds, unscale, b.min), cube_eb.output.size(),
                  stretch_eb.output.size());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "drc_axes: %s\n", e.what());
    return 1;
  }
  return 0;
}
