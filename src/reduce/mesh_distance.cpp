// Symmetric surface distance between triangle meshes (mesh_distance.hpp).
//
// \cite Cignoni, P., Rocchini, C., Scopigno, R. (1998). Metro: measuring error on simplified
//   surfaces. Computer Graphics Forum 17(2), 167–174: one-sided distances from samples of one
//   surface to the other, combined into the symmetric Hausdorff distance and mean/RMS values.
// \cite Turk, G. (1990). Generating random points in triangles. Graphics Gems: the square-root
//   mapping of two uniforms to a uniform point of a triangle.
//
// Samples are indexed: a mesh's used vertices first, then area samples k = 0 .. n−1 whose
// position is a pure function of (seed, mesh, k) — stratum k of the cumulated areas, jittered,
// then a uniform point of the triangle holding it — so any slicing of the parallel loops gives
// the same samples. Distances are exact closest-point distances (core/closest_point.hpp through
// PrimitiveLocator), summed in fixed chunks of samples whose sums are combined in order.

#include "isoforge/reduce/mesh_distance.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "isoforge/core/error.hpp"
#include "isoforge/core/mesh_topology.hpp"
#include "isoforge/core/parallel.hpp"
#include "isoforge/spatial/primitive_locator.hpp"

namespace isoforge {

namespace {

constexpr std::size_t kMinAutoSamples = 100000;   // automatic count: at least this many ...
constexpr std::size_t kSamplesPerTriangle = 10;   // ... or this many per triangle ...
constexpr std::size_t kMaxAutoSamples = 4000000;  // ... but no more than this
constexpr std::size_t kChunk = 2048;  // samples summed together (fixed, so sums are reproducible)

// A counter-based generator: a uniform double in [0, 1) from (seed, stream, index).
double uniform(std::uint64_t seed, std::uint64_t stream, std::uint64_t index) {
  std::uint64_t x =
      seed * 0x9E3779B97F4A7C15ull + stream * 0xD1B54A32D192ED03ull + index * 0x8CB92BA72F3D8DD7ull;
  // splitmix64's finalizer
  x ^= x >> 30;
  x *= 0xBF58476D1CE4E5B9ull;
  x ^= x >> 27;
  x *= 0x94D049BB133111EBull;
  x ^= x >> 31;
  return static_cast<double>(x >> 11) * 0x1p-53;
}

// One mesh: its used vertices, triangles over them, cumulated areas, locator.
struct Surface {
  std::vector<Vec3> vertices;
  std::vector<std::array<PrimitiveSet::Id, 3>> triangles;
  std::vector<double> cumulated;  // cumulated[t] = area of triangles 0 .. t
  Bounds bounds;
  PrimitiveSet set;
};

Surface make_surface(const PolyData& mesh, const char* name) {
  const std::string what = std::string("mesh_distance: ") + name;
  mesh.polys.validate(mesh.points.size(), (what + ": polys").c_str());
  mesh.strips.validate(mesh.points.size(), (what + ": strips").c_str());
  const auto tris = triangulate_faces(mesh);
  if (tris.empty()) throw Error(what + " has no triangles");
  if (mesh.points.size() >= PrimitiveSet::kNone || tris.size() >= PrimitiveSet::kNone) {
    throw Error(what + ": too many points or triangles (2^32 or more)");
  }
  Surface s;
  std::vector<PrimitiveSet::Id> remap(mesh.points.size(), PrimitiveSet::kNone);
  s.triangles.reserve(tris.size());
  for (const auto& t : tris) {
    std::array<PrimitiveSet::Id, 3> ids{};
    for (int k = 0; k < 3; ++k) {
      const auto old = static_cast<std::size_t>(t[static_cast<std::size_t>(k)]);
      if (remap[old] == PrimitiveSet::kNone) {
        const Vec3 p = mesh.points[old];
        if (!is_finite(p)) throw Error(what + ": point " + std::to_string(old) + " is not finite");
        remap[old] = static_cast<PrimitiveSet::Id>(s.vertices.size());
        s.vertices.push_back(p);
        s.bounds.extend(p);
      }
      ids[static_cast<std::size_t>(k)] = remap[old];
    }
    s.triangles.push_back(ids);
  }
  s.cumulated.resize(s.triangles.size());
  double sum = 0;
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    const auto& ids = s.triangles[t];
    const Vec3 &a = s.vertices[ids[0]], &b = s.vertices[ids[1]], &c = s.vertices[ids[2]];
    sum += 0.5 * norm(cross(b - a, c - a));
    s.cumulated[t] = sum;
  }
  s.set = PrimitiveSet(s.vertices, {}, {}, s.triangles);
  return s;
}

// Sample i of surface s (vertices, then `area_samples` area samples).
Vec3 sample(const Surface& s, std::size_t area_samples, std::uint64_t seed, std::uint64_t stream,
            std::size_t i) {
  if (i < s.vertices.size()) return s.vertices[i];
  const std::size_t k = i - s.vertices.size();
  const double total = s.cumulated.back();
  const double u = (static_cast<double>(k) + uniform(seed, stream, 3 * k)) /
                   static_cast<double>(area_samples) * total;
  auto it = std::upper_bound(s.cumulated.begin(), s.cumulated.end(), u);
  if (it == s.cumulated.end()) --it;
  const auto& ids = s.triangles[static_cast<std::size_t>(it - s.cumulated.begin())];
  const double r1 = std::sqrt(uniform(seed, stream, 3 * k + 1));
  const double r2 = uniform(seed, stream, 3 * k + 2);
  return s.vertices[ids[0]] * (1 - r1) + s.vertices[ids[1]] * (r1 * (1 - r2)) +
         s.vertices[ids[2]] * (r1 * r2);
}

struct OneSided {
  double max = 0, sum = 0, sum2 = 0;
  std::size_t samples = 0;
};

// Distances from the samples of `from` to the surface of `to`.
OneSided one_sided(const Surface& from, std::size_t requested, const PrimitiveLocator& to,
                   std::uint64_t seed, std::uint64_t stream, const ProgressCallback& progress) {
  // Zero-area meshes get no area samples (there is no area to spread them over).
  const std::size_t area_samples = from.cumulated.back() > 0 ? requested : 0;
  const std::size_t n = from.vertices.size() + area_samples;
  // Fixed chunks of samples, each summed in order, the chunks then combined in order: the same
  // sums for any thread count, in memory independent of the sample count.
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  std::vector<OneSided> partial(chunks);
  const PrimitiveSet& set = to.primitives();
  parallel_for_range(
      chunks, 1,
      [&](std::size_t begin, std::size_t end) {
        for (std::size_t c = begin; c < end; ++c) {
          OneSided& part = partial[c];
          // Consecutive samples are close together: the previous answer bounds the next search.
          ClosestPrimitive best;
          const std::size_t last = std::min(n, (c + 1) * kChunk);
          for (std::size_t i = c * kChunk; i < last; ++i) {
            const Vec3 p = sample(from, area_samples, seed, stream, i);
            if (best.id != PrimitiveSet::kNone) best.dist2 = set.dist2(best.id, p);
            to.nearest(p, std::numeric_limits<double>::infinity(), best);
            const double d = std::sqrt(best.dist2);
            part.max = std::max(part.max, d);
            part.sum += d;
            part.sum2 += best.dist2;
          }
          part.samples = last - c * kChunk;
        }
      },
      progress, "mesh_distance");
  OneSided r;
  for (const OneSided& part : partial) {
    r.max = std::max(r.max, part.max);
    r.sum += part.sum;
    r.sum2 += part.sum2;
    r.samples += part.samples;
  }
  return r;
}

}  // namespace

