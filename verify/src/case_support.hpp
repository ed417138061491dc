#pragma once
// Shared pieces of the verification cases: grids with cubic voxels over a box, and the standard
// groups of checks recorded from a MeshReport (closed surface; manifold surface with borders).

#include <string>

#include "accuracy.hpp"
#include "catalogue.hpp"
#include "isoforge/implicit/sample.hpp"
#include "mesh_checks.hpp"

namespace isoforge::verify {

/// A grid over `box` with cubic voxels and `n` samples along the box's longest axis; the other
/// axes get as many samples as fit, and the grid is centred on the box.
[[nodiscard]] GridSpec cubic_grid(const Bounds& box, Index n);

/// Records closed, manifold (edges and vertices), oriented, outward (exact), degenerate faces
/// (exact), duplicate points and self-intersections (exact) as checks.
void record_closed_surface(CaseResult& r, const MeshReport& m);

/// For surfaces that may leave their domain: manifold, oriented, degenerate faces, duplicate
/// points, self-intersections, and borders only on the domain's boundary.
void record_bordered_surface(CaseResult& r, const MeshReport& m, const BorderReport& b);

/// Notes the size and components of a mesh (vertices, triangles, components, genera).
void note_mesh(CaseResult& r, const MeshReport& m, const std::string& prefix = "");

}  // namespace isoforge::verify
