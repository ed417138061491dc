#pragma once
/// \file
/// glTF 2.0 binary (`.glb`): one or several named meshes per file, for transfer and for the
/// browser viewer (`viewer/`). Method, layout and measurements: docs/algorithms/gltf.md.
///
/// Each `PolyData` becomes one glTF mesh (and one node of the scene) whose primitives share its
/// vertices: polygons and strips (triangulated) as TRIANGLES, lines and polylines (as segments)
/// as LINES, vertices as POINTS. Point attributes: the normals (NORMAL, unit length), one uint8
/// RGB/RGBA array (taken as sRGB) as COLOR_0 (linear, as glTF defines it; read back exactly),
/// every other array of 1–4 components as the float custom attribute `_NAME`. Cell arrays and arrays of more than 4 components are left out (counted in the
/// stats). Units and colour legends go to `extras`, and the original array names to each mesh's
/// `extras`, so `read_gltf` restores them.

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"
#include "isoforge/io/draco.hpp"

namespace isoforge {

/// How vertex and index data are stored.
enum class GltfCodec {
  None,     ///< plain accessors (any glTF reader)
  Meshopt,  ///< EXT_meshopt_compression (meshoptimizer's lossless vertex/index codecs; required)
  Draco,    ///< KHR_draco_mesh_compression on the triangles (lines and points stay plain)
};
/// "none", "meshopt", "draco".
[[nodiscard]] std::string_view gltf_codec_name(GltfCodec codec);
/// The codec named `name` ("none", "meshopt", "draco"). \throw Error naming it otherwise.
[[nodiscard]] GltfCodec gltf_codec_from_name(std::string_view name);
/// Whether this build can write `codec` (all three: Draco is a dependency).
[[nodiscard]] bool gltf_codec_available(GltfCodec codec);

/// The colour legend of a mesh coloured by a colour map, stored in the mesh's `extras.legend`
/// (the viewer draws it).
struct GltfLegend {
  std::string array;     ///< the array that was mapped, e.g. "Elevation"
  std::string colormap;  ///< the map's name, e.g. "viridis"
  double min = 0;        ///< value at the first colour (data units)
  double max = 1;        ///< value at the last colour (data units)
  bool log_scale = false;                          ///< colours spaced logarithmically in value
  std::vector<std::array<std::uint8_t, 4>> colors; ///< RGBA samples from min to max (>= 2)
};

/// One mesh of a file: a name (kept in the file) and its surface/lines/points.
struct GltfMesh {
  std::string name;
  const PolyData& mesh;
  std::optional<GltfLegend> legend{};
  /// The uint8 array of 3 or 4 components written as COLOR_0; empty = the active scalars when
  /// they are such an array, else none.
  std::string colors{};
};

struct GltfWriteOptions {
  GltfCodec codec = GltfCodec::Draco;  ///< see GltfCodec
  /// Draco: quantization bits or error budgets, level, method (io/draco.hpp); every mesh's
  /// triangles are encoded, decoded and measured against them.
  DracoWriteOptions draco{};
  std::string units;                  ///< length unit of the coordinates ("mm"); empty = unknown
  /// Write NORMAL: the active normals, or area-weighted normals of the triangles when there are
  /// none. Zero or non-finite normals become (0, 0, 1) (glTF needs unit length; counted).
  bool normals = true;
  bool arrays = true;  ///< write the other point arrays as `_NAME` float attributes
  /// Told the fraction done (once the layout is made, then as the binary chunk is written);
  /// false cancels (`Cancelled`, nothing written).
  ProgressCallback progress{};
};

struct GltfWriteStats {
  std::size_t meshes = 0;
  std::size_t vertices = 0;   ///< over all meshes
  std::size_t triangles = 0;  ///< after triangulating polygons and strips
  std::size_t segments = 0;   ///< line segments (a polyline of n points gives n-1)
  std::size_t points = 0;     ///< POINTS primitive vertices
  std::size_t bytes = 0;      ///< the file's size
  std::size_t raw_bytes = 0;  ///< what the vertex and index data take as plain glTF buffers
  std::size_t normals_replaced = 0;  ///< zero/non-finite normals written as (0, 0, 1)
  std::vector<std::string> arrays_skipped;  ///< "mesh: array (why)"
  std::vector<DracoStats> draco;  ///< Draco codec: per mesh with triangles, the measured errors
};

/// Writes `meshes` as one `.glb` atomically. Names need not be unique (glTF allows it).
/// \throw Error naming `path` and the mesh for non-finite coordinates, more than 2^32 - 1
/// vertices, a codec this build lacks or an invalid legend; `Cancelled` from `progress`.
GltfWriteStats write_gltf(std::span<const GltfMesh> meshes, const std::filesystem::path& path,
                          const GltfWriteOptions& options = {});
/// One mesh named after the file's stem.
GltfWriteStats write_gltf(const PolyData& mesh, const std::filesystem::path& path,
                          const GltfWriteOptions& options = {});

/// What `read_gltf` returns.
struct GltfContent {
  struct Mesh {
    std::string name;
    PolyData mesh;
    std::optional<GltfLegend> legend;
  };
  std::vector<Mesh> meshes;  ///< in the order of the file's `meshes`
  std::string units;         ///< from extras; empty if absent
};

/// Reads a `.glb` (plain, EXT_meshopt_compression or KHR_draco_mesh_compression): every mesh
/// with its TRIANGLES, LINES and POINTS primitives (strips and fans are triangulated), NORMAL,
/// COLOR_0, and the other attributes as float arrays (names, types and roles restored from
/// isoforge's extras, else named after the attribute). Node transforms are not applied.
/// \throw Error naming the file, the byte offset or JSON place, and the problem.
[[nodiscard]] GltfContent read_gltf(const std::filesystem::path& path);
/// The same from the bytes of a file; `name` is used in error messages.
[[nodiscard]] GltfContent read_gltf(std::span<const std::byte> data, std::string_view name);

}  // namespace isoforge
