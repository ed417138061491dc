#pragma once
/// \file
/// Shrinking cells toward their centroids (VTK's vtkShrinkFilter; Fig. 1.24b shows voxels
/// shrunk 50%), which makes individual cells visible.

#include "isoforge/core/dataset.hpp"

namespace isoforge {

/// Each cell gets its own copies of its points, moved to centroid + factor (p − centroid), where
/// the centroid is the mean of the cell's points. factor 1 leaves cells unchanged, 0.5 halves
/// them, 0 collapses each to its centroid. Point data is copied to the duplicated points, cell
/// data is carried. \throw Error if factor is not in [0, 1].
[[nodiscard]] UnstructuredGrid shrink(DatasetRef input, double factor);

}  // namespace isoforge