MeshDistance mesh_distance(const PolyData& a, const PolyData& b,
                           const MeshDistanceOptions& options) {
  const Surface sa = make_surface(a, "a");
  const Surface sb = make_surface(b, "b");
  const auto count = [&](const Surface& s) {
    if (options.samples != 0) return options.samples;
    return std::min(kMaxAutoSamples,
                    std::max(kMinAutoSamples, kSamplesPerTriangle * s.triangles.size()));
  };
  const PrimitiveLocator la(sa.set), lb(sb.set);
  const OneSided ab =
      one_sided(sa, count(sa), lb, options.seed, 0, progress_range(options.progress, 0, 0.5));
  const OneSided ba =
      one_sided(sb, count(sb), la, options.seed, 1, progress_range(options.progress, 0.5, 1));

  MeshDistance r;
  r.max_a_to_b = ab.max;
  r.max_b_to_a = ba.max;
  r.hausdorff = std::max(ab.max, ba.max);
  r.samples_a = ab.samples;
  r.samples_b = ba.samples;
  r.rms_a_to_b = std::sqrt(ab.sum2 / static_cast<double>(ab.samples));
  r.rms_b_to_a = std::sqrt(ba.sum2 / static_cast<double>(ba.samples));
  const auto total = static_cast<double>(ab.samples + ba.samples);
  r.rms = std::sqrt((ab.sum2 + ba.sum2) / total);
  r.mean = (ab.sum + ba.sum) / total;
  r.diagonal = sa.bounds.diagonal();
  return r;
}

}  // namespace isoforge
