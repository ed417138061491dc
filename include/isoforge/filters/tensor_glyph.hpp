#pragma once
/// \file
/// Tensor glyphs (VTK's vtkTensorGlyph): at each (masked) point of a dataset with a symmetric
/// 3×3 tensor array, an ellipsoid whose axes are the tensor's eigenvectors scaled by its
/// eigenvalues; and the eigen-decomposition itself. See docs/algorithms/tensor_glyph.md.

#include <array>
#include <cstddef>
#include <string>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/core/result.hpp"
#include "isoforge/filters/mask_points.hpp"

namespace isoforge {

/// Eigenvalues of a symmetric 3×3 matrix, largest first, and unit eigenvectors (right-handed:
/// vectors[2] = vectors[0] × vectors[1]).
struct SymmetricEigen {
  std::array<double, 3> values{};
  std::array<Vec3, 3> vectors{};
};

/// The eigen-decomposition of the symmetric matrix `m` (row-major; only its upper triangle is
/// read, as VTK does), by Eigen's self-adjoint solver. \throw Error if an entry is not
/// finite.
[[nodiscard]] SymmetricEigen symmetric_eigen(const std::array<double, 9>& m);

enum class TensorColor : std::uint8_t {
  None,
  Eigenvalue,  ///< the largest eigenvalue
  Anisotropy,  ///< fractional anisotropy of the semi-axes |λ|: 0 (sphere) to 1 (line)
};

enum class TensorGlyphShape : std::uint8_t {
  Ellipsoid,     ///< the unit sphere scaled along the eigenvectors
  /// Kindlmann's superquadric glyph: a cylinder for a linear tensor, a disc for a planar one, a
  /// sphere for an isotropic one, edges as sharp as `gamma` makes them; scaled like the ellipsoid.
  Superquadric,
};

struct TensorGlyphOptions {
  /// Point array of 9 components (row-major 3×3) or 6 (symmetric, VTK's order XX YY ZZ XY YZ
  /// XZ); "" = the active tensors.
  std::string tensors;
  double scale = 1;          ///< ellipsoid semi-axis = scale × |eigenvalue| (finite, > 0)
  /// Largest semi-axis allowed (data units; 0 = none): larger glyphs are shrunk uniformly to it,
  /// as VTK's ClampScaling does.
  double max_size = 0;
  int resolution = 12;       ///< slices of the sphere source (≥ 3)
  TensorGlyphShape shape = TensorGlyphShape::Ellipsoid;
  double gamma = 3;          ///< superquadric edge sharpness (Kindlmann's γ; finite, > 0)
  TensorColor color = TensorColor::Eigenvalue;
  MaskOptions mask;          ///< which points get a glyph
  ProgressCallback progress{};
};

struct TensorGlyphStats {
  std::size_t glyphs = 0;           ///< ellipsoids placed
  std::size_t degenerate = 0;       ///< of them with a zero eigenvalue (flat or collapsed)
  double min_eigenvalue = 0, max_eigenvalue = 0;  ///< over the glyphed points
};

/// An ellipsoid at each masked point p with tensor T = Σ λᵢ eᵢeᵢᵀ: each unit-sphere source
/// point s becomes p + Σ scale |λᵢ| (s·xᵢ) eᵢ, normals transformed by the inverse transpose
/// (a superquadric likewise, from the superquadric of the tensor's shape in place of the sphere).
/// Output: one polydata of triangles, glyph g's points at [g·m, (g+1)·m), with "Normals",
/// "InputPointIds", "TensorColor" (by `color`) and the input's point arrays.
/// \throw Error if the tensor array is missing or has other than 6 or 9 components, an option
/// is out of range, or a glyphed tensor is not finite.
[[nodiscard]] Result<PolyData, TensorGlyphStats> tensor_glyph(
    DatasetRef input, const TensorGlyphOptions& options = {});

}  // namespace isoforge
