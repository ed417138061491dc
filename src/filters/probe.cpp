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
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "isoforge/core/interpolate.hpp"
#include "isoforge/core/parallel.hpp"
#include "isoforge/core/subset.hpp"
#include "isoforge/spatial/cell_locator.hpp"
#include "probe_grid.hpp"
#include "probe_tets.hpp"

namespace isoforge {

namespace {

using Term = AttributeInterpolator::Term;

/// Probe points are handled in blocks of this many consecutive points; the walk through a
/// structured grid restarts at each block, so the output does not depend on how the blocks are
/// spread over threads.
constexpr std::size_t kBlock = 512;
/// An image probe in a structured grid is cut into about this many slabs of layers.
constexpr std::size_t kSlabs = 32;

/// Where the points of a block were found, for interpolating each array over the whole block
/// in one typed loop (no per-point dispatch): per point its output id, its cell (or kMissed:
/// the nil value; kPending: decided by a second pass) and its terms (input point, weight).
struct BlockHits {
  static constexpr Index kMissed = -1;
  static constexpr Index kPending = -2;
  std::size_t size = 0;  // points, at most kBlock
  std::array<std::size_t, kBlock> out;
  std::array<Index, kBlock> cell;
  std::array<std::uint32_t, kBlock + 1> first;  // terms of point q: [first[q], first[q + 1])
  std::vector<Term> terms;
  // A structured grid's points: trilinear in the cell at `grid[q]` instead of terms.
  bool trilinear = false;
  std::array<std::size_t, 8> offsets{};  // corner (a, b, c) at base + offsets[a + 2b + 4c]
  std::array<probe_detail::GridHit, kBlock> grid;

