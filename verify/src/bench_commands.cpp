// The decimation benchmark's subcommands (see bench_commands.hpp).
//
// Distance: the reference is sampled once (sample_mesh at `spacing`) and put in one AABB tree;
// each mesh is sampled at the same spacing and put in its own tree. max_ref_to_mesh and
// rms_ref_to_mesh measure the reference's samples against the mesh, max_mesh_to_ref and
// rms_mesh_to_ref the other way (each RMS area-weighted); hausdorff is the larger maximum,
// rms = sqrt((rms_ref_to_mesh^2 + rms_mesh_to_ref^2) / 2). Relative values divide by the
// reference's bounding-box diagonal. Sampled maxima are lower bounds of the true ones.

#include "bench_commands.hpp"

#include <fmt/core.h>

#include <chrono>
#include <cmath>

#include "accuracy.hpp"
#include "cgal_decimate.hpp"
#include "decimate_inputs.hpp"
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
  const Samples ref_samples = sample_mesh(ref, spacing);
  const MeshDistance ref_tree(ref);
  for (const auto& path : command.meshes) {
    const auto t0 = std::chrono::steady_clock::now();
    const PolyData mesh = read_mesh(path);
    const MeshDistance tree(mesh);
    const OneWay ab = measure(ref_samples, tree);
    const OneWay ba = measure(sample_mesh(mesh, spacing), ref_tree);
    const double hausdorff = std::max(ab.max, ba.max);
    const double rms = std::sqrt(0.5 * (ab.rms * ab.rms + ba.rms * ba.rms));
    std::string line = fmt::format(
        "{{\"reference\": {}, \"mesh\": {}, \"spacing\": {:.9g}, \"diagonal\": {:.9g}, "
        "\"hausdorff\": {:.9g}, \"rms\": {:.9g}, \"max_ref_to_mesh\": {:.9g}, "
        "\"max_mesh_to_ref\": {:.9g}, \"rms_ref_to_mesh\": {:.9g}, \"rms_mesh_to_ref\": {:.9g}, "
        "\"relative_hausdorff\": {:.9g}, \"relative_rms\": {:.9g}",
        json_string(command.reference), json_string(path), spacing, diagonal, hausdorff, rms,
        ab.max, ba.max, ab.rms, ba.rms, hausdorff / diagonal, rms / diagonal);
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
