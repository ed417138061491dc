// Point masking (filters/mask_points.hpp): every nth point, a seeded random sample (selection
// sampling, Knuth TAOCP vol. 2, 3.4.2, Algorithm S), at most N, or one point per voxel.

#include "isoforge/filters/mask_points.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "isoforge/core/parallel.hpp"
#include "isoforge/core/subset.hpp"

namespace isoforge {
namespace {

__extension__ typedef unsigned __int128 U128;  // exact products of two 64-bit counts

// SplitMix64 (Steele, Lea and Flood 2014): a tiny generator whose stream depends only on the
// seed, so the same seed picks the same points on every platform and thread count.
struct SplitMix64 {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  // Uniform in [0, n) (Lemire's multiply-shift; the bias is below n / 2^64).
  std::uint64_t below(std::uint64_t n) {
    return static_cast<std::uint64_t>((static_cast<U128>(next()) * n) >> 64);
  }
};

std::vector<Index> random_ids(std::size_t n, std::size_t k, std::uint64_t seed) {
  std::vector<Index> ids;
  if (k >= n) {
    ids.resize(n);
    for (std::size_t i = 0; i < n; ++i) ids[i] = static_cast<Index>(i);
    return ids;
  }
  ids.reserve(k);
  SplitMix64 rng{seed};
  // Algorithm S: point i is kept with probability (still needed) / (still available).
  std::size_t needed = k;
  for (std::size_t i = 0; i < n && needed > 0; ++i) {
    if (rng.below(n - i) < needed) {
      ids.push_back(static_cast<Index>(i));
      --needed;
    }
  }
  return ids;
}

std::vector<Index> voxel_ids(DatasetRef input, double h) {
  const std::size_t n = num_points(input);
  if (n == 0) return {};
  const Bounds b = bounds(input);
  // Cells along each axis; the key i + nx (j + ny k) must fit 64 bits.
  const auto cells = [&](double lo, double hi) { return std::floor((hi - lo) / h) + 1; };
  const double cx = cells(b.min.x, b.max.x), cy = cells(b.min.y, b.max.y),
               cz = cells(b.min.z, b.max.z);
  if (!(cx * cy * cz < 1.8e19)) {
    throw Error("mask points: voxel " + std::to_string(h) +
                " is too small for the bounds (more than 2^64 voxels)");
  }
  const auto nx = static_cast<std::uint64_t>(cx), ny = static_cast<std::uint64_t>(cy),
             nz = static_cast<std::uint64_t>(cz);
  std::vector<std::pair<std::uint64_t, Index>> keyed(n);
  parallel_for_range(n, 4096, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const Vec3 p = point(input, static_cast<Index>(i));
      const auto axis = [&](double v, double lo, std::uint64_t cap) {
        const double c = std::floor((v - lo) / h);
        return std::min(static_cast<std::uint64_t>(c > 0 ? c : 0), cap - 1);
      };
      const std::uint64_t key =
          axis(p.x, b.min.x, nx) + nx * (axis(p.y, b.min.y, ny) + ny * axis(p.z, b.min.z, nz));
      keyed[i] = {key, static_cast<Index>(i)};
    }
  });
  std::sort(keyed.begin(), keyed.end());
  std::vector<Index> ids;
  for (std::size_t i = 0; i < n; ++i) {
    if (i == 0 || keyed[i].first != keyed[i - 1].first) ids.push_back(keyed[i].second);
  }
  std::sort(ids.begin(), ids.end());
  return ids;
}

}  // namespace

std::vector<Index> mask_point_ids(DatasetRef input, const MaskOptions& o) {
  const int modes = (o.every > 1 ? 1 : 0) + (o.random > 0 ? 1 : 0) + (o.voxel != 0 ? 1 : 0);
  if (modes > 1) {
    throw Error("mask points: every, random and voxel exclude each other (got " +
                std::string(o.every > 1 ? "every " : "") + (o.random > 0 ? "random " : "") +
                (o.voxel != 0 ? "voxel" : "") + ")");
  }
  if (!(std::isfinite(o.voxel) && o.voxel >= 0)) {
    throw Error("mask points: voxel must be a finite size >= 0, got " + std::to_string(o.voxel));
  }
  const std::size_t n = num_points(input);
  std::vector<Index> ids;
  if (o.random > 0) {
    ids = random_ids(n, o.random, o.seed);
  } else if (o.voxel > 0) {
    ids = voxel_ids(input, o.voxel);
  } else {
    const std::size_t step = std::max<std::size_t>(o.every, 1);
    ids.reserve(n / step + 1);
    for (std::size_t i = 0; i < n; i += step) ids.push_back(static_cast<Index>(i));
  }
  if (o.max_points > 0 && ids.size() > o.max_points) {
    const std::size_t k = ids.size();
    std::vector<Index> capped(o.max_points);
    for (std::size_t i = 0; i < o.max_points; ++i) {
      capped[i] = ids[static_cast<std::size_t>(static_cast<U128>(i) * k / o.max_points)];
    }
    ids = std::move(capped);
  }
  return ids;
}

PolyData mask_points(DatasetRef input, const MaskOptions& options) {
  const std::vector<Index> ids = mask_point_ids(input, options);
  const std::size_t k = ids.size();
  PolyData out;
  out.points = Points(k);
  out.point_data = empty_like(point_data(input), k);
  DataArray original("OriginalPointIds", ScalarType::Int64, 1, k);
  auto orig = original.values<std::int64_t>();
  for (std::size_t i = 0; i < k; ++i) {
    out.points.set(i, point(input, ids[i]));
    copy_tuple(point_data(input), static_cast<std::size_t>(ids[i]), out.point_data, i);
    orig[i] = ids[i];
  }
  out.point_data.add(std::move(original));
  Buffer<Index> offsets(k + 1), conn(k);
  for (std::size_t i = 0; i <= k; ++i) offsets[i] = static_cast<Index>(i);
  for (std::size_t i = 0; i < k; ++i) conn[i] = static_cast<Index>(i);
  out.verts = CellArray(std::move(offsets), std::move(conn));
  out.field_data = field_data(input);
  return out;
}

}  // namespace isoforge
