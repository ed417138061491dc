// Primitive fitting: closed-form / algebraic initialisation, then robust geometric refinement.
//
// Methods:
//   - Plane: principal component analysis (the normal is the covariance's least eigenvector).
//   - Sphere: the linear ("algebraic") sphere fit, |p|² = 2 c·p + (r² − |c|²) solved in the least
//     squares sense — I. Kåsa, "A circle fitting procedure and its error analysis", IEEE Trans.
//     Instrum. Meas. 25(1), 1976.
//   - Quadric: the algebraic fit minimising Σ Q(p)² subject to |coefficients| = 1 (the least
//     eigenvector of the scatter matrix of the monomials) — G. Taubin, "Estimation of planar
//     curves, surfaces and nonplanar space curves...", IEEE PAMI 13(11), 1991, which also gives
//     the first-order (Sampson) distance |Q| / |∇Q| used to refine it.
//   - Cylinder: the axis from the normals (the least eigenvector of Σ n nᵀ) or, without normals,
//     from the quadric (the eigenvector of its quadratic part with the smallest eigenvalue), then
//     a Kåsa circle fit of the points projected along the axis.
//   - Cone: the apex where the tangent planes meet (normals) or the quadric's center, the axis
//     from the quadric (the eigenvalue of the sign the other two do not have), the half angle
//     as the mean angle of the points about the axis.
// Refinement: Levenberg–Marquardt (Ceres) on the geometric distances with a Huber or Cauchy loss
// (P. J. Huber, "Robust estimation of a location parameter", Ann. Math. Statist. 35(1), 1964),
// scale from the median absolute residual. Everything runs in normalised coordinates (centroid
// at the origin, unit RMS radius) and is mapped back at the end.

#include "isoforge/fit/fit_primitive.hpp"
#include "fit/detail/fit_ops.hpp"
#include "fit/robust_constants.hpp"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>

