#pragma once
/// \file
/// Subsampling structured data (the chapter's Fig. 1.36; VTK's vtkExtractVOI / vtkExtractGrid):
/// every n-th point along i, j and k of a volume of interest, attributes carried.
/// Method: docs/algorithms/probe.md ("Subsampling").

#include <array>
#include <optional>

#include "isoforge/core/dataset.hpp"

namespace isoforge {

/// A volume of interest in point indices, inclusive: i0 i1 j0 j1 k0 k1.
using Voi = std::array<Index, 6>;

struct SubsampleOptions {
  std::array<Index, 3> rate{1, 1, 1};  ///< keep every rate-th point along i, j, k (each ≥ 1)
  std::optional<Voi> voi;              ///< the part to keep (default: the whole dataset)
  /// Also keep the last point of the VOI along an axis whose rate skips it (vtkExtractGrid's
  /// IncludeBoundary). Structured grids only: image data must stay evenly spaced.
  bool include_boundary = false;
};

/// Image data: points i0, i0 + rate, ... ≤ i1 (and likewise along j, k); the origin moves to
/// point (i0, j0, k0) and the spacing is multiplied by the rate. Point data is copied from the
/// kept points; an output cell takes the cell data of the input cell at its first point.
/// \throw Error if a rate is < 1, the VOI is inverted or out of range, or `include_boundary`.
[[nodiscard]] ImageData subsample(const ImageData& input, const SubsampleOptions& options);

/// A structured grid: the same selection of points with their coordinates and data
/// (vtkExtractGrid). \throw Error if a rate is < 1 or the VOI is inverted or out of range.
[[nodiscard]] StructuredGrid extract_voi(const StructuredGrid& input,
                                         const SubsampleOptions& options);

/// `subsample` or `extract_voi` by the input's type. \throw Error for polygonal data and
/// unstructured grids (they have no i, j, k), and as the two functions.
[[nodiscard]] Dataset subsample(DatasetRef input, const SubsampleOptions& options);

}  // namespace isoforge
