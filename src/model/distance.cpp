// Exact Euclidean distance fields into dense images (model/distance.hpp): the block engine
// (distance_engine.hpp) or, for points and segments, the rows along x (distance_rows.cpp), with a
// 6-connected flood fill of the signs beyond the band.

#include "isoforge/model/distance.hpp"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <vector>

#include "distance_engine.hpp"
#include "distance_internal.hpp"
#include "isoforge/core/memory.hpp"

namespace isoforge {

namespace model_detail {

namespace {

// 6-connected flood fill of the samples outside the band (flag 0) with the sign of the band
// samples they touch (+ if none); writes ±far into them.
template <class T>
void dense_flood_fill(const GridSpec& g, std::vector<std::uint8_t>& band, T* v, double far) {
  const Index nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
  const Index n = nx * ny * nz;
  std::vector<Index> queue;
  for (Index seed = 0; seed < n; ++seed) {
    if (band[static_cast<std::size_t>(seed)] != 0) continue;
    // Collect the region, remembering the first band neighbour's sign.
    queue.clear();
    queue.push_back(seed);
    band[static_cast<std::size_t>(seed)] = 2;
    int sign = 0;
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const Index id = queue[q];
      const Index i = id % nx, j = (id / nx) % ny, k = id / (nx * ny);
      const Index nbr[6] = {i > 0 ? id - 1 : -1,       i + 1 < nx ? id + 1 : -1,
                            j > 0 ? id - nx : -1,      j + 1 < ny ? id + nx : -1,
                            k > 0 ? id - nx * ny : -1, k + 1 < nz ? id + nx * ny : -1};
      for (Index m : nbr) {
        if (m < 0) continue;
        std::uint8_t& f = band[static_cast<std::size_t>(m)];
        if (f == 0) {
          f = 2;
          queue.push_back(m);
        } else if (f == 1 && sign == 0) {
          sign = v[m] < 0 ? -1 : 1;
        }
      }
    }
    const T value = static_cast<T>(sign < 0 ? -far : far);
    for (Index id : queue) v[id] = value;
  }
}

template <class T>
ImageData dense_field(const PolyData& input, const GridSpec& g, const DistanceOptions& o,
                      double far, DistanceStats& stats) {
  const PrimitiveSet P = distance_primitives(input, o);
  std::unique_ptr<Pseudonormals> signs;
  if (o.signed_distance) {
    signs = std::make_unique<Pseudonormals>(build_pseudonormals(input, P, o.require_closed));
    const double hmax = std::max({g.spacing.x, g.spacing.y, g.spacing.z});
    if (o.max_distance < hmax) {
      throw Error(
          fmt::format("distance: signed distance needs max_distance ({:g}) >= the largest "
                      "spacing ({:g}) so that the band separates inside from outside",
                      o.max_distance, hmax));
    }
  }
  ImageData img = g.image();
  const std::size_t n = img.num_points();
  DataArray arr = DataArray::uninitialized(o.name, ScalarTypeOf<T>::value, 1, n);
  T* v = arr.values<T>().data();
  // The block engine's options: with points and segments only, the strategy is decided here.
  DistanceOptions engine_options = o;
  if (!signs && !P.has_radii() && P.triangles().empty()) {
    // Points and segments: Scatter by rows along x (distance_rows.cpp), same values.
    engine_options.strategy = choose_strategy(P, g, o, 64, kRowGatherRatio, stats);
    if (engine_options.strategy == DistanceStrategy::Scatter) {
      std::vector<Vec3> centers(P.points().size());
      for (std::size_t i = 0; i < centers.size(); ++i) centers[i] = P.vertices()[P.points()[i]];
      std::vector<std::array<Vec3, 2>> segments(P.segments().size());
      for (std::size_t i = 0; i < segments.size(); ++i) {
        segments[i] = {P.vertices()[P.segments()[i][0]], P.vertices()[P.segments()[i][1]]};
      }
      report_progress(o.progress, 0.0, "distance");
      const RowStats r = distance_rows(centers, segments, g, o.max_distance, far, v, o.progress);
      stats.blocks = r.planes;
      stats.evaluations = r.evaluations;
      stats.active_voxels = r.active;
      img.point_data.add(std::move(arr), AttributeRole::Scalars);
      return img;
    }
  }
  const T far_t = static_cast<T>(far);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 16),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      std::fill(v + r.begin(), v + r.end(), far_t);
                    });
  std::vector<std::uint8_t> band;
  if (signs) band.assign(n, 0);
  const Index nx = g.dims[0], nxy = g.dims[0] * g.dims[1];
  run_blocks(
      P, signs.get(), g, engine_options, 64, stats, [](std::size_t) {},
      [&](std::size_t, const BlockOut& b) {
        for (int i = 0; i < b.ni; ++i)
          for (int j = 0; j < b.nj; ++j)
            for (int k = 0; k < b.nk; ++k) {
              const int off = (i * 8 + j) * b.kz + k;
              if (!b.active[off]) continue;
              const Index id = (b.i0 + i) + nx * (b.j0 + j) + nxy * (b.k0 + k);
              v[id] = static_cast<T>(b.value[off]);
              if (signs) band[static_cast<std::size_t>(id)] = 1;
            }
      });
  if (signs) dense_flood_fill(g, band, v, far);
  img.point_data.add(std::move(arr), AttributeRole::Scalars);
  return img;
}

}  // namespace

ImageData distance_image_far(const PolyData& input, const GridSpec& grid,
                             const DistanceOptions& options, double far_value,
                             DistanceStats& stats) {
  check_common(grid, options);
  // The values, and with signs a band flag and the flood fill's queue (up to 9 bytes a sample).
  require_volume_memory("distance", grid.dims, scalar_type_name(options.type),
                        static_cast<double>(scalar_size(options.type)) +
                            (options.signed_distance ? 9 : 0));
  if (std::isnan(far_value)) throw Error("distance: the far value is NaN");
  if (options.type == ScalarType::Float32)
    return dense_field<float>(input, grid, options, far_value, stats);
  if (options.type == ScalarType::Float64)
    return dense_field<double>(input, grid, options, far_value, stats);
  throw Error("distance: output type must be float32 or float64, got " +
              std::string(scalar_type_name(options.type)));
}

}  // namespace model_detail

DistanceImageResult distance_image(const PolyData& input, const GridSpec& grid,
                                   const DistanceOptions& options) {
  DistanceImageResult r;
  r.output = model_detail::distance_image_far(input, grid, options, options.max_distance, r.stats);
  return r;
}

}  // namespace isoforge