namespace isoforge {
namespace {

using V3 = Eigen::Vector3d;

using fit_detail::kCauchyK;
using fit_detail::kHuberK;
using fit_detail::kMadToSigma;
constexpr double kInlierK = 2.5;        // inliers: |r| <= 2.5 σ (FitStats::inliers)
constexpr int kMaxRounds = 8;           // robust solves with a re-estimated scale, at most
// σ below this (normalised units, i.e. relative to the points' RMS radius) is rounding: the data
// are exact, there is nothing to be robust against, and it floors the inlier threshold.
constexpr double kExactSigma = 1e-12;
// Relative size below which a singular value or eigenvalue counts as zero: far above the
// rounding of normalised coordinates (~1e-16), far below any real extent of the data.
constexpr double kDegenerate = 1e-10;

const char* kind_name(PrimitiveKind k) {
  return to_string(k);
}

[[noreturn]] void fail(PrimitiveKind k, const std::string& what) {
  throw Error(std::string("fit_primitive: ") + kind_name(k) + ": " + what);
}

// ---- the data, normalised ----

struct Data {
  std::vector<V3> p;   // normalised points
  std::vector<V3> n;   // unit normals, or empty
  V3 center{0, 0, 0};  // world = center + scale * normalised
  double scale = 1;
};

Data load(DatasetRef ds, const FitOptions& o) {
  Data d;
  const std::size_t n = num_points(ds);
  d.p.resize(n);
  V3 sum(0, 0, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 q = point(ds, static_cast<Index>(i));
    if (!is_finite(q)) throw Error("fit_primitive: point " + std::to_string(i) + " is not finite");
    d.p[i] = V3(q.x, q.y, q.z);
    sum += d.p[i];
  }
  if (n == 0) return d;
  d.center = sum / static_cast<double>(n);
  double s2 = 0;
  for (auto& q : d.p) s2 += (q - d.center).squaredNorm();
  d.scale = std::sqrt(s2 / static_cast<double>(n));
  if (!(d.scale > 0)) d.scale = 1;  // all points equal: the degeneracy checks report it
  for (auto& q : d.p) q = (q - d.center) / d.scale;
  if (!o.use_normals) return d;
  const Attributes& pd = point_data(ds);
  const DataArray* a = pd.find("Normals");
  if (!a) a = pd.normals();
  if (!a || a->components() != 3 || a->tuples() != n) return d;
  d.n.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const V3 v(a->get(i, 0), a->get(i, 1), a->get(i, 2));
    const double len = v.norm();
    if (!std::isfinite(len) || !(len > 0)) {  // unusable: fit without normals
      d.n.clear();
      return d;
    }
    d.n[i] = v / len;
  }
  return d;
}

// Eigen decomposition of a symmetric 3x3 matrix, eigenvalues ascending.
// Every symmetric eigenproblem and solve of this file goes through one dynamic-size
// instantiation: Eigen's fixed-size 3x3, 4x4 and 10x10 solvers each cost seconds of compile
// time, and these matrices are decomposed a handful of times per fit.
using Eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>;

// Eigen decomposition of a symmetric matrix, eigenvalues ascending.
Eig eig(const Eigen::MatrixXd& m) {
  return Eig(m);
}
Eig eig3(const Eigen::Matrix3d& m) {
  return eig(m);
}

// The least-squares solution of the symmetric system m x = rhs (the pseudo-inverse, ignoring
// eigenvalues below kDegenerate of the largest; callers have checked that m is regular).
Eigen::VectorXd solve_symmetric(const Eig& e, const Eigen::VectorXd& rhs) {
  const Eigen::VectorXd& lam = e.eigenvalues();
  const double top = lam.cwiseAbs().maxCoeff();
  Eigen::VectorXd y = e.eigenvectors().transpose() * rhs;
  for (Eigen::Index i = 0; i < y.size(); ++i)
    y(i) = std::abs(lam(i)) > kDegenerate * top ? y(i) / lam(i) : 0.0;
  return e.eigenvectors() * y;
}

// ---- initialisations (normalised coordinates) ----

// Plane n·x = d; parameters nx ny nz d.
std::vector<double> init_plane(const Data& d) {
  Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
  for (const V3& p : d.p) c += p * p.transpose();  // centroid is the origin
  const auto e = eig3(c);
  if (!(e.eigenvalues()(1) > kDegenerate * e.eigenvalues()(2)))
    fail(PrimitiveKind::Plane, "the points are collinear (or all equal): no unique plane");
  const V3 n = e.eigenvectors().col(0);
  return {n.x(), n.y(), n.z(), 0.0};
}

// Kåsa circle fit of 2D points: center (u, v) and radius. Returns false if degenerate.
bool fit_circle_2d(const std::vector<Eigen::Vector2d>& q, Eigen::Vector2d& c, double& r) {
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (const auto& x : q) {
    const Eigen::Vector3d row(2 * x.x(), 2 * x.y(), 1);
    m += row * row.transpose();
    rhs += row * x.squaredNorm();
  }
  const auto e = eig3(m);
  if (!(e.eigenvalues()(0) > kDegenerate * e.eigenvalues()(2))) return false;
  const Eigen::Vector3d s = solve_symmetric(e, rhs);
  c = s.head<2>();
  const double r2 = s(2) + c.squaredNorm();
  if (!(r2 > 0)) return false;
  r = std::sqrt(r2);
  return true;
}

std::vector<double> init_sphere(const Data& d) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  Eigen::Vector4d rhs = Eigen::Vector4d::Zero();
  for (const V3& p : d.p) {
    const Eigen::Vector4d row(2 * p.x(), 2 * p.y(), 2 * p.z(), 1);
    m += row * row.transpose();
    rhs += row * p.squaredNorm();
  }
  const Eig e = eig(m);
  if (!(e.eigenvalues()(0) > kDegenerate * e.eigenvalues()(3)))
    fail(PrimitiveKind::Sphere, "the points are coplanar (or collinear): no unique sphere");
  const Eigen::Vector4d s = solve_symmetric(e, rhs);
  const V3 c = s.head<3>();
  const double r2 = s(3) + c.squaredNorm();
  if (!(r2 > 0)) fail(PrimitiveKind::Sphere, "the points do not lie near a sphere");
  return {c.x(), c.y(), c.z(), std::sqrt(r2)};
}

