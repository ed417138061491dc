#include "isoforge/filters/streamline.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <iterator>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <type_traits>
#include <vector>

#include <fmt/format.h>
#include <tbb/task_arena.h>

#include "isoforge/core/cell.hpp"
#include "isoforge/core/cell_type.hpp"
#include "isoforge/core/interpolate.hpp"
#include "isoforge/core/memory.hpp"
#include "isoforge/core/parallel.hpp"
#include "isoforge/core/prefetch.hpp"
#include "isoforge/spatial/cell_locator.hpp"
#include "point_fields.hpp"
#include "probe_grid.hpp"
#include "probe_tets.hpp"

namespace isoforge {
namespace {

using filters_detail::finite;
using filters_detail::perpendicular;
using filters_detail::transport;
using filters_detail::unit_or_zero;
using StreamTerm = AttributeInterpolator::Term;

constexpr double kPcoordTolerance = 1e-9;  // parametric slack of the structured inside tests

/// Where a point lies: its cell (the dataset's numbering), sub-cell and parametric coordinates
/// there, and its interpolation stencil over the cell's points in the cell's VTK point order.
struct StreamHit {
  Index cell = -1;
  int sub_id = 0;
  Vec3 pcoords{};
  std::size_t n = 0;             // stencil size in `fixed`, or
  bool general = false;          // the stencil is in `terms`
  std::array<StreamTerm, 8> fixed{};
  std::vector<StreamTerm> terms;
  [[nodiscard]] std::span<const StreamTerm> stencil() const {
    return general ? std::span<const StreamTerm>(terms) : std::span<const StreamTerm>(fixed.data(), n);
  }
};

// ---------------------------------------------------------------------------------------------
// Point location, one class per kind of dataset: `find(p, cursor, hit)` is const and
// thread-safe; the cursor is one thread's state between consecutive queries.

/// Image data by arithmetic: the voxel, pixel or line holding p, with its multilinear weights.
class ImageField {
 public:
  struct Cursor {};
  ImageField(const ImageData& image, double cell_length) : image_(image) {
    std::size_t stride = 1;
    for (int a = 0; a < 3; ++a) {
      point_stride_[a] = stride;
      stride *= static_cast<std::size_t>(image.dims[a]);
    }
    // A flat axis (one point) holds points within a millionth of a cell of its plane.
    flat_tolerance_ = 1e-6 * cell_length;
    solid_ = image.dims[0] > 1 && image.dims[1] > 1 && image.dims[2] > 1;
    for (int a = 0; a < 3; ++a) {
      inverse_spacing_[a] = 1 / image.spacing[a];
      cells_[a] = static_cast<double>(image.dims[a] - 1);
    }
    for (int c = 0; c < 8; ++c) {
      corner_[static_cast<std::size_t>(c)] = ((c & 1) ? point_stride_[0] : 0) +
                                             ((c & 2) ? point_stride_[1] : 0) +
                                             ((c & 4) ? point_stride_[2] : 0);
    }
  }

  /// Whether the image is 3D (every axis has cells): `velocity` and `sample` apply.
  [[nodiscard]] bool solid() const { return solid_; }

  /// The trilinear interpolation of `values` at p (a 3D image), without building a stencil:
  /// false outside. Same weights, so the same value, as `find`.
  template <class Values>
  bool velocity(const Vec3& p, const Values& values, Vec3& v) const {
    double f[3];
    std::size_t base = 0;
    if (!voxel_of(p, base, f)) return false;
    const double gx[2] = {1 - f[0], f[0]}, gy[2] = {1 - f[1], f[1]}, gz[2] = {1 - f[2], f[2]};
    Vec3 sum{0, 0, 0};
    for (std::size_t c = 0; c < 8; ++c) {
      sum += values.at(base + corner_[c]) * (gx[c & 1] * gy[(c >> 1) & 1] * gz[c >> 2]);
    }
    v = sum;
    return true;
  }

  /// Prefetches the corners of the voxel holding p (a 3D image; nothing outside).
  template <class Values>
  void prefetch_voxel(const Vec3& p, const Values& values) const {
    double f[3];
    std::size_t base = 0;
    if (!voxel_of(p, base, f)) return;
    for (std::size_t c = 0; c < 8; ++c) prefetch(values.address(base + corner_[c]));
  }

  /// At p in a 3D image, from one load of the voxel's corners: the trilinear interpolation of
  /// `values` (as `velocity`), the hit with its stencil in VTK's order (as `find`), and with
  /// `grad` the gradients of the 3 components (grad[c] of component c: the trilinear map's
  /// derivatives, in closed form). False outside.
  template <class Values>
  bool sample(const Vec3& p, const Values& values, Vec3& v, StreamHit& hit,
              std::array<Vec3, 3>* grad) const {
    double f[3];
    std::size_t base = 0;
    if (!voxel_of(p, base, f)) return false;
    const double gx[2] = {1 - f[0], f[0]}, gy[2] = {1 - f[1], f[1]}, gz[2] = {1 - f[2], f[2]};
    Vec3 corner[8];
    Vec3 sum{0, 0, 0};
    for (std::size_t c = 0; c < 8; ++c) {
      corner[c] = values.at(base + corner_[c]);
      const double w = gx[c & 1] * gy[(c >> 1) & 1] * gz[c >> 2];
      sum += corner[c] * w;
      hit.fixed[c] = {base + corner_[c], w};
    }
    v = sum;
    hit.general = false;
    hit.n = 8;
    hit.sub_id = 0;
    hit.pcoords = {f[0], f[1], f[2]};
    if (grad) {
      Vec3 dr{0, 0, 0}, ds{0, 0, 0}, dt{0, 0, 0};
      for (std::size_t c = 0; c < 8; ++c) {
        const double sr = (c & 1) ? 1 : -1, ss = (c & 2) ? 1 : -1, st = (c & 4) ? 1 : -1;
        dr += corner[c] * (sr * gy[(c >> 1) & 1] * gz[c >> 2]);
        ds += corner[c] * (gx[c & 1] * ss * gz[c >> 2]);
        dt += corner[c] * (gx[c & 1] * gy[(c >> 1) & 1] * st);
      }
      for (int k = 0; k < 3; ++k) {
        (*grad)[static_cast<std::size_t>(k)] = {dr[k] * inverse_spacing_[0],
                                                 ds[k] * inverse_spacing_[1],
                                                 dt[k] * inverse_spacing_[2]};
      }
    }
    return true;
  }

