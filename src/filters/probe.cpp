// Probing (filters/probe.hpp): the input sampled at the points of a probe dataset.
//
// References implemented:
// - W. Schroeder, K. Martin, B. Lorensen, *The Visualization Toolkit* (4th ed.), 5.x "Probing"
//   and 8.x "Searching": point location in structured data by arithmetic, in curvilinear grids
//   by walking from cell to cell, guided by the parametric coordinates of the point in the
//   current cell (found by Newton's method on the trilinear map).
// Details and measurements: docs/algorithms/probe.md.

#include "isoforge/filters/probe.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "isoforge/core/interpolate.hpp"
#include "isoforge/core/parallel.hpp"
#include "isoforge/core/subset.hpp"
#include "isoforge/spatial/cell_locator.hpp"

namespace isoforge {

namespace {

using Term = AttributeInterpolator::Term;

/// Probe points are handled in blocks of this many consecutive points; the walk through a
/// structured grid restarts at each block, so the output does not depend on how the blocks are
/// spread over threads.
constexpr std::size_t kBlock = 512;
/// The walk gives up (and asks the locator) after this many cells.
constexpr int kMaxWalkSteps = 48;
/// Largest jump of the walk along one axis in one step, in cells.
constexpr double kMaxJump = 16;
/// Newton's method on the trilinear map: iteration cap and parametric convergence threshold.
constexpr int kMaxNewton = 16;
constexpr double kNewtonEps = 1e-12;

/// Where a probe point was found: a cell of the input and the weights of its points.
struct Hit {
  Index cell = -1;
  std::vector<Term> terms;  // (input point id, weight)
};

/// Cells of a structured dims: cells per axis (1 along an axis of one point).
std::array<Index, 3> cells_per_axis(const Dims& d) {
  return {d[0] > 1 ? d[0] - 1 : 1, d[1] > 1 ? d[1] - 1 : 1, d[2] > 1 ? d[2] - 1 : 1};
}

/// The trilinear map of one hexahedron of a structured grid, X = a + b r + c s + d t + e rs +
/// f rt + g st + h rst, for Newton's method.
struct Trilinear {
  Vec3 a, b, c, d, e, f, g, h;
  explicit Trilinear(const std::array<Vec3, 8>& x) {  // x[ia + 2 ib + 4 ic]
    a = x[0];
    b = x[1] - x[0];
    c = x[2] - x[0];
    d = x[4] - x[0];
    e = x[3] - x[1] - x[2] + x[0];
    f = x[5] - x[1] - x[4] + x[0];
    g = x[6] - x[2] - x[4] + x[0];
    h = x[7] - x[3] - x[5] - x[6] + x[1] + x[2] + x[4] - x[0];
  }
  /// Parametric coordinates of p (Newton from the center); false if it did not converge.
  bool solve(const Vec3& p, Vec3& pc) const {
    double r = 0.5, s = 0.5, t = 0.5;
    for (int it = 0; it < kMaxNewton; ++it) {
      const Vec3 x = a + b * r + c * s + d * t + e * (r * s) + f * (r * t) + g * (s * t) +
                     h * (r * s * t);
      const Vec3 F = x - p;
      const Vec3 jr = b + e * s + f * t + h * (s * t);
      const Vec3 js = c + e * r + g * t + h * (r * t);
      const Vec3 jt = d + f * r + g * s + h * (r * s);
      const Vec3 c0 = cross(js, jt);
      const double det = dot(jr, c0);
      const double scale = norm(jr) * norm(js) * norm(jt);
      if (!(std::abs(det) > 1e-14 * scale)) return false;
      const double inv = 1.0 / det;
      const double dr = dot(F, c0) * inv;
      const double ds = dot(jr, cross(F, jt)) * inv;
      const double dt = dot(jr, cross(js, F)) * inv;
      r -= dr;
      s -= ds;
      t -= dt;
      if (!(std::abs(r) < 1e6 && std::abs(s) < 1e6 && std::abs(t) < 1e6)) return false;
      if (std::max({std::abs(dr), std::abs(ds), std::abs(dt)}) < kNewtonEps) {
        pc = {r, s, t};
        return true;
      }
    }
    return false;
  }
};

/// The value a floating-point or integer array gets at a point not found.
template <class T>
T nil_of(double nil) {
  if constexpr (std::is_floating_point_v<T>) {
    return static_cast<T>(nil);
  } else {
    if (std::isnan(nil)) return T{0};
    const double lo = static_cast<double>(std::numeric_limits<T>::lowest());
    const double hi = static_cast<double>(std::numeric_limits<T>::max());
    const double v = std::clamp(std::nearbyint(nil), lo, hi);
    return v >= hi ? std::numeric_limits<T>::max() : static_cast<T>(v);
  }
}

/// The probe's point coordinates, without a per-point dispatch on the dataset type.
struct ProbePoints {
  const ImageData* image = nullptr;
  const Points* points = nullptr;
  [[nodiscard]] Vec3 operator()(std::size_t id) const {
    if (image) return image->point(static_cast<Index>(id));
    return (*points)[id];
  }
};

}  // namespace

struct Prober::Impl {
  DatasetRef input;
  ProbeOptions options;
  double dtol = 0;                       // resolved distance tolerance
  std::vector<std::uint8_t> cell_ok;     // empty: no cell is blanked
  std::size_t blanked = 0;
  std::optional<UnstructuredGrid> valid;  // the non-blanked cells, when some are blanked
  std::vector<Index> valid_ids;           // their ids in the input
  std::optional<CellLocator> locator;     // over the input or `valid`; none for image data
  bool walk = false;                      // a 3D structured grid: walk through its hexahedra