// The monomials of a quadric in the order of ImplicitFunction::quadric.
Eigen::Matrix<double, 10, 1> monomials(const V3& p) {
  Eigen::Matrix<double, 10, 1> m;
  m << p.x() * p.x(), p.y() * p.y(), p.z() * p.z(), p.x() * p.y(), p.y() * p.z(), p.x() * p.z(),
      p.x(), p.y(), p.z(), 1;
  return m;
}

// Algebraic quadric: the unit coefficient vector minimising Σ Q(p)².
std::vector<double> init_quadric(const Data& d, PrimitiveKind kind) {
  Eigen::Matrix<double, 10, 10> m = Eigen::Matrix<double, 10, 10>::Zero();
  for (const V3& p : d.p) {
    const auto row = monomials(p);
    m += row * row.transpose();
  }
  const Eig e = eig(m);
  // A second (near-)zero eigenvalue: several quadrics through the points (they lie on a plane,
  // a conic or too few distinct places), so the shape is not determined.
  if (!(e.eigenvalues()(1) > kDegenerate * e.eigenvalues()(9)))
    fail(kind,
         "the points do not determine a quadric (they lie on a plane, a curve or too few "
         "distinct places)");
  const auto v = e.eigenvectors().col(0);
  return std::vector<double>(v.data(), v.data() + 10);
}

void quadric_parts(const std::vector<double>& q, Eigen::Matrix3d& a, V3& b) {
  a << q[0], q[3] / 2, q[5] / 2, q[3] / 2, q[1], q[4] / 2, q[5] / 2, q[4] / 2, q[2];
  b = V3(q[6], q[7], q[8]);
}

// Axis a, then a circle fit of the points projected on the plane through the origin ⟂ a.
std::vector<double> cylinder_from_axis(const Data& d, V3 a) {
  a.normalize();
  const V3 u = a.unitOrthogonal(), v = a.cross(u);
  std::vector<Eigen::Vector2d> q(d.p.size());
  for (std::size_t i = 0; i < q.size(); ++i) q[i] = {d.p[i].dot(u), d.p[i].dot(v)};
  Eigen::Vector2d c;
  double r = 0;
  if (!fit_circle_2d(q, c, r))
    fail(PrimitiveKind::Cylinder,
         "the points project onto a line along the axis: no unique "
         "cylinder (are they planar?)");
  const V3 p = c.x() * u + c.y() * v;
  return {p.x(), p.y(), p.z(), a.x(), a.y(), a.z(), r};
}

std::vector<double> init_cylinder(const Data& d) {
  if (!d.n.empty()) {
    Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
    for (const V3& n : d.n) m += n * n.transpose();
    const auto e = eig3(m);
    // Normals spanning two directions fix the axis as their common perpendicular.
    if (e.eigenvalues()(1) > 1e-3 * e.eigenvalues()(2))
      return cylinder_from_axis(d, e.eigenvectors().col(0));
  }
  const auto q = init_quadric(d, PrimitiveKind::Cylinder);
  Eigen::Matrix3d a;
  V3 b;
  quadric_parts(q, a, b);
  const auto e = eig3(a);
  int k = 0;  // the eigenvalue of least magnitude
  for (int i = 1; i < 3; ++i)
    if (std::abs(e.eigenvalues()(i)) < std::abs(e.eigenvalues()(k))) k = i;
  return cylinder_from_axis(d, e.eigenvectors().col(k));
}

