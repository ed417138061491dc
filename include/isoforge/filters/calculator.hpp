#pragma once
/// \file
/// The array calculator (ParaView's Calculator, VTK's vtkArrayCalculator): a new point or cell
/// array from an expression over a dataset's arrays, its point coordinates and constants,
/// evaluated in parallel over blocks of tuples. Grammar, functions and measurements:
/// docs/algorithms/calculator.md.

#include <string>
#include <string_view>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"

namespace isoforge {

struct CalculatorOptions {
  /// Evaluate over the cell arrays (one value per cell) instead of the point arrays; `coords`
  /// is then not available.
  bool cells = false;
  ScalarType type = ScalarType::Float64;  ///< of the result: Float32 or Float64
  ProgressCallback progress{};
};

/// The array `name` = `expression` at every point (or cell) of `input`: 1 component when the
/// expression is a scalar, 3 when it is a vector. Operands: numbers, `pi`, array names (bare
/// identifiers, or "quoted" when they hold other characters), `A[i]` for component i of array
/// A, `coords` (the point) and `coordsX/Y/Z`, vectors `[a, b, c]`; operators `+ - * / ^`
/// (vectors: + and − between vectors, * and / by scalars); functions of scalars abs sqrt exp
/// log log10 sin cos tan asin acos atan sinh cosh tanh floor ceil, min max atan2 pow of two,
/// and of vectors mag, norm (unit vector), dot, cross. Arithmetic is IEEE double (x/0 is
/// inf, sqrt(−1) NaN).
/// \throw Error naming the column of the expression and the problem (unknown array — with the
/// arrays there are —, wrong kind of operand, an array of 2 or more than 3 components used
/// whole), or if `name` is empty or `type` not a float type.
[[nodiscard]] DataArray calculate(DatasetRef input, const std::string& name,
                                  std::string_view expression,
                                  const CalculatorOptions& options = {});

}  // namespace isoforge
