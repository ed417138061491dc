// Verification cases for file io: real meshes read, written in every mesh-capable format, read
// back, and re-checked with CGAL. The combinatorics and the exact geometry must be unchanged
// (area and volume bit-identical, since coordinates must survive a round trip exactly).

#include <filesystem>

#include "catalogue.hpp"
#include "isoforge/io/io.hpp"
#include "mesh_checks.hpp"

namespace isoforge::verify {

namespace {

void io_case(CaseResult& r, const std::string& file, std::size_t points, std::size_t faces) {
  const auto path = std::filesystem::path(ISOFORGE_DATA_DIR) / file;
  const auto mesh = std::get<PolyData>(read(path));
  r.equal("points read", mesh.points.size(), points);
  const MeshReport ref = check_mesh(mesh);
  r.equal("triangles", ref.faces, faces);
  r.equal("degenerate faces (exact)", ref.degenerate_faces, std::size_t{0});
  const auto dir = std::filesystem::temp_directory_path() / "isoforge-verify-io";
  std::filesystem::create_directories(dir);
  struct Target {
    const char* ext;
    WriteOptions options;
  };
  WriteOptions ascii;
  ascii.binary = false;
  WriteOptions legacy51;
  legacy51.vtk_legacy_version = "5.1";
  const Target targets[] = {{".vtp", {}}, {".vtk", legacy51}, {".vtk", ascii},
                            {".ply", {}}, {".ply", ascii},    {".off", {}}};
  int n = 0;
  for (const auto& t : targets) {
    const auto out =
        dir / (std::filesystem::path(file).stem().string() + "_" + std::to_string(n++) + t.ext);
    write(mesh, out, t.options);
    const auto back = std::get<PolyData>(read(out));
    std::filesystem::remove(out);
    const MeshReport rep = check_mesh(back);
    const std::string tag = std::string(t.ext) + (t.options.binary ? "" : " ascii") +
                            (t.options.vtk_legacy_version == "5.1" ? " 5.1" : "");
    const bool same = rep.vertices == ref.vertices && rep.faces == ref.faces &&
                      rep.edges == ref.edges && rep.border_edges == ref.border_edges &&
                      rep.non_manifold_edges == ref.non_manifold_edges &&
                      rep.non_manifold_vertices == ref.non_manifold_vertices &&
                      rep.self_intersections == ref.self_intersections &&
                      rep.components.size() == ref.components.size();
    r.is_true(tag + ": same combinatorics and self-intersections", same);
    r.equal(tag + ": area bits", rep.area, ref.area);
    r.equal(tag + ": volume bits", rep.volume, ref.volume);
  }
}

}  // namespace

void add_io_cases(std::vector<Case>& cases) {
  cases.push_back({"io/fran_cut", "fran_cut.vtk (2205 points, 4224 triangles) through 6 writers",
                   true, [](CaseResult& r) { io_case(r, "fran_cut.vtk", 2205, 4224); }});
  cases.push_back({"io/torso", "Torso.vtp (12015 points, quads + triangles) through 6 writers",
                   true, [](CaseResult& r) { io_case(r, "Torso.vtp", 12015, 11314 * 2 + 1134); }});
  cases.push_back({"io/bunny", "bunny.ply (35947 points, 69451 triangles) through 6 writers", false,
                   [](CaseResult& r) { io_case(r, "bunny.ply", 35947, 69451); }});
}

}  // namespace isoforge::verify
