// Verification cases for results that must lie on one side of an implicit function: cell
// selection (extract_cells) inside a sphere and outside a torus, checked point by point with the
// side check and cell by cell against an independent count; and the contour of a sampled plane,
// whose vertices must lie on the plane to within float rounding (linear interpolation of a
// linear function is exact).

#include <fmt/core.h>

#include "case_support.hpp"
#include "isoforge/contour/contour.hpp"
#include "isoforge/implicit/select.hpp"

namespace isoforge::verify {

namespace {

using F = ImplicitFunction;

// n^3 points over [-1, 1]^3 (spacing 2 / (n - 1)).
ImageData voxel_grid(Index n) {
  ImageData img;
  img.dims = {n, n, n};
  const double h = 2.0 / static_cast<double>(n - 1);
  img.origin = {-1, -1, -1};
  img.spacing = {h, h, h};
  return img;
}

void select_case(CaseResult& r, const F& f, bool inside) {
  const ImageData img = voxel_grid(41);
  SelectOptions o;
  o.inside = inside;
  const UnstructuredGrid out = extract_cells(img, f, o);
  // Independent count: voxels whose 8 corners are all in the region (F <= 0 counts as inside).
  std::size_t expected = 0;
  const Index n = img.dims[0];
  std::vector<double> v(img.num_points());
  for (std::size_t id = 0; id < v.size(); ++id) v[id] = f.value(img.point(static_cast<Index>(id)));
  for (Index k = 0; k + 1 < n; ++k)
    for (Index j = 0; j + 1 < n; ++j)
      for (Index i = 0; i + 1 < n; ++i) {
        bool all = true;
        for (int c = 0; c < 8; ++c) {
          const double x = v[static_cast<std::size_t>(
              img.point_id(i + (c & 1), j + ((c >> 1) & 1), k + (c >> 2)))];
          all = all && (inside ? x <= 0 : x > 0);
        }
        expected += all ? 1 : 0;
      }
  r.note("input", fmt::format("{}^3 voxels over [-1, 1]^3; {} selected, {} points", n - 1,
                              out.num_cells(), out.num_points()));
  r.at_least("selected cells", static_cast<double>(out.num_cells()), 1);
  r.equal("selected cells = voxels with every corner in the region", out.num_cells(), expected);
  const SideReport s = check_side(out.points, f, inside ? Side::Inside : Side::Outside, 4);
  r.equal(std::string("points on the wrong side (") + (inside ? "F <= tol" : "F >= -tol") +
              ", tol = 4 ulp(float) |grad F|)",
          s.violations, std::size_t{0});
  r.at_most("worst point: F / tol", s.worst_ratio, 1.0);
  r.note("points beyond F = 0 but within tol (float storage)",
         fmt::format("{}", s.within_tolerance));
}

void plane_case(CaseResult& r) {
  // Samples at multiples of 1/16 on [-1, 1]^3: x + 2y + 3z is a multiple of 1/16 there, so
  // with c = 1/32 no sample is closer than (1/32) / sqrt(14) to the plane and no crossing is
  // clamped to the 1/1024 margin at an edge end.
  ImageData img;
  img.dims = {33, 33, 33};
  img.origin = {-1, -1, -1};
  img.spacing = {1.0 / 16, 1.0 / 16, 1.0 / 16};
  const Vec3 normal{1, 2, 3};
  const double c = 1.0 / 32;
  const F plane = F::plane(normal * (c / 14.0), normal);
  const PolyData mesh =
      contour_image(sample_image(plane, {img.dims, img.origin, img.spacing})).output;
  const SideReport s = check_side(mesh.points, plane, Side::On, 4, 1.0);
  r.note("contour", fmt::format("{} points, {} triangles", mesh.points.size(), mesh.polys.size()));
  r.at_least("triangles", static_cast<double>(mesh.polys.size()), 1);
  r.equal("points off the plane (|F| > 4 ulp(float, max(|p|, 1)))", s.violations, std::size_t{0});
  r.at_most("worst point: |F| / tol", s.worst_ratio, 1.0);
  r.note("points with F != 0 (within tol)", fmt::format("{}", s.within_tolerance));
}

}  // namespace

void add_select_cases(std::vector<Case>& cases) {
  cases.push_back({"select/sphere-inside", "extract_cells of a 40^3 voxel grid inside a sphere",
                   true, [](CaseResult& r) {
                     select_case(r, F::sphere({0.05, -0.03, 0.02}, 0.6), true);
                   }});
  cases.push_back({"select/box-faces-on-grid-points",
                   "extract_cells inside the box [-0.3, 0.3]^3 whose faces pass through grid "
                   "points (F = 0 counts inside; stored as float, some are just outside)",
                   true, [](CaseResult& r) {
                     select_case(r, F::box({-0.3, -0.3, -0.3}, {0.3, 0.3, 0.3}), true);
                   }});
  cases.push_back({"select/torus-outside", "extract_cells of a 40^3 voxel grid outside a torus",
                   true, [](CaseResult& r) {
                     select_case(r, F::torus({0.02, 0.01, -0.03}, {0, 1, 1}, 0.55, 0.25), false);
                   }});
  cases.push_back({"side/plane-contour", "contour of a sampled plane: vertices on the plane", true,
                   [](CaseResult& r) { plane_case(r); }});
}

}  // namespace isoforge::verify
