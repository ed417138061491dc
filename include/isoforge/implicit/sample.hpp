#pragma once
/// \file
/// Sampling implicit functions onto dense volumes (`ImageData`) and onto the points of any
/// dataset (section 1.5.2: "evaluate these functions on a regular array of points").

#include <string>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/grid_spec.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/implicit/function.hpp"

namespace isoforge {

struct SampleOptions {
  std::string name = "F";           ///< name of the point scalars
  ScalarType type = ScalarType::Float32;  ///< Float32 or Float64 values
  bool normals = false;             ///< also store "Normals": the unit gradient (pointing to F > 0)
  bool gradients = false;           ///< also store "Gradient": the analytic gradient
  ProgressCallback progress;        ///< called with the fraction of slices done
};

/// Samples `f` at every point of the grid. Multi-threaded (TBB) and deterministic: the result
/// does not depend on the number of threads. \throw Error on an invalid grid or options.
[[nodiscard]] ImageData sample_image(const ImplicitFunction& f, const GridSpec& grid,
                                     const SampleOptions& options = {});

/// Values of `f` at the points of any dataset, as a 1-component array named `name`.
/// This is what cutting contours. Multi-threaded, deterministic.
[[nodiscard]] DataArray sample_points(const ImplicitFunction& f, DatasetRef ds,
                                      const std::string& name = "F",
                                      ScalarType type = ScalarType::Float32);

}  // namespace isoforge