  bool find(const Vec3& p, Cursor& /*cursor*/, StreamHit& hit) const {
    hit.general = false;
    hit.n = 1;
    hit.fixed[0] = {0, 1.0};
    hit.sub_id = 0;
    hit.pcoords = {};
    Index cell = 0, cell_stride = 1;
    int active = 0;
    for (int a = 0; a < 3; ++a) {
      const double offset = p[a] - image_.origin[a];
      if (image_.dims[a] == 1) {
        if (!(std::abs(offset) <= flat_tolerance_)) return false;
        continue;
      }
      const double u = offset / image_.spacing[a];
      const auto cells = static_cast<double>(image_.dims[a] - 1);
      if (!(u >= -kPcoordTolerance && u <= cells + kPcoordTolerance)) return false;
      const double i = std::clamp(std::floor(u), 0.0, cells - 1);
      const double f = std::clamp(u - i, 0.0, 1.0);
      const auto ii = static_cast<std::size_t>(i);
      const std::size_t s = point_stride_[a];
      for (std::size_t t = 0; t < hit.n; ++t) {  // (1 − f) terms first, then f terms: VTK order
        const StreamTerm lo = hit.fixed[t];
        hit.fixed[t] = {lo.first + ii * s, lo.second * (1 - f)};
        hit.fixed[hit.n + t] = {lo.first + (ii + 1) * s, lo.second * f};
      }
      hit.n *= 2;
      hit.pcoords[active++] = f;
      cell += static_cast<Index>(ii) * cell_stride;
      cell_stride *= image_.dims[a] - 1;
    }
    hit.cell = cell;
    return true;
  }

 private:
  /// The voxel of a 3D image holding p (its corner's point id `base`) and p's fractions in it,
  /// by multiplication with the inverse spacing; false outside (beyond the parametric slack).
  bool voxel_of(const Vec3& p, std::size_t& base, double (&f)[3]) const {
    for (int a = 0; a < 3; ++a) {
      const double u = (p[a] - image_.origin[a]) * inverse_spacing_[a];
      if (!(u >= -kPcoordTolerance && u <= cells_[a] + kPcoordTolerance)) return false;
      const double i = std::clamp(std::floor(u), 0.0, cells_[a] - 1);
      f[a] = std::clamp(u - i, 0.0, 1.0);
      base += static_cast<std::size_t>(i) * point_stride_[static_cast<std::size_t>(a)];
    }
    return true;
  }
  const ImageData& image_;
  std::array<std::size_t, 3> point_stride_{};
  std::array<std::size_t, 8> corner_{};
  double inverse_spacing_[3] = {1, 1, 1};
  double cells_[3] = {0, 0, 0};
  double flat_tolerance_ = 0;
  bool solid_ = false;
};

/// A 3D structured grid: the prober's walking locator (Newton's method in each hexahedron).
class GridField {
 public:
  using Cursor = probe_detail::GridCursor;
  explicit GridField(const StructuredGrid& grid)
      : locator_(grid, {}, kPcoordTolerance), offsets_(locator_.offsets()) {
    locator_.prepare();  // before the parallel traces find with it
  }
  /// Prefetches the cell predicted to hold p (see GridLocator::prefetch).
  template <class Values>
  void prefetch_cell(const Vec3& p, const Cursor& cursor, const Values& values) const {
    locator_.prefetch(p, cursor, static_cast<const std::byte*>(values.address(0)),
                      values.tuple_bytes());
  }
  bool find(const Vec3& p, Cursor& cursor, StreamHit& hit) const {
    probe_detail::GridHit g;
    if (!locator_.find(p, cursor, g)) return false;
    hit.general = false;
    hit.n = 8;
    hit.cell = g.cell;
    hit.sub_id = 0;
    hit.pcoords = {g.r, g.s, g.t};
    // Corner (a, b, c) in VTK's hexahedron order.
    static constexpr std::array<int, 8> kHexCorner = {0, 1, 3, 2, 4, 5, 7, 6};
    for (int k = 0; k < 8; ++k) {
      const int c = kHexCorner[static_cast<std::size_t>(k)];
      const double w = ((c & 1) ? g.r : 1 - g.r) * ((c & 2) ? g.s : 1 - g.s) *
                       ((c & 4) ? g.t : 1 - g.t);
      hit.fixed[static_cast<std::size_t>(k)] = {g.base + offsets_[static_cast<std::size_t>(c)], w};
    }
    return true;
  }

