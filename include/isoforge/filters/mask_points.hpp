#pragma once
/// \file
/// Point masking (VTK's vtkMaskPoints): a subset of a dataset's points, for glyphs and point
/// clouds — every nth, a seeded random sample, at most N, or one point per voxel.
/// See docs/algorithms/glyph.md.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "isoforge/core/dataset.hpp"

namespace isoforge {

/// Which points to keep. At most one of `every`, `random` and `voxel` is set (none: all points);
/// `max_points` caps any of them. Every mode is deterministic and independent of thread count.
struct MaskOptions {
  std::size_t every = 0;      ///< keep ids 0, n, 2n, ... (0 or 1 = off)
  std::size_t random = 0;     ///< keep exactly this many points chosen uniformly at random
                              ///< without replacement (all if the dataset has fewer; 0 = off)
  std::uint64_t seed = 0;     ///< seed of the random choice (same seed, same points)
  double voxel = 0;           ///< keep the lowest id in each cube of this edge (data units) of
                              ///< a lattice anchored at the bounds' minimum corner (0 = off)
  std::size_t max_points = 0; ///< after the above, at most this many, evenly spread over the
                              ///< kept ones in id order: kept[floor(i k / max)] (0 = no cap)
};

/// The kept point ids, increasing. \throw Error naming the option if two modes are set or
/// `voxel` is negative or not finite.
[[nodiscard]] std::vector<Index> mask_point_ids(DatasetRef input, const MaskOptions& options = {});

/// The kept points as a polydata of vertex cells (one per point), with the input's point data
/// carried and an Int64 point array "OriginalPointIds". \throw Error as mask_point_ids.
[[nodiscard]] PolyData mask_points(DatasetRef input, const MaskOptions& options = {});

}  // namespace isoforge
