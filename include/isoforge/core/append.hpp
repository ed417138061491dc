#pragma once
/// \file
/// Appending polygonal data (vtkAppendPolyData's role), for algorithms that build their output
/// in parts (one per isovalue, per cut value, per thread).

#include <vector>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/summary.hpp"

namespace isoforge {

/// One polydata made of `parts`: their points in order; their cells with point ids shifted, kind
/// by kind (all parts' verts, then lines, polys, strips: the PolyData cell order); the point and
/// cell arrays that every part has with the same type and components (others are dropped), with
/// the first part's active roles. Points are Float64 if any part's are. One part is returned as
/// it is (moved).
[[nodiscard]] PolyData append(std::vector<PolyData> parts);

/// The summary of `append(parts)` from the parts' summaries (polygonal data each), by the same
/// rules: counts, cell types and bounds added up; the point and cell arrays every part has with
/// the same type and components, their ranges merged; the first part's active roles. Lets a
/// reader that appends pieces summarise a file a piece at a time.
[[nodiscard]] DatasetSummary append_summaries(const std::vector<DatasetSummary>& parts);

}  // namespace isoforge