  Impl(DatasetRef in, const ProbeOptions& o) : input(in), options(o) {}

  [[nodiscard]] bool ok(Index cell) const {
    return cell_ok.empty() || cell_ok[static_cast<std::size_t>(cell)] != 0;
  }

  /// A locator hit mapped to the input's cell and point ids.
  bool from_locator(const Vec3& p, Hit& hit, std::vector<Index>& ids) const {
    const CellHit h = locator->find_cell(p);
    if (!h.found()) return false;
    hit.cell = valid ? valid_ids[static_cast<std::size_t>(h.cell)] : h.cell;
    cell_point_ids(input, hit.cell, ids);  // same point order as the locator's cell
    hit.terms.clear();
    for (std::size_t k = 0; k < ids.size(); ++k) {
      if (h.weights[k] != 0) hit.terms.emplace_back(static_cast<std::size_t>(ids[k]), h.weights[k]);
    }
    return true;
  }

  /// Image data by arithmetic: the smallest-id non-blanked cell containing p.
  bool locate_image(const ImageData& img, const Vec3& p, Hit& hit) const {
    const auto cpa = cells_per_axis(img.dims);
    Index lo[3], hi[3];
    double u[3];
    const double tol = options.tolerance;
    for (int a = 0; a < 3; ++a) {
      const double off = p[a] - img.origin[a];
      if (img.dims[a] == 1) {
        if (!(std::abs(off) <= dtol)) return false;
        u[a] = 0;
        lo[a] = hi[a] = 0;
        continue;
      }
      u[a] = off / img.spacing[a];
      const double top = static_cast<double>(img.dims[a] - 1);
      if (!(u[a] >= -tol && u[a] <= top + tol)) return false;
      lo[a] = std::clamp(static_cast<Index>(std::floor(u[a] - tol)), Index{0}, img.dims[a] - 2);
      hi[a] = std::clamp(static_cast<Index>(std::floor(u[a] + tol)), Index{0}, img.dims[a] - 2);
    }
    for (Index k = lo[2]; k <= hi[2]; ++k) {
      for (Index j = lo[1]; j <= hi[1]; ++j) {
        for (Index i = lo[0]; i <= hi[0]; ++i) {
          const Index cell = i + cpa[0] * (j + cpa[1] * k);
          if (!ok(cell)) continue;
          const Index c3[3] = {i, j, k};
          double w[3][2];
          Index step[3];
          for (int a = 0; a < 3; ++a) {
            const double r = img.dims[a] == 1 ? 0.0 : std::clamp(u[a] - double(c3[a]), 0.0, 1.0);
            w[a][0] = 1 - r;
            w[a][1] = r;
            step[a] = img.dims[a] == 1 ? 0 : 1;
          }
          hit.cell = cell;
          hit.terms.clear();
          const Index base = img.point_id(i, j, k);
          const Index sj = img.dims[0], sk = img.dims[0] * img.dims[1];
          for (int c = 0; c < 8; ++c) {
            const int a0 = c & 1, a1 = (c >> 1) & 1, a2 = (c >> 2) & 1;
            if ((a0 && !step[0]) || (a1 && !step[1]) || (a2 && !step[2])) continue;
            const double wt = w[0][a0] * w[1][a1] * w[2][a2];
            if (wt == 0) continue;
            hit.terms.emplace_back(static_cast<std::size_t>(base + a0 + a1 * sj + a2 * sk), wt);
          }
          if (hit.terms.empty()) hit.terms.emplace_back(static_cast<std::size_t>(base), 1.0);
          return true;
        }
      }
    }
    return false;
  }

