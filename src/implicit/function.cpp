// Implicit functions and their boolean combination (the VTK textbook, section 1.5.2: region
// separation, union = min, intersection = max, difference = max(F, −G)).
//
// Signed distance functions of the primitives follow the standard closed forms (e.g. Hart,
// "Sphere tracing", The Visual Computer 12, 1996; Quilez's catalogue of distance functions).
// Bounds over boxes use Lipschitz constants for distances and interval arithmetic (Moore,
// "Interval Analysis", 1966) for the algebraic quadric and superquadric, as in Duff,
// "Interval arithmetic and recursive subdivision for implicit functions and CSG", SIGGRAPH 1992.

#include "isoforge/implicit/function.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "function_node.hpp"
#include "isoforge/core/error.hpp"

namespace isoforge {

using Node = ImplicitFunction::Node;
using Kind = ImplicitFunction::Kind;

// ---------------------------------------------------------------------------------------------
// Affine

Affine Affine::translation(const Vec3& t) {
  Affine a;
  a.t = t;
  return a;
}

Affine Affine::scaling(const Vec3& s) {
  Affine a;
  a.a = {s.x, 0, 0, 0, s.y, 0, 0, 0, s.z};
  return a;
}

Affine Affine::rotation(const Vec3& axis, double degrees) {
  const Vec3 u = unit_direction(axis);
  if (u == Vec3{}) throw Error("rotate: axis must be a non-zero finite vector");
  if (!std::isfinite(degrees)) throw Error("rotate: angle must be finite");
  const double th = degrees * std::numbers::pi / 180.0;
  const double c = std::cos(th), s = std::sin(th), C = 1 - c;
  Affine r;
  r.a = {c + u.x * u.x * C,       u.x * u.y * C - u.z * s, u.x * u.z * C + u.y * s,
         u.y * u.x * C + u.z * s, c + u.y * u.y * C,       u.y * u.z * C - u.x * s,
         u.z * u.x * C - u.y * s, u.z * u.y * C + u.x * s, c + u.z * u.z * C};
  return r;
}

Affine Affine::operator*(const Affine& o) const {
  Affine r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double s = 0;
      for (int k = 0; k < 3; ++k) s += a[3 * i + k] * o.a[3 * k + j];
      r.a[3 * i + j] = s;
    }
  r.t = apply(o.t);
  return r;
}

Affine Affine::inverse() const {
  const auto& m = a;
  const double det = m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
                     m[2] * (m[3] * m[7] - m[4] * m[6]);
  double scale = 0;
  for (double v : m) scale = std::max(scale, std::abs(v));
  if (!std::isfinite(det) || !is_finite(t) || scale == 0 ||
      std::abs(det) <= 1e-14 * scale * scale * scale) {
    throw Error("transform: the matrix is singular or not finite");
  }
  Affine r;
  const double id = 1.0 / det;
  r.a = {(m[4] * m[8] - m[5] * m[7]) * id, (m[2] * m[7] - m[1] * m[8]) * id,
         (m[1] * m[5] - m[2] * m[4]) * id, (m[5] * m[6] - m[3] * m[8]) * id,
         (m[0] * m[8] - m[2] * m[6]) * id, (m[2] * m[3] - m[0] * m[5]) * id,
         (m[3] * m[7] - m[4] * m[6]) * id, (m[1] * m[6] - m[0] * m[7]) * id,
         (m[0] * m[4] - m[1] * m[3]) * id};
  Affine lin = r;
  lin.t = {0, 0, 0};
  const Vec3 mt = lin.apply(t);
  r.t = -mt;
  return r;
}

// ---------------------------------------------------------------------------------------------
// Parameter checks

namespace {

void check_finite(const Vec3& v, const char* fn, const char* param) {
  if (!is_finite(v)) {
    throw Error(std::string(fn) + ": parameter '" + param + "' is not finite");
  }
}

void check_finite(double v, const char* fn, const char* param) {
  if (!std::isfinite(v)) {
    throw Error(std::string(fn) + ": parameter '" + param + "' is not finite");
  }
}

Vec3 unit(const Vec3& v, const char* fn, const char* param) {
  check_finite(v, fn, param);
  const Vec3 u = unit_direction(v);  // (1e308, 1e308, 0) and (0, 0, 1e-320) have a direction
  if (u == Vec3{}) throw Error(std::string(fn) + ": parameter '" + param + "' has zero length");
  return u;
}

void put(std::array<double, 16>& p, int at, const Vec3& v) {
  p[at] = v.x;
  p[at + 1] = v.y;
  p[at + 2] = v.z;
}

// Sets the depth of a combination node from its children. Evaluation, bounds, gradients,
// printing and destruction recurse once per level, so the depth is bounded (kMaxFunctionDepth).
void set_depth(Node& n, const char* fn) {
  int deepest = 0;
  for (const auto& c : n.children) deepest = std::max(deepest, c.node().depth);
  n.depth = deepest + 1;
  if (n.depth > kMaxFunctionDepth) {
    throw Error(std::string(fn) + ": the function would be nested " + std::to_string(n.depth) +
                " levels deep; the limit is " + std::to_string(kMaxFunctionDepth));
  }
}

}  // namespace

