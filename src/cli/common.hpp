#pragma once
// Helpers shared by several subcommands: exit codes, usage errors, argument checks and
// conversion and small geometry/timing helpers.

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "isoforge/core/dataset.hpp"
#include "isoforge/implicit/function.hpp"
#include "isoforge/io/io.hpp"

namespace isoforge::cli {

/// Exit codes of the isoforge command (documented in README.md and `isoforge --help`).
inline constexpr int kExitOk = 0;        ///< success (also --help, --version)
inline constexpr int kExitError = 1;     ///< the work failed: bad input file, cannot write, ...
inline constexpr int kExitUsage = 2;     ///< the command line is wrong: unknown, missing,
                                         ///< malformed, out-of-range or contradictory options
inline constexpr int kExitInternal = 3;  ///< an internal error (a bug: please report it)

/// A mistake on the command line found after parsing (a contradictory or meaningless option, a
/// bad function expression): main reports it like CLI11's own errors, with kExitUsage.
using UsageError = CLI::ValidationError;

/// CLI11 check: a decimal integer in [min, max], e.g. "--steps: must be an integer >= 1, got
/// '-5'". Leading zeros and '+' are dropped before CLI11 converts the value (which would read
/// "010" as octal and wrap "-5" into a huge unsigned number).
[[nodiscard]] CLI::Validator integer_in(std::int64_t min, std::int64_t max = INT64_MAX);

/// The format of a file named on the command line (by its extension). \throw UsageError naming
/// the path when the extension is not known.
[[nodiscard]] FileFormat format_of(const std::string& path);

/// The function expression given to `option` (see docs/implicit.md). \throw UsageError naming
/// the option, the column and the problem.
[[nodiscard]] ImplicitFunction parse_function(const std::string& expression, const char* option);

/// "--bounds xmin xmax ymin ymax zmin zmax" → Bounds. \throw UsageError naming `option`.
Bounds parse_bounds(const std::vector<double>& values, const char* option);
/// "--dims N" or "--dims NX NY NZ" → Dims. \throw UsageError naming `option`.
Dims parse_dims(const std::vector<Index>& values, const char* option);

/// `b` grown by `pad` on every side.
Bounds grown(const Bounds& b, double pad);

/// Milliseconds since `t0`.
double elapsed_ms(std::chrono::steady_clock::time_point t0);

}  // namespace isoforge::cli
