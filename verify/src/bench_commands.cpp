// The decimation benchmark's subcommands (see bench_commands.hpp).
//
// Distance: ReferenceDistance (reference_distance.hpp), one JSON line per mesh.

#include "bench_commands.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "accuracy.hpp"
#include "cgal_decimate.hpp"
#include "decimate_inputs.hpp"
#include "isoforge/io/io.hpp"
#include "mesh_checks.hpp"
#include "reference_distance.hpp"

namespace isoforge::verify {

namespace {

PolyData read_mesh(const std::string& path) {
  Dataset ds = read(path);
  auto* pd = std::get_if<PolyData>(&ds);
  if (!pd)
    throw Error(path + ": is " + std::string(dataset_type_name(ds)) + ", not a polygonal mesh");
  return std::move(*pd);
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
  const ReferenceDistance ref(read_mesh(command.reference), command.spacing, command.max_samples);
  for (const auto& path : command.meshes) {
    const auto t0 = std::chrono::steady_clock::now();
    const PolyData mesh = read_mesh(path);
    const ReferenceError e = ref.measure(mesh);
    std::string line = fmt::format(
        "{{\"reference\": {}, \"mesh\": {}, \"spacing_reference\": {:.9g}, "
        "\"spacing_mesh\": {:.9g}, \"samples_reference\": {}, \"samples_mesh\": {}, "
        "\"diagonal\": {:.9g}, "
        "\"hausdorff\": {:.9g}, \"rms\": {:.9g}, \"max_ref_to_mesh\": {:.9g}, "
        "\"max_mesh_to_ref\": {:.9g}, \"rms_ref_to_mesh\": {:.9g}, \"rms_mesh_to_ref\": {:.9g}, "
        "\"relative_hausdorff\": {:.9g}, \"relative_rms\": {:.9g}",
        json_string(command.reference), json_string(path), ref.reference_spacing(), e.spacing_mesh,
        ref.reference_samples(), e.samples_mesh, ref.diagonal(), e.hausdorff, e.rms,
        e.max_ref_to_mesh, e.max_mesh_to_ref, e.rms_ref_to_mesh, e.rms_mesh_to_ref,
        e.relative_hausdorff, e.relative_rms);
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
