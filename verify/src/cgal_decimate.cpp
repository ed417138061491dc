// Edge-collapse simplification with CGAL 5.5 (see cgal_decimate.hpp).
//
// Garland, Heckbert: Surface simplification using quadric error metrics, SIGGRAPH 1997
// (GarlandHeckbert_plane_policies). Lindstrom, Turk: Fast and memory efficient polygonal
// simplification, IEEE Visualization 1998 (LindstromTurk_cost / LindstromTurk_placement).
// Both run through CGAL::Surface_mesh_simplification::edge_collapse on a CGAL::Surface_mesh with
// the Epick kernel; the Garland-Heckbert policies need Eigen (CGAL::Eigen3_support).

#include "cgal_decimate.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_plane_policies.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/LindstromTurk_cost.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/LindstromTurk_placement.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include <array>
#include <chrono>
#include <vector>

#include "isoforge/core/mesh_topology.hpp"

namespace isoforge::verify {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;
namespace SMS = CGAL::Surface_mesh_simplification;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Stop once the mesh has at most `target` faces (Surface_mesh counts its live faces in O(1)).
class FaceCountStop {
 public:
  FaceCountStop(const Mesh& mesh, std::size_t target) : mesh_(&mesh), target_(target) {}
  template <class Cost, class Profile>
  bool operator()(const Cost&, const Profile&, std::size_t, std::size_t) const {
    return mesh_->number_of_faces() <= target_;
  }

 private:
  const Mesh* mesh_;
  std::size_t target_;
};

}  // namespace

const char* to_string(CgalPolicy policy) {
  return policy == CgalPolicy::GarlandHeckbert ? "cgal-gh" : "cgal-lt";
}

CgalDecimateResult cgal_decimate(const PolyData& input, std::size_t target_faces,
                                 CgalPolicy policy) {
  CgalDecimateResult result;
  auto t0 = Clock::now();
  input.polys.validate(input.points.size(), "polys");
  input.strips.validate(input.points.size(), "strips");
  const auto tris = triangulate_faces(input);
  if (tris.empty()) throw Error("cgal_decimate: the input has no triangle");
  std::vector<Point> points(input.points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3 p = input.points[i];
    points[i] = Point(p.x, p.y, p.z);
  }
  std::vector<std::array<std::size_t, 3>> faces(tris.size());
  for (std::size_t f = 0; f < tris.size(); ++f) {
    for (int k = 0; k < 3; ++k) faces[f][k] = static_cast<std::size_t>(tris[f][k]);
  }
  Mesh mesh;
  if (!PMP::is_polygon_soup_a_polygon_mesh(faces)) {
    result.split_non_manifold = true;
    PMP::orient_polygon_soup(points, faces);
  }
  PMP::polygon_soup_to_polygon_mesh(points, faces, mesh);
  points.clear();
  faces.clear();
  result.convert_seconds = seconds_since(t0);

  t0 = Clock::now();
  const FaceCountStop stop(mesh, target_faces);
  int removed = 0;
  if (policy == CgalPolicy::GarlandHeckbert) {
    const SMS::GarlandHeckbert_plane_policies<Mesh, Kernel> gh(mesh);
    removed = SMS::edge_collapse(
        mesh, stop, CGAL::parameters::get_cost(gh.get_cost()).get_placement(gh.get_placement()));
  } else {
    removed = SMS::edge_collapse(mesh, stop,
                                 CGAL::parameters::get_cost(SMS::LindstromTurk_cost<Mesh>())
                                     .get_placement(SMS::LindstromTurk_placement<Mesh>()));
  }
  result.removed_edges = static_cast<std::size_t>(removed);
  result.collapse_seconds = seconds_since(t0);

  t0 = Clock::now();
  mesh.collect_garbage();
  PolyData& out = result.mesh;
  out.points.reserve(mesh.number_of_vertices());
  for (const auto v : mesh.vertices()) {
    const Point& p = mesh.point(v);
    out.points.push_back({p.x(), p.y(), p.z()});
  }
  out.polys.reserve(mesh.number_of_faces(), 3 * mesh.number_of_faces());
  for (const auto f : mesh.faces()) {
    std::array<Index, 3> ids{};
    int k = 0;
    for (const auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      if (k < 3) ids[static_cast<std::size_t>(k)] = static_cast<Index>(v.idx());
      ++k;
    }
    check_invariant(k == 3, "cgal_decimate: edge_collapse left a face that is not a triangle");
    out.polys.add(ids);
  }
  result.convert_seconds += seconds_since(t0);
  return result;
}

}  // namespace isoforge::verify
