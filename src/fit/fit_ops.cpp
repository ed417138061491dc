// The table of the Ceres-based fitting functions (detail/fit_ops.hpp). Part of libisoforge_fit in
// a shared build.

#include "detail/fit_ops.hpp"

namespace {

constexpr isoforge::fit_detail::FitOps kFitOps{isoforge::fit_detail::fit_primitive,
                                               isoforge::fit_detail::refine_mesh};

}  // namespace

extern "C" const isoforge::fit_detail::FitOps* isoforge_fit_ops() {
  return &kFitOps;
}
