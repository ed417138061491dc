// Exact geometric predicates (predicates.hpp).
//
// \cite Shewchuk, J. R. (1997). Adaptive precision floating-point arithmetic and fast robust
//   geometric predicates. Discrete & Computational Geometry 18(3), 305–363: the error bounds of
//   the floating-point filters and the expansion arithmetic (two-sum, two-product by Dekker's
//   split, growing, summing and scaling nonoverlapping expansions).
// \cite Dekker, T. J. (1971). A floating-point technique for extending the available precision.
//   Numerische Mathematik 18, 224–242.
// \cite Knuth, D. E. The Art of Computer Programming, vol. 2, §4.2.2 (the two-sum).
//
// Each predicate first evaluates its determinant in doubles and returns the sign when it exceeds
// the worst-case rounding error; otherwise it recomputes the determinant exactly as a sum of
// nonoverlapping doubles (an expansion) whose largest component carries the sign. The triangle
// tests use nothing but these signs and exact comparisons of coordinates (no constructed point),
// so they are exact too. Method: docs/algorithms/predicates.md.

#include "isoforge/core/predicates.hpp"

#include <algorithm>
#include <cmath>

namespace isoforge {

namespace {

// ---------------------------------------------------------------------------------------------
// Expansion arithmetic. An expansion is an array of doubles, increasing in magnitude and
// nonoverlapping, whose exact sum is the value represented; zero components are dropped, so the
// last component has the sign of the value (an empty expansion is zero).

constexpr double kEpsilon = 0x1p-53;      // half an ulp of 1: the unit roundoff
constexpr double kSplitter = 0x1p27 + 1;  // Dekker's split of a 53-bit significand into 26 + 26
// Relative error bounds of the plain double evaluations (Shewchuk, section 4.3).
constexpr double kOrient2dBound = (3.0 + 16.0 * kEpsilon) * kEpsilon;
constexpr double kOrient3dBound = (7.0 + 56.0 * kEpsilon) * kEpsilon;

// x + y = a + b exactly, x = fl(a + b) (any magnitudes).
inline void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double b_virtual = x - a;
  const double a_virtual = x - b_virtual;
  const double b_round = b - b_virtual;
  const double a_round = a - a_virtual;
  y = a_round + b_round;
}

// a = hi + lo with hi and lo of at most 26 significant bits each.
inline void split(double a, double& hi, double& lo) {
  const double c = kSplitter * a;
  const double big = c - a;
  hi = c - big;
  lo = a - hi;
}

// x + y = a * b exactly, x = fl(a * b).
inline void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  double ahi, alo, bhi, blo;
  split(a, ahi, alo);
  split(b, bhi, blo);
  const double err1 = x - ahi * bhi;
  const double err2 = err1 - alo * bhi;
  const double err3 = err2 - ahi * blo;
  y = alo * blo - err3;
}

// h = e + b; h may be e itself (in place). Returns the length of h (at most n + 1).
int grow_expansion(const double* e, int n, double b, double* h) {
  double q = b;
  int k = 0;
  for (int i = 0; i < n; ++i) {
    double sum, err;
    two_sum(q, e[i], sum, err);
    q = sum;
    if (err != 0) h[k++] = err;
  }
  if (q != 0 || k == 0) h[k++] = q;
  if (k == 1 && h[0] == 0) return 0;
  return k;
}

// h += f (h holds n components and room for n + m). Returns the new length.
int add_expansion(double* h, int n, const double* f, int m) {
  for (int j = 0; j < m; ++j) n = grow_expansion(h, n, f[j], h);
  return n;
}

// h = e * b. Returns the length of h (at most 2 n).
int scale_expansion(const double* e, int n, double b, double* h) {
  if (n == 0 || b == 0) return 0;
  int k = 0;
  double q, err;
  two_product(e[0], b, q, err);
  if (err != 0) h[k++] = err;
  for (int i = 1; i < n; ++i) {
    double p1, p0, sum;
    two_product(e[i], b, p1, p0);
    two_sum(q, p0, sum, err);
    if (err != 0) h[k++] = err;
    two_sum(p1, sum, q, err);
    if (err != 0) h[k++] = err;
  }
  if (q != 0) h[k++] = q;
  return k;
}

