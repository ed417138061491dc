// Verification cases of probing (filters/probe.hpp): a linear field probed in meshes of every
// cell type is reproduced to float precision (isoparametric interpolation of a linear function
// is exact), and which points are found is checked against analytic truth: the 3D meshes tile
// the unit box exactly (only interior points are jittered), so a point is inside a cell if and
// only if it is inside the box; the 2D and 1D meshes are probed at points on their cells and at
// points lifted off them by 1e-3 (far beyond the 1e-6 distance tolerance).

#include <fmt/core.h>

#include <cmath>
#include <random>

#include "case_support.hpp"
#include "isoforge/filters/probe.hpp"

namespace isoforge::verify {

namespace {

double field(const Vec3& p) { return 1.5 + 2 * p.x - 3 * p.y + 0.5 * p.z; }

/// n^3 cubes over [0, 1]^3; interior points jittered by up to 0.2 of a cube (boundary points
/// move only within their boundary faces' planes: not at all here, so the box is tiled exactly).
std::vector<Vec3> jittered_points(Index n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  const Index m = n + 1;
  std::vector<Vec3> pts;
  const double h = 1.0 / double(n);
  for (Index k = 0; k < m; ++k)
    for (Index j = 0; j < m; ++j)
      for (Index i = 0; i < m; ++i) {
        Vec3 p{double(i) * h, double(j) * h, double(k) * h};
        const bool interior = i > 0 && j > 0 && k > 0 && i < n && j < n && k < n;
        if (interior) p = p + Vec3{u(rng), u(rng), u(rng)} * h;
        pts.push_back(p);
      }
  return pts;
}

/// A 3D mesh of one cell type tiling [0, 1]^3: each of n^3 (jittered) cubes as one hexahedron,
/// 6 tetrahedra (Kuhn split about the 0-7 diagonal), 2 wedges, or 6 pyramids to its centroid;
/// voxels use an unjittered but unevenly spaced grid (voxels must be axis-aligned boxes).
UnstructuredGrid mesh_3d(CellType type, Index n) {
  UnstructuredGrid ug;
  ug.points = Points(0, ScalarType::Float64);
  std::vector<Vec3> pts;
  if (type == CellType::Voxel) {
    const Index m = n + 1;
    auto coord = [&](Index i) {  // uneven spacing, ends at 0 and 1
      const double t = double(i) / double(n);
      return t * t * (3 - 2 * t) * 0.5 + t * 0.5;
    };
    for (Index k = 0; k < m; ++k)
      for (Index j = 0; j < m; ++j)
        for (Index i = 0; i < m; ++i) pts.push_back({coord(i), coord(j), coord(k)});
  } else {
    pts = jittered_points(n, 7 + static_cast<unsigned>(type));
  }
  for (const Vec3& p : pts) ug.points.push_back(p);
  const Index m = n + 1;
  for (Index k = 0; k < n; ++k)
    for (Index j = 0; j < n; ++j)
      for (Index i = 0; i < n; ++i) {
        Index c[8];  // voxel order
        for (int q = 0; q < 8; ++q) c[q] = (i + (q & 1)) + m * ((j + ((q >> 1) & 1)) + m * (k + (q >> 2)));
        switch (type) {
          case CellType::Hexahedron:
            ug.add_cell(type, {c[0], c[1], c[3], c[2], c[4], c[5], c[7], c[6]});
            break;
          case CellType::Voxel:
            ug.add_cell(type, {c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]});
            break;
          case CellType::Tetra: {
            const int paths[6][2] = {{1, 3}, {1, 5}, {2, 3}, {2, 6}, {4, 5}, {4, 6}};
            for (const auto& p : paths) ug.add_cell(type, {c[0], c[p[0]], c[p[1]], c[7]});
            break;
          }
          case CellType::Wedge:  // triangles (0,1,3) and (0,3,2) of the bottom, extruded up
            ug.add_cell(type, {c[0], c[3], c[1], c[4], c[7], c[5]});
            ug.add_cell(type, {c[0], c[2], c[3], c[4], c[6], c[7]});
            break;
          case CellType::Pyramid: {
            Vec3 centre{};
            for (Index id : c) centre = centre + ug.points[std::size_t(id)] * 0.125;
            ug.points.push_back(centre);
            const Index a = Index(ug.points.size()) - 1;
            const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                     {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
            for (const auto& f : faces) ug.add_cell(type, {c[f[0]], c[f[1]], c[f[2]], c[f[3]], a});
            break;
          }
          default:
            break;
        }
      }
  return ug;
}

template <class D>
void add_field(D& ds) {
  DataArray f("f", ScalarType::Float64, 1, num_points(ds));
  for (std::size_t i = 0; i < num_points(ds); ++i) f.set(i, 0, field(point(ds, Index(i))));
  ds.point_data.add(std::move(f), AttributeRole::Scalars);
}

/// Probes `ds` at `pts` and checks: found exactly where `expected` says, the field reproduced
/// to float precision where found, NaN elsewhere.
void check_probe(CaseResult& r, DatasetRef ds, const std::vector<Vec3>& pts,
                 const std::vector<bool>& expected) {
  PolyData cloud;
  cloud.points = Points(0, ScalarType::Float64);
  for (const Vec3& p : pts) cloud.points.push_back(p);
  const auto [out, stats] = probe(ds, cloud);
  const Attributes& pd = point_data(out);
  const DataArray& f = pd.get("f");
  const DataArray& mask = pd.get("vtkValidPointMask");
  std::size_t wrong = 0, expected_found = 0, not_nan = 0;
  double worst = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    expected_found += expected[i] ? 1 : 0;
    if ((mask.get(i) != 0) != expected[i]) ++wrong;
    if (mask.get(i) != 0) {
      worst = std::max(worst, std::abs(f.get(i) - field(pts[i])));
    } else if (!std::isnan(f.get(i))) {
      ++not_nan;
    }
  }
  r.note("mesh", fmt::format("{} {} cells, {} points; {} probe points, {} inside", num_cells(ds),
                             dataset_type_name(ds), num_points(ds), pts.size(), expected_found));
  r.at_least("points expected inside", double(expected_found), double(pts.size()) / 4);
  r.equal("points found where not expected or missed where expected", wrong, std::size_t{0});
  r.equal("found count", stats.found, expected_found);
  r.at_most("max |probed - linear field| (range 6; float precision 1e-6)", worst, 1e-6);
  r.equal("points outside with a non-NaN value", not_nan, std::size_t{0});
}

/// Random points of the box [-0.1, 1.1]^3, inside iff in [0, 1]^3 (points within 1e-6 of a
/// face are left out: their side is a matter of rounding).
// Appends p with whether it lies in the unit cube, unless it is within 1e-6 of a face (where
// inside or outside is up to rounding).
void add_box_point(const Vec3& p, std::vector<Vec3>& pts, std::vector<bool>& in) {
  bool inside = true;
  for (int a = 0; a < 3; ++a) {
    if (std::abs(p[a]) < 1e-6 || std::abs(p[a] - 1) < 1e-6) return;
    inside = inside && p[a] >= 0 && p[a] <= 1;
  }
  pts.push_back(p);
  in.push_back(inside);
}

void box_points(std::size_t n, unsigned seed, std::vector<Vec3>& pts, std::vector<bool>& in) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.1, 1.1);
  while (pts.size() < n) add_box_point({u(rng), u(rng), u(rng)}, pts, in);
}