ImplicitFunction ImplicitFunction::plane(const Vec3& origin, const Vec3& normal) {
  check_finite(origin, "plane", "origin");
  auto n = std::make_shared<Node>();
  n->kind = Kind::Plane;
  put(n->p, 0, origin);
  put(n->p, 3, unit(normal, "plane", "normal"));
  n->direction = normal;
  return ImplicitFunction(std::move(n));
}

ImplicitFunction ImplicitFunction::sphere(const Vec3& center, double radius) {
  check_finite(center, "sphere", "center");
  check_finite(radius, "sphere", "r");
  if (radius < 0) throw Error("sphere: parameter 'r' (radius) is negative");
  auto n = std::make_shared<Node>();
  n->kind = Kind::Sphere;
  put(n->p, 0, center);
  n->p[3] = radius;
  return ImplicitFunction(std::move(n));
}

ImplicitFunction ImplicitFunction::cylinder(const Vec3& point, const Vec3& axis, double radius) {
  check_finite(point, "cylinder", "point");
  check_finite(radius, "cylinder", "r");
  if (radius < 0) throw Error("cylinder: parameter 'r' (radius) is negative");
  auto n = std::make_shared<Node>();
  n->kind = Kind::Cylinder;
  put(n->p, 0, point);
  put(n->p, 3, unit(axis, "cylinder", "axis"));
  n->direction = axis;
  n->p[6] = radius;
  return ImplicitFunction(std::move(n));
}

ImplicitFunction ImplicitFunction::cone(const Vec3& apex, const Vec3& axis,
                                        double half_angle_degrees) {
  check_finite(apex, "cone", "apex");
  check_finite(half_angle_degrees, "cone", "angle");
  if (!(half_angle_degrees > 0 && half_angle_degrees < 90)) {
    throw Error("cone: parameter 'angle' (half angle) must be in (0, 90) degrees, got " +
                std::to_string(half_angle_degrees));
  }
  auto n = std::make_shared<Node>();
  n->kind = Kind::Cone;
  put(n->p, 0, apex);
  put(n->p, 3, unit(axis, "cone", "axis"));
  n->direction = axis;
  const double th = half_angle_degrees * std::numbers::pi / 180.0;
  n->p[6] = std::cos(th);
  n->p[7] = std::sin(th);
  n->p[8] = half_angle_degrees;
  return ImplicitFunction(std::move(n));
}

ImplicitFunction ImplicitFunction::box(const Vec3& min, const Vec3& max) {
  check_finite(min, "box", "min");
  check_finite(max, "box", "max");
  for (int i = 0; i < 3; ++i) {
    if (min[i] > max[i]) {
      throw Error("box: parameter 'min' exceeds 'max' along axis " + std::to_string(i));
    }
  }
  auto n = std::make_shared<Node>();
  n->kind = Kind::Box;
  put(n->p, 0, min);
  put(n->p, 3, max);
  put(n->p, 6, (min + max) * 0.5);
  put(n->p, 9, (max - min) * 0.5);
  return ImplicitFunction(std::move(n));
}

ImplicitFunction ImplicitFunction::quadric(const std::array<double, 10>& c) {
  bool any = false;
  for (int i = 0; i < 10; ++i) {
    if (!std::isfinite(c[static_cast<std::size_t>(i)])) {
      throw Error("quadric: coefficient a" + std::to_string(i) + " is not finite");
    }
    if (i < 9 && c[static_cast<std::size_t>(i)] != 0) any = true;
  }
  if (!any) throw Error("quadric: all coefficients a0..a8 are zero (the function is constant)");
  auto n = std::make_shared<Node>();
  n->kind = Kind::Quadric;
  std::copy(c.begin(), c.end(), n->p.begin());
  return ImplicitFunction(std::move(n));
}

ImplicitFunction ImplicitFunction::superquadric(const Vec3& center, const Vec3& radii,
                                                double north_south, double east_west) {
  check_finite(center, "superquadric", "center");
  check_finite(radii, "superquadric", "radii");
  for (int i = 0; i < 3; ++i) {
    if (!(radii[i] > 0)) throw Error("superquadric: parameter 'radii' must be positive");
  }
  check_finite(north_south, "superquadric", "n");
  check_finite(east_west, "superquadric", "e");
  if (!(north_south > 0 && north_south <= 4)) {
    throw Error("superquadric: parameter 'n' (north-south roundness) must be in (0, 4]");
  }
  if (!(east_west > 0 && east_west <= 4)) {
    throw Error("superquadric: parameter 'e' (east-west roundness) must be in (0, 4]");
  }
  auto n = std::make_shared<Node>();
  n->kind = Kind::Superquadric;
  put(n->p, 0, center);
  put(n->p, 3, radii);
  n->p[6] = north_south;
  n->p[7] = east_west;
  n->p[8] = std::min({radii.x, radii.y, radii.z});
  return ImplicitFunction(std::move(n));
}

