// Cell machinery: shape functions, parametric <-> world mapping, derivatives, tables.
//
// References implemented:
// - Schroeder, Martin, Lorensen, "The Visualization Toolkit" (4th ed.), ch. 8: linear cell
//   types, VTK point orders, parametric coordinates, isoparametric interpolation functions and
//   the Newton iteration for the parametric coordinates of a world point.
// - Floater, "Mean value coordinates" (CAGD 2003); Hormann & Floater, "Mean value coordinates
//   for arbitrary planar polygons" (ACM TOG 2006): polygon interpolation weights.
// - Ericson, "Real-Time Collision Detection" (2005), ch. 5: closest points on segments,
//   triangles and convex cells (here: the minimum over faces).
// - Newell's method for the normal of a (possibly non-planar) polygon.

#include "isoforge/core/cell.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "isoforge/core/closest_point.hpp"
#include "isoforge/core/error.hpp"

namespace isoforge {

// ---------------------------------------------------------------------------------------------
// CellWeights
// ---------------------------------------------------------------------------------------------

void CellWeights::resize(std::size_t n) {
  size_ = n;
  if (n <= inline_.size()) {
    std::fill(inline_.begin(), inline_.end(), 0.0);
    heap_.clear();
  } else {
    heap_.assign(n, 0.0);
  }
}

namespace {

// ---------------------------------------------------------------------------------------------
// Tables
// ---------------------------------------------------------------------------------------------

constexpr Vec3 kVertexP[] = {{0, 0, 0}};
constexpr Vec3 kLineP[] = {{0, 0, 0}, {1, 0, 0}};
constexpr Vec3 kTriangleP[] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
constexpr Vec3 kPixelP[] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
constexpr Vec3 kQuadP[] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
constexpr Vec3 kTetraP[] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
constexpr Vec3 kVoxelP[] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0},
                            {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
constexpr Vec3 kHexP[] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                          {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
constexpr Vec3 kWedgeP[] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
constexpr Vec3 kPyramidP[] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 1}};

constexpr CellEdge kTriangleE[] = {{0, 1}, {1, 2}, {2, 0}};
constexpr CellEdge kPixelE[] = {{0, 1}, {1, 3}, {2, 3}, {0, 2}};
constexpr CellEdge kQuadE[] = {{0, 1}, {1, 2}, {3, 2}, {0, 3}};
constexpr CellEdge kTetraE[] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
constexpr CellEdge kVoxelE[] = {{0, 1}, {1, 3}, {2, 3}, {0, 2}, {4, 5}, {5, 7},
                                {6, 7}, {4, 6}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
constexpr CellEdge kHexE[] = {{0, 1}, {1, 2}, {3, 2}, {0, 3}, {4, 5}, {5, 6},
                              {7, 6}, {4, 7}, {0, 4}, {1, 5}, {3, 7}, {2, 6}};
constexpr CellEdge kWedgeE[] = {{0, 1}, {1, 2}, {2, 0}, {3, 4}, {4, 5},
                                {5, 3}, {0, 3}, {1, 4}, {2, 5}};
constexpr CellEdge kPyramidE[] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {0, 4}, {1, 4}, {2, 4}, {3, 4}};

constexpr CellFace kTetraF[] = {
    {{0, 1, 3, 0}, 3}, {{1, 2, 3, 0}, 3}, {{2, 0, 3, 0}, 3}, {{0, 2, 1, 0}, 3}};
constexpr CellFace kVoxelF[] = {{{0, 4, 6, 2}, 4}, {{1, 3, 7, 5}, 4}, {{0, 1, 5, 4}, 4},
                                {{2, 6, 7, 3}, 4}, {{0, 2, 3, 1}, 4}, {{4, 5, 7, 6}, 4}};
constexpr CellFace kHexF[] = {{{0, 4, 7, 3}, 4}, {{1, 2, 6, 5}, 4}, {{0, 1, 5, 4}, 4},
                              {{3, 7, 6, 2}, 4}, {{0, 3, 2, 1}, 4}, {{4, 5, 6, 7}, 4}};
constexpr CellFace kWedgeF[] = {
    {{0, 1, 2, 0}, 3}, {{3, 5, 4, 0}, 3}, {{0, 3, 4, 1}, 4}, {{1, 4, 5, 2}, 4}, {{2, 5, 3, 0}, 4}};
constexpr CellFace kPyramidF[] = {
    {{0, 3, 2, 1}, 4}, {{0, 1, 4, 0}, 3}, {{1, 2, 4, 0}, 3}, {{2, 3, 4, 0}, 3}, {{3, 0, 4, 0}, 3}};

// Newton iteration limits.
constexpr int kMaxNewtonIterations = 64;
constexpr int kMaxStepHalvings = 30;
constexpr double kNewtonStep = 1e-13;    // |delta| below this: converged
constexpr double kNewtonStalled = 1e-9;  // stalled with |delta| below this: converged
constexpr double kDiverged = 1e6;        // |pcoords| beyond this: diverged
constexpr double kSingular = 1e-14;      // relative determinant of a singular Jacobian
constexpr double kPyramidApexT = 1.0 - 1e-6;

// ---------------------------------------------------------------------------------------------
// Validation
// ---------------------------------------------------------------------------------------------

std::string tname(CellType type) {
  return std::string(cell_type_name(type));
}

[[noreturn]] void fail(const char* fn, const std::string& what) {
  throw Error(std::string(fn) + ": " + what);
}

void check_type(const char* fn, CellType type) {
  if (!is_valid_cell_type(static_cast<int>(type))) {
    fail(fn, type == CellType::Empty ? std::string("the empty cell type has no geometry")
                                     : "invalid cell type " + std::to_string(int(type)));
  }
}

void check_vec(const char* fn, const Vec3& v, const char* what) {
  if (!is_finite(v)) fail(fn, std::string(what) + " is not finite");
}

void check_points(const char* fn, CellType type, std::span<const Vec3> points) {
  check_type(fn, type);
  const int fixed = cell_fixed_size(type);
  if (fixed > 0 && points.size() != static_cast<std::size_t>(fixed)) {
    fail(fn, "a " + tname(type) + " needs " + std::to_string(fixed) + " points, got " +
                 std::to_string(points.size()));
  }
  if (fixed < 0 && points.size() < static_cast<std::size_t>(cell_min_size(type))) {
    fail(fn, "a " + tname(type) + " needs at least " + std::to_string(cell_min_size(type)) +
                 " points, got " + std::to_string(points.size()));
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!is_finite(points[i])) {
      fail(fn, "point " + std::to_string(i) + " of the " + tname(type) + " is not finite");
    }
  }
}

int require_fixed(const char* fn, CellType type) {
  check_type(fn, type);
  const int n = cell_fixed_size(type);
  if (n <= 0) {
    fail(fn, "a " + tname(type) +
                 " has no fixed parametric points (variable size: use evaluate_weights, "
                 "locate_in_cell or sub_cell)");
  }
  return n;
}

// ---------------------------------------------------------------------------------------------
// Shape functions (fixed-size types, no validation)
// ---------------------------------------------------------------------------------------------