 private:
  probe_detail::GridLocator locator_;
  std::array<std::size_t, 8> offsets_;
};

/// A mesh of tetrahedra: the prober's walk from the previous query's tetrahedron across the
/// face opposite the most negative barycentric coordinate, then the cell locator — built at the
/// first walk that fails inside the mesh's bounds (a point outside them is outside every cell).
class TetField {
 public:
  struct Cursor {
    Index cell = -1;
  };
  TetField(const UnstructuredGrid& mesh, double cell_length)
      : mesh_(mesh), walker_(mesh, {}, kPcoordTolerance), cell_length_(cell_length) {}
  bool find(const Vec3& p, Cursor& cursor, StreamHit& hit) const {
    std::array<double, 4> w{};
    Index cell = cursor.cell >= 0 ? cursor.cell : walker_.seed(p);
    if (cell < 0 || !walker_.walk(p, cell, w)) {
      if (!walker_.in_bounds(p)) return false;
      const CellHit h = locator().find_cell(p);
      if (!h.found()) return false;
      cell = h.cell;
      for (std::size_t k = 0; k < 4; ++k) w[k] = h.weights[k];
    }
    cursor.cell = cell;
    const std::uint32_t* ids = walker_.points_of(cell);  // in cache after the walk
    hit.general = false;
    hit.n = 4;
    hit.cell = cell;
    hit.sub_id = 0;
    hit.pcoords = {w[1], w[2], w[3]};  // a tetrahedron's r, s, t are the weights of points 1-3
    for (std::size_t k = 0; k < 4; ++k) hit.fixed[k] = {static_cast<std::size_t>(ids[k]), w[k]};
    return true;
  }
  /// The gradients of the field's components in the hit's tetrahedron (constant there).
  template <class T>
  bool gradient(const StreamHit& hit, const T* values, std::array<Vec3, 3>& grad) const {
    return walker_.gradient(hit.cell, values, grad);
  }

 private:
  const CellLocator& locator() const {
    // Isolated: while building, this thread must not pick up another seed's task that would
    // wait here for the locator it is building.
    std::call_once(locator_once_, [&] {
      tbb::this_task_arena::isolate([&] {
        CellLocatorOptions o;
        o.tolerance = kPcoordTolerance;
        o.distance_tolerance = 1e-6 * cell_length_;
        locator_.emplace(mesh_, o);
      });
    });
    return *locator_;
  }
  const UnstructuredGrid& mesh_;
  probe_detail::TetWalker walker_;
  double cell_length_;
  mutable std::once_flag locator_once_;
  mutable std::optional<CellLocator> locator_;
};

/// Any other dataset: the cell of the previous query first, then the cell locator.
class CellField {
 public:
  struct Cursor {
    Index cell = -1;
    CellType type = CellType::Empty;
    std::vector<Index> ids;
    std::vector<Vec3> points;
  };
  CellField(DatasetRef input, double cell_length)
      : input_(input), locator_(input, locator_options(cell_length)) {}
  bool find(const Vec3& p, Cursor& cursor, StreamHit& hit) const {
    if (cursor.cell >= 0) {
      const CellPosition pos = locate_in_cell(cursor.type, cursor.points, p, kTolerance);
      if (pos.inside && cell_dimension(cursor.type) == 3) {
        fill(cursor, pos.sub_id, pos.pcoords, pos.weights, hit);
        return true;
      }
    }
    const CellHit h = locator_.find_cell(p);
    if (!h.found()) return false;
    if (h.cell != cursor.cell) {
      cursor.cell = h.cell;
      cursor.type = cell_type(input_, h.cell);
      cell_point_ids(input_, h.cell, cursor.ids);
      cursor.points.resize(cursor.ids.size());
      for (std::size_t i = 0; i < cursor.ids.size(); ++i) {
        cursor.points[i] = point(input_, cursor.ids[i]);
      }
    }
    fill(cursor, h.sub_id, h.pcoords, h.weights, hit);
    return true;
  }

 private:
  static constexpr double kTolerance = 1e-9;
  static CellLocatorOptions locator_options(double cell_length) {
    CellLocatorOptions o;
    o.tolerance = kTolerance;
    o.distance_tolerance = 1e-6 * cell_length;
    return o;
  }
  static void fill(const Cursor& c, int sub_id, const Vec3& pcoords, const CellWeights& w,
                   StreamHit& hit) {
    hit.general = true;
    hit.cell = c.cell;
    hit.sub_id = sub_id;
    hit.pcoords = pcoords;
    hit.terms.clear();
    for (std::size_t i = 0; i < c.ids.size(); ++i) {
      hit.terms.emplace_back(static_cast<std::size_t>(c.ids[i]), w[i]);
    }
  }
  DatasetRef input_;
  CellLocator locator_;
};

// ---------------------------------------------------------------------------------------------
// The vector field's values: float arrays read in place, any other type as a double copy.

class VectorValues {
 public:
  explicit VectorValues(const DataArray& a) {
    if (a.type() == ScalarType::Float32) {
      f_ = a.values<float>().data();
    } else if (a.type() == ScalarType::Float64) {
      d_ = a.values<double>().data();
    } else {
      copy_.resize(3 * a.tuples());
      for (std::size_t i = 0; i < a.tuples(); ++i) {
        for (int c = 0; c < 3; ++c) copy_[3 * i + static_cast<std::size_t>(c)] = a.get(i, c);
      }
      d_ = copy_.data();
    }
  }
  [[nodiscard]] Vec3 at(std::size_t i) const {
    if (f_) return {f_[3 * i], f_[3 * i + 1], f_[3 * i + 2]};
    return {d_[3 * i], d_[3 * i + 1], d_[3 * i + 2]};
  }
  /// Where value i is stored (for prefetching).
  [[nodiscard]] const void* address(std::size_t i) const {
    return f_ ? static_cast<const void*>(f_ + 3 * i) : static_cast<const void*>(d_ + 3 * i);
  }
  /// The bytes of one value (a float or double triple).
  [[nodiscard]] std::size_t tuple_bytes() const { return f_ ? 3 * sizeof(float) : 3 * sizeof(double); }
  /// The values as float or double triples (one of the two is null).
  [[nodiscard]] const float* floats() const { return f_; }
  [[nodiscard]] const double* doubles() const { return d_; }
  [[nodiscard]] Vec3 interpolate(std::span<const StreamTerm> stencil) const {
    Vec3 v{};
    for (const StreamTerm& t : stencil) v += at(t.first) * t.second;
    return v;
  }

