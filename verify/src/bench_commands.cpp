// The decimation benchmark's subcommands (see bench_commands.hpp).
//
// Distance: the reference is sampled once (sample_mesh at `spacing`) and put in one AABB tree;
// each mesh is sampled at the same spacing and put in its own tree. max_ref_to_mesh and
// rms_ref_to_mesh measure the reference's samples against the mesh, max_mesh_to_ref and
// rms_mesh_to_ref the other way (each RMS area-weighted); hausdorff is the larger maximum,
// rms = sqrt((rms_ref_to_mesh^2 + rms_mesh_to_ref^2) / 2). Relative values divide by the
// reference's bounding-box diagonal. Sampled maxima are lower bounds of the true ones. Each side
// takes about `max_samples` samples at most (see budget_samples), so that a million-triangle
// reference is measured in seconds; the reference's samples are the same for every mesh.

#include "bench_commands.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "accuracy.hpp"
#include "cgal_decimate.hpp"
#include "decimate_inputs.hpp"
#include "isoforge/core/mesh_topology.hpp"
#include "isoforge/io/io.hpp"
#include "mesh_checks.hpp"
#include "mesh_distance.hpp"

namespace isoforge::verify {

namespace {

PolyData read_mesh(const std::string& path) {
  Dataset ds = read(path);
  auto* pd = std::get_if<PolyData>(&ds);
  if (!pd)
    throw Error(path + ": is " + std::string(dataset_type_name(ds)) + ", not a polygonal mesh");
  return std::move(*pd);
}

struct OneWay {
  double max = 0, rms = 0;
};

OneWay measure(const Samples& s, const MeshDistance& to) {
  const std::vector<double> d = to.distances(s.points);
  OneWay w;
  double sum = 0, wsum = 0;
  for (std::size_t i = 0; i < d.size(); ++i) {
    w.max = std::max(w.max, d[i]);
    sum += s.weights[i] * d[i] * d[i];
    wsum += s.weights[i];
  }
  w.rms = wsum > 0 ? std::sqrt(sum / wsum) : 0.0;
  return w;
}

// Samples of `mesh` for `measure`, at most about `budget` of them. When the barycentric grid of
// sample_mesh (at least 7 samples per triangle) fits, it is used at `spacing`, or at the smallest
// larger spacing that fits (every triangle keeps its corners, edge midpoints and centroid; only
// the grid inside gets coarser). Otherwise (a reference of more than budget / 7 triangles) the
// samples are the mesh's points (weight 0: they count toward the maximum only) and the triangle
// centroids weighted by the triangle areas. Returns the spacing used (0 for the second kind).
std::pair<Samples, double> budget_samples(const PolyData& mesh, double spacing,
                                          std::size_t budget) {
  const auto tris = triangulate_faces(mesh);
  const auto P = [&](Index id) { return mesh.points[static_cast<std::size_t>(id)]; };
  if (7 * tris.size() > budget) {
    Samples s;
    for (std::size_t i = 0; i < mesh.points.size(); ++i) {
      s.points.push_back(mesh.points[i]);
      s.weights.push_back(0);
    }
    for (const auto& t : tris) {
      s.points.push_back((P(t[0]) + P(t[1]) + P(t[2])) / 3.0);
      s.weights.push_back(0.5 * norm(cross(P(t[1]) - P(t[0]), P(t[2]) - P(t[0]))));
    }
    return {std::move(s), 0.0};
  }
  std::vector<double> longest(tris.size());
  for (std::size_t f = 0; f < tris.size(); ++f) {
    const auto& t = tris[f];
    longest[f] =
        std::max({norm(P(t[1]) - P(t[0])), norm(P(t[2]) - P(t[1])), norm(P(t[0]) - P(t[2]))});
  }
  const auto count = [&](double h) {  // sample_mesh's count at spacing h
    std::size_t c = 0;
    for (const double l : longest) {
      std::size_t n = std::max<std::size_t>(2, static_cast<std::size_t>(std::ceil(l / h)));
      n += n % 2;
      c += (n + 1) * (n + 2) / 2 + 1;
    }
    return c;
  };
  for (std::size_t c = count(spacing); c > budget; c = count(spacing)) {
    spacing *= 1.05 * std::sqrt(static_cast<double>(c) / static_cast<double>(budget));
  }
  return {sample_mesh(mesh, spacing), spacing};
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

}  // namespace

int run_distance(const DistanceCommand& command) {
  const PolyData ref = read_mesh(command.reference);
  const double diagonal = ref.bounds().diagonal();
  const double spacing = command.spacing > 0 ? command.spacing : 0.5 * mean_edge_length(ref);
  const auto [ref_samples, ref_spacing] = budget_samples(ref, spacing, command.max_samples);
  const MeshDistance ref_tree(ref);
  for (const auto& path : command.meshes) {
    const auto t0 = std::chrono::steady_clock::now();
    const PolyData mesh = read_mesh(path);
    const MeshDistance tree(mesh);
    const OneWay ab = measure(ref_samples, tree);
    const auto [mesh_samples, mesh_spacing] = budget_samples(mesh, spacing, command.max_samples);
    const OneWay ba = measure(mesh_samples, ref_tree);
    const double hausdorff = std::max(ab.max, ba.max);
    const double rms = std::sqrt(0.5 * (ab.rms * ab.rms + ba.rms * ba.rms));
    std::string line = fmt::format(
        "{{\"reference\": {}, \"mesh\": {}, \"spacing_reference\": {:.9g}, "
        "\"spacing_mesh\": {:.9g}, \"samples_reference\": {}, \"samples_mesh\": {}, "
        "\"diagonal\": {:.9g}, "
        "\"hausdorff\": {:.9g}, \"rms\": {:.9g}, \"max_ref_to_mesh\": {:.9g}, "
        "\"max_mesh_to_ref\": {:.9g}, \"rms_ref_to_mesh\": {:.9g}, \"rms_mesh_to_ref\": {:.9g}, "
        "\"relative_hausdorff\": {:.9g}, \"relative_rms\": {:.9g}",
        json_string(command.reference), json_string(path), ref_spacing, mesh_spacing,
        ref_samples.points.size(), mesh_samples.points.size(), diagonal, hausdorff, rms, ab.max,
        ba.max, ab.rms, ba.rms, hausdorff / diagonal, rms / diagonal);
    if (command.check) {
      const MeshReport m = check_mesh(mesh);
      long genus = 0;
      std::size_t loops = 0;
      for (const auto& c : m.components) {
        genus += c.genus;
        loops += c.border_loops;
      }
      line += fmt::format(
          ", \"triangles\": {}, \"vertices\": {}, \"self_intersections\": {}, \"manifold\": {}, "
          "\"closed\": {}, \"oriented\": {}, \"border_edges\": {}, \"border_loops\": {}, "
          "\"non_manifold_edges\": {}, \"non_manifold_vertices\": {}, \"degenerate_faces\": {}, "
          "\"duplicate_points\": {}, \"components\": {}, \"genus\": {}",
          m.faces, m.vertices, m.self_intersections, m.manifold, m.closed, m.oriented,
          m.border_edges, loops, m.non_manifold_edges, m.non_manifold_vertices, m.degenerate_faces,
          m.duplicate_points, m.components.size(), genus);
    }
    line +=
        fmt::format(", \"seconds\": {:.3f}}}",
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    fmt::print("{}\n", line);
    std::fflush(stdout);
  }
  return 0;
}

int run_cgal_decimate(const DecimateCommand& command) {
  const auto start = std::chrono::steady_clock::now();
  if (command.policy != "gh" && command.policy != "lt")
    throw Error("decimate: --policy must be gh or lt, not '" + command.policy + "'");
  const CgalPolicy policy =
      command.policy == "gh" ? CgalPolicy::GarlandHeckbert : CgalPolicy::LindstromTurk;
  const PolyData input = read_mesh(command.input);
  const CgalDecimateResult r = cgal_decimate(input, command.target, policy);
  write(r.mesh, command.output);
  fmt::print(
      "{{\"peer\": \"{}\", \"input\": {}, \"target\": {}, \"output_triangles\": {}, "
      "\"seconds\": {:.6f}, \"total_seconds\": {:.6f}, \"convert_seconds\": {:.6f}, "
      "\"removed_edges\": {}, \"split_non_manifold\": {}}}\n",
      to_string(policy), json_string(command.input), command.target, r.mesh.polys.size(),
      r.collapse_seconds,
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
      r.convert_seconds, r.removed_edges, r.split_non_manifold);
  return 0;
}

int run_make_mesh(const std::string& kind, const std::string& output) {
  const PolyData mesh = decimation_input(kind);
  write(mesh, output);
  fmt::print("wrote {}: {} points, {} triangles\n", output, mesh.points.size(), mesh.polys.size());
  return 0;
}

}  // namespace isoforge::verify
