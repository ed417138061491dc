#pragma once
// Helpers shared by several subcommands: argument conversion and small geometry/timing helpers.

#include <chrono>
#include <vector>

#include "isoforge/core/dataset.hpp"

namespace isoforge::cli {

/// "--bounds xmin xmax ymin ymax zmin zmax" → Bounds. \throw Error naming `option`.
Bounds parse_bounds(const std::vector<double>& values, const char* option);
/// "--dims N" or "--dims NX NY NZ" → Dims. \throw Error naming `option`.
Dims parse_dims(const std::vector<Index>& values, const char* option);

/// `b` grown by `pad` on every side.
Bounds grown(const Bounds& b, double pad);

/// Milliseconds since `t0`.
double elapsed_ms(std::chrono::steady_clock::time_point t0);

}  // namespace isoforge::cli
