// The figure registry (captions from the chapter) and the helpers the figure files share.

#include "figure.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <set>
#include <utility>

#include "isoforge/core/error.hpp"
#include "isoforge/io/io.hpp"

namespace isoforge::cli::figures {

const std::vector<Figure>& all() {
  static const std::vector<Figure> list = {
      {"1.4a", "streamlines in the office",
       "Section 1.4 (its pages are missing from the seed text; the VTK textbook's office "
       "example): streamlines from a line of 20 seeds, RK45, coloured by the office's scalar.",
       {1, -1.2, 0.9}, {0, 0, 1}, fig_1_4a},
      {"1.4b", "stream tubes in the combustor",
       "Section 1.4: stream tubes, radius and colour by speed, from a rake of 25 seeds, RK45 "
       "both ways (the combustor stands in for the carotid artery, which is not in data/).",
       {-0.6, -1, 0.5}, {0, 0, 1}, fig_1_4b},
      {"1.4c", "tensor ellipsoids of a point load",
       "Section 1.4: the stress of a point load on a half-space (Boussinesq) as tensor "
       "ellipsoids, coloured by the largest eigenvalue (VTK's TensorEllipsoids).",
       {1, -1.4, 0.8}, {0, 0, 1}, fig_1_4c},
      {"1.23a", "sphere sampled on a plane",
       "Sampling functions. (a) 2D depiction of sphere sampling: contour lines F < 0, F = 0, "
       "F > 0.",
       {0, 0, 1}, {0, 1, 0}, fig_1_23a},
      {"1.23b", "isosurface of a sampled sphere",
       "Sampling functions. (b) Isosurface of sampled sphere.", {0.6, 0.45, 1}, {0, 1, 0},
       fig_1_23b},
      {"1.23c", "ice cream cone",
       "Sampling functions. (c) Boolean combination of two spheres, a cone, and two planes. (One "
       "sphere intersects the other; the planes clip the cone.)",
       {0.3, 0.5, 1}, {0, 1, 0}, fig_1_23c},
      {"1.24a", "2D cells inside an ellipse",
       "Implicit functions used to select data: (a) 2D cells lying in ellipse are selected.",
       {0, 0, 1}, {0, 1, 0}, fig_1_24a},
      {"1.24b", "voxels in two ellipsoids",
       "Implicit functions used to select data: (b) two ellipsoids combined using the union "
       "operation used to select voxels from a volume. Voxels shrank 50%.",
       {0.6, 0.45, 1}, {0, 1, 0}, fig_1_24b},
      {"1.25", "Lorenz attractor",
       "Visualizing a Lorenz strange attractor by integrating the Lorenz equations in a volume. "
       "The number of visits in each voxel is recorded as a scalar function. The surface is "
       "extracted via marching cubes using a visit value of 50. The number of integration steps "
       "is 10 million, in a volume of dimensions 200^3. The surface roughness is caused by the "
       "discrete nature of the evaluation function.",
       {1, -0.6, 0.3}, {0, 0, 1}, fig_1_25},
      {"1.26", "distance to a point, a line, a triangle",
       "Distance functions to a point, line, and triangle.", {0.2, -1, 0.6}, {0, 0, 1},
       fig_1_26},
      {"1.27", "booleans of point and line generators",
       "Boolean operations using points and lines as generating primitives (original, union, "
       "intersection, difference; top row: the originals and their union).",
       {0.2, -1, 0.35}, {0, 0, 1}, fig_1_27},
      {"1.28", "HELLO thickened",
       "Implicit modeling used to thicken a stroked font. Original lines can be seen within the "
       "translucent implicit surface.",
       {0.15, -0.5, 1}, {0, 1, 0}, fig_1_28},
      {"1.29", "concave generator, several surfaces",
       "Concave features can result in multiple contour lines/surfaces.", {0.25, -1, 0.3},
       {0, 0, 1}, fig_1_29},
      {"1.30", "cone glyphs on a face",
       "Glyphs indicate surface normals on a model of a human face. Glyph positions are randomly "
       "selected.",
       {1, 0.1, -0.8}, {0, 1, 0}, fig_1_30},
      {"1.31", "combustor cut by a plane",
       "Cut through structured grid with plane. The cut plane is shown solid shaded. A "
       "computational plane of constant k value is shown in wireframe for comparison. The colors "
       "correspond to flow density.",
       {-0.6, -1, 0.5}, {0, 0, 1}, fig_1_31},
      {"1.32", "100 cut planes",
       "100 cut planes with opacity of 0.05, rendered back-to-front to simulate volume "
       "rendering.",
       {1, 0.4, 0.6}, {0, 0, 1}, fig_1_32},
      {"1.33", "skin contour lines in tubes",
       "Cutting a surface model of the skin with a series of planes produces contour lines. Lines "
       "are wrapped with tubes for visual clarity.",
       {0.35, 1, 0.2}, {0, 0, 1}, fig_1_33},
      {"1.35", "probes in the combustor",
       "Probing data in a combustor. Probes are regular arrays of 50^2 points that are passed "
       "through a contouring filter.",
       {-0.6, -1, 0.5}, {0, 0, 1}, fig_1_35},
      {"1.36", "subsampling a structured grid", "Subsampling structured data.",
       {-0.6, -1, 0.5}, {0, 0, 1}, fig_1_36},
      {"1.37", "decimation of the bunny",
       "Decimating unstructured data: edge collapse, vertex deletion and cell deletion, side by "
       "side at the same triangle count.",
       {0, 0, 1}, {0, 1, 0}, fig_1_37},
  };
  return list;
}

std::string file_stem(std::string_view id) {
  std::string s = "fig_" + std::string(id);
  std::replace(s.begin(), s.end(), '.', '_');
  return s;
}

PolyData translated(PolyData pd, const Vec3& t) {
  for (std::size_t i = 0; i < pd.points.size(); ++i) pd.points.set(i, pd.points[i] + t);
  return pd;
}

PolyData wireframe(const PolyData& pd) {
  PolyData out;
  out.points = pd.points;
  std::set<std::pair<Index, Index>> seen;
  for (std::size_t c = 0; c < pd.polys.size(); ++c) {
    const auto ids = pd.polys.cell(c);
    for (std::size_t k = 0; k < ids.size(); ++k) {
      Index a = ids[k], b = ids[(k + 1) % ids.size()];
      if (a > b) std::swap(a, b);
      if (seen.insert({a, b}).second) out.lines.add({a, b});
    }
  }
  out.point_data = pd.point_data;
  return out;
}

std::string topology_text(const SurfaceTopology& t) {
  std::string s = t.closed() ? "closed" : fmt::format("{} border edges", t.border_edges);
  s += t.manifold() ? ", manifold" : ", NOT manifold";
  s += fmt::format(", {} component{}", t.components.size(), t.components.size() == 1 ? "" : "s");
  if (t.closed() && t.manifold() && !t.components.empty()) {
    std::vector<long> g;
    for (const auto& c : t.components) g.push_back(c.genus);
    std::sort(g.begin(), g.end());
    if (g.front() == g.back()) {
      s += fmt::format(", genus {}", g.front());
    } else {
      s += ", genus";
      for (long x : g) s += fmt::format(" {}", x);
    }
  }
  return s;
}

std::filesystem::path data_file(const Context& ctx, std::string_view name) {
  const std::filesystem::path p = ctx.data / name;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(p, ec)) {
    throw Error(p.string() + ": no such data file (give the data directory with --data)");
  }
  return p;
}

