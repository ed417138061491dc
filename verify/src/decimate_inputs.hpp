#pragma once
// Inputs of the decimation cases and of the decimation benchmark, built in code so that both use
// the same meshes: a noisy sphere, a mesh cut open by a plane, two spheres glued along one edge
// (one non-manifold edge), and the marching-cubes skin of headsq.

#include <string>
#include <vector>

#include "isoforge/core/dataset.hpp"

namespace isoforge::verify {

/// An icosahedron subdivided `subdivisions` times (each triangle into four, midpoints pushed to
/// the sphere): 20 * 4^subdivisions triangles, outward, closed, genus 0.
[[nodiscard]] PolyData icosphere(int subdivisions, double radius = 1, const Vec3& center = {});

/// `icosphere` with every vertex moved radially by a uniform random amount in
/// [-amplitude, amplitude] * radius (std::mt19937 seeded with `seed`). A radial graph over the
/// sphere stays embedded: no self-intersections, for any amplitude below 1.
[[nodiscard]] PolyData noisy_sphere(int subdivisions, double amplitude, unsigned seed,
                                    double radius = 1);

/// The triangles of `mesh` whose centroid lies strictly on the negative side of the plane through
/// `origin` with `normal`, their points compacted (point data dropped): an open surface.
[[nodiscard]] PolyData cut_by_plane(const PolyData& mesh, const Vec3& origin, const Vec3& normal);

/// An icosphere and its mirror image through the plane that holds one of its edges and is normal
/// to the direction of that edge's midpoint: two closed spheres sharing exactly that edge (four
/// triangles on it: one non-manifold edge, and nothing else touches). Both outward.
[[nodiscard]] PolyData spheres_glued_on_edge(int subdivisions);

/// The marching-cubes surface of data/headsq/quarter.nhdr at `isovalue`, flipped (outward for
/// CT data): at 1150, the skin, 78 510 triangles with borders on the volume boundary.
[[nodiscard]] PolyData headsq_surface(const std::string& data_dir, double isovalue = 1150);

/// The inputs of the decimation cases and benchmark by name: "bunny" (data/bunny.ply, 69 451
/// triangles, five holes), "headsq" (`headsq_surface` at 1150), "noisy-sphere" (`noisy_sphere`
/// with 6 subdivisions, amplitude 0.005, seed 1: 81 920 triangles), "open-bunny" (bunny.ply cut
/// across x at the middle of its box, the half with the head: 41 860 triangles),
/// "glued-spheres" (`spheres_glued_on_edge(5)`: 40 960 triangles). \throw Error for another name.
[[nodiscard]] PolyData decimation_input(const std::string& kind);

/// The names `decimation_input` accepts.
[[nodiscard]] const std::vector<std::string>& decimation_input_kinds();

}  // namespace isoforge::verify
