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
};

namespace implicit_detail {

/// Points per evaluation block. Temporaries of this size live on the stack per tree level.
inline constexpr std::size_t kBlock = 128;

/// Evaluates `count` <= kBlock points given as structure-of-arrays.
void eval_block(const ImplicitFunction::Node& node, const double* x, const double* y,
                const double* z, std::size_t count, double* out);

}  // namespace implicit_detail
}  // namespace isoforge