PolyData grid_outline(const StructuredGrid& sg) {
  PolyData out;
  out.points = sg.points;
  const Index n[3] = {sg.dims[0], sg.dims[1], sg.dims[2]};
  for (int axis = 0; axis < 3; ++axis) {
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    for (int corner = 0; corner < 4; ++corner) {
      Index ijk[3];
      ijk[a] = corner & 1 ? n[a] - 1 : 0;
      ijk[b] = corner & 2 ? n[b] - 1 : 0;
      std::vector<Index> ids;
      for (Index t = 0; t < n[axis]; ++t) {
        ijk[axis] = t;
        ids.push_back(sg.point_id(ijk[0], ijk[1], ijk[2]));
      }
      out.lines.add(ids);
    }
  }
  return out;
}

PolyData box_outline(const Bounds& b) {
  PolyData out;
  for (int c = 0; c < 8; ++c) {
    out.points.push_back({c & 1 ? b.max.x : b.min.x, c & 2 ? b.max.y : b.min.y,
                          c & 4 ? b.max.z : b.min.z});
  }
  for (int c = 0; c < 8; ++c) {
    for (const int bit : {1, 2, 4}) {
      if (!(c & bit)) out.lines.add({Index(c), Index(c | bit)});
    }
  }
  return out;
}

double worst_tangency(const PolyData& lines, const std::string& vectors) {
  const DataArray& v = lines.point_data.get(vectors);
  double fastest = 0;
  for (std::size_t i = 0; i < v.tuples(); ++i) {
    fastest = std::max(fastest, norm(Vec3{v.get(i, 0), v.get(i, 1), v.get(i, 2)}));
  }
  double worst = 1;
  for (std::size_t c = 0; c < lines.lines.size(); ++c) {
    const auto ids = lines.lines.cell(c);
    const bool backward = lines.point_data.get("IntegrationTime").get(std::size_t(ids.back())) < 0;
    for (std::size_t k = 1; k < ids.size(); ++k) {
      const auto a = std::size_t(ids[k - 1]), b = std::size_t(ids[k]);
      const Vec3 chord = (lines.points[b] - lines.points[a]) * (backward ? -1.0 : 1.0);
      const Vec3 mean = Vec3{v.get(a, 0) + v.get(b, 0), v.get(a, 1) + v.get(b, 1),
                             v.get(a, 2) + v.get(b, 2)} / 2.0;
      if (norm(chord) > 0 && norm(mean) >= 0.01 * fastest) {
        worst = std::min(worst, dot(chord, mean) / (norm(chord) * norm(mean)));
      }
    }
  }
  return worst;
}

Output stream_output(const PolyData& lines, const PolyData& tubes, const std::string& tubes_name,
                     const std::string& color_by, const StructuredGrid& grid,
                     const std::string& outline_name) {
  const auto range = lines.point_data.get(color_by).range();
  Output out;
  out.datasets.emplace_back("streamlines", lines);
  out.datasets.emplace_back("tubes", tubes);
  out.meshes.push_back({tubes_name, tubes, color_by, Colormap::Rainbow,
                        std::array{range.first, range.second}});
  out.meshes.push_back({outline_name, grid_outline(grid), "", Colormap::Rainbow, std::nullopt,
                        {60, 60, 60, 255}});
  return out;
}

StructuredGrid combustor(const Context& ctx) {
  ReadOptions ro;
  ro.plot3d_q = data_file(ctx, "combq.bin").string();
  return std::get<StructuredGrid>(read(data_file(ctx, "combxyz.bin"), ro));
}

}  // namespace isoforge::cli::figures
