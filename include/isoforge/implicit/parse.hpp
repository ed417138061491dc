#pragma once
/// \file
/// A small expression language for implicit functions, used by the CLI (`--function`) and
/// printed by `ImplicitFunction::to_string()`. Full grammar and examples: docs/implicit.md.
///
/// \code
///   sphere(r=1)
///   difference(sphere(center=[1.333,0,0], r=0.5), sphere(center=[1.5,0,0.5], r=0.25))
///   union(scale(sphere(), [1, 0.5, 0.5]), translate(sphere(r=0.5), [1, 0, 0]))
///   icecream()
/// \endcode

#include <string_view>

#include "isoforge/implicit/function.hpp"

namespace isoforge {

/// Parses an expression. \throw Error naming the column and what was expected, or the function
/// and parameter that is invalid (e.g. "sphere: parameter 'r' (radius) is negative").
[[nodiscard]] ImplicitFunction parse_implicit(std::string_view expression);

}  // namespace isoforge