std::span<const Vec3> pcoords_table(CellType type) {
  switch (type) {
    case CellType::Vertex:
      return kVertexP;
    case CellType::Line:
      return kLineP;
    case CellType::Triangle:
      return kTriangleP;
    case CellType::Pixel:
      return kPixelP;
    case CellType::Quad:
      return kQuadP;
    case CellType::Tetra:
      return kTetraP;
    case CellType::Voxel:
      return kVoxelP;
    case CellType::Hexahedron:
      return kHexP;
    case CellType::Wedge:
      return kWedgeP;
    case CellType::Pyramid:
      return kPyramidP;
    default:
      return {};
  }
}

// Tensor-product (multilinear) shape functions of pixel, quad, voxel, hexahedron: the corner
// table gives, for each point, which end (0 or 1) of each parametric axis it sits at.
void tensor_weights(std::span<const Vec3> corners, int dim, const Vec3& pc, double* w) {
  for (std::size_t i = 0; i < corners.size(); ++i) {
    double v = 1;
    for (int d = 0; d < dim; ++d) v *= corners[i][d] > 0.5 ? pc[d] : 1 - pc[d];
    w[i] = v;
  }
}

void tensor_derivs(std::span<const Vec3> corners, int dim, const Vec3& pc, double* out) {
  const std::size_t n = corners.size();
  for (std::size_t i = 0; i < n; ++i) {
    for (int d = 0; d < 3; ++d) {
      double v = 0;
      if (d < dim) {
        v = corners[i][d] > 0.5 ? 1.0 : -1.0;
        for (int e = 0; e < dim; ++e) {
          if (e != d) v *= corners[i][e] > 0.5 ? pc[e] : 1 - pc[e];
        }
      }
      out[d * n + i] = v;
    }
  }
}

void shape(CellType type, const Vec3& pc, double* w) {
  const double r = pc.x, s = pc.y, t = pc.z;
  switch (type) {
    case CellType::Vertex:
      w[0] = 1;
      return;
    case CellType::Line:
      w[0] = 1 - r;
      w[1] = r;
      return;
    case CellType::Triangle:
      w[0] = 1 - r - s;
      w[1] = r;
      w[2] = s;
      return;
    case CellType::Tetra:
      w[0] = 1 - r - s - t;
      w[1] = r;
      w[2] = s;
      w[3] = t;
      return;
    case CellType::Pixel:
      tensor_weights(kPixelP, 2, pc, w);
      return;
    case CellType::Quad:
      tensor_weights(kQuadP, 2, pc, w);
      return;
    case CellType::Voxel:
      tensor_weights(kVoxelP, 3, pc, w);
      return;
    case CellType::Hexahedron:
      tensor_weights(kHexP, 3, pc, w);
      return;
    case CellType::Wedge: {
      const double u = 1 - r - s;
      w[0] = u * (1 - t);
      w[1] = r * (1 - t);
      w[2] = s * (1 - t);
      w[3] = u * t;
      w[4] = r * t;
      w[5] = s * t;
      return;
    }
    case CellType::Pyramid: {
      tensor_weights(kQuadP, 2, pc, w);
      for (int i = 0; i < 4; ++i) w[i] *= 1 - t;
      w[4] = t;
      return;
    }
    default:
      invariant_failed("shape: a fixed-size type", __FILE__, __LINE__);
  }
}

// d[k * n + i] = d N_i / d p_k.
void shape_derivs(CellType type, const Vec3& pc, double* d) {
  const double r = pc.x, s = pc.y, t = pc.z;
  switch (type) {
    case CellType::Vertex:
      d[0] = d[1] = d[2] = 0;
      return;
    case CellType::Line: {
      const double v[6] = {-1, 1, 0, 0, 0, 0};
      std::copy(v, v + 6, d);
      return;
    }
    case CellType::Triangle: {
      const double v[9] = {-1, 1, 0, -1, 0, 1, 0, 0, 0};
      std::copy(v, v + 9, d);
      return;
    }
    case CellType::Tetra: {
      const double v[12] = {-1, 1, 0, 0, -1, 0, 1, 0, -1, 0, 0, 1};
      std::copy(v, v + 12, d);
      return;
    }
    case CellType::Pixel:
      tensor_derivs(kPixelP, 2, pc, d);
      return;
    case CellType::Quad:
      tensor_derivs(kQuadP, 2, pc, d);
      return;
    case CellType::Voxel:
      tensor_derivs(kVoxelP, 3, pc, d);
      return;
    case CellType::Hexahedron:
      tensor_derivs(kHexP, 3, pc, d);
      return;
    case CellType::Wedge: {
      const double u = 1 - r - s;
      const double v[18] = {-(1 - t), 1 - t, 0,     -t, t, 0,   // d/dr
                            -(1 - t), 0,     1 - t, -t, 0, t,   // d/ds
                            -u,       -r,    -s,    u,  r, s};  // d/dt
      std::copy(v, v + 18, d);
      return;
    }
    case CellType::Pyramid: {
      double q[4], dq[12];
      tensor_weights(kQuadP, 2, pc, q);
      tensor_derivs(kQuadP, 2, pc, dq);
      for (int i = 0; i < 4; ++i) {
        d[0 * 5 + i] = dq[0 * 4 + i] * (1 - t);
        d[1 * 5 + i] = dq[1 * 4 + i] * (1 - t);
        d[2 * 5 + i] = -q[i];
      }
      d[0 * 5 + 4] = 0;
      d[1 * 5 + 4] = 0;
      d[2 * 5 + 4] = 1;
      return;
    }
    default:
      invariant_failed("shape_derivs: a fixed-size type", __FILE__, __LINE__);
  }
}

Vec3 center_of(CellType type) {
  switch (type) {
    case CellType::Vertex:
    case CellType::PolyVertex:
      return {0, 0, 0};
    case CellType::Line:
    case CellType::PolyLine:
      return {0.5, 0, 0};
    case CellType::Triangle:
    case CellType::TriangleStrip:
      return {1.0 / 3, 1.0 / 3, 0};
    case CellType::Pixel:
    case CellType::Quad:
    case CellType::Polygon:
      return {0.5, 0.5, 0};
    case CellType::Tetra:
      return {0.25, 0.25, 0.25};
    case CellType::Voxel:
    case CellType::Hexahedron:
      return {0.5, 0.5, 0.5};
    case CellType::Wedge:
      return {1.0 / 3, 1.0 / 3, 0.5};
    case CellType::Pyramid:
      return {0.5, 0.5, 0.2};
    case CellType::Empty:
      break;
  }
  return {};
}

CellType sub_type(CellType type) {
  switch (type) {
    case CellType::PolyVertex:
      return CellType::Vertex;
    case CellType::PolyLine:
      return CellType::Line;
    case CellType::TriangleStrip:
      return CellType::Triangle;
    default:
      return type;
  }
}