 private:
  const float* f_ = nullptr;
  const double* d_ = nullptr;
  std::vector<double> copy_;
};

// ---------------------------------------------------------------------------------------------
// Integration

struct Line {
  std::vector<Vec3> x;
  std::vector<double> time;
  StreamTermination reason = StreamTermination::OutOfDomain;
  std::size_t steps = 0, rejected = 0;
  // Filled right after tracing, while the field around the line is still in cache: the
  // input's point arrays at the line's points, and the vorticity arrays (3, 1, 1, 3 floats).
  Attributes arrays;
  std::vector<float> vorticity, angular, rotation, normals;
};

/// The options in world units.
struct Config {
  StreamIntegrator integrator;
  double step, min_step, max_step, max_error;  // lengths
  double shrink_limit;                          // smallest step tried near the boundary
  std::size_t max_steps;
  double max_length, terminal_speed;
};

// Dormand–Prince 5(4) (Hairer, Nørsett & Wanner, Solving ODEs I, II.5, Table 5.2): stages,
// fifth-order weights (also the last stage row: first same as last) and the differences of the
// fourth-order weights, whose combination estimates the local error.
constexpr double kA21 = 1.0 / 5;
constexpr double kA31 = 3.0 / 40, kA32 = 9.0 / 40;
constexpr double kA41 = 44.0 / 45, kA42 = -56.0 / 15, kA43 = 32.0 / 9;
constexpr double kA51 = 19372.0 / 6561, kA52 = -25360.0 / 2187, kA53 = 64448.0 / 6561,
                 kA54 = -212.0 / 729;
constexpr double kA61 = 9017.0 / 3168, kA62 = -355.0 / 33, kA63 = 46732.0 / 5247,
                 kA64 = 49.0 / 176, kA65 = -5103.0 / 18656;
constexpr double kB1 = 35.0 / 384, kB3 = 500.0 / 1113, kB4 = 125.0 / 192, kB5 = -2187.0 / 6784,
                 kB6 = 11.0 / 84;
constexpr double kE1 = 71.0 / 57600, kE3 = -71.0 / 16695, kE4 = 71.0 / 1920,
                 kE5 = -17253.0 / 339200, kE6 = 22.0 / 525, kE7 = -1.0 / 40;

/// How far ahead (in steps) a line on image data prefetches its voxel: measured on the 256³
/// benchmark field, RK4, 4 lanes, one thread: none 1.24–1.33 s, 1 step 0.91 s, 2–3 steps
/// 0.88–0.93 s, 4 steps 0.89–0.90 s.
constexpr double kPrefetchSteps = 2.5;

template <class Field>
class Tracer {
 public:
  Tracer(const Field& field, const VectorValues& values, const Config& config)
      : field_(field), values_(values), c_(config) {}

  /// The velocity at x (times `sign`), false outside the domain or where it is not finite. A
  /// step long enough to overflow the coordinates (a huge step option) leaves the domain.
  bool eval(const Vec3& x, double sign, Vec3& v) {
    if (!finite(x)) return false;
    if constexpr (std::is_same_v<Field, ImageField>) {
      if (field_.solid()) {
        if (!field_.velocity(x, values_, v)) return false;
        v = v * sign;
        return finite(v);
      }
    }
    if (!field_.find(x, cursor_, hit_)) return false;
    v = values_.interpolate(hit_.stencil()) * sign;
    return finite(v);
  }

  /// The line from `seed` along sign × the field; `v0` is sign × the velocity at the seed.
  Line trace(const Vec3& seed, const Vec3& v0, double sign) {
    Line line;
    line.x.push_back(seed);
    line.time.push_back(0);
    Vec3 x = seed, k1 = v0;
    double h = c_.step, arc = 0, time = 0;
    const bool adaptive = c_.integrator == StreamIntegrator::RK45;
    for (;;) {
      const double speed = norm(k1);
      if (!(speed > c_.terminal_speed)) {
        line.reason = StreamTermination::Stagnation;
        break;
      }
      if (line.steps >= c_.max_steps) {
        line.reason = StreamTermination::OutOfSteps;
        break;
      }
      const double left = c_.max_length - arc;
      const bool last = left <= h;
      const double hl = last ? left : h;
      const double dt = hl / speed;
      Vec3 xn, kn;
      double err = 0;
      bool inside = true;
      if (c_.integrator == StreamIntegrator::RK2) {
        Vec3 k2;
        inside = eval(x + k1 * (0.5 * dt), sign, k2);
        if (inside) {
          xn = x + k2 * dt;
          inside = eval(xn, sign, kn);
        }
      } else if (c_.integrator == StreamIntegrator::RK4) {
        Vec3 k2, k3, k4;
        inside = eval(x + k1 * (0.5 * dt), sign, k2) && eval(x + k2 * (0.5 * dt), sign, k3) &&
                 eval(x + k3 * dt, sign, k4);
        if (inside) {
          xn = x + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (dt / 6);
          inside = eval(xn, sign, kn);
        }
      } else {
        Vec3 k2, k3, k4, k5, k6;
        inside = eval(x + k1 * (kA21 * dt), sign, k2) &&
                 eval(x + (k1 * kA31 + k2 * kA32) * dt, sign, k3) &&
                 eval(x + (k1 * kA41 + k2 * kA42 + k3 * kA43) * dt, sign, k4) &&
                 eval(x + (k1 * kA51 + k2 * kA52 + k3 * kA53 + k4 * kA54) * dt, sign, k5) &&
                 eval(x + (k1 * kA61 + k2 * kA62 + k3 * kA63 + k4 * kA64 + k5 * kA65) * dt,
                      sign, k6);
        if (inside) {
          xn = x + (k1 * kB1 + k3 * kB3 + k4 * kB4 + k5 * kB5 + k6 * kB6) * dt;
          inside = eval(xn, sign, kn);
          if (inside) {
            err = norm((k1 * kE1 + k3 * kE3 + k4 * kE4 + k5 * kE5 + k6 * kE6 + kn * kE7) * dt);
          }
        }
      }
      if (!inside) {  // halve the step to end near the boundary
        h = hl / 2;
        if (h < c_.shrink_limit) {
          line.reason = StreamTermination::OutOfDomain;
          break;
        }
        continue;
      }
      if (adaptive && err > c_.max_error && hl > c_.min_step) {
        h = std::max(c_.min_step, hl * std::max(0.2, 0.9 * std::pow(c_.max_error / err, 0.2)));
        ++line.rejected;
        continue;
      }
      arc += norm(xn - x);
      time += sign * dt;
      x = xn;
      k1 = kn;
      prefetch_ahead(x, k1, dt);
      line.x.push_back(x);
      line.time.push_back(time);
      ++line.steps;
      if (last) {
        line.reason = StreamTermination::OutOfLength;
        break;
      }
      if (adaptive) {
        const double grow = err > 0 ? 0.9 * std::pow(c_.max_error / err, 0.2) : 5.0;
        h = std::clamp(hl * std::min(5.0, grow), c_.min_step, c_.max_step);
      }
    }
    return line;
  }

