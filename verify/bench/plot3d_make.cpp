// Writes a PLOT3D whole-format single grid of N^3 points (big-endian float32: a sheared box) and
// its Q file (density, momentum, energy varying smoothly) for plot3d.sh. Not a peer: the input
// both sides read. Usage: plot3d_make N GRID.xyz SOLUTION.q
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

std::uint32_t big_endian(float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  return __builtin_bswap32(u);
}

bool write_header(std::FILE* f, int n) {
  const std::uint32_t h[3] = {__builtin_bswap32(static_cast<std::uint32_t>(n)),
                              __builtin_bswap32(static_cast<std::uint32_t>(n)),
                              __builtin_bswap32(static_cast<std::uint32_t>(n))};
  return std::fwrite(h, 4, 3, f) == 3;
}

// One plane of n^3 values, value(i, j, k), i fastest.
template <class F>
bool write_plane(std::FILE* f, int n, F&& value) {
  std::vector<std::uint32_t> row(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) row[static_cast<std::size_t>(i)] = big_endian(value(i, j, k));
      if (std::fwrite(row.data(), 4, row.size(), f) != row.size()) return false;
    }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4 || std::atoi(argv[1]) < 2) {
    std::fprintf(stderr, "usage: plot3d_make N GRID.xyz SOLUTION.q  (N >= 2)\n");
    return 2;
  }
  const int n = std::atoi(argv[1]);
  std::FILE* g = std::fopen(argv[2], "wb");
  std::FILE* q = std::fopen(argv[3], "wb");
  if (!g || !q) {
    std::fprintf(stderr, "plot3d_make: cannot create %s or %s\n", argv[2], argv[3]);
    return 1;
  }
  bool ok = write_header(g, n);
  ok =
      ok && write_plane(g, n, [](int i, int j, int) { return float(i + 0.3 * std::sin(j * 0.1)); });
  ok =
      ok && write_plane(g, n, [](int, int j, int k) { return float(j + 0.3 * std::sin(k * 0.1)); });
  ok =
      ok && write_plane(g, n, [](int i, int, int k) { return float(k + 0.3 * std::sin(i * 0.1)); });
  ok = ok && write_header(q, n);
  for (float c : {0.5f, 0.1f, 1e6f, 0.0f}) {
    const std::uint32_t u = big_endian(c);
    ok = ok && std::fwrite(&u, 4, 1, q) == 1;
  }
  const auto rho = [](int i, int j, int) { return 1 + 0.1 * std::sin(i * 0.05 + j * 0.02); };
  ok = ok && write_plane(q, n, [&](int i, int j, int k) { return float(rho(i, j, k)); });
  for (int a = 1; a <= 3; ++a) {
    ok =
        ok && write_plane(q, n, [&](int i, int j, int k) { return float(0.1 * a * rho(i, j, k)); });
  }
  ok = ok && write_plane(q, n, [](int, int, int k) { return float(2.5 + 0.01 * k); });
  ok = (std::fclose(g) == 0) && ok;
  ok = (std::fclose(q) == 0) && ok;
  if (!ok) {
    std::fprintf(stderr, "plot3d_make: writing failed\n");
    return 1;
  }
  return 0;
}