double domain_distance(CellType type, const Vec3& pc) {
  const double r = pc.x, s = pc.y, t = pc.z;
  double d = 0;
  auto box = [&](int dims) {
    for (int k = 0; k < dims; ++k) d = std::max({d, -pc[k], pc[k] - 1});
  };
  switch (sub_type(type)) {
    case CellType::Vertex:
      break;
    case CellType::Line:
      box(1);
      break;
    case CellType::Triangle:
      d = std::max({d, -r, -s, r + s - 1});
      break;
    case CellType::Pixel:
    case CellType::Quad:
    case CellType::Polygon:
      box(2);
      break;
    case CellType::Tetra:
      d = std::max({d, -r, -s, -t, r + s + t - 1});
      break;
    case CellType::Voxel:
    case CellType::Hexahedron:
    case CellType::Pyramid:
      box(3);
      break;
    case CellType::Wedge:
      d = std::max({d, -r, -s, r + s - 1, -t, t - 1});
      break;
    default:
      break;
  }
  return d;
}

// ---------------------------------------------------------------------------------------------
// Small geometry helpers
// ---------------------------------------------------------------------------------------------

double max_abs(const Vec3& v) {
  return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
}

// Solves M g = b where M has rows c0, c1, c2. Returns false if M is singular relative to the
// lengths of its rows.
bool solve_rows(const Vec3& c0, const Vec3& c1, const Vec3& c2, const Vec3& b, Vec3& g) {
  const Vec3 x12 = cross(c1, c2), x20 = cross(c2, c0), x01 = cross(c0, c1);
  const double det = dot(c0, x12);
  const double scale = norm(c0) * norm(c1) * norm(c2);
  if (!(std::abs(det) > kSingular * scale) || !std::isfinite(det)) return false;
  g = (b.x * x12 + b.y * x20 + b.z * x01) / det;
  return true;
}

// Solves [c0 c1 c2] (as columns) d = b. Returns false if the matrix is singular relative to
// its column lengths, or a column is shorter than `min_col` (a collapsed direction whose
// length is rounding noise).
bool solve_cols(const Vec3& c0, const Vec3& c1, const Vec3& c2, const Vec3& b, Vec3& d,
                double min_col = 0) {
  const double l0 = norm(c0), l1 = norm(c1), l2 = norm(c2);
  if (!(l0 > min_col && l1 > min_col && l2 > min_col)) return false;
  const double det = dot(c0, cross(c1, c2));
  const double scale = l0 * l1 * l2;
  if (!(std::abs(det) > kSingular * scale) || !std::isfinite(det)) return false;
  d = Vec3{dot(b, cross(c1, c2)), dot(c0, cross(b, c2)), dot(c0, cross(c1, b))} / det;
  return true;
}

struct Closest {
  Vec3 point;
  double dist2 = std::numeric_limits<double>::infinity();
  void offer(const Vec3& p, const Vec3& x) {
    const double d2 = norm2(x - p);
    if (d2 < dist2) {
      dist2 = d2;
      point = p;
    }
  }
};

// Barycentric (r, s) of the projection of x onto the plane of triangle (a, b, c); false if the
// triangle is degenerate.
bool triangle_project(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& x, double& r,
                      double& s) {
  const Vec3 e1 = b - a, e2 = c - a, v = x - a;
  const double g11 = dot(e1, e1), g12 = dot(e1, e2), g22 = dot(e2, e2);
  const double det = g11 * g22 - g12 * g12;
  if (!(det > 1e-14 * g11 * g22) || !std::isfinite(det)) return false;
  const double b1 = dot(v, e1), b2 = dot(v, e2);
  r = (g22 * b1 - g12 * b2) / det;
  s = (g11 * b2 - g12 * b1) / det;
  return true;
}


// ---------------------------------------------------------------------------------------------
// Newton iterations
// ---------------------------------------------------------------------------------------------

// Length below which a Jacobian column of a cell counts as collapsed (relative to the cell).
double collapsed_length(std::span<const Vec3> pts) {
  Bounds b;
  for (const Vec3& p : pts) b.extend(p);
  return 1e-10 * b.diagonal();
}

struct NewtonResult {
  bool converged = false;
  Vec3 pc;
};

Vec3 location_fixed(CellType type, std::span<const Vec3> pts, const Vec3& pc) {
  double w[kMaxCellPoints] = {};
  shape(type, pc, w);
  Vec3 x{};
  for (std::size_t i = 0; i < pts.size(); ++i) x += w[i] * pts[i];
  return x;
}

// Columns dX/dr, dX/ds, dX/dt of the Jacobian of a fixed-size type.
void jacobian(CellType type, std::span<const Vec3> pts, const Vec3& pc, Vec3 cols[3]) {
  double d[3 * kMaxCellPoints] = {};
  shape_derivs(type, pc, d);
  const std::size_t n = pts.size();
  for (int k = 0; k < 3; ++k) {
    Vec3 c{};
    for (std::size_t i = 0; i < n; ++i) c += d[k * n + i] * pts[i];
    cols[k] = c;
  }
}

// Newton iteration for X(pc) = x on a 3D cell, from the parametric center, with step halving.
// Backtracking along a Newton step: halves `delta` until the merit (|f| or |f|^2) of the
// residual at pc + lambda delta drops below `merit`. On success sets pc, f and merit to the new
// point and returns true; returns false (leaving them alone) when no halving helps.
template <class Residual, class Merit>
bool halving_step(Vec3& pc, const Vec3& delta, Vec3& f, double& merit, Residual&& residual,
                  Merit&& merit_of) {
  double lambda = 1;
  for (int h = 0; h < kMaxStepHalvings; ++h) {
    const Vec3 pn = pc + lambda * delta;
    const Vec3 fn = residual(pn);
    const double mn = merit_of(fn);
    if (mn < merit) {
      pc = pn;
      f = fn;
      merit = mn;
      return true;
    }
    lambda *= 0.5;
  }
  return false;
}

NewtonResult newton_3d(CellType type, std::span<const Vec3> pts, const Vec3& x) {
  NewtonResult res;
  Vec3 pc = center_of(type);
  const double min_col = collapsed_length(pts);
  Vec3 f = location_fixed(type, pts, pc) - x;
  double fn = norm(f);
  for (int it = 0; it < kMaxNewtonIterations; ++it) {
    if (fn == 0) {
      res.converged = true;
      break;
    }
    Vec3 cols[3];
    Vec3 pj = pc;  // the pyramid's Jacobian is singular at the apex: evaluate just below it
    if (type == CellType::Pyramid) pj.z = std::min(pj.z, kPyramidApexT);
    jacobian(type, pts, pj, cols);
    Vec3 delta;
    if (!solve_cols(cols[0], cols[1], cols[2], -f, delta, min_col)) break;
    const double step = max_abs(delta);
    if (step <= kNewtonStep) {
      pc += delta;
      res.converged = true;
      break;
    }
    if (!halving_step(pc, delta, f, fn, [&](const Vec3& p) { return location_fixed(type, pts, p) - x; },
                      [](const Vec3& r) { return norm(r); })) {
      // At the rounding floor of the residual (converged) or at a non-zero local minimum.
      res.converged = step <= kNewtonStalled;
      break;
    }
    if (max_abs(pc) > kDiverged) break;
  }
  res.pc = pc;
  return res;
}