void volume_case(CaseResult& r, CellType type) {
  UnstructuredGrid ug = mesh_3d(type, 8);
  add_field(ug);
  std::vector<Vec3> pts;
  std::vector<bool> in;
  box_points(20000, 11, pts, in);
  check_probe(r, ug, pts, in);
}

/// A surface or line mesh on the tilted plane z = 0.2 + 0.3 x - 0.1 y (pixels: z = 0.4, they
/// must be axis-aligned), probed at random points on its cells and 1e-3 off them.
void surface_case(CaseResult& r, CellType type) {
  const Index n = 12;
  const bool pixel = type == CellType::Pixel;
  auto lift = [&](double x, double y) {
    return Vec3{x, y, pixel ? 0.4 : 0.2 + 0.3 * x - 0.1 * y};
  };
  UnstructuredGrid ug;
  ug.points = Points(0, ScalarType::Float64);
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> jit(-0.2, 0.2), u(0, 1);
  const double h = 1.0 / double(n);
  for (Index j = 0; j <= n; ++j)
    for (Index i = 0; i <= n; ++i) {
      const bool interior = !pixel && i > 0 && j > 0 && i < n && j < n;
      const double x = double(i) * h + (interior ? jit(rng) * h : 0);
      const double y = double(j) * h + (interior ? jit(rng) * h : 0);
      ug.points.push_back(lift(x, y));
    }
  std::vector<Vec3> pts;
  std::vector<bool> in;
  const Vec3 normal = pixel ? Vec3{0, 0, 1} : Vec3{-0.3, 0.1, 1} * (1 / norm(Vec3{-0.3, 0.1, 1}));
  for (Index j = 0; j < n; ++j)
    for (Index i = 0; i < n; ++i) {
      const Index a = i + (n + 1) * j, b = a + 1, c = a + n + 1, d = c + 1;
      const Vec3 pa = ug.points[std::size_t(a)], pb = ug.points[std::size_t(b)],
                 pc = ug.points[std::size_t(c)], pdd = ug.points[std::size_t(d)];
      std::vector<Vec3> on;
      if (type == CellType::Triangle) {
        ug.add_cell(type, {a, b, d});
        ug.add_cell(type, {a, d, c});
        for (int s = 0; s < 6; ++s) {
          double x = u(rng), y = u(rng);
          if (x + y > 1) { x = 1 - x; y = 1 - y; }
          on.push_back(pa + (pb - pa) * x + (pdd - pa) * y);
        }
      } else if (type == CellType::Quad || type == CellType::Pixel) {
        if (type == CellType::Quad) {
          ug.add_cell(type, {a, b, d, c});
        } else {
          ug.add_cell(type, {a, b, c, d});
        }
        for (int s = 0; s < 6; ++s) {
          const double x = u(rng), y = u(rng);
          on.push_back(pa * ((1 - x) * (1 - y)) + pb * (x * (1 - y)) + pc * ((1 - x) * y) + pdd * (x * y));
        }
      } else {  // lines: the grid's horizontal and vertical edges
        ug.add_cell(CellType::Line, {a, b});
        ug.add_cell(CellType::Line, {a, c});
        for (int s = 0; s < 3; ++s) {
          const double t = u(rng);
          on.push_back(pa + (pb - pa) * t);
          on.push_back(pa + (pc - pa) * t);
        }
      }
      for (const Vec3& p : on) {
        pts.push_back(p);
        in.push_back(true);
        pts.push_back(p + normal * 1e-3);  // off the plane: beyond the distance tolerance
        in.push_back(false);
      }
    }
  add_field(ug);
  check_probe(r, ug, pts, in);
}