// h = e * f. Returns the length of h (at most 2 n m).
template <int kMax>
int multiply_expansions(const double* e, int n, const double* f, int m, double* h) {
  int len = 0;
  double scaled[kMax];
  for (int j = 0; j < m; ++j) {
    const int s = scale_expansion(e, n, f[j], scaled);
    len = add_expansion(h, len, scaled, s);
  }
  return len;
}

inline int negate(double* e, int n) {
  for (int i = 0; i < n; ++i) e[i] = -e[i];
  return n;
}

inline int sign_of(const double* e, int n) {
  if (n == 0) return 0;
  return e[n - 1] > 0 ? 1 : (e[n - 1] < 0 ? -1 : 0);
}

inline int sign_of(double x) {
  return x > 0 ? 1 : (x < 0 ? -1 : 0);
}

// a − b exactly as an expansion of at most two components.
inline int difference(double a, double b, double* h) {
  double x, y;
  two_sum(a, -b, x, y);
  int k = 0;
  if (y != 0) h[k++] = y;
  if (x != 0) h[k++] = x;
  return k;
}

// e1 * f1 − e2 * f2 for two-component expansions: at most 16 components.
int cross_term(const double* e1, int n1, const double* f1, int m1, const double* e2, int n2,
               const double* f2, int m2, double* h) {
  double right[8];
  int len = multiply_expansions<4>(e1, n1, f1, m1, h);
  const int r = multiply_expansions<4>(e2, n2, f2, m2, right);
  return add_expansion(h, len, right, negate(right, r));
}

int orient2d_exact(const Vec2& a, const Vec2& b, const Vec2& c) {
  double acx[2], acy[2], bcx[2], bcy[2];
  const int nacx = difference(a[0], c[0], acx), nacy = difference(a[1], c[1], acy);
  const int nbcx = difference(b[0], c[0], bcx), nbcy = difference(b[1], c[1], bcy);
  double det[16];
  const int n = cross_term(acx, nacx, bcy, nbcy, acy, nacy, bcx, nbcx, det);
  return sign_of(det, n);
}

// Sign of det[a − d, b − d, c − d] (the filter's determinant), exactly.
int orient3d_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  double ad[3][2], bd[3][2], cd[3][2];
  int nad[3], nbd[3], ncd[3];
  for (int i = 0; i < 3; ++i) {
    nad[i] = difference(a[i], d[i], ad[i]);
    nbd[i] = difference(b[i], d[i], bd[i]);
    ncd[i] = difference(c[i], d[i], cd[i]);
  }
  constexpr int X = 0, Y = 1, Z = 2;
  double minor[16], term[64], det[192];
  int len = 0;
  // adz (bdx cdy − cdx bdy)
  int m = cross_term(bd[X], nbd[X], cd[Y], ncd[Y], cd[X], ncd[X], bd[Y], nbd[Y], minor);
  int t = multiply_expansions<32>(minor, m, ad[Z], nad[Z], term);
  len = add_expansion(det, len, term, t);
  // bdz (cdx ady − adx cdy)
  m = cross_term(cd[X], ncd[X], ad[Y], nad[Y], ad[X], nad[X], cd[Y], ncd[Y], minor);
  t = multiply_expansions<32>(minor, m, bd[Z], nbd[Z], term);
  len = add_expansion(det, len, term, t);
  // cdz (adx bdy − bdx ady)
  m = cross_term(ad[X], nad[X], bd[Y], nbd[Y], bd[X], nbd[X], ad[Y], nad[Y], minor);
  t = multiply_expansions<32>(minor, m, cd[Z], ncd[Z], term);
  len = add_expansion(det, len, term, t);
  return sign_of(det, len);
}

// ---------------------------------------------------------------------------------------------
// Exact tests built on the orientations.

// The projection of p dropping axis `drop` (the other two coordinates in cyclic order).
inline Vec2 project(const Vec3& p, int drop) {
  switch (drop) {
    case 0:
      return {p.y, p.z};
    case 1:
      return {p.z, p.x};
    default:
      return {p.x, p.y};
  }
}