// Orthogonal projection of x onto a bilinear quad (points in quad order) from one start:
// Newton on phi(r, s) = |x - X(r, s)|^2 / 2 with its exact Hessian J^T J - (x - X) . X_rs
// (X_rr = X_ss = 0 for a bilinear patch). Where that Hessian is not positive definite the
// Gauss-Newton step (J^T J) d = J^T (x - X) is used instead; it equals solving the square
// system [dX/dr dX/ds n] (dr ds dw) = x - X. Step halving keeps phi decreasing.
NewtonResult newton_quad_from(std::span<const Vec3> q, const Vec3& x, Vec3 pc) {
  NewtonResult res;
  const double min_col = collapsed_length(q);
  const Vec3 xrs = q[0] - q[1] + q[2] - q[3];
  Vec3 f = x - location_fixed(CellType::Quad, q, pc);
  double phi = norm2(f);
  for (int it = 0; it < kMaxNewtonIterations; ++it) {
    Vec3 cols[3];
    jacobian(CellType::Quad, q, pc, cols);
    const double l0 = norm(cols[0]), l1 = norm(cols[1]);
    if (!(l0 > min_col && l1 > min_col)) break;
    const double a11 = dot(cols[0], cols[0]), a12 = dot(cols[0], cols[1]);
    const double a22 = dot(cols[1], cols[1]);
    const double g1 = dot(cols[0], f), g2 = dot(cols[1], f);  // -gradient of phi
    const double det_gn = a11 * a22 - a12 * a12;
    if (!(det_gn > kSingular * a11 * a22)) break;  // J rank deficient
    const double h12 = a12 - dot(f, xrs);
    const double det_h = a11 * a22 - h12 * h12;
    Vec3 delta{};
    if (det_h > 1e-12 * a11 * a22) {  // Hessian positive definite (a11 > 0): Newton
      delta = {(a22 * g1 - h12 * g2) / det_h, (a11 * g2 - h12 * g1) / det_h, 0};
    } else {  // Gauss-Newton
      delta = {(a22 * g1 - a12 * g2) / det_gn, (a11 * g2 - a12 * g1) / det_gn, 0};
    }
    const double step = max_abs(delta);
    if (step <= kNewtonStep) {
      pc += delta;
      res.converged = true;
      break;
    }
    if (!halving_step(pc, delta, f, phi, [&](const Vec3& p) { return x - location_fixed(CellType::Quad, q, p); },
                      [](const Vec3& r) { return norm2(r); })) {
      res.converged = step <= kNewtonStalled;
      break;
    }
    if (max_abs(pc) > kDiverged) break;
  }
  res.pc = pc;
  return res;
}

// Orthogonal projection of x onto a bilinear quad: Newton from the center, and if that does
// not end inside the quad, from four more starts (a curved patch seen from far away can have
// several stationary points). Returns the converged in-quad result closest to x if any, else
// the result from the center.
NewtonResult newton_quad(std::span<const Vec3> q, const Vec3& x) {
  const NewtonResult first = newton_quad_from(q, x, {0.5, 0.5, 0});
  if (first.converged && domain_distance(CellType::Quad, first.pc) <= 0) return first;
  NewtonResult best = first;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (const Vec3 start :
       {Vec3{0.2, 0.2, 0}, Vec3{0.8, 0.2, 0}, Vec3{0.8, 0.8, 0}, Vec3{0.2, 0.8, 0}}) {
    const NewtonResult nr = newton_quad_from(q, x, start);
    if (!nr.converged || domain_distance(CellType::Quad, nr.pc) > 0) continue;
    const double d2 = norm2(x - location_fixed(CellType::Quad, q, nr.pc));
    if (d2 < best_d2) {
      best_d2 = d2;
      best = nr;
    }
  }
  return best;
}

// Closest point of a bilinear quad: the smaller of the interior stationary point found by
// Newton (if it lies in the quad) and the closest points of the four edges.
Vec3 closest_on_quad(std::span<const Vec3> q, const Vec3& x) {
  Closest best;
  for (int e = 0; e < 4; ++e) best.offer(closest_on_segment(x, q[e], q[(e + 1) % 4]).point, x);
  const NewtonResult nr = newton_quad(q, x);
  if (nr.converged && domain_distance(CellType::Quad, nr.pc) <= 0) {
    best.offer(location_fixed(CellType::Quad, q, nr.pc), x);
  }
  return best.point;
}

// Exact closest point of the boundary of a fixed-size 3D cell (its faces).
Vec3 closest_on_boundary_3d(CellType type, std::span<const Vec3> pts, const Vec3& x) {
  Closest best;
  for (const CellFace& f : cell_faces(type)) {
    if (f.size == 3) {
      best.offer(closest_on_triangle(x, pts[f.ids[0]], pts[f.ids[1]], pts[f.ids[2]]).point, x);
    } else {
      const Vec3 q[4] = {pts[f.ids[0]], pts[f.ids[1]], pts[f.ids[2]], pts[f.ids[3]]};
      best.offer(closest_on_quad(q, x), x);
    }
  }
  return best.point;
}

// ---------------------------------------------------------------------------------------------
// Polygon frame and mean value coordinates
// ---------------------------------------------------------------------------------------------

struct PolygonFrame {
  Vec3 origin, u, v, n;
  double u0 = 0, v0 = 0, du = 1, dv = 1;
  bool degenerate = false;
  [[nodiscard]] std::array<double, 2> to2d(const Vec3& p) const {
    const Vec3 d = p - origin;
    return {dot(d, u), dot(d, v)};
  }
  [[nodiscard]] Vec3 to3d(double a, double b) const { return origin + a * u + b * v; }
};

PolygonFrame polygon_frame(std::span<const Vec3> pts) {
  PolygonFrame fr;
  const std::size_t n = pts.size();
  Vec3 c{};
  for (const Vec3& p : pts) c += p;
  c = c / static_cast<double>(n);
  Vec3 nn{};
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 a = pts[i] - c, b = pts[(i + 1) % n] - c;
    nn += cross(a, b);  // Newell's method (twice the vector area)
  }
  double nl = norm(nn);
  double extent = 0;
  for (const Vec3& p : pts) extent = std::max(extent, norm(p - c));
  if (!(nl > 1e-14 * extent * extent)) {
    fr.degenerate = true;
    nn = {0, 0, 1};
    nl = 1;
  }
  fr.n = nn / nl;
  fr.origin = pts[0] - dot(pts[0] - c, fr.n) * fr.n;
  // r axis: first point direction from point 0 with an in-plane component.
  fr.u = {};
  for (std::size_t i = 1; i < n; ++i) {
    Vec3 d = pts[i] - pts[0];
    d -= dot(d, fr.n) * fr.n;
    const double l = norm(d);
    if (l > 1e-14 * extent) {
      fr.u = d / l;
      break;
    }
  }
  if (norm2(fr.u) == 0) {
    fr.degenerate = true;
    // Any unit vector perpendicular to n.
    const Vec3 a = std::abs(fr.n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    fr.u = cross(fr.n, a);
    fr.u = fr.u / norm(fr.u);
  }
  fr.v = cross(fr.n, fr.u);
  double umin = 0, umax = 0, vmin = 0, vmax = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto q = fr.to2d(pts[i]);
    if (i == 0) {
      umin = umax = q[0];
      vmin = vmax = q[1];
    }
    umin = std::min(umin, q[0]);
    umax = std::max(umax, q[0]);
    vmin = std::min(vmin, q[1]);
    vmax = std::max(vmax, q[1]);
  }
  fr.u0 = umin;
  fr.v0 = vmin;
  fr.du = umax - umin;
  fr.dv = vmax - vmin;
  if (!(fr.du > 0)) fr.du = 1;
  if (!(fr.dv > 0)) fr.dv = 1;
  return fr;
}

