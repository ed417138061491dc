#pragma once
// Human-readable summary of a dataset (used by `isoforge info` and the demo).

#include <string>

#include "isoforge/core/summary.hpp"

namespace isoforge::cli {

/// Multi-line description: type, dimensions, counts (with a cell-type histogram), bounds, and
/// every point/cell/field array with its type, components, role and range per component.
[[nodiscard]] std::string describe(const DatasetSummary& s);
[[nodiscard]] inline std::string describe(DatasetRef ds) { return describe(summarize(ds)); }

}  // namespace isoforge::cli