inline int orient2d_in(int drop, const Vec3& a, const Vec3& b, const Vec3& c) {
  return orient2d(project(a, drop), project(b, drop), project(c, drop));
}

// An axis whose dropping keeps the triangle non-degenerate (then the projection is a bijection
// of its plane), or −1 if the corners are collinear.
int triangle_projection(const Vec3& a, const Vec3& b, const Vec3& c) {
  // Try the axis of the largest normal component first: it is the one that works in practice.
  const Vec3 n = cross(b - a, c - a);
  const double ax = std::abs(n.x), ay = std::abs(n.y), az = std::abs(n.z);
  const int first = (az >= ax && az >= ay) ? 2 : (ay >= ax ? 1 : 0);
  for (int k = 0; k < 3; ++k) {
    const int drop = (first + k) % 3;
    if (orient2d_in(drop, a, b, c) != 0) return drop;
  }
  return -1;
}

inline bool collinear(const Vec3& a, const Vec3& b, const Vec3& c) {
  return triangle_projection(a, b, c) < 0;
}

// An axis along which not all of the points have the same coordinate, or −1 (all coincide).
int varying_axis(std::initializer_list<const Vec3*> pts) {
  for (int k = 0; k < 3; ++k) {
    const double first = (**pts.begin())[k];
    for (const Vec3* p : pts) {
      if ((*p)[k] != first) return k;
    }
  }
  return -1;
}

// Whether the closed segments [a, b] and [c, d], known to lie on one line, overlap.
bool collinear_segments_overlap(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const int k = varying_axis({&a, &b, &c, &d});
  if (k < 0) return true;  // all four points coincide
  // The points are collinear and differ along k, so their line maps one-to-one onto axis k.
  const double lo = std::max(std::min(a[k], b[k]), std::min(c[k], d[k]));
  const double hi = std::min(std::max(a[k], b[k]), std::max(c[k], d[k]));
  return lo <= hi;
}

// Whether w and z lie on the same open ray from v (all three collinear, w ≠ v, z ≠ v).
bool same_direction(const Vec3& v, const Vec3& w, const Vec3& z) {
  for (int k = 0; k < 3; ++k) {
    if (w[k] != v[k]) return (w[k] > v[k]) == (z[k] > v[k]) && z[k] != v[k];
  }
  return false;
}

// Whether p lies in the closed triangle t, p in its plane, `drop` a bijective projection.
bool point_in_triangle(int drop, const Vec3& p, const Vec3& t0, const Vec3& t1, const Vec3& t2) {
  const int o0 = orient2d_in(drop, t0, t1, p);
  const int o1 = orient2d_in(drop, t1, t2, p);
  const int o2 = orient2d_in(drop, t2, t0, p);
  return (o0 >= 0 && o1 >= 0 && o2 >= 0) || (o0 <= 0 && o1 <= 0 && o2 <= 0);
}

// Whether closed segments [a, b] and [c, d] meet, all four points in a plane on which the
// projection dropping `drop` is one-to-one (or all four collinear).
bool coplanar_segments_meet(int drop, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const int o1 = orient2d_in(drop, a, b, c), o2 = orient2d_in(drop, a, b, d);
  if (o1 * o2 > 0) return false;
  const int o3 = orient2d_in(drop, c, d, a), o4 = orient2d_in(drop, c, d, b);
  if (o3 * o4 > 0) return false;
  if (o1 == 0 && o2 == 0 && o3 == 0 && o4 == 0) return collinear_segments_overlap(a, b, c, d);
  return true;
}

// Whether closed segments [a, b] and [c, d] meet in 3D.
bool segments_meet(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  if (orient3d(a, b, c, d) != 0) return false;
  // Coplanar: find a projection that is one-to-one on their plane (any non-collinear triple).
  const std::array<std::array<const Vec3*, 3>, 4> triples{
      {{&a, &b, &c}, {&a, &b, &d}, {&a, &c, &d}, {&b, &c, &d}}};
  for (const auto& tri : triples) {
    const int drop = triangle_projection(*tri[0], *tri[1], *tri[2]);
    if (drop >= 0) return coplanar_segments_meet(drop, a, b, c, d);
  }
  return collinear_segments_overlap(a, b, c, d);  // all four on one line
}