  void clear() {
    size = 0;
    first[0] = 0;
    terms.clear();
  }
  void found(std::size_t o, const probe_detail::GridHit& g) {
    out[size] = o;
    cell[size] = g.cell;
    grid[size++] = g;
  }
  /// Ends the point `o` found in `c`, whose terms were appended.
  void found(std::size_t o, Index c) {
    out[size] = o;
    cell[size] = c;
    first[++size] = static_cast<std::uint32_t>(terms.size());
  }
  void missed(std::size_t o, Index why = kMissed) {
    out[size] = o;
    cell[size] = why;
    if (!trilinear) {
      terms.resize(first[size]);  // drops the terms of a failed attempt
      first[size + 1] = first[size];
    }
    ++size;
  }
};

/// The value a floating-point or integer array gets at a point not found.
template <class T>
T nil_of(double nil);

/// Output point array `dst` at the block's points: the weighted sums of `src`'s tuples, rounded
/// to the nearest integer for integer types; the nil value where nothing was found.
template <class T>
void interpolate_block(const DataArray& src, DataArray& dst, const BlockHits& h, double nil) {
  const auto nc = static_cast<std::size_t>(src.components());
  const T* s = src.values<T>().data();
  T* d = dst.values<T>().data();
  const T nil_t = nil_of<T>(nil);
  const auto store = [&](std::size_t at, double v) {
    if constexpr (std::is_floating_point_v<T>) {
      d[at] = static_cast<T>(v);
    } else {
      d[at] = static_cast<T>(std::round(v));  // halves away from zero, as VTK
    }
  };
  if (h.trilinear) {
    // The weights of the corners, summed in the order of the terms of the other cells; zero
    // weights skipped (a NaN at a corner of weight 0 does not spread).
    std::size_t off[8];
    for (int k = 0; k < 8; ++k) off[k] = h.offsets[std::size_t(k)] * nc;
    for (std::size_t q = 0; q < h.size; ++q) {
      const std::size_t o = h.out[q];
      if (h.cell[q] < 0) {
        if (h.cell[q] == BlockHits::kMissed) std::fill_n(d + o * nc, nc, nil_t);
        continue;
      }
      const probe_detail::GridHit& g = h.grid[q];
      const double r0 = 1 - g.r, s0 = 1 - g.s, t0 = 1 - g.t;
      const double rs00 = r0 * s0, rs10 = g.r * s0, rs01 = r0 * g.s, rs11 = g.r * g.s;
      const double w[8] = {rs00 * t0, rs10 * t0, rs01 * t0, rs11 * t0,
                           rs00 * g.t, rs10 * g.t, rs01 * g.t, rs11 * g.t};
      const T* sb = s + g.base * nc;
      if (nc == 1) {
        // One component: all eight terms; a zero weight adds nothing to a finite sum, so only
        // a sum that is not finite (a NaN or infinite corner) is redone skipping them.
        double v = 0;
        for (int k = 0; k < 8; ++k) v += w[k] * static_cast<double>(sb[off[k]]);
        if (std::isfinite(v)) {
          store(o, v);
          continue;
        }
      }
      for (std::size_t c = 0; c < nc; ++c) {
        double v = 0;
        for (int k = 0; k < 8; ++k) {
          if (w[k] != 0) v += w[k] * static_cast<double>(sb[off[k] + c]);
        }
        store(o * nc + c, v);
      }
    }
    return;
  }
  const Term* terms = h.terms.data();
  for (std::size_t q = 0; q < h.size; ++q) {
    const std::size_t o = h.out[q];
    if (h.cell[q] < 0) {
      if (h.cell[q] == BlockHits::kMissed) std::fill_n(d + o * nc, nc, nil_t);
      continue;
    }
    const std::uint32_t t0 = h.first[q], t1 = h.first[q + 1];
    for (std::size_t c = 0; c < nc; ++c) {
      double v = 0;
      for (std::uint32_t t = t0; t < t1; ++t)
        v += terms[t].second * static_cast<double>(s[terms[t].first * nc + c]);
      store(o * nc + c, v);
    }
  }
}

/// Output point array `dst` at the block's points: the tuple of `src` (a cell array) of the
/// cell each point was found in; the nil value where nothing was found.
template <class T>
void copy_block(const DataArray& src, DataArray& dst, const BlockHits& h, double nil) {
  const auto nc = static_cast<std::size_t>(src.components());
  const T* s = src.values<T>().data();
  T* d = dst.values<T>().data();
  const T nil_t = nil_of<T>(nil);
  for (std::size_t q = 0; q < h.size; ++q) {
    const std::size_t o = h.out[q];
    const Index c = h.cell[q];
    if (c >= 0) {
      std::copy_n(s + static_cast<std::size_t>(c) * nc, nc, d + o * nc);
    } else if (c == BlockHits::kMissed) {
      std::fill_n(d + o * nc, nc, nil_t);
    }
  }
}

using BlockKernel = void (*)(const DataArray&, DataArray&, const BlockHits&, double);

/// An output array per input array (n tuples, uninitialized: every value is written by the
/// block kernels) and the kernel that fills it.
struct Carried {
  const DataArray* src;
  std::string name;
  DataArray* dst = nullptr;
  BlockKernel kernel;
};

/// Cells of a structured dims: cells per axis (1 along an axis of one point).
std::array<Index, 3> cells_per_axis(const Dims& d) {
  return {d[0] > 1 ? d[0] - 1 : 1, d[1] > 1 ? d[1] - 1 : 1, d[2] > 1 ? d[2] - 1 : 1};
}

template <class T>
T nil_of(double nil) {
  if constexpr (std::is_floating_point_v<T>) {
    return static_cast<T>(nil);
  } else {
    if (std::isnan(nil)) return T{0};
    const double lo = static_cast<double>(std::numeric_limits<T>::lowest());
    const double hi = static_cast<double>(std::numeric_limits<T>::max());
    const double v = std::clamp(std::round(nil), lo, hi);
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

/// Consecutive probe points from `first` on: image points by incrementing (i, j, k) instead of
/// dividing the id for each.
class PointSequence {
 public:
  PointSequence(const ProbePoints& pp, std::size_t first) : pp_(pp), id_(first) {
    if (pp.image) {
      const Dims& d = pp.image->dims;
      const auto id = static_cast<Index>(first);
      ijk_ = {id % d[0], (id / d[0]) % d[1], id / (d[0] * d[1])};
    }
  }
  /// Whether the current point is the first of a row of an image probe.
  [[nodiscard]] bool row_start() const { return pp_.image && ijk_[0] == 0; }
  /// The current point; then advances.
  Vec3 next() {
    if (!pp_.image) return (*pp_.points)[id_++];
    const Vec3 p = pp_.image->point(ijk_[0], ijk_[1], ijk_[2]);
    const Dims& d = pp_.image->dims;
    if (++ijk_[0] == d[0]) {
      ijk_[0] = 0;
      if (++ijk_[1] == d[1]) {
        ijk_[1] = 0;
        ++ijk_[2];
      }
    }
    return p;
  }

 private:
  const ProbePoints& pp_;
  std::size_t id_;
  std::array<Index, 3> ijk_{};
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
  CellLocatorOptions locator_options;
  std::mutex build_mutex;
  std::optional<probe_detail::TetWalker> tets;  // tetrahedra: walk first, locator when needed
  std::optional<probe_detail::GridLocator> grid;  // a 3D structured grid: walk + blocks

  Impl(DatasetRef in, const ProbeOptions& o) : input(in), options(o) {}

  [[nodiscard]] bool ok(Index cell) const {
    return cell_ok.empty() || cell_ok[static_cast<std::size_t>(cell)] != 0;
  }

  /// Builds the cell locator (over the valid cells when some are blanked), once.
  void build_locator() {
    if (locator) return;
    if (blanked > 0) {
      for (std::size_t c = 0; c < cell_ok.size(); ++c) {
        if (cell_ok[c]) valid_ids.push_back(static_cast<Index>(c));
      }
      valid = subset_cells(input, valid_ids, false);
      valid->point_data.clear();
      valid->cell_data.clear();
      locator.emplace(*valid, locator_options);
    } else {
      locator.emplace(input, locator_options);
    }
  }

  /// A locator hit mapped to the input's cell; its terms appended to `terms`.
  bool from_locator(const Vec3& p, Index& cell, std::vector<Term>& terms,
                    std::vector<Index>& ids) const {
    const CellHit h = locator->find_cell(p);
    if (!h.found()) return false;
    cell = valid ? valid_ids[static_cast<std::size_t>(h.cell)] : h.cell;
    cell_point_ids(input, cell, ids);  // same point order as the locator's cell
    for (std::size_t k = 0; k < ids.size(); ++k) {
      if (h.weights[k] != 0) terms.emplace_back(static_cast<std::size_t>(ids[k]), h.weights[k]);
    }
    return true;
  }

  /// Image data by arithmetic: the smallest-id non-blanked cell containing p.
  bool locate_image(const ImageData& img, const Vec3& p, Index& cell_found,
                    std::vector<Term>& terms) const {
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
          cell_found = cell;
          const std::size_t before = terms.size();
          const Index base = img.point_id(i, j, k);
          const Index sj = img.dims[0], sk = img.dims[0] * img.dims[1];
          for (int c = 0; c < 8; ++c) {
            const int a0 = c & 1, a1 = (c >> 1) & 1, a2 = (c >> 2) & 1;
            if ((a0 && !step[0]) || (a1 && !step[1]) || (a2 && !step[2])) continue;
            const double wt = w[0][a0] * w[1][a1] * w[2][a2];
            if (wt == 0) continue;
            terms.emplace_back(static_cast<std::size_t>(base + a0 + a1 * sj + a2 * sk), wt);
          }
          if (terms.size() == before) terms.emplace_back(static_cast<std::size_t>(base), 1.0);
          return true;
        }
      }
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
  // The distance tolerance, resolved where surface, line and vertex cells may need it (a 3D
  // structured grid and a mesh of tetrahedra have none: their bounds are not computed).
  const auto resolve_dtol = [&] {
    m.dtol = options.distance_tolerance >= 0 ? options.distance_tolerance
                                             : 1e-6 * bounds(input).diagonal();
  };

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

  if (input.get_if<ImageData>()) {  // arithmetic: no locator
    resolve_dtol();
    return;
  }
  if (const auto* g = input.get_if<StructuredGrid>()) {
    if (g->points.first_non_finite() < g->points.size()) {
      throw Error(fmt::format("probe: point {} of the input is not finite",
                              g->points.first_non_finite()));
    }
    if (g->dims[0] > 1 && g->dims[1] > 1 && g->dims[2] > 1) {
      m.grid.emplace(*g, m.cell_ok, options.tolerance);
      return;
    }
  }
  resolve_dtol();
  m.locator_options.tolerance = options.tolerance;
  m.locator_options.distance_tolerance = m.dtol;
  if (const auto* ug = input.get_if<UnstructuredGrid>();
      ug && probe_detail::TetWalker::applicable(*ug)) {
    // Tetrahedra: walks, and the locator only if a walk fails (built then, between passes).
    if (ug->points.first_non_finite() < ug->points.size()) {
      throw Error(fmt::format("probe: point {} of the input is not finite",
                              ug->points.first_non_finite()));
    }
    m.tets.emplace(*ug, m.cell_ok, options.tolerance);
    return;
  }
  m.build_locator();
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

  // The output: the probe's structure; the input's point arrays, then its cell arrays (renamed
  // on a collision), each made once at full size and written once.
  ProbeResult result;
  result.output = probe_ds.visit([](const auto& d) -> Dataset {
    auto out = d;
    out.point_data.clear();
    out.cell_data.clear();
    out.field_data.clear();
    return out;
  });
  Attributes& out_pd = point_data(result.output);
  const Attributes& in_pd = point_data(m.input);
  const Attributes& in_cd = cell_data(m.input);
  std::vector<Carried> carried;
  auto add_output = [&](const DataArray& a, std::string name, bool interpolate) {
    DataArray d = DataArray::uninitialized(std::move(name), a.type(), a.components(), n);
    d.set_lookup_table(a.lookup_table());
    const BlockKernel kernel = a.visit([&](const auto& v) -> BlockKernel {
      using T = typename std::decay_t<decltype(v)>::value_type;
      return interpolate ? &interpolate_block<T> : &copy_block<T>;
    });
    carried.push_back({&a, d.name(), nullptr, kernel});
    out_pd.add(std::move(d));
  };
  for (const DataArray& a : in_pd) add_output(a, a.name(), true);
  for (std::size_t r = 0; r < kAttributeRoleCount; ++r) {
    const auto role = static_cast<AttributeRole>(r);
    if (!in_pd.active_name(role).empty()) out_pd.set_active(role, in_pd.active_name(role));
  }
  for (const DataArray& a : in_cd) {
    const std::string name = out_pd.has(a.name()) ? a.name() + " (cell)" : a.name();
    add_output(a, name, false);
    for (std::size_t r = 0; r < kAttributeRoleCount; ++r) {
      const auto role = static_cast<AttributeRole>(r);
      if (in_cd.active_name(role) == a.name() && out_pd.active_name(role).empty()) {
        out_pd.set_active(role, name);
      }
    }
  }
  out_pd.remove(m.options.mask_name);  // an input array named like the mask gives way to it
  // Each output array is filled by the last entry of its name (a later `add` replaced it).
  for (std::size_t a = carried.size(); a-- > 0;) {
    DataArray* dst = out_pd.find(carried[a].name);
    const bool taken = std::any_of(carried.begin() + std::ptrdiff_t(a) + 1, carried.end(),
                                   [&](const Carried& c) { return c.dst == dst; });
    if (!dst || taken) {
      carried.erase(carried.begin() + std::ptrdiff_t(a));
    } else {
      carried[a].dst = dst;
    }
  }
  const double nil = m.options.nil_value;
  auto carry = [&](const BlockHits& h) {
    for (const Carried& c : carried) c.kernel(*c.src, *c.dst, h, nil);
  };
  Buffer<std::uint8_t> mask;
  mask.resize(n);

  const ImageData* image = m.input.get_if<ImageData>();
  const probe_detail::TetWalker* tets = m.tets ? &*m.tets : nullptr;
  constexpr std::uint8_t kPending = 2;  // a tetra walk failed: the locator decides (second pass)
  std::atomic<std::size_t> found{0}, pending{0};
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  if (m.grid && pp.image && 4 * n >= num_cells(m.input) && m.grid->can_scan(*pp.image)) {
    // An image probe in a 3D structured grid: cell by cell, each cell's box scanned for the
    // image points in it (probe_grid.hpp), slab by slab of image layers. It visits every cell
    // once to plan, so an image of few points (fewer than a quarter of the cells) walks.
    const probe_detail::ImagePlan plan = m.grid->plan_image(*pp.image, kSlabs);
    parallel_for_range(
        plan.slabs(), 1,
        [&](std::size_t s0, std::size_t s1) {
          auto hits = std::make_unique<BlockHits>();
          BlockHits& h = *hits;
          h.trilinear = true;
          h.offsets = m.grid->offsets();
          // Hits are written in place in the block, carried when it is full.
          struct Sink final : probe_detail::GridHitSink {
            BlockHits& h;
            decltype(carry)& flush;
            Sink(BlockHits& hits, decltype(carry)& f) : h(hits), flush(f) {
              capacity = kBlock;
              out = h.out.data();
              cell = h.cell.data();
              hit = h.grid.data();
            }
            void full() override {
              h.size = size;
              flush(h);
              size = 0;
            }
            void missed(std::size_t id) {  // the nil value
              if (size == capacity) full();
              out[size] = id;
              cell[size++] = BlockHits::kMissed;
            }
          } sink(h, carry);
          std::size_t count = 0;
          for (std::size_t s = s0; s < s1; ++s) {
            const auto [p0, p1] = plan.points(s);
            std::fill(mask.data() + p0, mask.data() + p1, std::uint8_t{0});
            m.grid->scan_image(plan, s, mask.data(), sink);
            count += p1 - p0;
            for (std::size_t i = p0; i < p1; ++i) {
              if (mask[i]) continue;
              --count;
              sink.missed(i);
            }
          }
          if (sink.size > 0) sink.full();
          found += count;
        },
        m.options.progress, "probe");
  } else {
    if (m.grid) m.grid->prepare();
    parallel_for_range(
        blocks, 1,
        [&](std::size_t b0, std::size_t b1) {
          auto hits = std::make_unique<BlockHits>();
          BlockHits& h = *hits;
          if (m.grid) {
            h.trilinear = true;
            h.offsets = m.grid->offsets();
          } else {
            h.terms.reserve(8 * kBlock);
          }
          probe_detail::GridHit gh;
          std::array<double, 4> tw{};
          std::vector<Index> ids;
          std::size_t count = 0, waiting = 0;
          for (std::size_t b = b0; b < b1; ++b) {
            // The walks restart in every block. On an image probe, a row starts from where the
            // previous row's first point was found (in a grid or a tetra mesh), not from the
            // previous row's end.
            probe_detail::GridCursor cursor, row_cursor;
            bool have_row = false, row_saved = false;
            Index last_tet = -1, row_tet = -1;
            const std::size_t end = std::min(n, (b + 1) * kBlock);
            h.clear();
            if (m.grid && pp.image) {
              // An image probe in a structured grid: its rows point by point, hits written in
              // place.
              const ImageData& img = *pp.image;
              const auto first = static_cast<Index>(b * kBlock);
              Index x = first % img.dims[0], y = (first / img.dims[0]) % img.dims[1],
                    z = first / (img.dims[0] * img.dims[1]);
              for (std::size_t i = b * kBlock; i < end; ++i) {
                if (x == 0) {
                  if (have_row) cursor = row_cursor;
                  row_saved = false;
                }
                const Vec3 p = img.point(x, y, z);
                if (++x == img.dims[0]) {
                  x = 0;
                  if (++y == img.dims[1]) {
                    y = 0;
                    ++z;
                  }
                }
                probe_detail::GridHit& g = h.grid[h.size];
                if (is_finite(p) && m.grid->find(p, cursor, g)) {
                  mask[i] = 1;
                  ++count;
                  h.out[h.size] = i;
                  h.cell[h.size++] = g.cell;
                  if (!row_saved) {
                    row_cursor = cursor;
                    have_row = row_saved = true;
                  }
                } else {
                  mask[i] = 0;
                  h.missed(i);
                }
              }
              carry(h);
              continue;
            }
            PointSequence seq(pp, b * kBlock);
            for (std::size_t i = b * kBlock; i < end; ++i) {
              if (seq.row_start()) {
                if (have_row) cursor = row_cursor;
                if (row_tet >= 0) last_tet = row_tet;
                row_saved = false;
              }
              const Vec3 p = seq.next();
              Index cell = -1;
              bool hit_ok = false;
              if (!is_finite(p)) {
                hit_ok = false;
              } else if (image) {
                hit_ok = m.locate_image(*image, p, cell, h.terms);
              } else if (m.grid) {
                if (m.grid->find(p, cursor, gh)) {
                  mask[i] = 1;
                  ++count;
                  h.found(i, gh);
                  if (!row_saved) {
                    row_cursor = cursor;
                    have_row = row_saved = true;
                  }
                  continue;
                }
              } else if (tets) {
                cell = last_tet >= 0 ? last_tet : tets->seed(p);
                if (cell >= 0 && tets->walk(p, cell, tw)) {
                  hit_ok = true;
                  last_tet = cell;
                  if (!row_saved) {
                    row_tet = cell;
                    row_saved = true;
                  }
                  const std::uint32_t* cell_ids = tets->points_of(cell);  // in cache after the walk
                  for (int k = 0; k < 4; ++k) {
                    if (tw[std::size_t(k)] != 0) {
                      h.terms.emplace_back(std::size_t(cell_ids[std::size_t(k)]),
                                           tw[std::size_t(k)]);
                    }
                  }
                } else if (tets->in_bounds(p)) {
                  mask[i] = kPending;
                  h.missed(i, BlockHits::kPending);
                  ++waiting;
                  continue;
                }  // else outside the mesh's bounds: in no cell, no locator needed
              } else {
                hit_ok = m.from_locator(p, cell, h.terms, ids);
              }
              mask[i] = hit_ok ? 1 : 0;
              if (hit_ok) {
                ++count;
                h.found(i, cell);
              } else {
                h.missed(i);
              }
            }
            carry(h);
          }
          found += count;
          pending += waiting;
        },
        m.options.progress, "probe");
  }
  if (pending > 0) {
    // The points a tetra walk did not reach, by the exact locator (built now if it was not).
    {
      const std::lock_guard<std::mutex> lock(impl_->build_mutex);  // probe() is thread-safe
      impl_->build_locator();
    }
    std::vector<std::size_t> rest;
    rest.reserve(pending);
    for (std::size_t i = 0; i < n; ++i) {
      if (mask[i] == kPending) rest.push_back(i);
    }
    parallel_for_range(rest.size(), 256, [&](std::size_t r0, std::size_t r1) {
      auto hits = std::make_unique<BlockHits>();
      BlockHits& h = *hits;
      std::vector<Index> ids;
      std::size_t count = 0;
      for (std::size_t r = r0; r < r1; ++r) {
        const std::size_t i = rest[r];
        Index cell = -1;
        const bool hit_ok = m.from_locator(pp(i), cell, h.terms, ids);
        mask[i] = hit_ok ? 1 : 0;
        if (hit_ok) {
          ++count;
          h.found(i, cell);
        } else {
          h.missed(i);
        }
        if (h.size == kBlock || r + 1 == r1) {
          carry(h);
          h.clear();
        }
      }
      found += count;
    });
  }
  const std::size_t nfound = found.load();
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
