#pragma once
/// \file
/// Symmetric surface distance between two triangle meshes (Hausdorff, RMS and mean distance,
/// in the manner of Metro): the error measure of decimation. Each surface is sampled at its
/// vertices and at area-proportional points; each sample's exact distance to the other surface
/// comes from a `PrimitiveLocator`. Method: docs/algorithms/decimation.md, "Measuring error".

#include <cstddef>
#include <cstdint>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"

namespace isoforge {

struct MeshDistanceOptions {
  /// Area samples per mesh (besides its vertices); 0 = automatic: max(1e5, 10 × triangles),
  /// at most 4e6.
  std::size_t samples = 0;
  std::uint64_t seed = 1;     ///< seed of the sample positions (results are reproducible)
  ProgressCallback progress;  ///< fraction done; false cancels
};

/// Distances between surfaces a and b, in data units. "a_to_b" values are over the samples of
/// a (distance to the surface of b), "b_to_a" the other way round.
struct MeshDistance {
  double hausdorff = 0;   ///< max(max_a_to_b, max_b_to_a): the symmetric Hausdorff distance
  double rms = 0;         ///< root mean square over the samples of both meshes together
  double mean = 0;        ///< mean over the samples of both meshes together
  double max_a_to_b = 0;  ///< largest distance from a sample of a to b
  double max_b_to_a = 0;
  double rms_a_to_b = 0;  ///< root mean square over the samples of a
  double rms_b_to_a = 0;
  double diagonal = 0;  ///< bounding-box diagonal of a's triangles, for relative values
  std::size_t samples_a = 0, samples_b = 0;  ///< samples taken on each (vertices included)

  /// hausdorff / diagonal (0 when the diagonal is 0).
  [[nodiscard]] double relative_hausdorff() const {
    return diagonal > 0 ? hausdorff / diagonal : 0;
  }
  /// rms / diagonal (0 when the diagonal is 0).
  [[nodiscard]] double relative_rms() const { return diagonal > 0 ? rms / diagonal : 0; }
};

/// The symmetric distance between the triangles of a and b (polygons fan-triangulated, strips
/// split; verts and lines ignored). Samples of a mesh: each point used by a triangle, plus
/// `samples` points placed by area — stratified along the cumulated triangle areas with jitter
/// from a counter-based generator seeded by `seed` — so results do not depend on the thread
/// count. Parallel. \throw Error if a mesh has no triangle, an invalid cell or a non-finite
/// point; `Cancelled` through `progress`.
[[nodiscard]] MeshDistance mesh_distance(const PolyData& a, const PolyData& b,
                                         const MeshDistanceOptions& options = {});

}  // namespace isoforge