// Whether the closed segment [a, b] meets the closed triangle t (either may be degenerate);
// `drop` is triangle_projection(t0, t1, t2), computed once by the caller.
bool segment_meets_triangle(const Vec3& a, const Vec3& b, const Vec3& t0, const Vec3& t1,
                            const Vec3& t2, int drop) {
  if (drop < 0) {  // the triangle is the union of its edges
    return segments_meet(a, b, t0, t1) || segments_meet(a, b, t1, t2) ||
           segments_meet(a, b, t2, t0);
  }
  const int oa = orient3d(t0, t1, t2, a), ob = orient3d(t0, t1, t2, b);
  if (oa * ob > 0) return false;
  if (oa == 0 && ob == 0) {  // in the triangle's plane
    return point_in_triangle(drop, a, t0, t1, t2) || point_in_triangle(drop, b, t0, t1, t2) ||
           coplanar_segments_meet(drop, a, b, t0, t1) ||
           coplanar_segments_meet(drop, a, b, t1, t2) || coplanar_segments_meet(drop, a, b, t2, t0);
  }
  if (oa == 0) return point_in_triangle(drop, a, t0, t1, t2);
  if (ob == 0) return point_in_triangle(drop, b, t0, t1, t2);
  // The segment crosses the plane at an interior point: inside iff the line through a, b passes
  // on the same side of the three edge lines (zeros: on an edge or a corner).
  const int s0 = orient3d(a, b, t0, t1), s1 = orient3d(a, b, t1, t2), s2 = orient3d(a, b, t2, t0);
  return (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
}

bool boxes_disjoint(const std::array<Vec3, 3>& p, const std::array<Vec3, 3>& q) {
  for (int k = 0; k < 3; ++k) {
    const double plo = std::min({p[0][k], p[1][k], p[2][k]});
    const double phi = std::max({p[0][k], p[1][k], p[2][k]});
    const double qlo = std::min({q[0][k], q[1][k], q[2][k]});
    const double qhi = std::max({q[0][k], q[1][k], q[2][k]});
    if (phi < qlo || qhi < plo) return true;
  }
  return false;
}

// Whether all three corners of q lie strictly on one side of the plane of p (p non-degenerate).
bool strictly_one_side(const std::array<Vec3, 3>& p, const std::array<Vec3, 3>& q) {
  const int o0 = orient3d(p[0], p[1], p[2], q[0]);
  if (o0 == 0) return false;
  const int o1 = orient3d(p[0], p[1], p[2], q[1]);
  if (o1 != o0) return false;
  return orient3d(p[0], p[1], p[2], q[2]) == o0;
}

// Shared vertex: whether the open ray piece (v, w] meets the closed triangle t, where t's
// corner j is at v (t_drop: its triangle_projection).
bool ray_piece_meets(const Vec3& v, const Vec3& w, const std::array<Vec3, 3>& t, int j,
                     int t_drop) {
  const Vec3& t1 = t[static_cast<std::size_t>((j + 1) % 3)];
  const Vec3& t2 = t[static_cast<std::size_t>((j + 2) % 3)];
  if (t_drop >= 0) {
    // [v, w] ∩ t is a segment [v, y]: y = w inside t, or y on the edge opposite v.
    return segment_meets_triangle(w, w, t[0], t[1], t[2], t_drop) || segments_meet(v, w, t1, t2);
  }
  // t is a segment through v: the pieces meet off v iff they leave v the same way.
  for (const Vec3* z : {&t1, &t2}) {
    if (*z != v && collinear(v, w, *z) && same_direction(v, w, *z)) return true;
  }
  return false;
}

// Shared vertex at corner i of a and j of b: whether a and b have a common point off v. The
// intersection is convex and holds v; if it holds another point, the ray from v through it
// leaves a or b through the part of that face away from v (the edge opposite v when the face is
// a proper triangle), and that exit point lies in both faces.
bool meet_off_vertex(const std::array<Vec3, 3>& a, int i, int a_drop, const std::array<Vec3, 3>& b,
                     int j, int b_drop) {
  const Vec3& v = a[static_cast<std::size_t>(i)];
  const auto pieces_meet = [&v](const std::array<Vec3, 3>& s, int si, int s_drop,
                                const std::array<Vec3, 3>& t, int ti, int t_drop) {
    const Vec3& s1 = s[static_cast<std::size_t>((si + 1) % 3)];
    const Vec3& s2 = s[static_cast<std::size_t>((si + 2) % 3)];
    bool far_edge = s_drop >= 0;
    if (!far_edge) {  // a segment: is v off the edge opposite it (then v ends the segment)?
      far_edge = !collinear_segments_overlap(v, v, s1, s2);
    }
    if (far_edge) return segment_meets_triangle(s1, s2, t[0], t[1], t[2], t_drop);
    // v lies on the opposite edge: s minus v is the two pieces (v, s1] and (v, s2].
    return (s1 != v && ray_piece_meets(v, s1, t, ti, t_drop)) ||
           (s2 != v && ray_piece_meets(v, s2, t, ti, t_drop));
  };
  return pieces_meet(a, i, a_drop, b, j, b_drop) || pieces_meet(b, j, b_drop, a, i, a_drop);
}

// Shared edge (u, v), third corners ra and rb: whether the faces overlap off the edge.
bool meet_off_edge(const Vec3& u, const Vec3& v, const Vec3& ra, const Vec3& rb) {
  // Not coplanar: both faces are proper triangles and meet only on the line of the edge, which
  // cuts each of them exactly in the edge.
  if (orient3d(u, v, ra, rb) != 0) return false;
  const int drop_a = triangle_projection(u, v, ra);
  const int drop_b = triangle_projection(u, v, rb);
  if (drop_a >= 0 && drop_b >= 0) {
    return orient2d_in(drop_a, u, v, ra) * orient2d_in(drop_a, u, v, rb) > 0;
  }
  // A proper triangle meets the line of its edge (which holds the other, flat, face) only in
  // the edge.
  if (drop_a >= 0 || drop_b >= 0) return false;
  if (u == v) {  // two segments from one point
    return ra != u && rb != u && collinear(u, ra, rb) && same_direction(u, ra, rb);
  }
  // Both flat on the line of the edge: do their spans overlap beyond the edge?
  const int k = varying_axis({&u, &v});
  const double elo = std::min(u[k], v[k]), ehi = std::max(u[k], v[k]);
  const double lo = std::max(std::min(elo, ra[k]), std::min(elo, rb[k]));
  const double hi = std::min(std::max(ehi, ra[k]), std::max(ehi, rb[k]));
  return lo < elo || hi > ehi;
}

}  // namespace