std::vector<double> init_cone(const Data& d) {
  const auto q = init_quadric(d, PrimitiveKind::Cone);
  Eigen::Matrix3d a;
  V3 b;
  quadric_parts(q, a, b);
  const auto e = eig3(a);
  const V3 lam = e.eigenvalues();
  // A cone's quadratic part has signature (+, +, −) up to sign: the axis is the odd one.
  int k = -1;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, l = (i + 2) % 3;
    if ((lam(i) > 0) != (lam(j) > 0) && (lam(j) > 0) == (lam(l) > 0)) k = i;
  }
  if (k < 0)
    fail(PrimitiveKind::Cone,
         "the points do not lie near a cone (the fitted quadric "
         "has no axis of opposite curvature)");
  V3 axis = e.eigenvectors().col(k);
  V3 apex;
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  V3 rhs(0, 0, 0);
  if (!d.n.empty()) {  // the tangent planes n·(x − p) = 0 all contain the apex
    for (std::size_t i = 0; i < d.p.size(); ++i) {
      const Eigen::Matrix3d nn = d.n[i] * d.n[i].transpose();
      m += nn;
      rhs += nn * d.p[i];
    }
  }
  const auto em = eig3(m);
  if (!d.n.empty() && em.eigenvalues()(0) > 1e-3 * em.eigenvalues()(2)) {
    apex = solve_symmetric(em, rhs);
  } else {  // the quadric's center: ∇Q = 2 A x + b = 0
    apex = solve_symmetric(eig3(a), -b / 2);
  }
  if (!apex.allFinite()) fail(PrimitiveKind::Cone, "no apex found (are the points a cylinder?)");
  double h_sum = 0, angle = 0;
  for (const V3& p : d.p) h_sum += (p - apex).dot(axis);
  if (h_sum < 0) axis = -axis;
  for (const V3& p : d.p) {
    const V3 w = p - apex;
    const double h = w.dot(axis);
    angle += std::atan2(w.cross(axis).norm(), std::abs(h));
  }
  angle /= static_cast<double>(d.p.size());
  angle = std::clamp(angle, 0.01, std::numbers::pi / 2 - 0.01);
  return {apex.x(), apex.y(), apex.z(), axis.x(), axis.y(), axis.z(), angle};
}

// ---- forward-mode derivatives ----
//
// A dual number v + Σ d_i ε_i carries the derivatives with respect to the N parameters through
// the residual formulas below (written once, templated on the number type). Ceres's Jet does
// the same with an Eigen vector inside; these few operations are all the residuals need and
// compile faster (docs/algorithms/fitting.md, "Compile time").

template <int N>
struct Dual {
  double v = 0;
  std::array<double, N> d{};
};
template <int N>
Dual<N> operator+(Dual<N> a, const Dual<N>& b) {
  a.v += b.v;
  for (int i = 0; i < N; ++i) a.d[i] += b.d[i];
  return a;
}
template <int N>
Dual<N> operator-(Dual<N> a, const Dual<N>& b) {
  a.v -= b.v;
  for (int i = 0; i < N; ++i) a.d[i] -= b.d[i];
  return a;
}
template <int N>
Dual<N> operator*(const Dual<N>& a, const Dual<N>& b) {
  Dual<N> r;
  r.v = a.v * b.v;
  for (int i = 0; i < N; ++i) r.d[i] = a.d[i] * b.v + a.v * b.d[i];
  return r;
}
template <int N>
Dual<N> operator/(const Dual<N>& a, const Dual<N>& b) {
  Dual<N> r;
  r.v = a.v / b.v;
  for (int i = 0; i < N; ++i) r.d[i] = (a.d[i] - r.v * b.d[i]) / b.v;
  return r;
}
template <int N>
Dual<N> operator*(double s, Dual<N> a) {
  a.v *= s;
  for (double& x : a.d) x *= s;
  return a;
}
template <int N>
Dual<N> operator*(const Dual<N>& a, double s) {
  return s * a;
}
template <int N>
Dual<N> operator+(Dual<N> a, double s) {
  a.v += s;
  return a;
}
template <int N>
Dual<N> operator-(double s, const Dual<N>& a) {
  return (-1.0 * a) + s;
}
template <int N>
Dual<N> operator-(const Dual<N>& a, double s) {
  return a + (-s);
}
// f(a) with f'(a) = df: the chain rule.
template <int N>
Dual<N> chain(const Dual<N>& a, double f, double df) {
  Dual<N> r;
  r.v = f;
  for (int i = 0; i < N; ++i) r.d[i] = df * a.d[i];
  return r;
}
template <int N>
Dual<N> sqrt(const Dual<N>& a) {
  const double s = std::sqrt(a.v);
  return chain(a, s, 0.5 / s);
}
template <int N>
Dual<N> cos(const Dual<N>& a) {
  return chain(a, std::cos(a.v), -std::sin(a.v));
}
template <int N>
Dual<N> sin(const Dual<N>& a) {
  return chain(a, std::sin(a.v), std::cos(a.v));
}
template <int N>
Dual<N> abs(const Dual<N>& a) {
  return a.v < 0 ? -1.0 * a : a;
}

// ---- geometric residuals (normalised coordinates), templated on the number type ----

