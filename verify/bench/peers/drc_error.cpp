// drc_error ORIGINAL DECODED: the position error of a decoded Draco file, measured the same way
// for every encoder (run by draco.sh): the largest distance from a point of ORIGINAL that lies
// in a face (or any point of a point cloud) to the nearest point of DECODED, and the bounding-box
// diagonal of ORIGINAL. Quantization moves each point to its nearest grid point, and no other
// decoded point is nearer than that one, so for a correct codec this is the largest error of a
// point. Prints one JSON line: {"max_error": E, "diagonal": D, "points": N}.

#include <cmath>
#include <cstdio>
#include <exception>
#include <variant>
#include <vector>

#include "isoforge/io/io.hpp"
#include "isoforge/spatial/primitive_locator.hpp"

int main(int argc, char** argv) {
  using namespace isoforge;
  if (argc != 3) {
    std::fprintf(stderr, "usage: drc_error ORIGINAL DECODED\n");
    return 2;
  }
  try {
    const PolyData a = std::get<PolyData>(read(argv[1]));
    const PolyData b = std::get<PolyData>(read(argv[2]));
    std::vector<Vec3> verts(b.points.size());
    std::vector<PrimitiveSet::Id> ids(b.points.size());
    for (std::size_t j = 0; j < b.points.size(); ++j) {
      verts[j] = b.points[j];
      ids[j] = static_cast<PrimitiveSet::Id>(j);
    }
    const PrimitiveSet set(std::move(verts), std::move(ids), {}, {});
    const PrimitiveLocator locator(set);
    std::vector<char> used(a.points.size(), a.polys.empty() ? 1 : 0);
    for (Index id : a.polys.connectivity()) used[static_cast<std::size_t>(id)] = 1;
    double worst2 = 0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.points.size(); ++i) {
      if (!used[i]) continue;
      ++n;
      worst2 = std::max(worst2, locator.closest(a.points[i]).dist2);
    }
    std::printf("{\"max_error\": %.9g, \"diagonal\": %.9g, \"points\": %zu}\n", std::sqrt(worst2),
                a.bounds().diagonal(), n);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "drc_error: %s\n", e.what());
    return 1;
  }
  return 0;
}