int orient2d(const Vec2& a, const Vec2& b, const Vec2& c) {
  const double left = (a[0] - c[0]) * (b[1] - c[1]);
  const double right = (a[1] - c[1]) * (b[0] - c[0]);
  const double det = left - right;
  const double bound = kOrient2dBound * (std::abs(left) + std::abs(right));
  if (det > bound || -det > bound) return sign_of(det);
  return orient2d_exact(a, b, c);
}

int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double adx = a.x - d.x, bdx = b.x - d.x, cdx = c.x - d.x;
  const double ady = a.y - d.y, bdy = b.y - d.y, cdy = c.y - d.y;
  const double adz = a.z - d.z, bdz = b.z - d.z, cdz = c.z - d.z;
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
  const double permanent = (std::abs(bdxcdy) + std::abs(cdxbdy)) * std::abs(adz) +
                           (std::abs(cdxady) + std::abs(adxcdy)) * std::abs(bdz) +
                           (std::abs(adxbdy) + std::abs(bdxady)) * std::abs(cdz);
  const double bound = kOrient3dBound * permanent;
  // det[a − d, b − d, c − d] = −det[b − a, c − a, d − a]: flip to the documented convention.
  if (det > bound || -det > bound) return -sign_of(det);
  return -orient3d_exact(a, b, c, d);
}

bool triangle_degenerate(const Vec3& a, const Vec3& b, const Vec3& c) {
  return collinear(a, b, c);
}