template <class T>
T norm3(const T* v) {
  using std::sqrt;
  return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

struct PlaneCost {
  V3 p;
  template <class T>
  bool operator()(const T* q, T* r) const {
    r[0] = (q[0] * p.x() + q[1] * p.y() + q[2] * p.z() - q[3]) / norm3(q);
    return true;
  }
};

struct SphereCost {
  V3 p;
  template <class T>
  bool operator()(const T* q, T* r) const {
    const T w[3] = {p.x() - q[0], p.y() - q[1], p.z() - q[2]};
    r[0] = norm3(w) - q[3];
    return true;
  }
};

// Distance from the axis: |(p − c) × a| / |a|.
template <class T>
T axis_distance(const V3& p, const T* c, const T* a, T& h) {
  const T w[3] = {p.x() - c[0], p.y() - c[1], p.z() - c[2]};
  const T x[3] = {w[1] * a[2] - w[2] * a[1], w[2] * a[0] - w[0] * a[2], w[0] * a[1] - w[1] * a[0]};
  const T na = norm3(a);
  h = (w[0] * a[0] + w[1] * a[1] + w[2] * a[2]) / na;
  return norm3(x) / na;
}

struct CylinderCost {
  V3 p;
  template <class T>
  bool operator()(const T* q, T* r) const {
    T h;
    r[0] = axis_distance(p, q, q + 3, h) - q[6];
    return true;
  }
};

struct ConeCost {
  V3 p;
  template <class T>
  bool operator()(const T* q, T* r) const {
    T h;
    const T rho = axis_distance(p, q, q + 3, h);
    using std::abs, std::cos, std::sin;
    r[0] = rho * cos(q[6]) - abs(h) * sin(q[6]);
    return true;
  }
};

struct QuadricCost {
  V3 p;
  template <class T>
  bool operator()(const T* a, T* r) const {
    const double x = p.x(), y = p.y(), z = p.z();
    const T v = a[0] * x * x + a[1] * y * y + a[2] * z * z + a[3] * x * y + a[4] * y * z +
                a[5] * x * z + a[6] * x + a[7] * y + a[8] * z + a[9];
    const T g[3] = {2.0 * a[0] * x + a[3] * y + a[5] * z + a[6],
                    2.0 * a[1] * y + a[3] * x + a[4] * z + a[7],
                    2.0 * a[2] * z + a[4] * y + a[5] * x + a[8]};
    r[0] = v / norm3(g);
    return true;
  }
};

// Residual of each point for parameters q (plain doubles, normalised coordinates).
std::vector<double> residuals(PrimitiveKind k, const Data& d, const std::vector<double>& q) {
  std::vector<double> r(d.p.size());
  for (std::size_t i = 0; i < d.p.size(); ++i) {
    switch (k) {
      case PrimitiveKind::Plane:
        PlaneCost{d.p[i]}(q.data(), &r[i]);
        break;
      case PrimitiveKind::Sphere:
        SphereCost{d.p[i]}(q.data(), &r[i]);
        break;
      case PrimitiveKind::Cylinder:
        CylinderCost{d.p[i]}(q.data(), &r[i]);
        break;
      case PrimitiveKind::Cone:
        ConeCost{d.p[i]}(q.data(), &r[i]);
        break;
      case PrimitiveKind::Quadric:
        QuadricCost{d.p[i]}(q.data(), &r[i]);
        break;
    }
  }
  return r;
}

double median_abs(std::vector<double> r) {
  if (r.empty()) return 0;
  for (double& x : r) x = std::abs(x);
  const auto mid = r.begin() + static_cast<std::ptrdiff_t>(r.size() / 2);
  std::nth_element(r.begin(), mid, r.end());
  return *mid;
}

// The residual of one point and its derivatives (dual numbers) for Ceres.
template <class Cost, int N>
class PointCost final : public ceres::SizedCostFunction<1, N> {
 public:
  explicit PointCost(const V3& p) : cost_{p} {}
  bool Evaluate(double const* const* q, double* r, double** jac) const override {
    if (!jac || !jac[0]) {
      cost_(q[0], r);
      return std::isfinite(r[0]);
    }
    std::array<Dual<N>, N> x;
    for (int i = 0; i < N; ++i) {
      x[i].v = q[0][i];
      x[i].d[i] = 1;
    }
    Dual<N> out;
    cost_(x.data(), &out);
    r[0] = out.v;
    bool finite = std::isfinite(out.v);
    for (int i = 0; i < N; ++i) {
      jac[0][i] = out.d[i];
      finite = finite && std::isfinite(out.d[i]);
    }
    return finite;
  }

 private:
  Cost cost_;
};

template <class Cost, int N>
ceres::CostFunction* cost(const V3& p) {
  return new PointCost<Cost, N>(p);
}

// Stops the solver when the progress callback asks to cancel.
class CancelCheck : public ceres::IterationCallback {
 public:
  CancelCheck(const ProgressCallback& progress, double from, double to, int max_iterations)
      : progress_(progress), from_(from), to_(to), max_(max_iterations) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    if (!progress_) return ceres::SOLVER_CONTINUE;
    const double f = std::min(1.0, static_cast<double>(s.iteration) / max_);
    if (!progress_(from_ + f * (to_ - from_))) {
      cancelled = true;
      return ceres::SOLVER_ABORT;
    }
    return ceres::SOLVER_CONTINUE;
  }
  bool cancelled = false;

 private:
  const ProgressCallback& progress_;
  double from_, to_;
  int max_;
};

