#pragma once
/// \file
/// Subsets of datasets: an unstructured grid of chosen cells (selection, thresholding,
/// shrinking, connectivity), and tuple copies between attribute sets of the same layout.

#include <vector>

#include "isoforge/core/dataset.hpp"

namespace isoforge {

/// The cells `cells` (increasing ids) of `input`, with only the points they use, renumbered in
/// increasing original id; point and cell data carried; optionally "OriginalPointIds" and
/// "OriginalCellIds" (Int64).
[[nodiscard]] UnstructuredGrid subset_cells(DatasetRef input, const std::vector<Index>& cells,
                                            bool original_ids);

/// Copies tuple `from` of every array in `src` to tuple `to` of the same-named array in `dst`
/// (which must have the same layout).
void copy_tuple(const Attributes& src, std::size_t from, Attributes& dst, std::size_t to);

/// An `Attributes` with the same arrays (names, types, components, roles) and `tuples` tuples.
[[nodiscard]] Attributes empty_like(const Attributes& src, std::size_t tuples);

}  // namespace isoforge
