#pragma once
/// \file
/// Sampling an implicit function into an OpenVDB narrow-band level set without visiting the
/// whole domain: the VDB tree is descended from 4096³ to 128³ to 8³ blocks and a block is
/// skipped when `ImplicitFunction::bound` proves |F| exceeds the band there. Memory therefore
/// scales with the surface area, not the volume.

#include <cstddef>

#include <openvdb/openvdb.h>

#include "isoforge/core/progress.hpp"
#include "isoforge/core/result.hpp"
#include "isoforge/implicit/function.hpp"
#include "isoforge/implicit/sample.hpp"

namespace isoforge {

struct SparseSampleOptions {
  /// Voxels within `half_width` voxels of F = 0 (|F| < half_width * voxel size) are active.
  double half_width = 3.0;
  ProgressCallback progress;  ///< called with the fraction of top-level blocks done
};

struct SparseSampleStats {
  std::size_t active_voxels = 0;
  std::size_t leaves = 0;            ///< 8³ leaf nodes allocated
  std::size_t inside_tiles = 0;      ///< blocks proven inside (stored as one tile each)
  std::size_t evaluated_voxels = 0;  ///< function evaluations made
  std::size_t memory_bytes = 0;      ///< the tree's memory use
};

using SparseSampleResult = Result<openvdb::FloatGrid::Ptr, SparseSampleStats>;

/// Samples `f` on the grid `grid` (which must have equal spacing on all axes: VDB voxels are
/// cubes) into a level set: voxel (i, j, k) of the VDB is sample (i, j, k) of the grid, with
/// world position grid.origin + (i, j, k) * spacing. Active voxels hold F where
/// |F| < half_width * spacing and lie inside the grid's dims; every other voxel is inactive
/// with value ±background (background = half_width * spacing; the sign is F's), so the result
/// follows OpenVDB's level-set convention. Values equal `sample_image` on the band exactly.
/// Multi-threaded (TBB), deterministic.
/// \throw Error on unequal spacing, half_width <= 0 or an invalid grid.
[[nodiscard]] SparseSampleResult sample_level_set(const ImplicitFunction& f, const GridSpec& grid,
                                                  const SparseSampleOptions& options = {});

}  // namespace isoforge