struct SolveResult {
  int iterations = 0;
  bool converged = false;
};

// One Levenberg–Marquardt solve of all point residuals with `loss` of scale `a` (normalised).
SolveResult solve(PrimitiveKind k, const Data& d, std::vector<double>& q, RobustLoss loss, double a,
                  const FitOptions& o, double from, double to) {
  ceres::Problem::Options po;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  std::unique_ptr<ceres::LossFunction> lf;
  if (loss == RobustLoss::Huber) lf = std::make_unique<ceres::HuberLoss>(a);
  if (loss == RobustLoss::Cauchy) lf = std::make_unique<ceres::CauchyLoss>(a);
  for (const V3& p : d.p) {
    ceres::CostFunction* c = nullptr;
    switch (k) {
      case PrimitiveKind::Plane:
        c = cost<PlaneCost, 4>(p);
        break;
      case PrimitiveKind::Sphere:
        c = cost<SphereCost, 4>(p);
        break;
      case PrimitiveKind::Cylinder:
        c = cost<CylinderCost, 7>(p);
        break;
      case PrimitiveKind::Cone:
        c = cost<ConeCost, 7>(p);
        break;
      case PrimitiveKind::Quadric:
        c = cost<QuadricCost, 10>(p);
        break;
    }
    problem.AddResidualBlock(c, lf.get(), q.data());
  }
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = o.max_iterations;
  so.num_threads = 1;  // determinism: the sums never depend on a thread count
  so.function_tolerance = 1e-15;
  so.gradient_tolerance = 1e-15;
  so.parameter_tolerance = 1e-14;
  so.logging_type = ceres::SILENT;
  CancelCheck check(o.progress, from, to, o.max_iterations);
  so.callbacks.push_back(&check);
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  if (check.cancelled) throw Cancelled("fit_primitive");
  SolveResult out;
  out.iterations = static_cast<int>(summary.iterations.size());
  out.converged = summary.termination_type == ceres::CONVERGENCE;
  return out;
}

// ---- results in world coordinates ----

V3 world(const Data& d, const V3& p) {
  return d.center + d.scale * p;
}
Vec3 vec(const V3& v) {
  return {v.x(), v.y(), v.z()};
}

// Orients a direction without other information: its largest component positive.
V3 canonical_sign(V3 a) {
  int k = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(a(i)) > std::abs(a(k))) k = i;
  return a(k) < 0 ? V3(-a) : a;
}