ImplicitFunction ImplicitFunction::torus(const Vec3& center, const Vec3& axis, double major,
                                         double minor) {
  check_finite(center, "torus", "center");
  check_finite(major, "torus", "R");
  check_finite(minor, "torus", "r");
  if (!(major > 0)) throw Error("torus: parameter 'R' (ring radius) must be positive");
  if (minor < 0) throw Error("torus: parameter 'r' (tube radius) is negative");
  auto n = std::make_shared<Node>();
  n->kind = Kind::Torus;
  put(n->p, 0, center);
  put(n->p, 3, unit(axis, "torus", "axis"));
  n->direction = axis;
  n->p[6] = major;
  n->p[7] = minor;
  return ImplicitFunction(std::move(n));
}

ImplicitFunction ImplicitFunction::transformed(const Affine& placement) const {
  auto n = std::make_shared<Node>();
  n->kind = Kind::Transform;
  n->forward = placement;
  n->inverse = placement.inverse();
  n->children = {*this};
  set_depth(*n, "transform");
  return ImplicitFunction(std::move(n));
}

ImplicitFunction ImplicitFunction::union_of(std::vector<ImplicitFunction> parts) {
  if (parts.empty()) throw Error("union: needs at least one function");
  if (parts.size() == 1) return parts.front();
  auto n = std::make_shared<Node>();
  n->kind = Kind::Union;
  n->children = std::move(parts);
  set_depth(*n, "union");
  return ImplicitFunction(std::move(n));
}

ImplicitFunction ImplicitFunction::intersection_of(std::vector<ImplicitFunction> parts) {
  if (parts.empty()) throw Error("intersection: needs at least one function");
  if (parts.size() == 1) return parts.front();
  auto n = std::make_shared<Node>();
  n->kind = Kind::Intersection;
  n->children = std::move(parts);
  set_depth(*n, "intersection");
  return ImplicitFunction(std::move(n));
}

ImplicitFunction ImplicitFunction::minus(const ImplicitFunction& other) const {
  auto n = std::make_shared<Node>();
  n->kind = Kind::Difference;
  n->children = {*this, other};
  set_depth(*n, "difference");
  return ImplicitFunction(std::move(n));
}

ImplicitFunction ImplicitFunction::complement() const {
  auto n = std::make_shared<Node>();
  n->kind = Kind::Complement;
  n->children = {*this};
  set_depth(*n, "complement");
  return ImplicitFunction(std::move(n));
}

ImplicitFunction ImplicitFunction::offset(double distance) const {
  check_finite(distance, "offset", "d");
  auto n = std::make_shared<Node>();
  n->kind = Kind::Offset;
  n->p[0] = distance;
  n->children = {*this};
  set_depth(*n, "offset");
  return ImplicitFunction(std::move(n));
}

ImplicitFunction::Kind ImplicitFunction::kind() const { return node_->kind; }

int ImplicitFunction::depth() const { return node_->depth; }

ImplicitFunction ice_cream_cone() {
  using F = ImplicitFunction;
  const F cone = F::cone({0, 0, 0}, {1, 0, 0}, 20.0);
  const F vertical_plane = F::plane({0.1, 0, 0}, {-1, 0, 0});
  const F base_plane = F::plane({1.2, 0, 0}, {1, 0, 0});
  const F cream = F::sphere({1.333, 0, 0}, 0.5);
  const F bite = F::sphere({1.5, 0, 0.5}, 0.25);
  return F::union_of({F::intersection_of({cone, vertical_plane, base_plane}), cream.minus(bite)});
}

// ---------------------------------------------------------------------------------------------
// Block evaluation: one pass over the tree per block, a tight loop per node.