using P2 = std::array<double, 2>;

// Mean value coordinates of x w.r.t. the 2D polygon q (Hormann & Floater 2006).
void mean_value_weights(std::span<const P2> q, const P2& x, double* w) {
  const std::size_t n = q.size();
  std::vector<double> r(n), t(n);
  std::vector<P2> s(n);
  double scale = 0;
  for (std::size_t i = 0; i < n; ++i) {
    s[i] = {q[i][0] - x[0], q[i][1] - x[1]};
    r[i] = std::hypot(s[i][0], s[i][1]);
    scale = std::max(scale, r[i]);
  }
  for (std::size_t i = 0; i < n; ++i) w[i] = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (r[i] <= 1e-15 * scale) {  // at a vertex
      w[i] = 1;
      return;
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    const double a = s[i][0] * s[j][1] - s[i][1] * s[j][0];  // 2 * signed area
    const double d = s[i][0] * s[j][0] + s[i][1] * s[j][1];
    if (std::abs(a) <= 1e-14 * r[i] * r[j] && d < 0) {  // on edge (i, j): linear
      w[i] = r[j] / (r[i] + r[j]);
      w[j] = r[i] / (r[i] + r[j]);
      return;
    }
    t[i] = a / (r[i] * r[j] + d);  // tan(alpha_i / 2)
  }
  double sum = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t prev = (i + n - 1) % n;
    w[i] = (t[prev] + t[i]) / r[i];
    sum += w[i];
  }
  if (!(std::abs(sum) > 1e-300) || !std::isfinite(sum)) {
    // Should not happen off the boundary; fall back to the nearest vertex.
    std::size_t best = 0;
    for (std::size_t i = 1; i < n; ++i) {
      if (r[i] < r[best]) best = i;
    }
    for (std::size_t i = 0; i < n; ++i) w[i] = i == best ? 1 : 0;
    return;
  }
  for (std::size_t i = 0; i < n; ++i) w[i] /= sum;
}

std::vector<P2> polygon_2d(const PolygonFrame& fr, std::span<const Vec3> pts) {
  std::vector<P2> q(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) q[i] = fr.to2d(pts[i]);
  return q;
}

// Even-odd point in polygon test.
bool point_in_polygon(std::span<const P2> q, const P2& x) {
  bool in = false;
  const std::size_t n = q.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const P2& a = q[i];
    const P2& b = q[j];
    if ((a[1] > x[1]) != (b[1] > x[1])) {
      const double xc = a[0] + (x[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
      if (x[0] < xc) in = !in;
    }
  }
  return in;
}

double distance_to_polygon_boundary_2d(std::span<const P2> q, const P2& x) {
  double best = std::numeric_limits<double>::infinity();
  const std::size_t n = q.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 a{q[i][0], q[i][1], 0}, b{q[(i + 1) % n][0], q[(i + 1) % n][1], 0};
    const Vec3 p{x[0], x[1], 0};
    best = std::min(best, std::sqrt(segment_distance2(p, a, b)));
  }
  return best;
}

Vec3 polygon_location(const PolygonFrame& fr, const Vec3& pc) {
  return fr.to3d(fr.u0 + pc.x * fr.du, fr.v0 + pc.y * fr.dv);
}

// ---------------------------------------------------------------------------------------------
// Implementations without validation
// ---------------------------------------------------------------------------------------------

SubCell sub_cell_impl(CellType type, int sub_id) {
  SubCell sc;
  sc.type = sub_type(type);
  switch (type) {
    case CellType::PolyVertex:
      sc.ids = {sub_id, 0, 0};
      sc.size = 1;
      break;
    case CellType::PolyLine:
      sc.ids = {sub_id, sub_id + 1, 0};
      sc.size = 2;
      break;
    case CellType::TriangleStrip:
      if (sub_id % 2 == 0) {
        sc.ids = {sub_id, sub_id + 1, sub_id + 2};
      } else {
        sc.ids = {sub_id + 1, sub_id, sub_id + 2};
      }
      sc.size = 3;
      break;
    default:
      break;
  }
  return sc;
}

int num_sub_cells_impl(CellType type, std::size_t n) {
  switch (type) {
    case CellType::PolyVertex:
      return static_cast<int>(n);
    case CellType::PolyLine:
      return static_cast<int>(n) - 1;
    case CellType::TriangleStrip:
      return static_cast<int>(n) - 2;
    default:
      return 1;
  }
}

void check_sub_id(const char* fn, CellType type, std::size_t n, int sub_id) {
  const int count = num_sub_cells_impl(type, n);
  if (sub_id < 0 || sub_id >= count) {
    fail(fn, "sub_id " + std::to_string(sub_id) + " is out of range for a " + tname(type) +
                 " with " + std::to_string(n) + " points (" + std::to_string(count) +
                 " sub-cells)");
  }
}

Vec3 evaluate_location_impl(CellType type, std::span<const Vec3> pts, const Vec3& pc, int sub_id) {
  if (is_composite_cell(type)) {
    const SubCell sc = sub_cell_impl(type, sub_id);
    Vec3 sp[3];
    for (int i = 0; i < sc.size; ++i) sp[i] = pts[sc.ids[i]];
    return location_fixed(sc.type, std::span<const Vec3>(sp, sc.size), pc);
  }
  if (type == CellType::Polygon) return polygon_location(polygon_frame(pts), pc);
  return location_fixed(type, pts, pc);
}

void evaluate_weights_impl(CellType type, std::span<const Vec3> pts, const Vec3& pc, int sub_id,
                           CellWeights& w) {
  w.resize(pts.size());
  if (is_composite_cell(type)) {
    const SubCell sc = sub_cell_impl(type, sub_id);
    double sw[3];
    shape(sc.type, pc, sw);
    for (int i = 0; i < sc.size; ++i) w[sc.ids[i]] = sw[i];
    return;
  }
  if (type == CellType::Polygon) {
    const PolygonFrame fr = polygon_frame(pts);
    const auto q = polygon_2d(fr, pts);
    mean_value_weights(q, {fr.u0 + pc.x * fr.du, fr.v0 + pc.y * fr.dv}, w.data());
    return;
  }
  shape(type, pc, w.data());
}

void finish_fixed(CellType type, CellPosition& pos) {
  pos.weights.resize(static_cast<std::size_t>(cell_fixed_size(type)));
  shape(type, pos.pcoords, pos.weights.data());
}

CellPosition locate_impl(CellType type, std::span<const Vec3> pts, const Vec3& x, double tol);

CellPosition locate_line(std::span<const Vec3> p, const Vec3& x, double tol) {
  CellPosition pos;
  const Vec3 e = p[1] - p[0];
  const double l2 = norm2(e);
  if (!(l2 > 0)) {
    pos.converged = false;
    pos.pcoords = {0, 0, 0};
  } else {
    pos.pcoords = {dot(x - p[0], e) / l2, 0, 0};
  }
  pos.inside = pos.converged && domain_distance(CellType::Line, pos.pcoords) <= tol;
  pos.closest_point = pos.inside ? p[0] + pos.pcoords.x * e : closest_on_segment(x, p[0], p[1]).point;
  pos.dist2 = norm2(x - pos.closest_point);
  finish_fixed(CellType::Line, pos);
  return pos;
}