void image_case(CaseResult& r) {
  ImageData img;
  img.dims = {9, 7, 5};
  img.spacing = {1.0 / 8, 1.0 / 6, 1.0 / 4};
  add_field(img);
  std::vector<Vec3> pts;
  std::vector<bool> in;
  box_points(20000, 12, pts, in);
  check_probe(r, img, pts, in);
}

void curvilinear_case(CaseResult& r) {
  const Index n = 10;
  StructuredGrid g;
  g.dims = {n + 1, n + 1, n + 1};
  g.points = Points(0, ScalarType::Float64);
  for (const Vec3& p : jittered_points(n, 13)) g.points.push_back(p);
  add_field(g);
  std::vector<Vec3> pts;
  std::vector<bool> in;
  box_points(20000, 14, pts, in);
  // And a coherent sweep (the walk from cell to cell): a 40^3 volume probe over [-0.05, 1.05]^3.
  for (int k = 0; k < 40; ++k)
    for (int j = 0; j < 40; ++j)
      for (int i = 0; i < 40; ++i) {
        add_box_point(Vec3{double(i), double(j), double(k)} * (1.1 / 39) - Vec3{0.05, 0.05, 0.05},
                      pts, in);
      }
  check_probe(r, g, pts, in);
}

}  // namespace

void add_probe_cases(std::vector<Case>& cases) {
  const struct {
    const char* name;
    CellType type;
    bool quick;
  } volumes[] = {{"tetra", CellType::Tetra, true},   {"hexahedron", CellType::Hexahedron, false},
                 {"voxel", CellType::Voxel, false},  {"wedge", CellType::Wedge, false},
                 {"pyramid", CellType::Pyramid, false}};
  for (const auto& v : volumes) {
    const CellType type = v.type;
    cases.push_back({fmt::format("probe/{}", v.name),
                     fmt::format("a linear field probed in {} cells tiling the unit box "
                                 "(jittered): reproduced to float precision, found iff inside",
                                 v.name),
                     v.quick, [type](CaseResult& r) { volume_case(r, type); }});
  }
  const struct {
    const char* name;
    CellType type;
  } surfaces[] = {{"triangle", CellType::Triangle},
                  {"quad", CellType::Quad},
                  {"pixel", CellType::Pixel},
                  {"line", CellType::Line}};
  for (const auto& s : surfaces) {
    const CellType type = s.type;
    cases.push_back({fmt::format("probe/{}", s.name),
                     fmt::format("a linear field probed on {} cells of a plane: found on them, "
                                 "not 1e-3 off them, reproduced to float precision",
                                 s.name),
                     false, [type](CaseResult& r) { surface_case(r, type); }});
  }
  cases.push_back({"probe/image", "image data located by arithmetic: a linear field reproduced, "
                                  "found iff inside",
                   true, [](CaseResult& r) { image_case(r); }});
  cases.push_back({"probe/curvilinear",
                   "a jittered curvilinear grid (walk + block locator): a linear field "
                   "reproduced, found iff inside, random and coherent points",
                   false, [](CaseResult& r) { curvilinear_case(r); }});
}

}  // namespace isoforge::verify