  /// RK4 lines of several jobs at once (kLanes), their stage evaluations interleaved so that
  /// the memory loads of different lines overlap. Each line's arithmetic is trace()'s, in the
  /// same order, so the lines are bit-identical to it. `next(job, seed, v0, sign)` starts the
  /// next job (false when there is none); `done(job, line)` takes each finished line.
  template <class Next, class Done>
  void trace_rk4_lanes(Next&& next, Done&& done) {
    constexpr int kLanes = 4;
    struct Lane {
      bool busy = false, ok = false, last = false, tried = false;
      std::size_t job = 0;
      double sign = 1, h = 0, arc = 0, time = 0, hl = 0, dt = 0;
      Vec3 x, k1, k2, k3, k4, xn, kn;
      Line line;
    };
    std::array<Lane, kLanes> lanes;
    const auto start = [&](Lane& l) {
      Vec3 seed, v0;
      l.busy = next(l.job, seed, v0, l.sign);
      if (!l.busy) return;
      l.line = Line{};
      l.line.x.push_back(seed);
      l.line.time.push_back(0);
      l.x = seed;
      l.k1 = v0;
      l.h = c_.step;
      l.arc = l.time = 0;
    };
    const auto end = [&](Lane& l, StreamTermination reason) {
      l.line.reason = reason;
      done(l.job, std::move(l.line));
      start(l);
    };
    for (Lane& l : lanes) start(l);
    for (;;) {
      bool any = false;
      for (Lane& l : lanes) {
        l.ok = l.tried = false;
        // A lane whose line ends here takes its next job at once.
        while (l.busy) {
          const double speed = norm(l.k1);
          if (!(speed > c_.terminal_speed)) {
            end(l, StreamTermination::Stagnation);
            continue;
          }
          if (l.line.steps >= c_.max_steps) {
            end(l, StreamTermination::OutOfSteps);
            continue;
          }
          const double left = c_.max_length - l.arc;
          l.last = left <= l.h;
          l.hl = l.last ? left : l.h;
          l.dt = l.hl / speed;
          l.ok = l.tried = true;
          any = true;
          break;
        }
      }
      if (!any) return;
      for (Lane& l : lanes) {
        if (l.ok) l.ok = eval(l.x + l.k1 * (0.5 * l.dt), l.sign, l.k2);
      }
      for (Lane& l : lanes) {
        if (l.ok) l.ok = eval(l.x + l.k2 * (0.5 * l.dt), l.sign, l.k3);
      }
      for (Lane& l : lanes) {
        if (l.ok) l.ok = eval(l.x + l.k3 * l.dt, l.sign, l.k4);
      }
      for (Lane& l : lanes) {
        if (!l.ok) continue;
        l.xn = l.x + (l.k1 + l.k2 * 2.0 + l.k3 * 2.0 + l.k4) * (l.dt / 6);
        l.ok = eval(l.xn, l.sign, l.kn);
      }
      for (Lane& l : lanes) {
        if (!l.tried) continue;
        const double dt = l.dt;
        if (!l.ok) {  // halve the step to end near the boundary
          l.h = l.hl / 2;
          if (l.h < c_.shrink_limit) end(l, StreamTermination::OutOfDomain);
          continue;
        }
        l.arc += norm(l.xn - l.x);
        l.time += l.sign * dt;
        l.x = l.xn;
        l.k1 = l.kn;
        prefetch_ahead(l.x, l.k1, dt);
        l.line.x.push_back(l.x);
        l.line.time.push_back(l.time);
        ++l.line.steps;
        if (l.last) end(l, StreamTermination::OutOfLength);
      }
    }
  }

  typename Field::Cursor& cursor() { return cursor_; }

