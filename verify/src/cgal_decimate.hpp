#pragma once
// CGAL's edge-collapse simplification (Surface_mesh_simplification::edge_collapse) as a peer of
// isoforge::decimate: the third and last translation unit of verify/ that includes CGAL (see
// cgal_decimate.cpp). Used by the decimation cases and by `isoforge-verify decimate`, the CGAL
// peer of the decimation benchmark (verify/bench/decimate.sh).

#include <cstddef>

#include "isoforge/core/dataset.hpp"

namespace isoforge::verify {

/// The cost and placement policies of CGAL's edge collapse.
enum class CgalPolicy {
  GarlandHeckbert,  ///< GarlandHeckbert_plane_policies: classic plane quadrics, optimal placement
  LindstromTurk,    ///< LindstromTurk_cost + LindstromTurk_placement (CGAL's default)
};

[[nodiscard]] const char* to_string(CgalPolicy policy);

struct CgalDecimateResult {
  PolyData mesh;                  ///< triangles, float32 points, the survivors compacted
  std::size_t removed_edges = 0;  ///< edge_collapse's return value (3 per interior collapse)
  double collapse_seconds = 0;    ///< edge_collapse alone (the policies' set-up included)
  double convert_seconds = 0;     ///< PolyData -> Surface_mesh -> PolyData
  bool split_non_manifold =
      false;  ///< the input needed points duplicated to become a halfedge mesh
};

/// Collapses edges of the triangles of `input` (polygons fan-triangulated, strips split) until
/// at most `target_faces` faces remain, with CGAL's default filters (none) and constraints (none;
/// the policies weigh borders themselves). CGAL 5.5 has no face-count stop predicate (5.6 adds
/// Face_count_stop_predicate); the one used here stops at the first collapse proposed while the
/// mesh has at most `target_faces` faces, so the result has `target_faces` or one fewer, unless
/// no collapsible edge remains. Non-manifold input is made a halfedge mesh first by CGAL's
/// orient_polygon_soup, which duplicates the points of non-manifold edges and vertices.
/// Single-threaded. \throw Error if the input has no triangle or ids are out of range.
[[nodiscard]] CgalDecimateResult cgal_decimate(const PolyData& input, std::size_t target_faces,
                                               CgalPolicy policy);

}  // namespace isoforge::verify
