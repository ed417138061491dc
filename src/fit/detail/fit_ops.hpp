#pragma once
// The fitting functions that use Ceres. In a shared build they live in libisoforge_fit, which
// libisoforge's fit_primitive() and refine_mesh() load on their first call (fit_loader.cpp), so
// that a program which never fits does not load Ceres and its solvers (about 10 ms per process
// start, docs/architecture.md). In a static build they are linked in.

#include "isoforge/fit/fit_primitive.hpp"
#include "isoforge/fit/refine.hpp"

namespace isoforge::fit_detail {

/// The implementations (fit_primitive.cpp, refine.cpp) behind the public functions.
[[nodiscard]] FitResult fit_primitive(DatasetRef points, const FitOptions& options);
[[nodiscard]] RefineResult refine_mesh(const PolyData& original, const PolyData& simplified,
                                       const RefineOptions& options);

struct FitOps {
  FitResult (*fit_primitive)(DatasetRef points, const FitOptions& options);
  RefineResult (*refine_mesh)(const PolyData& original, const PolyData& simplified,
                              const RefineOptions& options);
};

}  // namespace isoforge::fit_detail

/// Defined in libisoforge_fit (fit_ops.cpp); looked up by name when it is loaded.
extern "C" const isoforge::fit_detail::FitOps* isoforge_fit_ops();
