#pragma once
// Private: the node of an implicit function tree, and block evaluation used by the samplers.

#include <array>
#include <cstddef>
#include <vector>

#include "isoforge/implicit/function.hpp"

namespace isoforge {

struct ImplicitFunction::Node {
  Kind kind = Kind::Plane;
  /// Parameters (layout per kind documented in function.cpp's factories).
  std::array<double, 16> p{};
  Affine forward;  ///< Transform: placement (object → world), kept for printing
  Affine inverse;  ///< Transform: world → object, applied to points
  std::vector<ImplicitFunction> children;
  int depth = 1;  ///< 1 + the deepest child (<= kMaxFunctionDepth)
  /// Plane normal, or cylinder, cone or torus axis, as given (p holds it normalized). Printed,
  /// so that parsing the print normalizes the same vector again: normalizing a normalized vector
  /// can change its last bits.
  Vec3 direction{0, 0, 1};
};

namespace implicit_detail {

/// Points per evaluation block (16 x 8 x 4 samples when sampling grids). Temporaries of this size
/// live on the stack per tree level (4 KiB per array).
inline constexpr std::size_t kBlock = 512;

/// Evaluates `count` <= kBlock points given as structure-of-arrays.
void eval_block(const ImplicitFunction::Node& node, const double* x, const double* y,
                const double* z, std::size_t count, double* out);

/// Like eval_block for points known to lie in `box`: boolean children whose bounds over the box
/// prove they cannot decide the result are not evaluated. The values are bit-identical to
/// eval_block's (min/max of the remaining children is the same number).
void eval_pruned(const ImplicitFunction::Node& node, const Bounds& box, const double* x,
                 const double* y, const double* z, std::size_t count, double* out);

/// Conservative bounds of a node over a box (ImplicitFunction::bound without the checks).
Interval bound_of(const ImplicitFunction::Node& node, const Bounds& box);

}  // namespace implicit_detail
}  // namespace isoforge
