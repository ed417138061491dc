#pragma once
/// \file
/// A tiny 3-vector value type for public APIs (Eigen stays inside the .cpp files).

#include <algorithm>
#include <array>
#include <cmath>

namespace isoforge {

/// A point or direction in 3D, double precision.
struct Vec3 {
  double x = 0, y = 0, z = 0;

  constexpr double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }

  constexpr Vec3& operator+=(const Vec3& o) { x += o.x; y += o.y; z += o.z; return *this; }
  constexpr Vec3& operator-=(const Vec3& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
  constexpr Vec3& operator*=(double s) { x *= s; y *= s; z *= s; return *this; }
  friend constexpr Vec3 operator+(Vec3 a, const Vec3& b) { return a += b; }
  friend constexpr Vec3 operator-(Vec3 a, const Vec3& b) { return a -= b; }
  friend constexpr Vec3 operator-(const Vec3& a) { return {-a.x, -a.y, -a.z}; }
  friend constexpr Vec3 operator*(Vec3 a, double s) { return a *= s; }
  friend constexpr Vec3 operator*(double s, Vec3 a) { return a *= s; }
  friend constexpr Vec3 operator/(const Vec3& a, double s) { return {a.x / s, a.y / s, a.z / s}; }
  friend constexpr bool operator==(const Vec3&, const Vec3&) = default;
};

constexpr double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
constexpr double norm2(const Vec3& a) { return dot(a, a); }
inline bool is_finite(const Vec3& a) {
  return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}
/// The unit vector along `a`, scaled by its largest component first so that neither (1e308,
/// 1e308, 0) overflows nor (0, 0, 1e-320) underflows; the zero vector when `a` is zero or not
/// finite (callers name the option in their error).
inline Vec3 unit_direction(const Vec3& a) {
  const double n2 = dot(a, a);
  if (n2 > 1e-290 && n2 < 1e290) return a / std::sqrt(n2);  // no overflow nor underflow
  if (!is_finite(a)) return {};
  const double m = std::max({std::abs(a.x), std::abs(a.y), std::abs(a.z)});
  if (!(m > 0)) return {};
  const Vec3 w = a / m;
  return w / norm(w);
}

/// Axis-aligned bounds. An empty box has min > max (the default).
struct Bounds {
  Vec3 min{1, 1, 1};
  Vec3 max{-1, -1, -1};

  [[nodiscard]] bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
  void extend(const Vec3& p) {
    if (empty()) {
      min = max = p;
      return;
    }
    for (int i = 0; i < 3; ++i) {
      if (p[i] < min[i]) min[i] = p[i];
      if (p[i] > max[i]) max[i] = p[i];
    }
  }
  /// Grows to contain `b` too.
  void merge(const Bounds& b) {
    if (b.empty()) return;
    extend(b.min);
    extend(b.max);
  }
  [[nodiscard]] Vec3 center() const { return (min + max) * 0.5; }
  [[nodiscard]] Vec3 size() const { return empty() ? Vec3{} : max - min; }
  [[nodiscard]] double diagonal() const { return empty() ? 0.0 : norm(max - min); }
  [[nodiscard]] bool contains(const Vec3& p, double tol = 0) const {
    return p.x >= min.x - tol && p.x <= max.x + tol && p.y >= min.y - tol &&
           p.y <= max.y + tol && p.z >= min.z - tol && p.z <= max.z + tol;
  }
};

}  // namespace isoforge