FittedPrimitive finish(PrimitiveKind k, const Data& d, std::vector<double> q) {
  FittedPrimitive out;
  out.kind = k;
  switch (k) {
    case PrimitiveKind::Plane: {
      V3 n(q[0], q[1], q[2]);
      const double len = n.norm();
      n /= len;
      double off = q[3] / len;
      V3 oriented = canonical_sign(n);
      if (!d.n.empty()) {
        V3 mean(0, 0, 0);
        for (const V3& m : d.n) mean += m;
        if (mean.norm() > 0) oriented = mean.dot(n) < 0 ? V3(-n) : n;
      }
      if (oriented.dot(n) < 0) off = -off;
      n = oriented;
      const double dw = d.scale * off + n.dot(d.center);
      out.parameters = {n.x(), n.y(), n.z(), dw};
      out.function = ImplicitFunction::plane(vec(dw * n), vec(n));
      break;
    }
    case PrimitiveKind::Sphere: {
      const V3 c = world(d, V3(q[0], q[1], q[2]));
      const double r = d.scale * std::abs(q[3]);
      out.parameters = {c.x(), c.y(), c.z(), r};
      out.function = ImplicitFunction::sphere(vec(c), r);
      break;
    }
    case PrimitiveKind::Cylinder: {
      const V3 a = canonical_sign(V3(q[3], q[4], q[5]).normalized());
      V3 c(q[0], q[1], q[2]);
      c -= c.dot(a) * a;  // nearest the centroid (the origin)
      const V3 cw = world(d, c);
      const double r = d.scale * std::abs(q[6]);
      out.parameters = {cw.x(), cw.y(), cw.z(), a.x(), a.y(), a.z(), r};
      out.function = ImplicitFunction::cylinder(vec(cw), vec(a), r);
      break;
    }
    case PrimitiveKind::Cone: {
      V3 a = V3(q[3], q[4], q[5]).normalized();
      const V3 apex(q[0], q[1], q[2]);
      double h = 0;
      for (const V3& p : d.p) h += (p - apex).dot(a);
      if (h < 0) a = -a;  // towards the points
      const double deg = q[6] * 180 / std::numbers::pi;
      if (!(deg > 0 && deg < 90))
        fail(k, "the fitted half angle " + std::to_string(deg) +
                    " degrees is not in (0, 90): the points are not a cone");
      const V3 aw = world(d, apex);
      out.parameters = {aw.x(), aw.y(), aw.z(), a.x(), a.y(), a.z(), deg};
      out.function = ImplicitFunction::cone(vec(aw), vec(a), deg);
      break;
    }
    case PrimitiveKind::Quadric: {
      // Q'(x') with x' = (x − m)/s, in world coordinates: A = A'/s², b = b'/s − 2A'm/s²,
      // c = mᵀA'm/s² − b'·m/s + c'.
      Eigen::Matrix3d a;
      V3 b;
      quadric_parts(q, a, b);
      const double s = d.scale;
      const V3& m = d.center;
      const Eigen::Matrix3d aw = a / (s * s);
      const V3 bw = b / s - 2 * aw * m;
      const double cw = m.dot(aw * m) - b.dot(m) / s + q[9];
      std::array<double, 10> w{aw(0, 0),     aw(1, 1), aw(2, 2), 2 * aw(0, 1), 2 * aw(1, 2),
                               2 * aw(0, 2), bw.x(),   bw.y(),   bw.z(),       cw};
      // Scale: mean |∇Q| over the points = 1; sign: ∇Q along the normals, else Q(centroid) < 0.
      double g = 0, along = 0;
      for (std::size_t i = 0; i < d.p.size(); ++i) {
        const V3 x = world(d, d.p[i]);
        const V3 grad = 2 * aw * x + bw;
        g += grad.norm();
        if (!d.n.empty()) along += grad.dot(d.n[i]);
      }
      g /= static_cast<double>(d.p.size());
      if (!(g > 0) || !std::isfinite(g))
        fail(k, "the fitted quadric has no gradient at the points");
      double f = 1 / g;
      if (d.n.empty() ? (m.dot(aw * m) + bw.dot(m) + cw > 0) : (along < 0)) f = -f;
      for (double& c : w) c *= f;
      out.parameters.assign(w.begin(), w.end());
      out.function = ImplicitFunction::quadric(w);
      break;
    }
  }
  out.expression = out.function.to_string();
  return out;
}

std::size_t min_points(PrimitiveKind k) {
  switch (k) {
    case PrimitiveKind::Plane:
      return 3;
    case PrimitiveKind::Sphere:
      return 4;
    default:
      return 9;
  }
}

}  // namespace

