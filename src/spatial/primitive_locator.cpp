// Closest-primitive queries (spatial/primitive_locator.hpp): the 4-wide hierarchy of bvh4.hpp
// over points, segments and triangles, with slab-disc bounds for segments, triangles and
// nearly coplanar subtrees.

#include "isoforge/spatial/primitive_locator.hpp"

#include "bvh4.hpp"

namespace isoforge {

// The items are outside the anonymous namespace because PrimitiveLocator::Impl, which has
// external linkage, holds them.
namespace spatial_detail {

/// The `Items` policy of Bvh4 for a PrimitiveSet.
struct PrimitiveItems {
  const PrimitiveSet& set;

  [[nodiscard]] u32 size() const { return set.size(); }
  [[nodiscard]] Bounds bounds(u32 id) const { return set.bounds(id); }
  [[nodiscard]] double dist2(u32 id, const Vec3& p) const { return set.dist2(id, p); }
  template <class F>
  void for_each_vertex(u32 id, F&& f) const {
    set.for_each_vertex(id, f);
  }
  // The primitive itself as a slab-disc: a triangle's plane about its centroid (none when it is
  // degenerate), a segment's axis about its midpoint, a point.
  bool slab(u32 id, Vec3& c, Vec3& n) const {
    const auto& v = set.vertices();
    if (id >= set.triangle_begin()) {
      const auto& t = set.triangles()[id - set.triangle_begin()];
      const Vec3 a = v[t[0]], b = v[t[1]], d = v[t[2]];
      const Vec3 nrm = cross(b - a, d - a);
      const double len = norm(nrm);
      if (!(len > 0)) return false;
      c = (a + b + d) / 3.0;
      n = nrm / len;
    } else if (id >= set.segment_begin()) {
      const auto& s = set.segments()[id - set.segment_begin()];
      const Vec3 a = v[s[0]], b = v[s[1]];
      const double len = norm(b - a);
      c = (a + b) * 0.5;
      n = len > 0 ? (b - a) / len : Vec3{0, 0, 1};
    } else {
      c = v[set.points()[id]];
      n = {0, 0, 1};
    }
    return true;
  }
  bool plane_normal(u32 id, Vec3& n) const {
    if (id < set.triangle_begin()) return false;
    const auto& v = set.vertices();
    const auto& t = set.triangles()[id - set.triangle_begin()];
    n = cross(v[t[1]] - v[t[0]], v[t[2]] - v[t[0]]);
    return true;
  }
};

}  // namespace spatial_detail

namespace {

using spatial_detail::PrimitiveItems;
using spatial_detail::u32;

double tolerance_of(const PrimitiveSet& set) {
  double m = 0;
  Bounds all;
  for (const Vec3& p : set.vertices()) {
    all.extend(p);
    m = std::max({m, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  }
  return spatial_detail::bvh_tolerance(m, all.diagonal());
}

}  // namespace

struct PrimitiveLocator::Impl {
  explicit Impl(const PrimitiveSet& s) : items{s}, tree(items, tolerance_of(s)) {}
  PrimitiveItems items;
  spatial_detail::Bvh4<PrimitiveItems> tree;
};

PrimitiveLocator::PrimitiveLocator(const PrimitiveSet& primitives)
    : impl_(std::make_unique<Impl>(primitives)) {}
PrimitiveLocator::~PrimitiveLocator() = default;
PrimitiveLocator::PrimitiveLocator(PrimitiveLocator&&) noexcept = default;
PrimitiveLocator& PrimitiveLocator::operator=(PrimitiveLocator&&) noexcept = default;

const PrimitiveSet& PrimitiveLocator::primitives() const {
  return impl_->items.set;
}

void PrimitiveLocator::nearest(const Vec3& p, double limit2, ClosestPrimitive& best) const {
  impl_->tree.nearest(p, limit2, best.dist2, best.id, best.evaluations);
}

ClosestPrimitive PrimitiveLocator::closest(const Vec3& p) const {
  ClosestPrimitive best;
  nearest(p, std::numeric_limits<double>::infinity(), best);
  return best;
}

bool PrimitiveLocator::any_within(const Vec3& lo, const Vec3& hi, double r2) const {
  return impl_->tree.any_within(lo, hi, r2);
}

ClosestPrimitive closest_primitive(const PrimitiveSet& primitives, const Vec3& p) {
  return PrimitiveLocator(primitives).closest(p);
}

}  // namespace isoforge