CellPosition locate_triangle(std::span<const Vec3> p, const Vec3& x, double tol) {
  CellPosition pos;
  double r = 0, s = 0;
  if (!triangle_project(p[0], p[1], p[2], x, r, s)) {
    pos.converged = false;
    // Degenerate: the closest point of its edges, with its parametric coordinates.
    const TriangleClosest c = closest_on_triangle_edges(x, p[0], p[1], p[2]);
    pos.closest_point = c.point;
    pos.pcoords = {c.s, c.t, 0};
  } else {
    pos.pcoords = {r, s, 0};
    pos.inside = domain_distance(CellType::Triangle, pos.pcoords) <= tol;
    pos.closest_point = pos.inside ? p[0] + r * (p[1] - p[0]) + s * (p[2] - p[0])
                                   : closest_on_triangle(x, p[0], p[1], p[2]).point;
  }
  pos.dist2 = norm2(x - pos.closest_point);
  finish_fixed(CellType::Triangle, pos);
  return pos;
}

// Pixel and voxel: p0 + r e1 + s e2 (+ t e3) with orthogonal edge vectors from point 0.
CellPosition locate_box(CellType type, std::span<const Vec3> p, const Vec3& x, double tol) {
  CellPosition pos;
  const int dim = type == CellType::Voxel ? 3 : 2;
  const Vec3 axes[3] = {p[1] - p[0], p[2] - p[0], dim == 3 ? p[4] - p[0] : Vec3{}};
  Vec3 pc{}, clamped{};
  Vec3 proj = p[0], closest = p[0];
  for (int d = 0; d < dim; ++d) {
    const double l2 = norm2(axes[d]);
    if (!(l2 > 0)) {
      pos.converged = false;
      continue;
    }
    pc[d] = dot(x - p[0], axes[d]) / l2;
    clamped[d] = std::clamp(pc[d], 0.0, 1.0);
    proj += pc[d] * axes[d];
    closest += clamped[d] * axes[d];
  }
  pos.pcoords = pc;
  pos.inside = pos.converged && domain_distance(type, pc) <= tol;
  if (pos.inside) {
    pos.closest_point = dim == 3 ? x : proj;
  } else {
    pos.closest_point = closest;
  }
  pos.dist2 = pos.inside && dim == 3 ? 0.0 : norm2(x - pos.closest_point);
  finish_fixed(type, pos);
  return pos;
}

CellPosition locate_quad(std::span<const Vec3> p, const Vec3& x, double tol) {
  CellPosition pos;
  const NewtonResult nr = newton_quad(p, x);
  pos.converged = nr.converged;
  if (nr.converged) {
    pos.pcoords = nr.pc;
    pos.inside = domain_distance(CellType::Quad, nr.pc) <= tol;
  }
  Closest edge;
  for (int e = 0; e < 4; ++e) edge.offer(closest_on_segment(x, p[e], p[(e + 1) % 4]).point, x);
  if (pos.inside) {
    pos.closest_point = location_fixed(CellType::Quad, p, nr.pc);
    // A strongly curved or folded quad can have a projection that is only a local minimum of
    // the distance: then the boundary is closer and x does not project into the quad.
    const double proj_d2 = norm2(x - pos.closest_point);
    if (edge.dist2 < proj_d2 * (1 - 1e-9)) pos.inside = false;
  }
  if (!pos.inside) {
    pos.closest_point = edge.point;
    if (!nr.converged) {
      const NewtonResult nc = newton_quad(p, pos.closest_point);
      pos.pcoords = nc.converged ? nc.pc : center_of(CellType::Quad);
    }
  }
  pos.dist2 = norm2(x - pos.closest_point);
  finish_fixed(CellType::Quad, pos);
  return pos;
}

CellPosition locate_tetra(std::span<const Vec3> p, const Vec3& x, double tol) {
  CellPosition pos;
  Vec3 pc;
  if (solve_cols(p[1] - p[0], p[2] - p[0], p[3] - p[0], x - p[0], pc)) {
    pos.pcoords = pc;
    pos.inside = domain_distance(CellType::Tetra, pc) <= tol;
  } else {
    pos.converged = false;
  }
  if (pos.inside) {
    pos.closest_point = x;
    pos.dist2 = 0;
  } else {
    pos.closest_point = closest_on_boundary_3d(CellType::Tetra, p, x);
    pos.dist2 = norm2(x - pos.closest_point);
    if (!pos.converged) {
      // Barycentric coordinates of the closest point in its best face.
      pos.pcoords = center_of(CellType::Tetra);
      double best = std::numeric_limits<double>::infinity();
      for (const CellFace& f : kTetraF) {
        const Vec3& a = p[f.ids[0]];
        const Vec3& b = p[f.ids[1]];
        const Vec3& c = p[f.ids[2]];
        double r, s;
        if (!triangle_project(a, b, c, pos.closest_point, r, s)) continue;
        const double d = domain_distance(CellType::Triangle, {r, s, 0});
        if (d < best) {
          best = d;
          pos.pcoords =
              kTetraP[f.ids[0]] * (1 - r - s) + kTetraP[f.ids[1]] * r + kTetraP[f.ids[2]] * s;
        }
      }
    }
  }
  finish_fixed(CellType::Tetra, pos);
  return pos;
}

CellPosition locate_newton(CellType type, std::span<const Vec3> p, const Vec3& x, double tol) {
  CellPosition pos;
  const NewtonResult nr = newton_3d(type, p, x);
  pos.converged = nr.converged;
  if (nr.converged) {
    pos.pcoords = nr.pc;
    pos.inside = domain_distance(type, nr.pc) <= tol;
  }
  if (pos.inside) {
    pos.closest_point = x;
    pos.dist2 = 0;
  } else {
    pos.closest_point = closest_on_boundary_3d(type, p, x);
    pos.dist2 = norm2(x - pos.closest_point);
    if (!nr.converged) {
      const NewtonResult nc = newton_3d(type, p, pos.closest_point);
      pos.pcoords = nc.converged ? nc.pc : center_of(type);
    }
  }
  finish_fixed(type, pos);
  return pos;
}

CellPosition locate_polygon(std::span<const Vec3> p, const Vec3& x, double tol) {
  CellPosition pos;
  const PolygonFrame fr = polygon_frame(p);
  const auto q = polygon_2d(fr, p);
  const P2 x2 = fr.to2d(x);
  const Vec3 proj = fr.to3d(x2[0], x2[1]);
  Closest edge;
  for (std::size_t i = 0; i < p.size(); ++i) {
    edge.offer(closest_on_segment(x, p[i], p[(i + 1) % p.size()]).point, x);
  }
  pos.weights.resize(p.size());
  if (fr.degenerate) {
    pos.converged = false;
    pos.closest_point = edge.point;
    const P2 c2 = fr.to2d(edge.point);
    pos.pcoords = {(c2[0] - fr.u0) / fr.du, (c2[1] - fr.v0) / fr.dv, 0};
    // Linear weights along the closest edge.
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < p.size(); ++i) {
      const std::size_t j = (i + 1) % p.size();
      const SegmentClosest c = closest_on_segment(x, p[i], p[j]);
      const double d2 = c.dist2, t = c.t;
      if (d2 < best) {
        best = d2;
        for (double& w : pos.weights) w = 0;
        pos.weights[i] = 1 - t;
        pos.weights[j] += t;
      }
    }
  } else {
    pos.pcoords = {(x2[0] - fr.u0) / fr.du, (x2[1] - fr.v0) / fr.dv, 0};
    pos.inside = point_in_polygon(q, x2) ||
                 distance_to_polygon_boundary_2d(q, x2) <= tol * std::max(fr.du, fr.dv);
    pos.closest_point = pos.inside ? proj : edge.point;
    mean_value_weights(q, x2, pos.weights.data());
  }
  pos.dist2 = norm2(x - pos.closest_point);
  return pos;
}

