#pragma once
/// \file
/// Draco `.drc` (read and write): compressed triangle meshes and point clouds.
///
/// Written: positions, triangles (polygons are fan-triangulated, strips split), and every point
/// array: the active normals become Draco's NORMAL, a UInt8 array of 3 or 4 components (the
/// active scalars or one named "Colors") COLOR, 2-component float texture coordinates TEX_COORD,
/// every other array a GENERIC attribute. Each array's name, element type and role are kept in
/// Draco metadata, so `read_draco` restores them. Float arrays are quantized; integer arrays are
/// stored exactly. Verts-only polydata is a point cloud; lines have no Draco equivalent and are
/// refused; cell data is not stored (Draco has none). Method and measurements:
/// docs/algorithms/draco.md.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/core/result.hpp"

namespace isoforge {

/// Connectivity coding: Edgebreaker (smaller; reorders points and faces) or sequential (keeps
/// the order of points and faces).
enum class DracoMethod : std::uint8_t { Edgebreaker, Sequential };

/// Quantization bits per kind of float attribute, each in [1, 30] (draco_encoder's defaults).
struct DracoBits {
  int position = 11;
  int normal = 8;     ///< octahedral coding of unit vectors
  int color = 8;      ///< float colours (UInt8 colours are stored exactly)
  int texcoord = 10;
  int generic = 8;    ///< every other float array
};

/// A maximum error for one point array, in the array's units: the largest Euclidean norm of the
/// difference between an original tuple and its decoded tuple (for one component: |a - a'|).
struct DracoArrayBudget {
  std::string name;
  double max_error = 0;  ///< > 0
};

struct DracoWriteOptions {
  DracoBits bits{};  ///< quantization when no budget applies
  int level = 7;     ///< compression level, 0 (fastest) to 10 (smallest): Draco speed 10 - level
  DracoMethod method = DracoMethod::Edgebreaker;
  /// Error budget for positions (at most one of the two > 0; 0 = use `bits.position`): the
  /// largest distance between an original point and its decoded point, in position units ...
  double max_position_error = 0;
  /// ... or as a fraction of the bounding-box diagonal.
  double max_position_error_relative = 0;
  /// Error budgets for named point arrays (float arrays only; others use `bits`).
  std::vector<DracoArrayBudget> max_array_errors;
  /// With a budget, quantization is refined until no face is lost to quantization (Draco drops
  /// faces whose corners quantize to one point), up to 30 bits; false accepts the loss.
  bool keep_faces = true;
  ProgressCallback progress{};  ///< fraction done (encode, then the verifying decode)
};

/// The measured outcome of one attribute (positions first, then the point arrays).
struct DracoAttributeStats {
  std::string name;       ///< "Points" for the positions, else the array name
  int bits = 0;           ///< quantization bits; 0 = stored exactly
  double step = 0;        ///< quantization step in data units (0 when exact or octahedral)
  double budget = 0;      ///< the maximum error asked for; 0 = none
  double max_error = 0;   ///< measured on the decoded file (Euclidean norm per tuple)
};

struct DracoStats {
  std::uint64_t bytes = 0;      ///< size of the encoded file
  std::uint64_t raw_bytes = 0;  ///< float32 positions + int32 triangle ids + arrays at 4 bytes/value
  double ratio = 0;             ///< raw_bytes / bytes
  std::size_t points = 0;            ///< points written
  std::size_t triangles = 0;         ///< triangles written (after triangulation)
  std::size_t decoded_points = 0;    ///< points a decoder sees (Edgebreaker may split/merge)
  std::size_t decoded_triangles = 0;
  /// Triangles lost in the file: degenerate after quantization (or already in the input).
  std::size_t lost_triangles = 0;
  /// Of those, triangles that were degenerate in the input (repeated ids or equal positions):
  /// no quantization can keep them.
  std::size_t degenerate_input_triangles = 0;
  std::size_t unreferenced_points = 0;  ///< points in no triangle, dropped by Edgebreaker
  double max_position_error = 0;        ///< measured, position units
  std::vector<DracoAttributeStats> attributes;  ///< positions first
  int encodes = 0;          ///< encodings tried (more than one when a budget needed refining)
  std::vector<std::string> dropped;  ///< what Draco cannot hold and was left out (cell data, ...)
  std::string note;         ///< why a budget's wish could not be met, "" otherwise
};

using DracoEncodeResult = Result<std::vector<std::uint8_t>, DracoStats>;

/// Encodes `mesh` with `options` (the bytes of a `.drc` file), decodes them and measures them.
/// \throw Error naming `name` if the mesh has lines, a bad option, or an array Draco cannot hold.
[[nodiscard]] DracoEncodeResult encode_draco(const PolyData& mesh,
                                             const DracoWriteOptions& options = {},
                                             std::string_view name = "draco");

/// Writes `mesh` to `path` atomically and returns what the verifying decode measured.
/// \throw Error naming the path as `encode_draco`, or on I/O failure.
DracoStats write_draco(const PolyData& mesh, const std::filesystem::path& path,
                       const DracoWriteOptions& options = {});

/// Reads a `.drc` file (mesh or point cloud). \throw Error naming the file for a corrupt,
/// truncated or unsupported file; `Cancelled` if `progress` returns false.
[[nodiscard]] PolyData read_draco(const std::filesystem::path& path,
                                  const ProgressCallback& progress = {});
/// The same from bytes in memory; `name` is used in error messages.
[[nodiscard]] PolyData read_draco(std::span<const std::byte> data, std::string_view name);

}  // namespace isoforge
