#pragma once
/// \file
/// Derivatives of point data on every dataset type (vtkGradientFilter): the gradient of each
/// component, and for vector fields the divergence and the vorticity (curl).
/// Method: docs/algorithms/attributes.md.

#include <optional>
#include <string>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"

namespace isoforge {

struct GradientOptions {
  std::string array;  ///< point array to differentiate; empty: the active scalars
  std::string gradient_name = "Gradient";  ///< name of the gradient array
  bool compute_gradient = true;            ///< false: only divergence and/or vorticity
  bool divergence = false;  ///< also ∇·v (the array must have 3 components): "Divergence"
  bool vorticity = false;   ///< also ∇×v (3 components): "Vorticity"
  ProgressCallback progress = {};
};

struct GradientResult {
  /// Float64 point array of 3 n components for an n-component input: component c's gradient is
  /// at 3 c .. 3 c + 2 (d/dx, d/dy, d/dz). Empty when not asked for.
  DataArray gradient;
  std::optional<DataArray> divergence;  ///< 1 component
  std::optional<DataArray> vorticity;   ///< 3 components
};

/// Derivatives at the points. Image data: central differences inside, one-sided differences on
/// the faces (exact for fields linear along each axis; inside also for quadratic ones).
/// Structured grids: the same differences in index space mapped through the inverse of the
/// grid's own Jacobian. Polygonal data and unstructured grids: each cell's derivative at its
/// centre (core/cell.hpp), averaged over the cells that use the point, weighted equally (exact
/// for linear fields on linear cells); vertices and degenerate cells are left out. Points used
/// by no cell with derivatives get 0.
/// \throw Error naming the array when it is missing or (for divergence/vorticity) not 3
/// components, or when nothing was asked for.
[[nodiscard]] GradientResult gradient(DatasetRef input, const GradientOptions& options = {});

}  // namespace isoforge