bool triangles_intersect(const std::array<Vec3, 3>& p, const std::array<Vec3, 3>& q) {
  if (boxes_disjoint(p, q)) return false;
  const int p_drop = triangle_projection(p[0], p[1], p[2]);
  const int q_drop = triangle_projection(q[0], q[1], q[2]);
  if (p_drop >= 0 && strictly_one_side(p, q)) return false;
  if (q_drop >= 0 && strictly_one_side(q, p)) return false;
  // Two closed triangles meet iff an edge of one meets the other: if they are not coplanar their
  // intersection is an interval of the common line whose ends lie on edges; if they are, a
  // triangle meeting the other without an edge crossing it lies inside it, edges included.
  for (int e = 0; e < 3; ++e) {
    const auto s = static_cast<std::size_t>(e), t = static_cast<std::size_t>((e + 1) % 3);
    if (segment_meets_triangle(p[s], p[t], q[0], q[1], q[2], q_drop)) return true;
  }
  for (int e = 0; e < 3; ++e) {
    const auto s = static_cast<std::size_t>(e), t = static_cast<std::size_t>((e + 1) % 3);
    if (segment_meets_triangle(q[s], q[t], p[0], p[1], p[2], p_drop)) return true;
  }
  return false;
}

bool faces_intersect(const std::array<Vec3, 3>& p, const std::array<Index, 3>& pid,
                     const std::array<Vec3, 3>& q, const std::array<Index, 3>& qid) {
  // Distinct ids of p that q shares, with their first corner in p and in q.
  int shared = 0;
  int in_p[3] = {0, 0, 0}, in_q[3] = {0, 0, 0};
  for (int i = 0; i < 3; ++i) {
    const Index id = pid[static_cast<std::size_t>(i)];
    bool seen = false;
    for (int k = 0; k < i; ++k) seen = seen || pid[static_cast<std::size_t>(k)] == id;
    if (seen) continue;
    for (int j = 0; j < 3; ++j) {
      if (qid[static_cast<std::size_t>(j)] == id) {
        in_p[shared] = i;
        in_q[shared] = j;
        ++shared;
        break;
      }
    }
  }
  if (shared == 0) return triangles_intersect(p, q);
  if (shared >= 3) return true;  // the same corners: the faces coincide
  if (shared == 1) {
    if (boxes_disjoint(p, q)) return false;
    const int p_drop = triangle_projection(p[0], p[1], p[2]);
    const int q_drop = triangle_projection(q[0], q[1], q[2]);
    // If the corners of one face other than v lie strictly on one side of the other face's
    // plane, the first face meets that plane only at v (the common case of neighbours).
    const auto far_off_plane = [](const std::array<Vec3, 3>& s, int si,
                                  const std::array<Vec3, 3>& t) {
      const int o1 = orient3d(t[0], t[1], t[2], s[static_cast<std::size_t>((si + 1) % 3)]);
      return o1 != 0 && o1 == orient3d(t[0], t[1], t[2], s[static_cast<std::size_t>((si + 2) % 3)]);
    };
    if (q_drop >= 0 && far_off_plane(p, in_p[0], q)) return false;
    if (p_drop >= 0 && far_off_plane(q, in_q[0], p)) return false;
    return meet_off_vertex(p, in_p[0], p_drop, q, in_q[0], q_drop);
  }
  // A shared edge. The third corners: a corner whose id is not shared (a face made of the two
  // shared ids only lies in the edge and cannot overlap).
  const auto third = [](const std::array<Index, 3>& ids, const std::array<Index, 3>& other) {
    for (int i = 0; i < 3; ++i) {
      const Index id = ids[static_cast<std::size_t>(i)];
      if (id != other[0] && id != other[1] && id != other[2]) return i;
    }
    return -1;
  };
  const int ra = third(pid, qid), rb = third(qid, pid);
  if (ra < 0 || rb < 0) return false;
  const Vec3& u = p[static_cast<std::size_t>(in_p[0])];
  const Vec3& v = p[static_cast<std::size_t>(in_p[1])];
  return meet_off_edge(u, v, p[static_cast<std::size_t>(ra)], q[static_cast<std::size_t>(rb)]);
}

}  // namespace isoforge
