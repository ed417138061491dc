#pragma once
/// \file
/// The stress field of a point load on a half-space (Boussinesq's problem; VTK's vtkPointLoad),
/// sampled on a grid: the analytic data source for tensor glyphs. A downward force `load` acts at
/// the centre of the box's top face (z = zmax); the body fills the box below it. Stresses are
/// tension-positive. See docs/algorithms/tensor_glyph.md.

#include <array>
#include <cstddef>
#include <string>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/core/result.hpp"

namespace isoforge {

struct PointLoadOptions {
  Bounds bounds = {{-1, -1, -1}, {1, 1, 1}};  ///< the sampled box (VTK's ModelBounds)
  Dims dims{50, 50, 50};                      ///< samples per axis, each ≥ 2
  double load = 1;                            ///< force magnitude (finite, ≥ 0)
  double poisson_ratio = 0.3;                 ///< ν, in [0, 0.5]
  std::string tensors = "stress";             ///< 9-component point array (active tensors)
  /// The von Mises stress ("" = none; active scalars). VTK's "effective stress" is the
  /// octahedral shear stress, √2/3 of it.
  std::string scalars = "effective_stress";
  ProgressCallback progress{};
};

struct PointLoadStats {
  /// Samples at the load point itself, where the stress is infinite: their tensor and scalar are
  /// 0 and their "vtkValidPointMask" entry is 0 (every other sample's is 1). 0 or 1.
  std::size_t singular = 0;
  double max_effective_stress = 0;  ///< over the regular samples
};

/// The stress tensor σ (row-major 3×3, tension positive, axes x, y and z up out of the body) at
/// `depth` ≥ 0 below a downward `load` applied at the origin of the surface, horizontal offset
/// (x, y): Boussinesq's closed form. Its trace is −(1+ν) P depth / (π ρ³). Infinite at the load
/// point.
[[nodiscard]] std::array<double, 9> boussinesq_stress(double x, double y, double depth,
                                                      double load, double poisson_ratio);

/// The sampled field: ImageData with the tensors, the effective (von Mises) stress and
/// "vtkValidPointMask" (UInt8; the probe's name for it). \throw Error on an empty or non-finite
/// box, dims < 2, a load or Poisson ratio out of range, a grid larger than memory, or a stress
/// beyond the Float32 range (a huge load, or a sample very close to the load point).
[[nodiscard]] Result<ImageData, PointLoadStats> point_load(const PointLoadOptions& options = {});

}  // namespace isoforge