 private:
  /// On a 3D image, the voxel about kPrefetchSteps steps ahead of x (along k1, which is sign ×
  /// the velocity, over the last step's time dt) is asked into the cache, so that its corners
  /// have arrived when the line gets there: the evaluations of a line in a large field wait on
  /// memory whenever the line enters a new voxel.
  void prefetch_ahead(const Vec3& x, const Vec3& k1, double dt) const {
    if constexpr (std::is_same_v<Field, ImageField>) {
      if (field_.solid()) field_.prefetch_voxel(x + k1 * (dt * kPrefetchSteps), values_);
    } else if constexpr (std::is_same_v<Field, GridField>) {
      field_.prefetch_cell(x + k1 * (dt * kPrefetchSteps), cursor_, values_);
    }
  }
  const Field& field_;
  const VectorValues& values_;
  const Config& c_;
  typename Field::Cursor cursor_{};
  StreamHit hit_;
};

/// The mean cell size: the bounding-box diagonal over the d-th root of the cell count.
double mean_cell_length(DatasetRef input) {
  const std::size_t cells = num_cells(input);
  if (cells == 0) throw Error("streamlines: the input has no cells");
  int dim = 0;
  if (const auto* image = input.get_if<ImageData>()) {
    dim = structured_dimension(image->dims);
  } else if (const auto* grid = input.get_if<StructuredGrid>()) {
    dim = structured_dimension(grid->dims);
  } else {
    for (std::size_t c = 0; c < cells && dim < 3; ++c) {
      dim = std::max(dim, cell_dimension(cell_type(input, static_cast<Index>(c))));
    }
  }
  const Bounds b = bounds(input);
  const double diagonal = norm(b.max - b.min);
  if (dim == 0 || !(diagonal > 0)) {
    throw Error("streamlines: the input's cells span no length (all its points coincide)");
  }
  return diagonal / std::pow(static_cast<double>(cells), 1.0 / dim);
}

void check_stream_options(const StreamlineOptions& o) {
  auto positive = [](double v, const char* name) {
    if (!(std::isfinite(v) && v > 0)) {
      throw Error(fmt::format("streamlines: {} must be positive and finite (got {})", name, v));
    }
  };
  positive(o.step, "step");
  positive(o.min_step, "min_step");
  positive(o.max_step, "max_step");
  positive(o.max_error, "max_error");
  if (o.min_step > o.max_step) {
    throw Error(fmt::format("streamlines: min_step {} exceeds max_step {}", o.min_step,
                            o.max_step));
  }
  if (!(o.max_length > 0)) {  // NaN fails too; infinity is allowed
    throw Error(fmt::format("streamlines: max_length must be positive (got {})", o.max_length));
  }
  if (!(std::isfinite(o.terminal_speed) && o.terminal_speed >= 0)) {
    throw Error(fmt::format("streamlines: terminal_speed must be finite and ≥ 0 (got {})",
                            o.terminal_speed));
  }
  if (o.max_steps == 0) throw Error("streamlines: max_steps must be at least 1");
}

constexpr const char* kStreamArrays[] = {"IntegrationTime", "ArcLength", "Vorticity",
                                        "AngularVelocity", "Rotation", "Normals"};

template <class Field>
StreamlineResult trace_all(DatasetRef input, const Field& field, const DataArray& vectors,
                     DatasetRef seeds, const StreamlineOptions& o, double cell_length) {
  const VectorValues values(vectors);
  Config c{};
  c.integrator = o.integrator;
  c.step = o.step * cell_length;
  if (o.integrator == StreamIntegrator::RK45) c.step = std::clamp(o.step, o.min_step, o.max_step) * cell_length;
  c.min_step = o.min_step * cell_length;
  c.max_step = o.max_step * cell_length;
  c.max_error = o.max_error * cell_length;
  c.shrink_limit = o.integrator == StreamIntegrator::RK45 ? c.min_step : c.step / 1024;
  c.max_steps = o.max_steps;
  c.max_length = o.max_length;
  c.terminal_speed = o.terminal_speed;

  // 1. Every seed and direction, in parallel; each line owned by its seed's slot. Each line,
  // once traced, is located again point by point (the field around it is still in cache) for
  // the input's arrays and the vorticity.
  const std::size_t nseeds = num_points(seeds);
  std::vector<double> signs;
  if (o.direction != StreamDirection::Backward) signs.push_back(1);
  if (o.direction != StreamDirection::Forward) signs.push_back(-1);
  const std::size_t per_seed = signs.size();
  std::vector<Line> lines(nseeds * per_seed);
  std::vector<std::uint8_t> outside(nseeds, 0);
  const Attributes& input_arrays = point_data(input);
  Attributes no_cells;
  // The lines' memory, checked as they grow (their length is not known before): a point holds
  // its position and time, the carried arrays and the vorticity arrays, once while traced and
  // once in the output.
  double point_bytes = 32 + (o.vorticity ? 32 : 0) + 12;
  for (const DataArray& a : input_arrays) {
    point_bytes += static_cast<double>(scalar_size(a.type())) * a.components();
  }
  point_bytes *= 2;
  std::atomic<std::size_t> traced_points{0};
  const std::uint64_t physical = physical_memory();
  const double memory = physical ? static_cast<double>(physical) : INFINITY;
  parallel_for_range(
      nseeds, 16,
      [&](std::size_t s0, std::size_t s1) {
        Tracer<Field> tracer(field, values, c);
        std::vector<Vec3> cell_points;
        std::vector<double> cell_values;
        std::array<Vec3, 3> grad{};
        std::vector<Vec3> direction;
        StreamHit hit;
        const auto finish = [&](Line& line) {
          const std::size_t n = line.x.size();
          AttributeInterpolator carry(input_arrays, no_cells, n, 0);
          direction.assign(n, Vec3{0, 0, 0});
          if (o.vorticity) {
            line.vorticity.assign(3 * n, 0.0f);
            line.angular.assign(n, 0.0f);
          }
          // Vorticity ω = curl v from the gradients of v's components; angular velocity ½ ω·v̂.
          const auto store_vorticity = [&](const Vec3& v, std::size_t i) {
            const Vec3 w{grad[2].y - grad[1].z, grad[0].z - grad[2].x, grad[1].x - grad[0].y};
            line.vorticity[3 * i] = static_cast<float>(w.x);
            line.vorticity[3 * i + 1] = static_cast<float>(w.y);
            line.vorticity[3 * i + 2] = static_cast<float>(w.z);
            const double speed = norm(v);
            line.angular[i] = speed > 0 ? static_cast<float>(0.5 * dot(w, v) / speed) : 0.0f;
          };
          for (std::size_t i = 0; i < n; ++i) {
            if constexpr (std::is_same_v<Field, ImageField>) {
              if (field.solid()) {  // one load of the voxel for the velocity and the gradient
                Vec3 v;
                if (!field.sample(line.x[i], values, v, hit, o.vorticity ? &grad : nullptr)) continue;
                direction[i] = unit_or_zero(v);
                carry.combine(i, hit.stencil());
                if (o.vorticity) store_vorticity(v, i);
                continue;
              }
            }
            if (!field.find(line.x[i], tracer.cursor(), hit)) continue;  // found when traced
            const auto stencil = hit.stencil();
            const Vec3 v = values.interpolate(stencil);
            direction[i] = unit_or_zero(v);
            carry.combine(i, stencil);
            if (!o.vorticity) continue;
            if constexpr (std::is_same_v<Field, TetField>) {
              const bool linear = values.floats() ? field.gradient(hit, values.floats(), grad)
                                                  : field.gradient(hit, values.doubles(), grad);
              if (linear) {
                store_vorticity(v, i);
                continue;
              }
            }
            cell_points.resize(stencil.size());
            cell_values.resize(3 * stencil.size());
            for (std::size_t j = 0; j < stencil.size(); ++j) {
              cell_points[j] = point(input, static_cast<Index>(stencil[j].first));
              const Vec3 u = values.at(stencil[j].first);
              cell_values[3 * j] = u.x, cell_values[3 * j + 1] = u.y, cell_values[3 * j + 2] = u.z;
            }
            derivatives(cell_type(input, hit.cell), cell_points, hit.pcoords, cell_values, 3, grad,
                        hit.sub_id);
            store_vorticity(v, i);
          }
          carry.move_into(line.arrays, no_cells);
          if (!o.vorticity) return;
          // Rotation: the angular velocity integrated over time (trapezoids); Normals: a frame
          // carried along the flow direction without twisting, turned by the rotation.
          line.rotation.assign(n, 0.0f);
          line.normals.assign(3 * n, 0.0f);
          double angle = 0;
          Vec3 nrm = perpendicular(direction[0]);
          for (std::size_t i = 0; i < n; ++i) {
            if (i > 0) {
              angle += 0.5 * double(line.angular[i - 1] + line.angular[i]) *
                       (line.time[i] - line.time[i - 1]);
              nrm = transport(nrm, direction[i]);
            }
            const Vec3 turned = nrm * std::cos(angle) + cross(direction[i], nrm) * std::sin(angle);
            line.rotation[i] = static_cast<float>(angle);
            line.normals[3 * i] = static_cast<float>(turned.x);
            line.normals[3 * i + 1] = static_cast<float>(turned.y);
            line.normals[3 * i + 2] = static_cast<float>(turned.z);
          }
        };
        const auto store = [&](std::size_t job, Line&& traced) {
          Line& line = lines[job];
          line = std::move(traced);
          const std::size_t total = traced_points += line.x.size();
          if (static_cast<double>(total) * point_bytes > memory) {
            require_memory(static_cast<double>(total) * point_bytes,
                           fmt::format("streamlines: {} line points (so far; lower max_steps "
                                       "or the number of seeds)", total));
          }
          if (line.x.size() >= 2) finish(line);
        };
        bool lanes = c.integrator == StreamIntegrator::RK4;
        if constexpr (std::is_same_v<Field, ImageField>) {
          lanes = lanes && field.solid();
        } else {
          lanes = false;
        }
        if (lanes) {
          // Jobs (seed, direction) in order; a seed outside gives none.
          std::size_t s = s0, d = 0;
          Vec3 v;
          tracer.trace_rk4_lanes(
              [&](std::size_t& job, Vec3& seed, Vec3& v0, double& sign) {
                for (;;) {
                  if (s >= s1) return false;
                  if (d == 0) {
                    if (!tracer.eval(point(seeds, static_cast<Index>(s)), 1.0, v)) {
                      outside[s++] = 1;
                      continue;
                    }
                  }
                  seed = point(seeds, static_cast<Index>(s));
                  job = s * per_seed + d;
                  sign = signs[d];
                  v0 = v * sign;
                  if (++d == per_seed) d = 0, ++s;
                  return true;
                }
              },
              store);
          return;
        }
        for (std::size_t s = s0; s < s1; ++s) {
          const Vec3 seed = point(seeds, static_cast<Index>(s));
          Vec3 v;
          if (!tracer.eval(seed, 1.0, v)) {
            outside[s] = 1;
            continue;
          }
          // Each direction is traced, and then located again point by point, from the seed's
          // cell: a walk from where the last line ended would cross the whole line first.
          const typename Field::Cursor at_seed = tracer.cursor();
          for (std::size_t d = 0; d < per_seed; ++d) {
            tracer.cursor() = at_seed;
            Line line = tracer.trace(seed, v * signs[d], signs[d]);
            tracer.cursor() = at_seed;
            store(s * per_seed + d, std::move(line));
          }
        }
      },
      progress_range(o.progress, 0, 0.9), "streamlines");

  // 2. The output: lines of two or more points, in seed order (forward first).
  StreamlineResult r;
  StreamlineStats& st = r.stats;
  st.seeds = nseeds;
  st.cell_length = cell_length;
  std::vector<std::size_t> first(lines.size() + 1, 0);
  std::vector<Index> offsets{0};
  std::vector<std::size_t> kept;
  for (std::size_t s = 0; s < nseeds; ++s) {
    if (outside[s]) {
      ++st.seeds_outside;
      continue;
    }
    for (std::size_t d = 0; d < per_seed; ++d) {
      const std::size_t l = s * per_seed + d;
      const Line& line = lines[l];
      ++st.by_reason[static_cast<std::size_t>(line.reason)];
      st.steps += line.steps;
      st.rejected_steps += line.rejected;
      if (line.x.size() < 2) continue;
      first[kept.size()] = static_cast<std::size_t>(offsets.back());
      offsets.push_back(offsets.back() + static_cast<Index>(line.x.size()));
      kept.push_back(l);
    }
  }
  const std::size_t np = static_cast<std::size_t>(offsets.back());
  st.lines = kept.size();
  st.points = np;

  PolyData& out = r.output;
  out.points = Points(np, ScalarType::Float32);
  std::vector<Index> connectivity(np);
  for (std::size_t i = 0; i < np; ++i) connectivity[i] = static_cast<Index>(i);
  out.lines = CellArray(offsets, connectivity);
  {
    AttributeInterpolator shapes(input_arrays, no_cells, np, 0);  // the input's arrays, np long
    shapes.move_into(out.point_data, no_cells);
  }
  DataArray time("IntegrationTime", ScalarType::Float64, 1, np);
  DataArray arc("ArcLength", ScalarType::Float64, 1, np);
  DataArray vorticity, angular, rotation, normals;
  if (o.vorticity) {
    vorticity = DataArray("Vorticity", ScalarType::Float32, 3, np);
    angular = DataArray("AngularVelocity", ScalarType::Float32, 1, np);
    rotation = DataArray("Rotation", ScalarType::Float32, 1, np);
    normals = DataArray("Normals", ScalarType::Float32, 3, np);
  }
  auto* tp = time.values<double>().data();
  auto* ap = arc.values<double>().data();

  // 3. Each line copied to its slots.
  parallel_for_range(
      kept.size(), 16,
      [&](std::size_t l0, std::size_t l1) {
        for (std::size_t k = l0; k < l1; ++k) {
          const Line& line = lines[kept[k]];
          const std::size_t at = first[k], n = line.x.size();
          double length = 0;
          for (std::size_t i = 0; i < n; ++i) {
            out.points.set(at + i, line.x[i]);
            if (i > 0) length += norm(line.x[i] - line.x[i - 1]);
            tp[at + i] = line.time[i];
            ap[at + i] = length;
          }
          for (std::size_t a = 0; a < line.arrays.size(); ++a) {
            DataArray& dst = out.point_data[a];
            const DataArray& src = line.arrays[a];
            const std::size_t tuple = scalar_size(dst.type()) * static_cast<std::size_t>(dst.components());
            std::memcpy(dst.bytes() + at * tuple, src.bytes(), src.size_bytes());
          }
          if (!o.vorticity) continue;
          std::copy(line.vorticity.begin(), line.vorticity.end(),
                    vorticity.values<float>().begin() + std::ptrdiff_t(3 * at));
          std::copy(line.angular.begin(), line.angular.end(),
                    angular.values<float>().begin() + std::ptrdiff_t(at));
          std::copy(line.rotation.begin(), line.rotation.end(),
                    rotation.values<float>().begin() + std::ptrdiff_t(at));
          std::copy(line.normals.begin(), line.normals.end(),
                    normals.values<float>().begin() + std::ptrdiff_t(3 * at));
        }
      },
      progress_range(o.progress, 0.9, 1.0), "streamlines");

  // The arrays made here replace input arrays of the same names.
  for (std::size_t a = 0; a < (o.vorticity ? std::size(kStreamArrays) : 2); ++a) {
    out.point_data.remove(kStreamArrays[a]);
  }
  out.point_data.add(std::move(time));
  out.point_data.add(std::move(arc));
  if (o.vorticity) {
    out.point_data.add(std::move(vorticity));
    out.point_data.add(std::move(angular));
    out.point_data.add(std::move(rotation));
    out.point_data.add(std::move(normals), AttributeRole::Normals);
  }
  DataArray seed_ids("SeedIds", ScalarType::Int64, 1, kept.size());
  DataArray reasons("ReasonForTermination", ScalarType::UInt8, 1, kept.size());
  for (std::size_t k = 0; k < kept.size(); ++k) {
    seed_ids.set(k, 0, static_cast<double>(kept[k] / per_seed));
    reasons.set(k, 0, static_cast<double>(lines[kept[k]].reason));
  }
  out.cell_data.add(std::move(seed_ids));
  out.cell_data.add(std::move(reasons));
  return r;
}

}  // namespace

StreamlineResult streamlines(DatasetRef input, DatasetRef seeds, const StreamlineOptions& o) {
  check_stream_options(o);
  validate(input);
  validate(seeds);
  const DataArray& vectors =
      filters_detail::point_field(input, o.vectors, AttributeRole::Vectors, 3, "streamlines");
  for (std::size_t i = 0; i < num_points(seeds); ++i) {
    if (!finite(point(seeds, static_cast<Index>(i)))) {
      throw Error(fmt::format("streamlines: seed {} is not a finite point", i));
    }
  }
  const Points* pts = nullptr;
  if (const auto* g = input.get_if<StructuredGrid>()) pts = &g->points;
  if (const auto* m = input.get_if<PolyData>()) pts = &m->points;
  if (const auto* u = input.get_if<UnstructuredGrid>()) pts = &u->points;
  if (pts && pts->first_non_finite() < pts->size()) {
    throw Error(fmt::format("streamlines: input point {} is not finite", pts->first_non_finite()));
  }
  const double cell_length = mean_cell_length(input);
  if (const auto* image = input.get_if<ImageData>()) {
    return trace_all(input, ImageField(*image, cell_length), vectors, seeds, o, cell_length);
  }
  if (const auto* grid = input.get_if<StructuredGrid>()) {
    if (structured_dimension(grid->dims) == 3) {
      return trace_all(input, GridField(*grid), vectors, seeds, o, cell_length);
    }
  }
  if (const auto* mesh = input.get_if<UnstructuredGrid>()) {
    if (probe_detail::TetWalker::applicable(*mesh)) {
      return trace_all(input, TetField(*mesh, cell_length), vectors, seeds, o, cell_length);
    }
  }
  return trace_all(input, CellField(input, cell_length), vectors, seeds, o, cell_length);
}

}  // namespace isoforge
