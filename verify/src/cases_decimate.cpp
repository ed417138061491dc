// Verification cases for decimation (isoforge::decimate, the quadric method with its defaults:
// topology and boundary preserved): five inputs (bunny.ply, the marching-cubes skin of headsq,
// a noisy sphere, the bunny cut open, two spheres glued along one edge) reduced to 50 %, 10 %
// and 2 % of their triangles. Every output is certified with the exact checks of mesh_checks
// (valid, manifold when the input was, no self-intersections, genus, components and border loops
// preserved); its distance to the input is compared with CGAL's edge collapse at the same face
// count (Garland-Heckbert plane policies and Lindstrom-Turk), measured the same way. Each
// output is then refined (isoforge::refine_mesh, the decimate command's --refine): the refined
// mesh is certified the same way and must be closer to the input than the plain output.

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "accuracy.hpp"
#include "case_support.hpp"
#include "cgal_decimate.hpp"
#include "decimate_inputs.hpp"
#include "isoforge/fit/refine.hpp"
#include "isoforge/reduce/decimate.hpp"
#include "reference_distance.hpp"

namespace isoforge::verify {

namespace {

// The quality the quadric method is expected to reach: within 10 % of the better CGAL policy in
// Hausdorff distance and in RMS. Recorded in the notes, not yet required.
constexpr double kQualityRatio = 1.10;

long total_genus(const MeshReport& m) {
  long g = 0;
  for (const auto& c : m.components) g += c.genus;
  return g;
}

std::size_t border_loops(const MeshReport& m) {
  std::size_t b = 0;
  for (const auto& c : m.components) b += c.border_loops;
  return b;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The exact certification of a decimated mesh against its input (`prefix` names the refined one).
void certify(CaseResult& r, const std::string& prefix, const MeshReport& in, const MeshReport& out) {
  r.equal(prefix + "degenerate faces (exact)", out.degenerate_faces, std::size_t{0});
  r.equal(prefix + "duplicate points", out.duplicate_points, std::size_t{0});
  r.equal(prefix + "inconsistently oriented edges", out.inconsistent_edges, std::size_t{0});
  if (in.manifold) {
    r.equal(prefix + "non-manifold edges", out.non_manifold_edges, std::size_t{0});
    r.equal(prefix + "non-manifold vertices", out.non_manifold_vertices, std::size_t{0});
  } else {
    r.at_most(prefix + "non-manifold edges (at most the input's)",
              static_cast<double>(out.non_manifold_edges),
              static_cast<double>(in.non_manifold_edges));
    r.at_most(prefix + "non-manifold vertices (at most the input's)",
              static_cast<double>(out.non_manifold_vertices),
              static_cast<double>(in.non_manifold_vertices));
  }
  r.is_true(prefix + "self-intersection test ran", out.self_intersection_checked);
  r.equal(prefix + "self-intersecting face pairs (exact)", out.self_intersections, std::size_t{0});
  if (in.outward) r.is_true(prefix + "closed and outward oriented, every component (exact)", out.outward);
  r.equal(prefix + "components (as the input)", out.components.size(), in.components.size());
  r.equal(prefix + "genus, summed over components (as the input)", total_genus(out), total_genus(in));
  r.equal(prefix + "border loops (as the input)", border_loops(out), border_loops(in));

}

void decimate_case(CaseResult& r, const std::string& kind, double keep) {
  const PolyData input = decimation_input(kind);
  const MeshReport in = check_mesh(input);
  const auto target = static_cast<std::size_t>(std::llround(keep * static_cast<double>(in.faces)));
  // The metric of `isoforge-verify distance` (the benchmark's), the input measured once.
  const ReferenceDistance error(input, 0);
  r.note("input", fmt::format("{}: {} triangles, {} components, genus {}, {} border loops, "
                              "manifold {}, {} self-intersecting pairs",
                              kind, in.faces, in.components.size(), total_genus(in),
                              border_loops(in), in.manifold ? "yes" : "no", in.self_intersections));
  r.note("target triangles", fmt::format("{} ({:g} %)", target, 100 * keep));

  DecimateOptions o;
  o.target_triangles = target;
  auto t0 = std::chrono::steady_clock::now();
  const auto [output, stats] = decimate(input, o);
  const double seconds = seconds_since(t0);
  const MeshReport out = check_mesh(output);
  r.note("isoforge", fmt::format("{} triangles in {:.3f} s, stop: {}; {} operations, refused: "
                                 "{} topology, {} flip, {} intersection; {} locked vertices",
                                 out.faces, seconds, to_string(stats.stop), stats.operations,
                                 stats.refused_topology, stats.refused_flip,
                                 stats.refused_intersection, stats.locked_vertices));

  // Certification of the output (exact).
  certify(r, "", in, out);
  r.at_least("output triangles", static_cast<double>(out.faces), 1);
  r.equal("stats.output_triangles = triangles of the output", stats.output_triangles,
          output.polys.size());
  // Quality against CGAL at the same face count, one metric for all.
  const ReferenceError ours = error.measure(output);
  r.note("isoforge error", fmt::format("Hausdorff {:.4e}, RMS {:.4e} (relative to the diagonal)",
                                       ours.relative_hausdorff, ours.relative_rms));
  double best_hausdorff = INFINITY, best_rms = INFINITY;
  for (const CgalPolicy policy : {CgalPolicy::GarlandHeckbert, CgalPolicy::LindstromTurk}) {
    const CgalDecimateResult c = cgal_decimate(input, target, policy);
    const ReferenceError e = error.measure(c.mesh);
    const MeshReport m = check_mesh(c.mesh);
    best_hausdorff = std::min(best_hausdorff, e.relative_hausdorff);
    best_rms = std::min(best_rms, e.relative_rms);
    r.note(to_string(policy),
           fmt::format("{} triangles in {:.3f} s: Hausdorff {:.4e}, RMS {:.4e}; {} "
                       "self-intersecting pairs, manifold {}, genus {}, {} border loops{}",
                       m.faces, c.collapse_seconds, e.relative_hausdorff, e.relative_rms,
                       m.self_intersections, m.manifold ? "yes" : "no", total_genus(m),
                       border_loops(m),
                       c.split_non_manifold ? " (input split at its non-manifold edge)" : ""));
  }
  const double rh = ours.relative_hausdorff / best_hausdorff;
  const double rr = ours.relative_rms / best_rms;
  r.note(
      "isoforge / best CGAL",
      fmt::format("Hausdorff {:.3f}, RMS {:.3f} (expected <= {:.2f}, not yet required): {}", rh, rr,
                  kQualityRatio, rh <= kQualityRatio && rr <= kQualityRatio ? "met" : "NOT met"));

  // The refinement: certified like the output, and closer to the input than it.
  t0 = std::chrono::steady_clock::now();
  const auto [refined, rstats] = refine_mesh(input, output);
  const double refine_seconds = seconds_since(t0);
  const MeshReport ref = check_mesh(refined);
  certify(r, "refined: ", in, ref);
  r.equal("refined: triangles (as the output)", ref.faces, out.faces);
  const ReferenceError refined_error = error.measure(refined);
  r.note("refined",
         fmt::format("in {:.3f} s ({} solves, {} vertices moved, {} moves shortened "
                     "or undone, {} triangles changed by edge flips): Hausdorff "
                     "{:.4e}, RMS {:.4e}",
                     refine_seconds, rstats.solves, rstats.moved_vertices, rstats.rejected_moves,
                     rstats.flips, refined_error.relative_hausdorff, refined_error.relative_rms));
  r.at_most("refined: Hausdorff distance / the output's", refined_error.relative_hausdorff /
                                                               ours.relative_hausdorff, 1.0);
  r.at_most("refined: RMS distance / the output's", refined_error.relative_rms / ours.relative_rms,
            1.0);
  const double fh = refined_error.relative_hausdorff / best_hausdorff;
  const double fr = refined_error.relative_rms / best_rms;
  r.note("refined / best CGAL",
         fmt::format("Hausdorff {:.3f}, RMS {:.3f} (expected <= 1, not yet required): {}", fh, fr,
                     fh <= 1 && fr <= 1 ? "met" : "NOT met"));
}

}  // namespace

void add_decimate_cases(std::vector<Case>& cases) {
  const std::vector<std::pair<std::string, std::string>> inputs = {
      {"bunny", "bunny.ply (69 451 triangles, five holes)"},
      {"headsq",
       "the marching-cubes skin of headsq at 1150 (78 510 triangles, open at the volume "
       "boundary)"},
      {"noisy-sphere", "an icosphere (81 920 triangles) with +-0.5 % radial noise"},
      {"open-bunny", "bunny.ply cut in half across x (41 860 triangles, a long border)"},
      {"glued-spheres",
       "two icospheres (2 x 20 480 triangles) sharing one edge: one non-manifold "
       "edge"},
  };
  for (const auto& [kind, what] : inputs) {
    for (const int percent : {50, 10, 2}) {
      const double keep = percent / 100.0;
      cases.push_back(
          {fmt::format("decimate/{}/{}", kind, percent),
           fmt::format("{} decimated to {} %: exact certification, error vs CGAL", what, percent),
           percent == 10, [kind = kind, keep](CaseResult& r) { decimate_case(r, kind, keep); }});
    }
  }
}

}  // namespace isoforge::verify
