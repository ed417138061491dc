#pragma once
/// \file
/// PLOT3D whole-format reader (single grid, 3D, binary, big or little endian, no Fortran record
/// markers; with or without IBLANK), with the Q (solution) file.
///
/// Point arrays produced from a Q file: "Density" (ρ), "Momentum" (ρu, ρv, ρw; 3 components),
/// "StagnationEnergy" (e), and the derived "Velocity" (momentum / density) and "Pressure"
/// (p = (γ − 1)(e − ½ρ|v|²), γ = 1.4). Field data holds "FreeStreamMach", "AngleOfAttack",
/// "ReynoldsNumber", "Time". With IBLANK the point array "IBlank" (int32, 0 = blanked) and
/// the cell array "Valid" (uint8, 1 when all points of the cell are unblanked) are added.

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"

namespace isoforge {

enum class Plot3dByteOrder { Auto, Big, Little };

struct Plot3dOptions {
  Plot3dByteOrder byte_order = Plot3dByteOrder::Auto;  ///< Auto: the order that makes the header sane
  double gamma = 1.4;  ///< ratio of specific heats, for the derived pressure
  /// Told the fraction of the files loaded and parsed (about every megabyte); false cancels.
  ProgressCallback progress{};
};

/// Reads a PLOT3D grid and, if `q_path` is not empty, its solution.
/// \throw Error naming the file and byte offset on malformed or mismatched files.
[[nodiscard]] StructuredGrid read_plot3d(const std::filesystem::path& xyz_path,
                                         const std::filesystem::path& q_path = {},
                                         const Plot3dOptions& options = {});
/// In-memory variant (q may be empty).
[[nodiscard]] StructuredGrid read_plot3d(std::span<const std::byte> xyz, std::string_view xyz_name,
                                         std::span<const std::byte> q, std::string_view q_name,
                                         const Plot3dOptions& options = {});

}  // namespace isoforge