CellPosition locate_composite(CellType type, std::span<const Vec3> p, const Vec3& x, double tol) {
  CellPosition best;
  bool have = false;
  const int count = num_sub_cells_impl(type, p.size());
  for (int id = 0; id < count; ++id) {
    const SubCell sc = sub_cell_impl(type, id);
    Vec3 sp[3];
    for (int i = 0; i < sc.size; ++i) sp[i] = p[sc.ids[i]];
    CellPosition c = locate_impl(sc.type, std::span<const Vec3>(sp, sc.size), x, tol);
    const bool better =
        !have || c.dist2 < best.dist2 || (c.dist2 == best.dist2 && c.inside && !best.inside);
    if (!better) continue;
    have = true;
    CellWeights w(p.size());
    for (int i = 0; i < sc.size; ++i) w[sc.ids[i]] = c.weights[i];
    c.weights = w;
    c.sub_id = id;
    best = std::move(c);
  }
  return best;
}

CellPosition locate_impl(CellType type, std::span<const Vec3> p, const Vec3& x, double tol) {
  switch (type) {
    case CellType::Vertex: {
      CellPosition pos;
      pos.closest_point = p[0];
      pos.dist2 = norm2(x - p[0]);
      pos.inside = pos.dist2 == 0;
      pos.weights.resize(1);
      pos.weights[0] = 1;
      return pos;
    }
    case CellType::Line:
      return locate_line(p, x, tol);
    case CellType::Triangle:
      return locate_triangle(p, x, tol);
    case CellType::Pixel:
    case CellType::Voxel:
      return locate_box(type, p, x, tol);
    case CellType::Quad:
      return locate_quad(p, x, tol);
    case CellType::Tetra:
      return locate_tetra(p, x, tol);
    case CellType::Hexahedron:
    case CellType::Wedge:
    case CellType::Pyramid:
      return locate_newton(type, p, x, tol);
    case CellType::Polygon:
      return locate_polygon(p, x, tol);
    case CellType::PolyVertex:
    case CellType::PolyLine:
    case CellType::TriangleStrip:
      return locate_composite(type, p, x, tol);
    case CellType::Empty:
      break;
  }
  return {};
}

// World gradients of a fixed-size cell (values point-major).
void derivatives_fixed(CellType type, std::span<const Vec3> p, Vec3 pc,
                       std::span<const double> values, int comps, std::span<Vec3> out) {
  const std::size_t n = p.size();
  const int dim = cell_dimension(type);
  for (int c = 0; c < comps; ++c) out[c] = {};
  if (dim == 0) return;
  if (type == CellType::Pyramid) pc.z = std::min(pc.z, kPyramidApexT);
  double d[3 * kMaxCellPoints] = {};
  shape_derivs(type, pc, d);
  Vec3 cols[3];
  jacobian(type, p, pc, cols);
  if (dim == 2) {
    const Vec3 nrm = cross(cols[0], cols[1]);
    const double nl = norm(nrm);
    if (!(nl > 0)) return;
    cols[2] = nrm / nl;
  }
  const double l2 = norm2(cols[0]);
  for (int c = 0; c < comps; ++c) {
    Vec3 b{};  // d value / d (r, s, t)
    for (int k = 0; k < dim; ++k) {
      double sum = 0;
      for (std::size_t i = 0; i < n; ++i) sum += d[k * n + i] * values[i * comps + c];
      b[k] = sum;
    }
    if (dim == 1) {
      if (l2 > 0) out[c] = cols[0] * (b.x / l2);
    } else {
      Vec3 g;
      if (solve_rows(cols[0], cols[1], cols[2], b, g)) out[c] = g;
    }
  }
}