namespace implicit_detail {

// Cloned for AVX-512 and AVX2 (ISOFORGE_SIMD_CLONES, src/CMakeLists.txt): 8 and 4 doubles per instruction, the same
// bits as the baseline.
ISOFORGE_SIMD_CLONES
void eval_block(const Node& n, const double* x, const double* y, const double* z, std::size_t count,
                double* out) {
  const auto& p = n.p;
  switch (n.kind) {
    case Kind::Plane:
      for (std::size_t i = 0; i < count; ++i) {
        out[i] = (x[i] - p[0]) * p[3] + (y[i] - p[1]) * p[4] + (z[i] - p[2]) * p[5];
      }
      return;
    case Kind::Sphere:
      for (std::size_t i = 0; i < count; ++i) {
        const double dx = x[i] - p[0], dy = y[i] - p[1], dz = z[i] - p[2];
        out[i] = std::sqrt(dx * dx + dy * dy + dz * dz) - p[3];
      }
      return;
    case Kind::Cylinder:
      for (std::size_t i = 0; i < count; ++i) {
        const double dx = x[i] - p[0], dy = y[i] - p[1], dz = z[i] - p[2];
        const double h = dx * p[3] + dy * p[4] + dz * p[5];
        const double rx = dx - h * p[3], ry = dy - h * p[4], rz = dz - h * p[5];
        out[i] = std::sqrt(rx * rx + ry * ry + rz * rz) - p[6];
      }
      return;
    case Kind::Cone:
      for (std::size_t i = 0; i < count; ++i) {
        const double dx = x[i] - p[0], dy = y[i] - p[1], dz = z[i] - p[2];
        const double h = dx * p[3] + dy * p[4] + dz * p[5];
        const double rx = dx - h * p[3], ry = dy - h * p[4], rz = dz - h * p[5];
        out[i] = std::sqrt(rx * rx + ry * ry + rz * rz) * p[6] - std::abs(h) * p[7];
      }
      return;
    case Kind::Box:
      for (std::size_t i = 0; i < count; ++i) {
        const double qx = std::abs(x[i] - p[6]) - p[9];
        const double qy = std::abs(y[i] - p[7]) - p[10];
        const double qz = std::abs(z[i] - p[8]) - p[11];
        const double ox = std::max(qx, 0.0), oy = std::max(qy, 0.0), oz = std::max(qz, 0.0);
        out[i] = std::sqrt(ox * ox + oy * oy + oz * oz) + std::min(std::max(qx, std::max(qy, qz)), 0.0);
      }
      return;
    case Kind::Quadric:
      for (std::size_t i = 0; i < count; ++i) {
        const double X = x[i], Y = y[i], Z = z[i];
        out[i] = p[0] * X * X + p[1] * Y * Y + p[2] * Z * Z + p[3] * X * Y + p[4] * Y * Z +
                 p[5] * X * Z + p[6] * X + p[7] * Y + p[8] * Z + p[9];
      }
      return;
    case Kind::Superquadric: {
      const double ns = p[6], ew = p[7];
      for (std::size_t i = 0; i < count; ++i) {
        const double ax = std::abs((x[i] - p[0]) / p[3]);
        const double ay = std::abs((y[i] - p[1]) / p[4]);
        const double az = std::abs((z[i] - p[2]) / p[5]);
        const double xy = std::pow(std::pow(ax, 2 / ew) + std::pow(ay, 2 / ew), ew / ns);
        const double g = xy + std::pow(az, 2 / ns);
        out[i] = (std::pow(g, ns / 2) - 1) * p[8];
      }
      return;
    }
    case Kind::Torus:
      for (std::size_t i = 0; i < count; ++i) {
        const double dx = x[i] - p[0], dy = y[i] - p[1], dz = z[i] - p[2];
        const double h = dx * p[3] + dy * p[4] + dz * p[5];
        const double rx = dx - h * p[3], ry = dy - h * p[4], rz = dz - h * p[5];
        const double q = std::sqrt(rx * rx + ry * ry + rz * rz) - p[6];
        out[i] = std::sqrt(q * q + h * h) - p[7];
      }
      return;
    case Kind::Transform: {
      const auto& m = n.inverse.a;
      const auto& t = n.inverse.t;
      double tx[kBlock], ty[kBlock], tz[kBlock];
      for (std::size_t i = 0; i < count; ++i) {
        tx[i] = m[0] * x[i] + m[1] * y[i] + m[2] * z[i] + t.x;
        ty[i] = m[3] * x[i] + m[4] * y[i] + m[5] * z[i] + t.y;
        tz[i] = m[6] * x[i] + m[7] * y[i] + m[8] * z[i] + t.z;
      }
      eval_block(n.children[0].node(), tx, ty, tz, count, out);
      return;
    }
    case Kind::Union:
    case Kind::Intersection: {
      eval_block(n.children[0].node(), x, y, z, count, out);
      double tmp[kBlock];
      const bool is_union = n.kind == Kind::Union;
      for (std::size_t c = 1; c < n.children.size(); ++c) {
        eval_block(n.children[c].node(), x, y, z, count, tmp);
        if (is_union) {
          for (std::size_t i = 0; i < count; ++i) out[i] = std::min(out[i], tmp[i]);
        } else {
          for (std::size_t i = 0; i < count; ++i) out[i] = std::max(out[i], tmp[i]);
        }
      }
      return;
    }
    case Kind::Difference: {
      eval_block(n.children[0].node(), x, y, z, count, out);
      double tmp[kBlock];
      eval_block(n.children[1].node(), x, y, z, count, tmp);
      for (std::size_t i = 0; i < count; ++i) out[i] = std::max(out[i], -tmp[i]);
      return;
    }
    case Kind::Complement:
      eval_block(n.children[0].node(), x, y, z, count, out);
      for (std::size_t i = 0; i < count; ++i) out[i] = -out[i];
      return;
    case Kind::Offset:
      eval_block(n.children[0].node(), x, y, z, count, out);
      for (std::size_t i = 0; i < count; ++i) out[i] -= p[0];
      return;
  }
}

namespace {

// Value and gradient at one point.
double eval_grad(const Node& n, const Vec3& q, Vec3& g) {
  const auto& p = n.p;
  switch (n.kind) {
    case Kind::Plane:
      g = {p[3], p[4], p[5]};
      return (q.x - p[0]) * p[3] + (q.y - p[1]) * p[4] + (q.z - p[2]) * p[5];
    case Kind::Sphere: {
      const Vec3 d = q - Vec3{p[0], p[1], p[2]};
      const double len = norm(d);
      g = len > 0 ? d / len : Vec3{0, 0, 1};
      return len - p[3];
    }
    case Kind::Cylinder: {
      const Vec3 a{p[3], p[4], p[5]};
      const Vec3 d = q - Vec3{p[0], p[1], p[2]};
      const Vec3 r = d - a * dot(d, a);
      const double len = norm(r);
      g = len > 0 ? r / len : Vec3{0, 0, 0};
      return len - p[6];
    }
    case Kind::Cone: {
      const Vec3 a{p[3], p[4], p[5]};
      const Vec3 d = q - Vec3{p[0], p[1], p[2]};
      const double h = dot(d, a);
      const Vec3 r = d - a * h;
      const double len = norm(r);
      const Vec3 rhat = len > 0 ? r / len : Vec3{0, 0, 0};
      const double sgn = h > 0 ? 1.0 : (h < 0 ? -1.0 : 0.0);
      g = rhat * p[6] - a * (sgn * p[7]);
      return len * p[6] - std::abs(h) * p[7];
    }
    case Kind::Box: {
      const Vec3 c{p[6], p[7], p[8]}, hs{p[9], p[10], p[11]};
      Vec3 qd, s;
      for (int i = 0; i < 3; ++i) {
        const double d = q[i] - c[i];
        s[i] = d >= 0 ? 1.0 : -1.0;
        qd[i] = std::abs(d) - hs[i];
      }
      const Vec3 o{std::max(qd.x, 0.0), std::max(qd.y, 0.0), std::max(qd.z, 0.0)};
      const double olen = norm(o);
      if (olen > 0) {
        g = Vec3{o.x * s.x, o.y * s.y, o.z * s.z} / olen;
        return olen;
      }
      int k = 0;
      if (qd.y > qd[k]) k = 1;
      if (qd.z > qd[k]) k = 2;
      g = {0, 0, 0};
      g[k] = s[k];
      return qd[k];
    }
    case Kind::Quadric: {
      const double X = q.x, Y = q.y, Z = q.z;
      g = {2 * p[0] * X + p[3] * Y + p[5] * Z + p[6], 2 * p[1] * Y + p[3] * X + p[4] * Z + p[7],
           2 * p[2] * Z + p[4] * Y + p[5] * X + p[8]};
      return p[0] * X * X + p[1] * Y * Y + p[2] * Z * Z + p[3] * X * Y + p[4] * Y * Z +
             p[5] * X * Z + p[6] * X + p[7] * Y + p[8] * Z + p[9];
    }
    case Kind::Superquadric: {
      const double ns = p[6], ew = p[7];
      const double ux = (q.x - p[0]) / p[3], uy = (q.y - p[1]) / p[4], uz = (q.z - p[2]) / p[5];
      const double ax = std::abs(ux), ay = std::abs(uy), az = std::abs(uz);
      const double px = std::pow(ax, 2 / ew), py = std::pow(ay, 2 / ew);
      const double s = px + py;
      const double xy = std::pow(s, ew / ns);
      const double gz = std::pow(az, 2 / ns);
      const double G = xy + gz;
      const double val = (std::pow(G, ns / 2) - 1) * p[8];
      // d val / d G = (ns / 2) G^(ns/2 - 1) * min radius
      const double dG = G > 0 ? (ns / 2) * std::pow(G, ns / 2 - 1) * p[8] : 0.0;
      // d xy / d s = (ew / ns) s^(ew/ns - 1); d s / d ax = (2/ew) ax^(2/ew - 1)
      const double dxy = s > 0 ? (ew / ns) * std::pow(s, ew / ns - 1) : 0.0;
      auto dpow = [](double a, double e) { return a > 0 ? e * std::pow(a, e - 1) : 0.0; };
      const double sx = ux >= 0 ? 1.0 : -1.0, sy = uy >= 0 ? 1.0 : -1.0, sz = uz >= 0 ? 1.0 : -1.0;
      g = {dG * dxy * dpow(ax, 2 / ew) * sx / p[3], dG * dxy * dpow(ay, 2 / ew) * sy / p[4],
           dG * dpow(az, 2 / ns) * sz / p[5]};
      return val;
    }
    case Kind::Torus: {
      const Vec3 a{p[3], p[4], p[5]};
      const Vec3 d = q - Vec3{p[0], p[1], p[2]};
      const double h = dot(d, a);
      const Vec3 r = d - a * h;
      const double rl = norm(r);
      const Vec3 rhat = rl > 0 ? r / rl : Vec3{0, 0, 0};
      const double qq = rl - p[6];
      const double len = std::sqrt(qq * qq + h * h);
      g = len > 0 ? (rhat * qq + a * h) / len : Vec3{0, 0, 0};
      return len - p[7];
    }
    case Kind::Transform: {
      const Vec3 local = n.inverse.apply(q);
      Vec3 gl;
      const double v = eval_grad(n.children[0].node(), local, gl);
      const auto& m = n.inverse.a;  // ∇(F∘M) = Mᵀ ∇F
      g = {m[0] * gl.x + m[3] * gl.y + m[6] * gl.z, m[1] * gl.x + m[4] * gl.y + m[7] * gl.z,
           m[2] * gl.x + m[5] * gl.y + m[8] * gl.z};
      return v;
    }
    case Kind::Union:
    case Kind::Intersection: {
      double best = eval_grad(n.children[0].node(), q, g);
      for (std::size_t c = 1; c < n.children.size(); ++c) {
        Vec3 gc;
        const double v = eval_grad(n.children[c].node(), q, gc);
        if (n.kind == Kind::Union ? v < best : v > best) {
          best = v;
          g = gc;
        }
      }
      return best;
    }
    case Kind::Difference: {
      Vec3 gb;
      const double a = eval_grad(n.children[0].node(), q, g);
      const double b = -eval_grad(n.children[1].node(), q, gb);
      if (b > a) {
        g = -gb;
        return b;
      }
      return a;
    }
    case Kind::Complement: {
      const double v = eval_grad(n.children[0].node(), q, g);
      g = -g;
      return -v;
    }
    case Kind::Offset:
      return eval_grad(n.children[0].node(), q, g) - p[0];
  }
  return 0;
}

// ---- bounds ----

Interval iv_add(Interval a, Interval b) { return {a.lo + b.lo, a.hi + b.hi}; }
Interval iv_scale(Interval a, double s) {
  return s >= 0 ? Interval{a.lo * s, a.hi * s} : Interval{a.hi * s, a.lo * s};
}
Interval iv_mul(Interval a, Interval b) {
  const double c[4] = {a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi};
  return {*std::min_element(c, c + 4), *std::max_element(c, c + 4)};
}
Interval iv_sqr(Interval a) {
  if (a.lo >= 0) return {a.lo * a.lo, a.hi * a.hi};
  if (a.hi <= 0) return {a.hi * a.hi, a.lo * a.lo};
  return {0, std::max(a.lo * a.lo, a.hi * a.hi)};
}
Interval iv_abs(Interval a) {
  if (a.lo >= 0) return a;
  if (a.hi <= 0) return {-a.hi, -a.lo};
  return {0, std::max(-a.lo, a.hi)};
}
// Monotone increasing power of a non-negative interval.
Interval iv_pow(Interval a, double e) { return {std::pow(a.lo, e), std::pow(a.hi, e)}; }

// Slightly widened, so that rounding in the point evaluation can never leave the bound.
Interval widen(Interval a) {
  const double eps = 1e-12 * (1 + std::max(std::abs(a.lo), std::abs(a.hi)));
  return {a.lo - eps, a.hi + eps};
}

Interval lipschitz_bound(const Node& n, const Bounds& b) {
  const Vec3 c = b.center();
  double v;
  const double cx = c.x, cy = c.y, cz = c.z;
  eval_block(n, &cx, &cy, &cz, 1, &v);
  const double h = 0.5 * b.diagonal();
  return {v - h, v + h};
}

Interval bound_node(const Node& n, const Bounds& b) {
  const auto& p = n.p;
  switch (n.kind) {
    case Kind::Plane: {
      const Vec3 c = b.center(), hs = b.size() * 0.5;
      double v;
      eval_block(n, &c.x, &c.y, &c.z, 1, &v);
      const double r = std::abs(p[3]) * hs.x + std::abs(p[4]) * hs.y + std::abs(p[5]) * hs.z;
      return {v - r, v + r};
    }
    case Kind::Sphere: {
      // Exact: nearest and farthest points of the box from the center.
      double dmin2 = 0, dmax2 = 0;
      for (int i = 0; i < 3; ++i) {
        const double c = p[static_cast<std::size_t>(i)];
        const double lo = b.min[i] - c, hi = b.max[i] - c;
        const double near = lo > 0 ? lo : (hi < 0 ? hi : 0.0);
        const double far = std::max(std::abs(lo), std::abs(hi));
        dmin2 += near * near;
        dmax2 += far * far;
      }
      return {std::sqrt(dmin2) - p[3], std::sqrt(dmax2) - p[3]};
    }
    case Kind::Cylinder:
    case Kind::Cone:
    case Kind::Box:
    case Kind::Torus: return lipschitz_bound(n, b);
    case Kind::Quadric: {
      const Interval X{b.min.x, b.max.x}, Y{b.min.y, b.max.y}, Z{b.min.z, b.max.z};
      Interval r{p[9], p[9]};
      r = iv_add(r, iv_scale(iv_sqr(X), p[0]));
      r = iv_add(r, iv_scale(iv_sqr(Y), p[1]));
      r = iv_add(r, iv_scale(iv_sqr(Z), p[2]));
      r = iv_add(r, iv_scale(iv_mul(X, Y), p[3]));
      r = iv_add(r, iv_scale(iv_mul(Y, Z), p[4]));
      r = iv_add(r, iv_scale(iv_mul(X, Z), p[5]));
      r = iv_add(r, iv_scale(X, p[6]));
      r = iv_add(r, iv_scale(Y, p[7]));
      r = iv_add(r, iv_scale(Z, p[8]));
      return widen(r);
    }
    case Kind::Superquadric: {
      const double ns = p[6], ew = p[7];
      const Interval ax = iv_abs(iv_scale(Interval{b.min.x - p[0], b.max.x - p[0]}, 1 / p[3]));
      const Interval ay = iv_abs(iv_scale(Interval{b.min.y - p[1], b.max.y - p[1]}, 1 / p[4]));
      const Interval az = iv_abs(iv_scale(Interval{b.min.z - p[2], b.max.z - p[2]}, 1 / p[5]));
      const Interval xy = iv_pow(iv_add(iv_pow(ax, 2 / ew), iv_pow(ay, 2 / ew)), ew / ns);
      const Interval g = iv_add(xy, iv_pow(az, 2 / ns));
      const Interval v = iv_pow(g, ns / 2);
      return widen({(v.lo - 1) * p[8], (v.hi - 1) * p[8]});
    }
    case Kind::Transform: {
      Bounds local;
      for (int c = 0; c < 8; ++c) {
        const Vec3 corner{(c & 1) ? b.max.x : b.min.x, (c & 2) ? b.max.y : b.min.y,
                          (c & 4) ? b.max.z : b.min.z};
        local.extend(n.inverse.apply(corner));
      }
      return bound_node(n.children[0].node(), local);
    }
    case Kind::Union:
    case Kind::Intersection: {
      Interval r = bound_node(n.children[0].node(), b);
      for (std::size_t c = 1; c < n.children.size(); ++c) {
        const Interval k = bound_node(n.children[c].node(), b);
        if (n.kind == Kind::Union) {
          r = {std::min(r.lo, k.lo), std::min(r.hi, k.hi)};
        } else {
          r = {std::max(r.lo, k.lo), std::max(r.hi, k.hi)};
        }
      }
      return r;
    }
    case Kind::Difference: {
      const Interval a = bound_node(n.children[0].node(), b);
      const Interval g = bound_node(n.children[1].node(), b);
      return {std::max(a.lo, -g.hi), std::max(a.hi, -g.lo)};
    }
    case Kind::Complement: {
      const Interval a = bound_node(n.children[0].node(), b);
      return {-a.hi, -a.lo};
    }
    case Kind::Offset: {
      const Interval a = bound_node(n.children[0].node(), b);
      return {a.lo - p[0], a.hi - p[0]};
    }
  }
  return {-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
}

}  // namespace

Interval bound_of(const Node& n, const Bounds& box) { return bound_node(n, box); }

void eval_pruned(const Node& n, const Bounds& box, const double* x, const double* y, const double* z,
                 std::size_t count, double* out) {
  switch (n.kind) {
    case Kind::Transform: {
      Bounds local;
      for (int c = 0; c < 8; ++c) {
        const Vec3 corner{(c & 1) ? box.max.x : box.min.x, (c & 2) ? box.max.y : box.min.y,
                          (c & 4) ? box.max.z : box.min.z};
        local.extend(n.inverse.apply(corner));
      }
      const auto& m = n.inverse.a;
      const auto& t = n.inverse.t;
      double tx[kBlock], ty[kBlock], tz[kBlock];
      for (std::size_t i = 0; i < count; ++i) {
        tx[i] = m[0] * x[i] + m[1] * y[i] + m[2] * z[i] + t.x;
        ty[i] = m[3] * x[i] + m[4] * y[i] + m[5] * z[i] + t.y;
        tz[i] = m[6] * x[i] + m[7] * y[i] + m[8] * z[i] + t.z;
      }
      eval_pruned(n.children[0].node(), local, tx, ty, tz, count, out);
      return;
    }
    case Kind::Union:
    case Kind::Intersection: {
      // A child whose bound cannot reach the running min (max) never decides the result, so it
      // is skipped: exact, because min/max of the remaining children is the same number.
      const bool is_union = n.kind == Kind::Union;
      const std::size_t nc = n.children.size();
      Interval iv[16];
      bool use_bounds = nc <= 16;
      double decisive = is_union ? std::numeric_limits<double>::infinity()
                                 : -std::numeric_limits<double>::infinity();
      if (use_bounds) {
        for (std::size_t c = 0; c < nc; ++c) {
          iv[c] = widen(bound_node(n.children[c].node(), box));
          decisive = is_union ? std::min(decisive, iv[c].hi) : std::max(decisive, iv[c].lo);
        }
      }
      bool first = true;
      double tmp[kBlock];
      for (std::size_t c = 0; c < nc; ++c) {
        if (use_bounds && (is_union ? iv[c].lo > decisive : iv[c].hi < decisive)) continue;
        if (first) {
          eval_pruned(n.children[c].node(), box, x, y, z, count, out);
          first = false;
          continue;
        }
        eval_pruned(n.children[c].node(), box, x, y, z, count, tmp);
        if (is_union) {
          for (std::size_t i = 0; i < count; ++i) out[i] = std::min(out[i], tmp[i]);
        } else {
          for (std::size_t i = 0; i < count; ++i) out[i] = std::max(out[i], tmp[i]);
        }
      }
      return;
    }
    case Kind::Difference: {
      const Interval a = widen(bound_node(n.children[0].node(), box));
      const Interval b = widen(bound_node(n.children[1].node(), box));
      if (a.lo > -b.lo) {  // F > -G everywhere in the box: the result is F
        eval_pruned(n.children[0].node(), box, x, y, z, count, out);
        return;
      }
      if (-b.hi > a.hi) {  // -G > F everywhere: the result is -G
        eval_pruned(n.children[1].node(), box, x, y, z, count, out);
        for (std::size_t i = 0; i < count; ++i) out[i] = -out[i];
        return;
      }
      eval_pruned(n.children[0].node(), box, x, y, z, count, out);
      double tmp[kBlock];
      eval_pruned(n.children[1].node(), box, x, y, z, count, tmp);
      for (std::size_t i = 0; i < count; ++i) out[i] = std::max(out[i], -tmp[i]);
      return;
    }
    case Kind::Complement:
      eval_pruned(n.children[0].node(), box, x, y, z, count, out);
      for (std::size_t i = 0; i < count; ++i) out[i] = -out[i];
      return;
    case Kind::Offset:
      eval_pruned(n.children[0].node(), box, x, y, z, count, out);
      for (std::size_t i = 0; i < count; ++i) out[i] -= n.p[0];
      return;
    default: eval_block(n, x, y, z, count, out); return;
  }
}

}  // namespace implicit_detail

double ImplicitFunction::value(const Vec3& p) const {
  double v;
  implicit_detail::eval_block(*node_, &p.x, &p.y, &p.z, 1, &v);
  return v;
}

Vec3 ImplicitFunction::gradient(const Vec3& p) const {
  Vec3 g;
  (void)implicit_detail::eval_grad(*node_, p, g);
  return g;
}

void ImplicitFunction::evaluate(std::span<const double> x, std::span<const double> y,
                                std::span<const double> z, std::span<double> values) const {
  if (x.size() != values.size() || y.size() != values.size() || z.size() != values.size()) {
    throw Error("evaluate: x, y, z and values must have the same size");
  }
  using implicit_detail::kBlock;
  for (std::size_t i = 0; i < values.size(); i += kBlock) {
    const std::size_t n = std::min(kBlock, values.size() - i);
    implicit_detail::eval_block(*node_, x.data() + i, y.data() + i, z.data() + i, n,
                                values.data() + i);
  }
}

void ImplicitFunction::evaluate(std::span<const double> xyz, std::span<double> values) const {
  if (xyz.size() != 3 * values.size()) {
    throw Error("evaluate: xyz must hold 3 doubles per value");
  }
  using implicit_detail::kBlock;
  double x[kBlock], y[kBlock], z[kBlock];
  for (std::size_t i = 0; i < values.size(); i += kBlock) {
    const std::size_t n = std::min(kBlock, values.size() - i);
    for (std::size_t k = 0; k < n; ++k) {
      x[k] = xyz[3 * (i + k)];
      y[k] = xyz[3 * (i + k) + 1];
      z[k] = xyz[3 * (i + k) + 2];
    }
    implicit_detail::eval_block(*node_, x, y, z, n, values.data() + i);
  }
}

Interval ImplicitFunction::bound(const Bounds& box) const {
  if (box.empty()) throw Error("bound: the box is empty");
  return implicit_detail::bound_node(*node_, box);
}

}  // namespace isoforge
