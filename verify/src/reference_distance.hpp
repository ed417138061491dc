#pragma once
// The error of a decimated (or otherwise approximated) mesh against its reference: the one metric
// of the decimation cases and of `isoforge-verify distance`, which the decimation benchmark runs
// on every decimator's output. The reference's samples and AABB tree are made once and reused for
// every mesh measured against it.

#include <cstddef>
#include <memory>

#include "accuracy.hpp"
#include "isoforge/core/dataset.hpp"

namespace isoforge::verify {

class MeshDistance;

struct ReferenceError {
  double hausdorff = 0;        ///< the larger of the two sampled maxima (data units)
  double rms = 0;              ///< sqrt((rms_ref_to_mesh^2 + rms_mesh_to_ref^2) / 2)
  double max_ref_to_mesh = 0;  ///< over the reference's samples
  double max_mesh_to_ref = 0;  ///< over the mesh's samples
  double rms_ref_to_mesh = 0;  ///< area-weighted
  double rms_mesh_to_ref = 0;
  double relative_hausdorff = 0;  ///< divided by the reference's bounding-box diagonal
  double relative_rms = 0;
  double spacing_mesh = 0;  ///< the spacing the mesh was sampled at (see `ReferenceDistance`)
  std::size_t samples_mesh = 0;
};

/// Distances of meshes to one reference. Both sides are sampled by `sample_mesh` at `spacing`
/// (at least 7 samples per triangle: corners, edge midpoints, centroid) and measured with CGAL's
/// AABB tree of the other mesh. A side whose samples would exceed about `max_samples` is sampled
/// at the smallest larger spacing that fits (only the grid inside each triangle gets coarser);
/// a reference too large even for 7 samples per triangle is sampled at its points (counted in the
/// maximum only) and its triangle centroids (weighted by area). Sampled maxima are lower bounds
/// of the true one-sided Hausdorff distances.
class ReferenceDistance {
 public:
  /// `spacing` <= 0: half the reference's mean edge length. \throw Error if the reference has no
  /// non-degenerate triangle.
  ReferenceDistance(const PolyData& reference, double spacing, std::size_t max_samples = 2'000'000);
  ~ReferenceDistance();
  ReferenceDistance(const ReferenceDistance&) = delete;
  ReferenceDistance& operator=(const ReferenceDistance&) = delete;

  [[nodiscard]] ReferenceError measure(const PolyData& mesh) const;

  [[nodiscard]] double diagonal() const { return diagonal_; }
  [[nodiscard]] double spacing() const { return spacing_; }  ///< asked for (or the default)
  [[nodiscard]] double reference_spacing() const { return reference_spacing_; }  ///< 0: points
  [[nodiscard]] std::size_t reference_samples() const { return samples_.points.size(); }

 private:
  double diagonal_ = 0, spacing_ = 0, reference_spacing_ = 0;
  std::size_t max_samples_ = 0;
  Samples samples_;
  std::unique_ptr<MeshDistance> tree_;
};

}  // namespace isoforge::verify
