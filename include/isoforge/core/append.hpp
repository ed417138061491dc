#pragma once
/// \file
/// Appending polygonal data (vtkAppendPolyData's role), for algorithms that build their output
/// in parts (one per isovalue, per cut value, per thread).

#include <vector>

#include "isoforge/core/dataset.hpp"

namespace isoforge {

/// One polydata made of `parts`: their points in order; their cells with point ids shifted, kind
/// by kind (all parts' verts, then lines, polys, strips: the PolyData cell order); the point and
/// cell arrays that every part has with the same type and components (others are dropped), with
/// the first part's active roles. Points are Float64 if any part's are. One part is returned as
/// it is (moved).
[[nodiscard]] PolyData append(std::vector<PolyData> parts);

}  // namespace isoforge
