#pragma once
// Private (io/ only): the Draco codec behind `.drc` (io/draco.cpp), shared with the glTF writer
// (io/gltf.cpp, KHR_draco_mesh_compression). Implemented in io/draco.cpp, the one file that
// includes Draco's headers: nothing here exposes a Draco type.
//
// What encode_draco_mesh guarantees:
//  - `bytes` is a complete Draco bitstream (exactly the bytes of a .drc file; a glTF buffer
//    view of a KHR_draco_mesh_compression primitive holds the same bytes).
//  - `attributes` lists every attribute in the bitstream with its Draco *unique id* — the number
//    KHR_draco_mesh_compression's "attributes" object maps a glTF semantic to — and its kind:
//    positions first (name "Points", kind Position), then one entry per encoded point array,
//    named as the array.
//  - `decoded` is what any conforming decoder gets from `bytes` (it was decoded with Draco's
//    decoder): its point count, triangle count (polys, all triangles) and values are the ones a
//    glTF accessor of the primitive must declare (count, min/max of positions). Edgebreaker may
//    reorder, split or drop points (unreferenced ones) and drops faces made degenerate by
//    quantization; DracoStats reports how many.
//  - `stats` holds the measured errors of that decoded mesh against the input; with a budget in
//    the options they never exceed it (else encode_draco_mesh throws), except for the triangles
//    counted in stats.lost_triangles when options.keep_faces could not keep them (stats.note
//    says why).
//  - Lines are refused (Error); verts-only polydata is encoded as a Draco point cloud.
// Thread-safe: no shared state.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "isoforge/core/dataset.hpp"
#include "isoforge/io/draco.hpp"

namespace isoforge::io_detail {

/// Draco's semantic of an attribute (glTF: POSITION, NORMAL, COLOR_n, TEXCOORD_n, custom _NAME).
enum class DracoKind : std::uint8_t { Position, Normal, Color, TexCoord, Generic };

/// Which point arrays take Draco's semantic roles. "" = automatic (as in io/draco.hpp: the
/// active normals; a UInt8 3/4-component array that is the active scalars or named "Colors";
/// the active 2-component float tcoords). A named array must exist and fit the role.
struct DracoRoles {
  std::string normals;
  std::string colors;
  std::string tcoords;
  /// Arrays to leave out of the bitstream (e.g. ones glTF cannot type).
  std::vector<std::string> skip;
};

struct DracoAttributeId {
  std::string name;  ///< "Points" for positions, else the point array's name
  int unique_id = -1;
  DracoKind kind = DracoKind::Generic;
};

struct DracoEncodedMesh {
  std::vector<std::uint8_t> bytes;
  std::vector<DracoAttributeId> attributes;
  PolyData decoded;
  DracoStats stats;
};

/// Encodes, decodes and measures `mesh` (see the guarantees above). `name` names the mesh in
/// errors. \throw Error for lines, bad options, arrays Draco cannot hold, a failed budget.
[[nodiscard]] DracoEncodedMesh encode_draco_mesh(const PolyData& mesh,
                                                 const DracoWriteOptions& options,
                                                 const DracoRoles& roles = {},
                                                 std::string_view name = "draco");

struct DracoDecodedMesh {
  PolyData mesh;  ///< points, triangles (polys) or verts for a point cloud, point arrays
  std::vector<DracoAttributeId> attributes;
};

/// Decodes a Draco bitstream; names and types come from the metadata isoforge writes, and
/// attributes without it get names from their kind ("Normals", "Colors", "TCoords",
/// "generic_<id>"). \throw Error naming `name` for corrupt or truncated data.
[[nodiscard]] DracoDecodedMesh decode_draco_mesh(std::span<const std::byte> data,
                                                 std::string_view name);

}  // namespace isoforge::io_detail
