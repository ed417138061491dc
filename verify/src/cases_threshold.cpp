// Verification cases of thresholding and surface extraction (docs/algorithms/threshold.md):
// - the surface of a closed volume mesh is a closed, manifold, outward-oriented surface without
//   self-intersections (CGAL's exact predicates) whose signed volume is the sum of the cells'
//   volumes: a jittered tetrahedral box, the real post.vtk, and image data (the structured path,
//   also compared with the unstructured path on the converted grid);
// - thresholding with a range covering every value gives the input back; complementary ranges
//   partition the cells, for a cell array ([lo, t] and (t, hi]) and for a point array (a cell
//   either has a point in [lo, t] or has all its points in (t, hi]).

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>

#include "case_support.hpp"
#include "isoforge/filters/surface.hpp"
#include "isoforge/filters/threshold.hpp"
#include "isoforge/io/io.hpp"

namespace isoforge::verify {

namespace {

double tet_volume(const UnstructuredGrid& g, std::span<const Index> ids) {
  const Vec3 a = g.points[static_cast<std::size_t>(ids[0])];
  return dot(g.points[static_cast<std::size_t>(ids[1])] - a,
             cross(g.points[static_cast<std::size_t>(ids[2])] - a,
                   g.points[static_cast<std::size_t>(ids[3])] - a)) / 6;
}

// n^3 hexahedra over [0, 1]^3, 5 tetrahedra each (the central one on the corners of alternating
// parity, so neighbours share face diagonals), interior points moved by up to 0.1 of a cell along
// each axis (deterministic): 0.1 h cannot invert a tetrahedron whose heights are >= h / sqrt(3).
UnstructuredGrid jittered_tets(Index n) {
  const Index m = n + 1;
  const double h = 1.0 / static_cast<double>(n);
  UnstructuredGrid g;
  std::uint64_t state = 0x9e3779b97f4a7c15ULL;
  const auto jitter = [&] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (static_cast<double>(state >> 11) / 9007199254740992.0 - 0.5) * 0.2 * h;
  };
  for (Index k = 0; k < m; ++k)
    for (Index j = 0; j < m; ++j)
      for (Index i = 0; i < m; ++i) {
        Vec3 p{static_cast<double>(i) * h, static_cast<double>(j) * h, static_cast<double>(k) * h};
        const double dx = jitter(), dy = jitter(), dz = jitter();
        if (i > 0 && i < n) p.x += dx;
        if (j > 0 && j < n) p.y += dy;
        if (k > 0 && k < n) p.z += dz;
        g.points.push_back(p);
      }
  static constexpr int kEven[5][4] = {{0, 3, 5, 6}, {1, 0, 3, 5}, {2, 0, 6, 3}, {4, 0, 5, 6}, {7, 3, 5, 6}};
  static constexpr int kOdd[5][4] = {{1, 2, 4, 7}, {0, 1, 2, 4}, {3, 1, 2, 7}, {5, 1, 4, 7}, {6, 2, 4, 7}};
  for (Index k = 0; k < n; ++k)
    for (Index j = 0; j < n; ++j)
      for (Index i = 0; i < n; ++i)
        for (const auto& t : (i + j + k) % 2 == 0 ? kEven : kOdd) {
          Index ids[4];
          for (int v = 0; v < 4; ++v)
            ids[v] = (i + (t[v] & 1)) + m * ((j + (t[v] >> 1 & 1)) + m * (k + (t[v] >> 2 & 1)));
          if (tet_volume(g, ids) < 0) std::swap(ids[1], ids[2]);
          g.add_cell(CellType::Tetra, std::span<const Index>(ids, 4));
        }
  return g;
}

// Points of `g` sharing their coordinates with another point.
std::size_t duplicate_points(const Points& p) {
  std::vector<std::array<double, 3>> xyz(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) xyz[i] = {p[i].x, p[i].y, p[i].z};
  std::sort(xyz.begin(), xyz.end());
  std::size_t n = 0;
  for (std::size_t i = 0; i < xyz.size(); ++i)
    n += (i > 0 && xyz[i] == xyz[i - 1]) || (i + 1 < xyz.size() && xyz[i] == xyz[i + 1]);
  return n;
}

// `seam`: the input has unmerged coincident points (post.vtk's seam): the surface then has two
// coincident, oppositely oriented sheets there, whose faces touch; the checks that such a seam
// fails are replaced by the check that every duplicate point of the surface is one of the input.
void closed_tets_case(CaseResult& r, const UnstructuredGrid& g, const std::string& what,
                      bool seam = false) {
  double volume = 0, smallest = 1e300;
  for (std::size_t c = 0; c < g.num_cells(); ++c) {
    const double v = tet_volume(g, g.cells.cell(c));
    volume += v;
    smallest = std::min(smallest, v);
  }
  auto [s, stats] = extract_surface(g);
  r.note("input", fmt::format("{}: {} tetrahedra, {} points; volume {:.9g}", what, g.num_cells(),
                              g.num_points(), volume));
  r.note("surface", fmt::format("{} triangles, {} points", s.polys.size(), s.num_points()));
  r.at_least("smallest tetrahedron volume (all positive: valid input)", smallest, 1e-300);
  const MeshReport m = check_mesh(s);
  if (!seam) {
    record_closed_surface(r, m);
  } else {
    r.equal("border edges (closed)", m.border_edges, std::size_t{0});
    r.equal("non-manifold edges", m.non_manifold_edges, std::size_t{0});
    r.equal("non-manifold vertices", m.non_manifold_vertices, std::size_t{0});
    r.equal("inconsistently oriented edges", m.inconsistent_edges, std::size_t{0});
    r.is_true("outward oriented, every component (exact)", m.outward);
    r.equal("degenerate faces (exact)", m.degenerate_faces, std::size_t{0});
    const std::size_t in_dup = duplicate_points(g.points);
    r.at_most("duplicate points of the surface <= those of the input (its unmerged seam)",
              static_cast<double>(m.duplicate_points), static_cast<double>(in_dup));
    r.note("input points sharing their coordinates", fmt::format("{}", in_dup));
    r.note("face pairs touching beyond a shared edge (the two sheets of the seam; exact)",
           fmt::format("{}", m.self_intersections));
  }
  r.equal("boundary faces = triangles written", stats.boundary_faces, s.polys.size());
  // Each tetrahedron has 4 faces; interior ones are shared by two: 4 T = 2 I + B.
  r.equal("4 x tetrahedra - boundary faces is even (interior faces counted twice)",
          (4 * g.num_cells() - stats.boundary_faces) % 2, std::size_t{0});
  r.at_most("|signed volume of the surface - sum of cell volumes| / volume",
            std::abs(m.volume - volume) / volume, 1e-9);
}

void image_case(CaseResult& r) {
  ImageData img;
  img.dims = {17, 12, 9};
  img.origin = {-1, 0.5, 2};
  img.spacing = {0.25, 0.5, 0.125};
  const double volume = 16 * 0.25 * 11 * 0.5 * 8 * 0.125;
  auto [s, stats] = extract_surface(img);
  const PolyData general = extract_surface(to_unstructured(img)).output;
  r.note("input", "17 x 12 x 9 points of image data (the structured path)");
  const MeshReport m = check_mesh(s);
  record_closed_surface(r, m);
  r.equal("outer faces = 2 (16*11 + 16*8 + 11*8)", s.polys.size(),
          std::size_t{2 * (16 * 11 + 16 * 8 + 11 * 8)});
  r.at_most("|signed volume - box volume| / box volume", std::abs(m.volume - volume) / volume, 1e-6);
  r.is_true("same output as the unstructured path on the converted grid", s == general);
}

void whole_range_case(CaseResult& r) {
  const auto g = std::get<UnstructuredGrid>(read(ISOFORGE_DATA_DIR "/post.vtk"));
  const auto [lo, hi] = g.point_data.get("Pressure").range();
  ThresholdOptions o;
  o.array = "Pressure";
  o.lower = lo;
  o.upper = hi;
  bool all_same = true;
  for (ThresholdMode mode : {ThresholdMode::AllPoints, ThresholdMode::AnyPoint, ThresholdMode::Overlap}) {
    o.mode = mode;
    all_same = all_same && threshold(g, o).output == g;
  }
  r.note("input", fmt::format("post.vtk, Pressure in [{:.6g}, {:.6g}]", lo, hi));
  r.is_true("threshold over [min, max] = the input (points, cells, arrays; all three modes)",
            all_same);
}

std::set<Index> original_cells(const UnstructuredGrid& g) {
  std::set<Index> ids;
  const auto v = g.cell_data.get("OriginalCellIds").values<std::int64_t>();
  ids.insert(v.begin(), v.end());
  return ids;
}

void partition_case(CaseResult& r) {
  auto g = std::get<UnstructuredGrid>(read(ISOFORGE_DATA_DIR "/post.vtk"));
  const std::size_t n = g.num_cells();
  DataArray cv("cv", ScalarType::Float32, 1, n);
  for (std::size_t c = 0; c < n; ++c) cv.set(c, 0, std::cos(0.011 * static_cast<double>(c * c % 977)));
  g.cell_data.add(std::move(cv));
  const double t = 0.25;
  ThresholdOptions o;
  o.original_ids = true;
  o.array = "cv";
  o.upper = t;
  const auto lo_cells = threshold(g, o).output;
  o.lower = std::nextafter(t, 2.0);
  o.upper = 1;
  const auto hi_cells = threshold(g, o).output;
  std::set<Index> a = original_cells(lo_cells), b = original_cells(hi_cells);
  std::size_t common = 0;
  for (Index id : a) common += b.count(id);
  r.note("cells", fmt::format("post.vtk: {} cells; cell array split {} + {}", n,
                              lo_cells.num_cells(), hi_cells.num_cells()));
  r.at_least("cells in [lo, t] (cell array)", static_cast<double>(lo_cells.num_cells()), 1);
  r.at_least("cells in (t, hi] (cell array)", static_cast<double>(hi_cells.num_cells()), 1);
  r.equal("cell array: [lo, t] + (t, hi] cells = all cells", lo_cells.num_cells() + hi_cells.num_cells(), n);
  r.equal("cell array: cells in both parts", common, std::size_t{0});
  // Point array: AnyPoint of [lo, t] and AllPoints of (t, hi] partition the cells.
  const auto [plo, phi] = g.point_data.get("Pressure").range();
  const double pt = 0.5 * (plo + phi);
  o.array = "Pressure";
  o.lower = plo;
  o.upper = pt;
  o.mode = ThresholdMode::AnyPoint;
  const auto any = threshold(g, o).output;
  o.lower = std::nextafter(pt, phi);
  o.upper = phi;
  o.mode = ThresholdMode::AllPoints;
  const auto all = threshold(g, o).output;
  a = original_cells(any);
  b = original_cells(all);
  common = 0;
  for (Index id : a) common += b.count(id);
  r.note("point array", fmt::format("Pressure split at {:.6g}: {} (a point below) + {} (all above)",
                                    pt, any.num_cells(), all.num_cells()));
  r.equal("point array: any point in [lo, t] + all points in (t, hi] = all cells",
          any.num_cells() + all.num_cells(), n);
  r.equal("point array: cells in both parts", common, std::size_t{0});
  r.at_least("both parts non-empty (smaller part)", static_cast<double>(std::min(any.num_cells(), all.num_cells())), 1);
}

}  // namespace

void add_threshold_cases(std::vector<Case>& cases) {
  cases.push_back({"surface/jittered-tets", "surface of 6^3 x 5 jittered tetrahedra: closed, outward, volume",
                   true, [](CaseResult& r) { closed_tets_case(r, jittered_tets(6), "jittered box"); }});
  cases.push_back({"surface/post", "surface of post.vtk (8750 tetrahedra): closed, outward, volume", false,
                   [](CaseResult& r) {
                     closed_tets_case(r, std::get<UnstructuredGrid>(read(ISOFORGE_DATA_DIR "/post.vtk")),
                                      "post.vtk", true);
                   }});
  cases.push_back({"surface/image", "outer faces of image data: closed, outward, box volume, = general path",
                   false, [](CaseResult& r) { image_case(r); }});
  cases.push_back({"threshold/whole-range", "threshold of post.vtk over [min, max] is the input", true,
                   [](CaseResult& r) { whole_range_case(r); }});
  cases.push_back({"threshold/partition", "complementary ranges partition the cells (cell and point arrays)",
                   false, [](CaseResult& r) { partition_case(r); }});
}

}  // namespace isoforge::verify