FitResult fit_detail::fit_primitive(DatasetRef points, const FitOptions& options) {
  const PrimitiveKind k = options.kind;
  if (static_cast<unsigned>(k) > static_cast<unsigned>(PrimitiveKind::Quadric))
    throw Error("fit_primitive: unknown primitive kind");
  if (static_cast<unsigned>(options.loss) > static_cast<unsigned>(RobustLoss::Cauchy))
    throw Error("fit_primitive: unknown robust loss");
  if (!std::isfinite(options.loss_scale) || options.loss_scale < 0)
    throw Error("fit_primitive: loss_scale must be a finite number >= 0, got " +
                std::to_string(options.loss_scale));
  if (options.max_iterations < 1)
    throw Error("fit_primitive: max_iterations must be >= 1, got " +
                std::to_string(options.max_iterations));
  const std::size_t n = num_points(points);
  if (n < min_points(k)) {
    fail(k,
         "needs at least " + std::to_string(min_points(k)) + " points, got " + std::to_string(n));
  }
  const Data d = load(points, options);
  report_progress(options.progress, 0, "fit_primitive");

  std::vector<double> q;
  switch (k) {
    case PrimitiveKind::Plane:
      q = init_plane(d);
      break;
    case PrimitiveKind::Sphere:
      q = init_sphere(d);
      break;
    case PrimitiveKind::Cylinder:
      q = init_cylinder(d);
      break;
    case PrimitiveKind::Cone:
      q = init_cone(d);
      break;
    case PrimitiveKind::Quadric:
      q = init_quadric(d, k);
      break;
  }
  report_progress(options.progress, 0.1, "fit_primitive");

  FitStats stats;
  stats.points = n;
  const double sigma0 = kMadToSigma * median_abs(residuals(k, d, q));
  const double k_loss = options.loss == RobustLoss::Cauchy ? kCauchyK : kHuberK;
  // Exact data (σ at rounding level) leave nothing to be robust against.
  const bool robust =
      options.loss != RobustLoss::None && (options.loss_scale > 0 || sigma0 > kExactSigma);
  SolveResult s;
  if (!robust) {
    s = solve(k, d, q, RobustLoss::None, 0, options, 0.1, 1.0);
    stats.iterations = s.iterations;
  } else if (options.loss_scale > 0) {
    s = solve(k, d, q, options.loss, options.loss_scale / d.scale, options, 0.1, 1.0);
    stats.iterations = s.iterations;
  } else {
    // The initial fit is pulled by the outliers, so its σ is too large: σ is estimated again
    // from each robust fit and the problem solved again, until σ settles (it shrinks by less
    // than 10%) or kMaxRounds solves were made.
    double sigma = sigma0;
    for (int round = 0; round < kMaxRounds; ++round) {
      const double from = 0.1 + 0.9 * round / kMaxRounds, to = 0.1 + 0.9 * (round + 1) / kMaxRounds;
      s = solve(k, d, q, options.loss, k_loss * sigma, options, from, to);
      stats.iterations += s.iterations;
      const double next = kMadToSigma * median_abs(residuals(k, d, q));
      if (!(next > kExactSigma) || next > 0.9 * sigma) break;
      sigma = next;
    }
  }
  stats.converged = s.converged;
  for (double v : q)
    if (!std::isfinite(v)) fail(k, "the refinement diverged (the points are not near this shape)");

  FittedPrimitive fitted = finish(k, d, std::move(q));
  // Final residuals in data units, from the returned function itself.
  std::vector<double> r(n);
  double sum2 = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 p = vec(world(d, d.p[i]));
    double v = fitted.function.value(p);
    if (k == PrimitiveKind::Quadric) v /= norm(fitted.function.gradient(p));
    r[i] = v;
    sum2 += v * v;
    stats.max_abs = std::max(stats.max_abs, std::abs(v));
  }
  stats.rms = std::sqrt(sum2 / static_cast<double>(n));
  stats.median_abs = median_abs(r);
  const double limit = kInlierK * std::max(kMadToSigma * stats.median_abs, kExactSigma * d.scale);
  for (double v : r) stats.inliers += std::abs(v) <= limit ? 1 : 0;
  report_progress(options.progress, 1, "fit_primitive");
  return {std::move(fitted), stats};
}

}  // namespace isoforge
