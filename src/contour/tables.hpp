#pragma once
// Private: marching-cells case tables, generated at start-up from each cell's faces, shared by the
// dense (image), sparse (OpenVDB) and unstructured contouring so they agree exactly.
//
// Construction (per case = set of corners at or above the isovalue, per variant = how each
// ambiguous quad face is resolved): on every face the edge crossings are joined into segments
// directed from an "exit" crossing to an "entry" crossing (with the face traversed
// counter-clockwise as seen from outside the cell), which keeps the corners at or above the
// isovalue on the left. Every crossing is an exit on one of its two faces and an entry on the
// other, so the segments chain into closed loops on the cell's boundary. Each loop is
// triangulated without any diagonal that joins two crossings of one face (such a diagonal lies
// in the face, where the neighbouring cell could make the same one: four triangles on an edge);
// the few loops of ambiguous cases that admit no such triangulation are fanned around an extra
// point inside the cell, the mean of the loop's crossings (as Marching Cubes 33 does for its
// interior cases). Adjacent cells resolve a shared face identically (the decision depends
// only on the face's four values), so the surface has no cracks, and every triangle's normal
// (right-hand rule) points toward increasing scalar values.
//
// Ambiguous quad faces use the asymptotic decider (Nielson & Hamann, "The asymptotic decider:
// resolving the ambiguity in marching cubes", Visualization '91): the corners at or above the
// isovalue are connected across the face when the bilinear saddle value is at or above it, i.e.
// when (a0 − c)(a1 − c) ≥ (b0 − c)(b1 − c) for the above diagonal a and below diagonal b.

#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "isoforge/core/vec.hpp"

namespace isoforge::contour_detail {

/// A cell's corners, edges and faces (faces as corner cycles; orientation is fixed up by the
/// builder so they run counter-clockwise seen from outside).
struct CellTopology {
  int corners = 0;
  std::vector<std::array<int, 2>> edges;
  std::vector<std::vector<int>> faces;
  std::vector<std::array<double, 3>> positions;  ///< reference positions, for orientation
};

/// Case table of one cell type.
class CaseTable {
 public:
  explicit CaseTable(const CellTopology& topology);

  struct Case {
    std::uint8_t ambiguous = 0;           ///< number of ambiguous quad faces
    std::array<std::uint8_t, 6> faces{};  ///< their face indices
    std::uint32_t first_variant = 0;      ///< index into variants_
  };
  struct Variant {
    std::uint32_t first = 0;  ///< index of the first edge in tri_edges_
    std::uint8_t triangles = 0;
    std::uint8_t centers = 0;        ///< points inside the cell this variant needs
    std::uint32_t first_center = 0;  ///< index into the center loops
  };
  /// A point inside the cell: the mean of the crossings on `count` edges.
  struct CenterLoop {
    std::uint32_t first = 0;  ///< index into center_edges_
    std::uint8_t count = 0;
  };

  [[nodiscard]] const Case& at(unsigned index) const { return cases_[index]; }
  [[nodiscard]] const Variant& variant(const Case& c, unsigned bits) const {
    return variants_[c.first_variant + bits];
  }
  /// Edge indices of a variant's triangles, 3 per triangle. An index e >= edges() refers to the
  /// variant's center point e - edges().
  [[nodiscard]] std::span<const std::uint8_t> triangles(const Variant& v) const {
    return {tri_edges_.data() + v.first, 3u * v.triangles};
  }
  [[nodiscard]] std::size_t edges() const { return topo_.edges.size(); }
  /// Edges whose crossings average to center point `c` of variant `v`.
  [[nodiscard]] std::span<const std::uint8_t> center_edges(const Variant& v, unsigned c) const {
    const CenterLoop& l = center_loops_[v.first_center + c];
    return {center_edges_.data() + l.first, l.count};
  }
  [[nodiscard]] const CellTopology& topology() const { return topo_; }
  /// Corner ids of face f's two diagonals: {p0, p2} and {p1, p3} (quad faces only).
  [[nodiscard]] std::array<int, 4> quad_face(int f) const {
    const auto& q = topo_.faces[static_cast<std::size_t>(f)];
    return {q[0], q[1], q[2], q[3]};
  }

 private:
  CellTopology topo_;
  std::vector<Case> cases_;
  std::vector<Variant> variants_;
  std::vector<std::uint8_t> tri_edges_;
  std::vector<CenterLoop> center_loops_;
  std::vector<std::uint8_t> center_edges_;
};

/// Voxel in VTK voxel order: corner c at (c & 1, (c >> 1) & 1, (c >> 2) & 1). Edges 0-3 are the
/// x-edges (0,1) (2,3) (4,5) (6,7); 4-7 the y-edges (0,2) (1,3) (4,6) (5,7); 8-11 the z-edges
/// (0,4) (1,5) (2,6) (3,7). Hexahedra map onto it with kHexToVoxel.
const CaseTable& voxel_table();
const CaseTable& tetra_table();
const CaseTable& wedge_table();
const CaseTable& pyramid_table();

/// Voxel corner c is hexahedron corner kHexToVoxel[c] (VTK orders: voxel is x fastest, the
/// hexahedron goes around each quad).
inline constexpr std::array<int, 8> kHexToVoxel = {0, 1, 3, 2, 4, 5, 7, 6};

/// Whether a hexahedron given by its corners in voxel order is mirrored with respect to the voxel
/// table's reference cell: the sign of its Jacobian at the centre (trilinear map).
inline bool mirrored_voxel(const Vec3* c) {
  const Vec3 dx = (c[1] - c[0]) + (c[3] - c[2]) + (c[5] - c[4]) + (c[7] - c[6]);
  const Vec3 dy = (c[2] - c[0]) + (c[3] - c[1]) + (c[6] - c[4]) + (c[7] - c[5]);
  const Vec3 dz = (c[4] - c[0]) + (c[5] - c[1]) + (c[6] - c[2]) + (c[7] - c[3]);
  return dot(dx, cross(dy, dz)) < 0;
}

/// The asymptotic decider on a quad face with values v0..v3 in cyclic order, relative to the
/// isovalue c: true when the corners at or above c are connected across the face.
/// Deterministic: both cells sharing the face compute it from the same four numbers.
inline bool above_connected(double v0, double v1, double v2, double v3, double c) {
  const bool a0 = v0 >= c;
  const double d02 = (v0 - c) * (v2 - c), d13 = (v1 - c) * (v3 - c);
  return a0 ? d02 >= d13 : d13 >= d02;
}

/// Where a crossing lies on an edge from value a to value b (a and b on opposite sides of c):
/// t = (c − a) / (b − a), kept within [kMinT, 1 − kMinT] so that crossings never coincide with
/// grid points (values equal to the isovalue count as above it) and no two vertices or
/// triangles degenerate. A NaN end (NaN counts as below every isovalue) gives NaN: the value
/// is undefined there, and the output drops such points and the cells using them.
inline constexpr double kMinT = 1.0 / 1024.0;
inline double crossing(double a, double b, double c) {
  if (a != a || b != b) return std::numeric_limits<double>::quiet_NaN();
  double t = (c - a) / (b - a);
  if (!(t >= kMinT)) t = kMinT;
  if (t > 1.0 - kMinT) t = 1.0 - kMinT;
  return t;
}

}  // namespace isoforge::contour_detail
