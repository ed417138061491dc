#pragma once
// Helpers shared by the subcommands that handle OpenVDB grids (apart from common.hpp, which every
// subcommand includes, because OpenVDB's headers are heavy to compile).

#include <openvdb/openvdb.h>

#include <string>

namespace isoforge::cli {

/// What a grid holds, for a warning: "'distance' ranges 0.01 .. 0.3 over 1234 active voxels
/// (background 0.3)", or "'F' has no active voxels (background 3)".
[[nodiscard]] std::string range_text(const openvdb::FloatGrid& grid);

}  // namespace isoforge::cli
