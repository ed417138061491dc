// Point location in the cells of any dataset (spatial/cell_locator.hpp): the 4-wide hierarchy of
// bvh4.hpp over the cells' bounding boxes (grown by the tolerances), with `locate_in_cell`
// deciding every candidate.

#include "isoforge/spatial/cell_locator.hpp"

#include <fmt/format.h>

#include <cmath>
#include <mutex>
#include <vector>

#include "bvh4.hpp"
#include "isoforge/core/parallel.hpp"

namespace isoforge {

// The items are outside the anonymous namespace because CellLocator::Impl, which has external
// linkage, holds them.
namespace spatial_detail {

/// The `Items` policy of Bvh4 for the cells of a dataset: boxes only (no slab-discs), exact
/// distances from `locate_in_cell`.
struct CellItems {
  DatasetRef ds;
  double tolerance = 0;
  Buffer<Bounds> boxes;  // grown by the tolerances
  Buffer<CellType> types;

  [[nodiscard]] u32 size() const { return static_cast<u32>(boxes.size()); }
  [[nodiscard]] Bounds bounds(u32 id) const { return boxes[id]; }
  bool slab(u32, Vec3&, Vec3&) const { return false; }
  bool plane_normal(u32, Vec3&) const { return false; }
  template <class F>
  void for_each_vertex(u32 id, F&& f) const {
    f(boxes[id].min);
    f(boxes[id].max);
  }
  /// The cell's points (into a per-thread buffer).
  std::span<const Vec3> points(u32 id) const {
    thread_local std::vector<Index> ids;
    thread_local std::vector<Vec3> pts;
    cell_point_ids(ds, static_cast<Index>(id), ids);
    pts.resize(ids.size());
    for (std::size_t k = 0; k < ids.size(); ++k) pts[k] = point(ds, ids[k]);
    return pts;
  }
  [[nodiscard]] CellPosition locate(u32 id, const Vec3& p) const {
    return locate_in_cell(types[id], points(id), p, tolerance);
  }
  [[nodiscard]] double dist2(u32 id, const Vec3& p) const {
    if (types[id] == CellType::Empty) return std::numeric_limits<double>::infinity();
    return locate(id, p).dist2;
  }
};

}  // namespace spatial_detail

namespace {

using spatial_detail::CellItems;
using spatial_detail::u32;

CellHit hit_of(Index cell, CellPosition&& pos) {
  CellHit h;
  h.cell = cell;
  h.sub_id = pos.sub_id;
  h.pcoords = pos.pcoords;
  h.weights = std::move(pos.weights);
  h.closest_point = pos.closest_point;
  h.dist2 = pos.dist2;
  return h;
}

}  // namespace

struct CellLocator::Impl {
  CellItems items;
  double distance_tolerance = 0;
  std::unique_ptr<spatial_detail::Bvh4<CellItems>> tree;
};

CellLocator::CellLocator(DatasetRef dataset, const CellLocatorOptions& options)
    : impl_(std::make_unique<Impl>(Impl{CellItems{dataset, options.tolerance, {}, {}}, 0, {}})) {
  validate(dataset);
  if (!(options.tolerance >= 0) || !std::isfinite(options.tolerance)) {
    throw Error(fmt::format("cell locator: tolerance must be finite and >= 0, got {:g}",
                            options.tolerance));
  }
  if (!std::isfinite(options.distance_tolerance)) {
    throw Error("cell locator: distance tolerance must be finite");
  }
  const std::size_t nc = num_cells(dataset);
  if (nc >= static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
    throw Error(fmt::format("cell locator: {} cells exceed 2^31 - 1", nc));
  }
  const Bounds all = bounds(dataset);
  for (std::size_t i = 0; i < num_points(dataset); ++i) {
    if (!is_finite(point(dataset, static_cast<Index>(i)))) {
      throw Error(fmt::format("cell locator: point {} is not finite", i));
    }
  }
  impl_->distance_tolerance =
      options.distance_tolerance >= 0 ? options.distance_tolerance : 1e-6 * all.diagonal();
  CellItems& items = impl_->items;
  items.boxes.resize(nc);
  items.types.resize(nc);
  // Each cell's box, grown by the tolerances, in parallel.
  double max_abs = 0;  // of the boxes' coordinates (a maximum: the same for any slicing)
  std::mutex max_mutex;
  parallel_for_range(nc, 4096, [&](std::size_t c0, std::size_t c1) {
    std::vector<Index> ids;
    double m = 0;
    for (std::size_t c = c0; c < c1; ++c) {
      Bounds b;
      items.types[c] = cell_type(dataset, static_cast<Index>(c));
      cell_point_ids(dataset, static_cast<Index>(c), ids);
      for (Index id : ids) b.extend(point(dataset, id));
      if (b.empty()) b.extend(all.empty() ? Vec3{} : all.center());  // an empty cell is never hit
      // A parametric tolerance reaches about tolerance x the cell's size beyond it.
      const double grow = std::max(options.tolerance * b.diagonal(), impl_->distance_tolerance);
      b.min -= Vec3{grow, grow, grow};
      b.max += Vec3{grow, grow, grow};
      m = std::max({m, std::abs(b.min.x), std::abs(b.min.y), std::abs(b.min.z),
                    std::abs(b.max.x), std::abs(b.max.y), std::abs(b.max.z)});
      items.boxes[c] = b;
    }
    const std::lock_guard lock(max_mutex);
    max_abs = std::max(max_abs, m);
  });
  impl_->tree = std::make_unique<spatial_detail::Bvh4<CellItems>>(
      items, spatial_detail::bvh_tolerance(max_abs, all.diagonal()));
}

CellLocator::~CellLocator() = default;
CellLocator::CellLocator(CellLocator&&) noexcept = default;
CellLocator& CellLocator::operator=(CellLocator&&) noexcept = default;

CellHit CellLocator::find_cell(const Vec3& p) const {
  const CellItems& items = impl_->items;
  const double dtol2 = impl_->distance_tolerance * impl_->distance_tolerance;
  CellHit best;
  if (!is_finite(p)) return best;
  impl_->tree->for_each_containing(p, 0.0, [&](u32 id) {
    if (best.found() && static_cast<Index>(id) > best.cell) return false;  // keep the smallest id
    const CellType type = items.types[id];
    if (type == CellType::Empty) return false;
    CellPosition pos = items.locate(id, p);
    const int dim = cell_dimension(type);
    const bool hit = dim == 3 ? pos.inside : (dim == 0 || pos.inside) && pos.dist2 <= dtol2;
    if (hit) best = hit_of(static_cast<Index>(id), std::move(pos));
    return false;
  });
  return best;
}

CellHit CellLocator::closest_point(const Vec3& p) const {
  double best2 = std::numeric_limits<double>::infinity();
  u32 best_id = spatial_detail::kNone;
  std::size_t evals = 0;
  if (is_finite(p)) impl_->tree->nearest(p, best2, best2, best_id, evals);
  if (best_id == spatial_detail::kNone) return {};
  return hit_of(static_cast<Index>(best_id), impl_->items.locate(best_id, p));
}

CellHit find_cell(DatasetRef dataset, const Vec3& p, const CellLocatorOptions& options) {
  return CellLocator(dataset, options).find_cell(p);
}

CellHit closest_cell_point(DatasetRef dataset, const Vec3& p, const CellLocatorOptions& options) {
  return CellLocator(dataset, options).closest_point(p);
}

}  // namespace isoforge