  /// A 3D structured grid: walks from cell `cur` (updated) toward p. True when a cell
  /// containing p was reached and is not blanked; false means "ask the locator".
  template <class T>
  bool walk_grid(const StructuredGrid& g, const T* pts, const Vec3& p, std::array<Index, 3>& cur,
                 Hit& hit) const {
    const Index nx = g.dims[0], ny = g.dims[1];
    const Index cx = nx - 1, cy = ny - 1, cz = g.dims[2] - 1;
    const double tol = options.tolerance;
    for (int step = 0; step < kMaxWalkSteps; ++step) {
      const auto [i, j, k] = cur;
      std::array<Vec3, 8> x;
      std::array<std::size_t, 8> id;
      for (int c = 0; c < 8; ++c) {
        const Index pid = (i + (c & 1)) + nx * ((j + ((c >> 1) & 1)) + ny * (k + ((c >> 2) & 1)));
        id[c] = static_cast<std::size_t>(pid);
        const T* q = pts + 3 * pid;
        x[c] = {double(q[0]), double(q[1]), double(q[2])};
      }
      Vec3 pc;
      if (!Trilinear(x).solve(p, pc)) return false;
      if (pc.x >= -tol && pc.x <= 1 + tol && pc.y >= -tol && pc.y <= 1 + tol && pc.z >= -tol &&
          pc.z <= 1 + tol) {
        const Index cell = i + cx * (j + cy * k);
        if (!ok(cell)) return false;
        hit.cell = cell;
        hit.terms.clear();
        const double r = std::clamp(pc.x, 0.0, 1.0), s = std::clamp(pc.y, 0.0, 1.0),
                     t = std::clamp(pc.z, 0.0, 1.0);
        for (int c = 0; c < 8; ++c) {
          const double w = ((c & 1) ? r : 1 - r) * (((c >> 1) & 1) ? s : 1 - s) *
                           (((c >> 2) & 1) ? t : 1 - t);
          if (w != 0) hit.terms.emplace_back(id[c], w);
        }
        return true;
      }
      // Move toward p by the whole cells its parametric coordinates lie beyond this one.
      const Index lim[3] = {cx, cy, cz};
      bool moved = false;
      for (int a = 0; a < 3; ++a) {
        const double v = pc[a];
        double jump = 0;
        if (v < -tol) jump = std::max(-kMaxJump, std::floor(v));
        if (v > 1 + tol) jump = std::min(kMaxJump, std::floor(v));
        const Index next = std::clamp(cur[a] + static_cast<Index>(jump), Index{0}, lim[a] - 1);
        moved = moved || next != cur[a];
        cur[a] = next;
      }
      if (!moved) return false;  // at the boundary, p beyond it: maybe outside, ask the locator
    }
    return false;
  }
};

Prober::Prober(DatasetRef input, const ProbeOptions& options)
    : impl_(std::make_unique<Impl>(input, options)) {
  Impl& m = *impl_;
  validate(input);
  if (!(options.tolerance >= 0) || !std::isfinite(options.tolerance)) {
    throw Error(fmt::format("probe: tolerance must be finite and >= 0, got {:g}",
                            options.tolerance));
  }
  if (!std::isfinite(options.distance_tolerance)) {
    throw Error("probe: distance tolerance must be finite");
  }
  if (options.mask_name.empty()) throw Error("probe: the mask array needs a name");
  const Bounds box = bounds(input);
  m.dtol = options.distance_tolerance >= 0 ? options.distance_tolerance : 1e-6 * box.diagonal();

  // Blanking: cells marked invalid, or with a blanked point.
  const std::size_t nc = num_cells(input);
  const DataArray* pblank =
      options.point_blanking.empty() ? nullptr : point_data(input).find(options.point_blanking);
  const DataArray* cvalid =
      options.cell_validity.empty() ? nullptr : cell_data(input).find(options.cell_validity);
  for (const DataArray* a : {pblank, cvalid}) {
    if (a && a->components() != 1) {
      throw Error(fmt::format("probe: blanking array '{}' has {} components, expected 1",
                              a->name(), a->components()));
    }
  }
  if (pblank || cvalid) {
    m.cell_ok.assign(nc, 1);
    std::vector<Index> ids;
    for (std::size_t c = 0; c < nc; ++c) {
      bool good = !cvalid || cvalid->get(c) != 0;
      if (good && pblank) {
        cell_point_ids(input, static_cast<Index>(c), ids);
        for (Index id : ids) good = good && pblank->get(static_cast<std::size_t>(id)) != 0;
      }
      if (!good) {
        m.cell_ok[c] = 0;
        ++m.blanked;
      }
    }
    if (m.blanked == 0) m.cell_ok.clear();
  }

  if (input.get_if<ImageData>()) return;  // arithmetic: no locator
  if (const auto* g = input.get_if<StructuredGrid>()) {
    m.walk = g->dims[0] > 1 && g->dims[1] > 1 && g->dims[2] > 1;
    if (g->points.first_non_finite() < g->points.size()) {
      throw Error(fmt::format("probe: point {} of the input is not finite",
                              g->points.first_non_finite()));
    }
  }
  CellLocatorOptions lo;
  lo.tolerance = options.tolerance;
  lo.distance_tolerance = m.dtol;
  if (m.blanked > 0) {
    for (std::size_t c = 0; c < nc; ++c) {
      if (m.cell_ok[c]) m.valid_ids.push_back(static_cast<Index>(c));
    }
    m.valid = subset_cells(input, m.valid_ids, false);
    m.valid->point_data.clear();
    m.valid->cell_data.clear();
    m.locator.emplace(*m.valid, lo);
  } else {
    m.locator.emplace(input, lo);
  }
}

Prober::~Prober() = default;
Prober::Prober(Prober&&) noexcept = default;
Prober& Prober::operator=(Prober&&) noexcept = default;

ProbeResult Prober::probe(DatasetRef probe_ds) const {
  const Impl& m = *impl_;
  validate(probe_ds);
  const std::size_t n = num_points(probe_ds);
  ProbePoints pp;
  if (const auto* img = probe_ds.get_if<ImageData>()) {
    pp.image = img;
  } else {
    pp.points = probe_ds.visit([](const auto& d) -> const Points* {
      if constexpr (std::is_same_v<std::decay_t<decltype(d)>, ImageData>) {
        return nullptr;
      } else {
        return &d.points;
      }
    });
  }

  // The output: the probe's structure, no arrays.
  ProbeResult result;
  result.output = probe_ds.visit([](const auto& d) -> Dataset {
    auto out = d;
    out.point_data.clear();
    out.cell_data.clear();
    out.field_data.clear();
    return out;
  });
  const Attributes none;
  AttributeInterpolator from_points(point_data(m.input), none, n, 0);
  AttributeInterpolator from_cells(cell_data(m.input), none, n, 0);
  Buffer<std::uint8_t> mask;
  mask.resize(n);

  const StructuredGrid* grid = m.walk ? m.input.get_if<StructuredGrid>() : nullptr;
  const ImageData* image = m.input.get_if<ImageData>();
  std::atomic<std::size_t> found{0};
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  parallel_for_range(
      blocks, 1,
      [&](std::size_t b0, std::size_t b1) {
        Hit hit;
        std::vector<Index> ids;
        std::size_t count = 0;
        for (std::size_t b = b0; b < b1; ++b) {
          bool have_cell = false;  // the walk restarts in every block
          std::array<Index, 3> cur{};
          const std::size_t end = std::min(n, (b + 1) * kBlock);
          for (std::size_t i = b * kBlock; i < end; ++i) {
            const Vec3 p = pp(i);
            bool hit_ok = false;
            if (!is_finite(p)) {
              hit_ok = false;
            } else if (image) {
              hit_ok = m.locate_image(*image, p, hit);
            } else if (grid) {
              if (have_cell) {
                hit_ok = grid->points.type() == ScalarType::Float32
                             ? m.walk_grid(*grid, grid->points.floats().data(), p, cur, hit)
                             : m.walk_grid(*grid, grid->points.array().values<double>().data(), p,
                                           cur, hit);
              }
              if (!hit_ok) {
                hit_ok = m.from_locator(p, hit, ids);
                if (hit_ok) {
                  const Index cx = grid->dims[0] - 1, cy = grid->dims[1] - 1;
                  cur = {hit.cell % cx, (hit.cell / cx) % cy, hit.cell / (cx * cy)};
                  have_cell = true;
                }
              }
            } else {
              hit_ok = m.from_locator(p, hit, ids);
            }
            mask[i] = hit_ok ? 1 : 0;
            if (!hit_ok) continue;
            ++count;
            from_points.combine(i, hit.terms);
            from_cells.copy_point(i, static_cast<std::size_t>(hit.cell));
          }
        }
        found += count;
      },
      m.options.progress, "probe");

  // Arrays of the output, nil where nothing was found.
  Attributes& out_pd = point_data(result.output);
  Attributes unused, cell_arrays;
  from_points.move_into(out_pd, unused);
  from_cells.move_into(cell_arrays, unused);
  for (std::size_t a = 0; a < cell_arrays.size(); ++a) {
    DataArray arr = std::move(cell_arrays[a]);
    const std::string name = arr.name();
    if (out_pd.has(name)) arr.set_name(name + " (cell)");
    out_pd.add(std::move(arr));
    for (std::size_t r = 0; r < kAttributeRoleCount; ++r) {
      const auto role = static_cast<AttributeRole>(r);
      if (cell_arrays.active_name(role) == name && out_pd.active_name(role).empty()) {
        out_pd.set_active(role, out_pd[out_pd.size() - 1].name());
      }
    }
  }
  const std::size_t nfound = found.load();
  if (nfound < n) {
    for (std::size_t a = 0; a < out_pd.size(); ++a) {
      DataArray& arr = out_pd[a];
      const auto nc = static_cast<std::size_t>(arr.components());
      arr.visit([&](auto& v) {
        using T = typename std::decay_t<decltype(v)>::value_type;
        const T nil = nil_of<T>(m.options.nil_value);
        parallel_for_range(n, 1 << 14, [&](std::size_t i0, std::size_t i1) {
          for (std::size_t i = i0; i < i1; ++i) {
            if (!mask[i]) std::fill_n(v.data() + i * nc, nc, nil);
          }
        });
      });
    }
  }
  if (out_pd.has(m.options.mask_name)) out_pd.remove(m.options.mask_name);
  out_pd.add(DataArray::from_buffer(m.options.mask_name, 1, std::move(mask)));
  result.stats.points = n;
  result.stats.found = nfound;
  result.stats.blanked = m.blanked;
  return result;
}

ProbeResult probe(DatasetRef input, DatasetRef probe_ds, const ProbeOptions& options) {
  return Prober(input, options).probe(probe_ds);
}

// ---------------------------------------------------------------------------------------------
// Probe generators
// ---------------------------------------------------------------------------------------------

PolyData probe_line(const Vec3& p0, const Vec3& p1, Index n) {
  if (n < 1) throw Error(fmt::format("probe line: {} points, expected at least 1", n));
  if (!is_finite(p0) || !is_finite(p1)) throw Error("probe line: an end point is not finite");
  PolyData line;
  line.points = Points(static_cast<std::size_t>(n), ScalarType::Float64);
  std::vector<Index> ids(static_cast<std::size_t>(n));
  for (Index i = 0; i < n; ++i) {
    const double t = n == 1 ? 0.0 : static_cast<double>(i) / static_cast<double>(n - 1);
    line.points.set(static_cast<std::size_t>(i), i == n - 1 && n > 1 ? p1 : p0 + (p1 - p0) * t);
    ids[static_cast<std::size_t>(i)] = i;
  }
  if (n == 1) {
    line.verts.add(ids);
  } else {
    line.lines.add(ids);
  }
  return line;
}

PolyData probe_plane(const Vec3& origin, const Vec3& p1, const Vec3& p2, Index nu, Index nv) {
  if (nu < 2 || nv < 2) {
    throw Error(fmt::format("probe plane: {} x {} points, expected at least 2 x 2", nu, nv));
  }
  if (!is_finite(origin) || !is_finite(p1) || !is_finite(p2)) {
    throw Error("probe plane: a corner is not finite");
  }
  const Vec3 u = p1 - origin, v = p2 - origin;
  const double area = norm(cross(u, v));
  if (!(area > 1e-12 * std::max(dot(u, u), dot(v, v))) || area == 0) {
    throw Error("probe plane: the axes origin->p1 and origin->p2 are parallel or of zero length");
  }
  PolyData plane;
  plane.points =
      Points(static_cast<std::size_t>(nu) * static_cast<std::size_t>(nv), ScalarType::Float64);
  for (Index b = 0; b < nv; ++b) {
    for (Index a = 0; a < nu; ++a) {
      const double s = static_cast<double>(a) / static_cast<double>(nu - 1);
      const double t = static_cast<double>(b) / static_cast<double>(nv - 1);
      plane.points.set(static_cast<std::size_t>(a + nu * b), origin + u * s + v * t);
    }
  }
  for (Index b = 0; b + 1 < nv; ++b) {
    for (Index a = 0; a + 1 < nu; ++a) {
      const Index i0 = a + nu * b;
      plane.polys.add({i0, i0 + 1, i0 + 1 + nu, i0 + nu});
    }
  }
  return plane;
}

ImageData probe_volume(const Bounds& box, const Dims& dims) {
  if (box.empty() || !is_finite(box.min) || !is_finite(box.max)) {
    throw Error("probe volume: the box is empty or not finite");
  }
  (void)checked_point_count(dims, "probe volume");
  ImageData img;
  img.dims = dims;
  img.origin = box.min;
  for (int a = 0; a < 3; ++a) {
    const double extent = box.max[a] - box.min[a];
    if (dims[a] > 1 && !(extent > 0)) {
      throw Error(fmt::format("probe volume: {} points along {} but the box has zero extent",
                              dims[a], "xyz"[a]));
    }
    img.spacing[a] = dims[a] > 1 ? extent / static_cast<double>(dims[a] - 1) : 1.0;
  }
  return img;
}

}  // namespace isoforge