void derivatives_polygon(std::span<const Vec3> p, std::span<const double> values, int comps,
                         std::span<Vec3> out) {
  const PolygonFrame fr = polygon_frame(p);
  const auto q = polygon_2d(fr, p);
  const std::size_t n = p.size();
  for (int c = 0; c < comps; ++c) out[c] = {};
  if (fr.degenerate) return;
  P2 mean{0, 0};
  for (const P2& a : q) {
    mean[0] += a[0] / static_cast<double>(n);
    mean[1] += a[1] / static_cast<double>(n);
  }
  double a11 = 0, a12 = 0, a22 = 0;
  for (const P2& a : q) {
    const double dx = a[0] - mean[0], dy = a[1] - mean[1];
    a11 += dx * dx;
    a12 += dx * dy;
    a22 += dy * dy;
  }
  const double det = a11 * a22 - a12 * a12;
  if (!(det > 1e-14 * a11 * a22)) return;
  for (int c = 0; c < comps; ++c) {
    double fm = 0;
    for (std::size_t i = 0; i < n; ++i) fm += values[i * comps + c] / static_cast<double>(n);
    double b1 = 0, b2 = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double df = values[i * comps + c] - fm;
      b1 += (q[i][0] - mean[0]) * df;
      b2 += (q[i][1] - mean[1]) * df;
    }
    const double gu = (a22 * b1 - a12 * b2) / det;
    const double gv = (a11 * b2 - a12 * b1) / det;
    out[c] = gu * fr.u + gv * fr.v;
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Public API
// ---------------------------------------------------------------------------------------------

std::span<const Vec3> parametric_points(CellType type) {
  require_fixed("parametric_points", type);
  return pcoords_table(type);
}

Vec3 parametric_center(CellType type) {
  check_type("parametric_center", type);
  return center_of(type);
}

double parametric_distance(CellType type, const Vec3& pcoords) {
  check_type("parametric_distance", type);
  check_vec("parametric_distance", pcoords, "pcoords");
  return domain_distance(type, pcoords);
}

void interpolation_weights(CellType type, const Vec3& pcoords, std::span<double> weights) {
  const int n = require_fixed("interpolation_weights", type);
  check_vec("interpolation_weights", pcoords, "pcoords");
  if (weights.size() != static_cast<std::size_t>(n)) {
    fail("interpolation_weights", "a " + tname(type) + " has " + std::to_string(n) +
                                      " weights, the output has room for " +
                                      std::to_string(weights.size()));
  }
  shape(type, pcoords, weights.data());
}

CellWeights interpolation_weights(CellType type, const Vec3& pcoords) {
  const int n = require_fixed("interpolation_weights", type);
  CellWeights w(static_cast<std::size_t>(n));
  interpolation_weights(type, pcoords, w.span());
  return w;
}

void interpolation_derivatives(CellType type, const Vec3& pcoords, std::span<double> derivs) {
  const int n = require_fixed("interpolation_derivatives", type);
  check_vec("interpolation_derivatives", pcoords, "pcoords");
  if (derivs.size() != static_cast<std::size_t>(3 * n)) {
    fail("interpolation_derivatives", "a " + tname(type) + " has " + std::to_string(3 * n) +
                                          " derivatives (3 per point), the output has room for " +
                                          std::to_string(derivs.size()));
  }
  shape_derivs(type, pcoords, derivs.data());
}

Vec3 evaluate_location(CellType type, std::span<const Vec3> points, const Vec3& pcoords,
                       int sub_id) {
  check_points("evaluate_location", type, points);
  check_vec("evaluate_location", pcoords, "pcoords");
  check_sub_id("evaluate_location", type, points.size(), sub_id);
  return evaluate_location_impl(type, points, pcoords, sub_id);
}

void evaluate_weights(CellType type, std::span<const Vec3> points, const Vec3& pcoords, int sub_id,
                      CellWeights& weights) {
  check_points("evaluate_weights", type, points);
  check_vec("evaluate_weights", pcoords, "pcoords");
  check_sub_id("evaluate_weights", type, points.size(), sub_id);
  evaluate_weights_impl(type, points, pcoords, sub_id, weights);
}

void polygon_weights(std::span<const Vec3> points, const Vec3& x, CellWeights& weights) {
  check_points("polygon_weights", CellType::Polygon, points);
  check_vec("polygon_weights", x, "x");
  const PolygonFrame fr = polygon_frame(points);
  const auto q = polygon_2d(fr, points);
  weights.resize(points.size());
  mean_value_weights(q, fr.to2d(x), weights.data());
}

CellPosition locate_in_cell(CellType type, std::span<const Vec3> points, const Vec3& x,
                            double tolerance) {
  check_points("locate_in_cell", type, points);
  check_vec("locate_in_cell", x, "x");
  if (!std::isfinite(tolerance) || tolerance < 0) {
    fail("locate_in_cell", "tolerance " + std::to_string(tolerance) + " must be finite and >= 0");
  }
  return locate_impl(type, points, x, tolerance);
}

void derivatives(CellType type, std::span<const Vec3> points, const Vec3& pcoords,
                 std::span<const double> values, int components, std::span<Vec3> gradients,
                 int sub_id) {
  const char* fn = "derivatives";
  check_points(fn, type, points);
  check_vec(fn, pcoords, "pcoords");
  check_sub_id(fn, type, points.size(), sub_id);
  if (components < 1) fail(fn, "components must be >= 1, got " + std::to_string(components));
  const std::size_t comps = static_cast<std::size_t>(components);
  if (values.size() != points.size() * comps) {
    fail(fn, "expected " + std::to_string(points.size() * comps) + " values (" +
                 std::to_string(points.size()) + " points x " + std::to_string(components) +
                 " components), got " + std::to_string(values.size()));
  }
  if (gradients.size() != comps) {
    fail(fn, "the output has room for " + std::to_string(gradients.size()) + " gradients, need " +
                 std::to_string(components));
  }
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      fail(fn, "value " + std::to_string(i % comps) + " of point " + std::to_string(i / comps) +
                   " is not finite");
    }
  }
  if (is_composite_cell(type)) {
    const SubCell sc = sub_cell_impl(type, sub_id);
    Vec3 sp[3];
    std::vector<double> sv(static_cast<std::size_t>(sc.size) * comps);
    for (int i = 0; i < sc.size; ++i) {
      sp[i] = points[sc.ids[i]];
      for (std::size_t c = 0; c < comps; ++c) {
        sv[i * comps + c] = values[static_cast<std::size_t>(sc.ids[i]) * comps + c];
      }
    }
    derivatives_fixed(sc.type, std::span<const Vec3>(sp, sc.size), pcoords, sv, components,
                      gradients);
    return;
  }
  if (type == CellType::Polygon) {
    derivatives_polygon(points, values, components, gradients);
    return;
  }
  derivatives_fixed(type, points, pcoords, values, components, gradients);
}

std::vector<Vec3> derivatives(CellType type, std::span<const Vec3> points, const Vec3& pcoords,
                              std::span<const double> values, int components, int sub_id) {
  if (components < 1) {
    fail("derivatives", "components must be >= 1, got " + std::to_string(components));
  }
  std::vector<Vec3> out(static_cast<std::size_t>(components));
  derivatives(type, points, pcoords, values, components, std::span<Vec3>(out), sub_id);
  return out;
}

std::span<const CellEdge> cell_edges(CellType type) {
  require_fixed("cell_edges", type);
  switch (type) {
    case CellType::Triangle:
      return kTriangleE;
    case CellType::Pixel:
      return kPixelE;
    case CellType::Quad:
      return kQuadE;
    case CellType::Tetra:
      return kTetraE;
    case CellType::Voxel:
      return kVoxelE;
    case CellType::Hexahedron:
      return kHexE;
    case CellType::Wedge:
      return kWedgeE;
    case CellType::Pyramid:
      return kPyramidE;
    default:
      return {};
  }
}

std::span<const CellFace> cell_faces(CellType type) {
  require_fixed("cell_faces", type);
  switch (type) {
    case CellType::Tetra:
      return kTetraF;
    case CellType::Voxel:
      return kVoxelF;
    case CellType::Hexahedron:
      return kHexF;
    case CellType::Wedge:
      return kWedgeF;
    case CellType::Pyramid:
      return kPyramidF;
    default:
      return {};
  }
}

CellEdge polygon_edge(std::size_t num_points, int edge) {
  if (num_points < 3) {
    fail("polygon_edge", "a polygon needs at least 3 points, got " + std::to_string(num_points));
  }
  if (edge < 0 || static_cast<std::size_t>(edge) >= num_points) {
    fail("polygon_edge", "edge " + std::to_string(edge) + " is out of range for a polygon with " +
                             std::to_string(num_points) + " points");
  }
  return {edge, static_cast<int>((static_cast<std::size_t>(edge) + 1) % num_points)};
}

bool is_composite_cell(CellType type) {
  return type == CellType::PolyVertex || type == CellType::PolyLine ||
         type == CellType::TriangleStrip;
}

int num_sub_cells(CellType type, std::size_t num_points) {
  check_type("num_sub_cells", type);
  const int fixed = cell_fixed_size(type);
  if ((fixed > 0 && num_points != static_cast<std::size_t>(fixed)) ||
      num_points < static_cast<std::size_t>(cell_min_size(type))) {
    fail("num_sub_cells",
         "a " + tname(type) + " cannot have " + std::to_string(num_points) + " points");
  }
  return num_sub_cells_impl(type, num_points);
}

SubCell sub_cell(CellType type, std::size_t num_points, int sub_id) {
  if (!is_composite_cell(type)) {
    check_type("sub_cell", type);
    fail("sub_cell", "a " + tname(type) + " is not a composite cell");
  }
  (void)num_sub_cells(type, num_points);
  check_sub_id("sub_cell", type, num_points, sub_id);
  return sub_cell_impl(type, sub_id);
}

}  // namespace isoforge
