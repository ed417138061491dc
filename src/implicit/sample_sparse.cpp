// Narrow-band sampling into OpenVDB (Museth, "VDB: High-resolution sparse volumes with dynamic
// topology", ACM TOG 32(3), 2013, for the tree; Duff 1992 for culling by interval bounds).
//
// Descent: blocks of 4096³, 128³ and 8³ voxels (the default FloatTree's node sizes). A block whose
// bound lies entirely above the band is skipped (outside: the background already says so); one
// entirely below becomes one inactive tile of -background at that level (inside); the rest are
// subdivided. Surviving 8³ leaves are evaluated in parallel and then inserted serially, so the
// result does not depend on the number of threads.

#include "isoforge/implicit/sample_sparse.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "function_node.hpp"
#include "isoforge/core/memory.hpp"
#include "isoforge/core/parallel.hpp"
#include "isoforge/sparse/grid.hpp"

namespace isoforge {

namespace {

using implicit_detail::eval_pruned;
using openvdb::Coord;
using SampleTree = openvdb::FloatTree;
using SampleLeaf = SampleTree::LeafNodeType;

struct Tile {
  Coord origin;
  int level;  // 1: 8³ leaf-sized tile in an internal node, 2: 128³, 3: 4096³
};

// Bytes one leaf of the band costs while it is built: the node, its 8³ values, and its entries in
// the descent's list and the evaluated-leaf list.
constexpr double kLeafBytes =
    sizeof(SampleLeaf) + SampleLeaf::SIZE * sizeof(float) + sizeof(Coord) + sizeof(SampleLeaf*);

// The leaves of the band, estimated before any is built: the cells of a coarse grid (at most
// kCoarse per axis, each at least a leaf wide) where F's interval bound meets the band are counted.
// A surface meeting n cells of side c voxels has an area of about n c² / 1.5 voxels² (a randomly
// oriented plane meets 1.5 unit cubes per unit area), and a band of half width w voxels around
// it lies in about 1.5 (area / 8²) (1 + 2w / 8) leaves. Bounds are conservative, so the count
// does not miss surfaces; detail finer than a cell is not seen (the descent's budget catches it).
double estimate_band_leaves(const ImplicitFunction& f, const GridSpec& g, double band,
                            double half_width) {
  constexpr Index kCoarse = 64;
  Index c = 8;  // cell side in voxels
  for (int a = 0; a < 3; ++a) c = std::max(c, (g.dims[a] + kCoarse - 1) / kCoarse);
  double crossed = 0;
  for (Index i = 0; i < g.dims[0]; i += c)
    for (Index j = 0; j < g.dims[1]; j += c)
      for (Index k = 0; k < g.dims[2]; k += c) {
        Bounds box;
        box.min = {g.coordinate(0, i), g.coordinate(1, j), g.coordinate(2, k)};
        box.max = {g.coordinate(0, std::min(i + c, g.dims[0] - 1)),
                   g.coordinate(1, std::min(j + c, g.dims[1] - 1)),
                   g.coordinate(2, std::min(k + c, g.dims[2] - 1))};
        const Interval iv = f.bound(box);
        if (iv.lo < band && iv.hi > -band) ++crossed;
      }
  const double cell = static_cast<double>(c) / 8;  // cell side in leaves
  return crossed * cell * cell * (1 + 2 * half_width / 8);
}

struct Descent {
  const ImplicitFunction& f;
  const GridSpec& g;
  double band;
  std::size_t max_leaves;  // the leaves that fit in memory
  std::vector<Coord> leaves;
  std::vector<Tile> tiles;

  // World box of the sample points of the index block [o, o + size).
  Bounds world_box(const Coord& o, int size) const {
    Bounds b;
    b.min = {g.coordinate(0, o.x()), g.coordinate(1, o.y()), g.coordinate(2, o.z())};
    b.max = {g.coordinate(0, o.x() + size - 1), g.coordinate(1, o.y() + size - 1),
             g.coordinate(2, o.z() + size - 1)};
    return b;
  }

  bool overlaps_domain(const Coord& o, int size) const {
    for (int a = 0; a < 3; ++a) {
      if (o[a] + size <= 0 || o[a] >= g.dims[a]) return false;
    }
    return true;
  }

  // level: 3 = 4096³ block, 2 = 128³, 1 = 8³ (leaf).
  void visit(const Coord& o, int level) {
    static constexpr int kSize[4] = {1, 8, 128, 4096};
    const int size = kSize[level];
    if (!overlaps_domain(o, size)) return;
    const Interval iv = f.bound(world_box(o, size));
    if (iv.lo >= band) return;  // entirely outside the band, on the positive side
    if (iv.hi <= -band) {       // entirely inside
      tiles.push_back({o, level});
      return;
    }
    if (level == 1) {
      if (leaves.size() == max_leaves) {
        require_memory(static_cast<double>(max_leaves + 1) * kLeafBytes,
                       fmt::format("sparse sample: a narrow band of more than {} leaves (8³ voxels)",
                                   max_leaves));
      }
      leaves.push_back(o);
      return;
    }
    const int child = kSize[level - 1];
    for (int x = 0; x < size; x += child)
      for (int y = 0; y < size; y += child)
        for (int z = 0; z < size; z += child) visit(o.offsetBy(x, y, z), level - 1);
  }
};

// Top-level (4096³) blocks the descent visits one by one: 2^24 of them is a 1.1M³-voxel box.
constexpr double kMaxTopBlocks = 1 << 24;

bool all_equal(const SampleLeaf& leaf) {
  const float first = leaf.getFirstValue();
  for (auto it = leaf.cbeginValueAll(); it; ++it) {
    if (*it != first) return false;
  }
  return true;
}

}  // namespace

SparseSampleResult sample_level_set(const ImplicitFunction& f, const GridSpec& grid,
                                    const SparseSampleOptions& options) {
  ensure_openvdb_initialized();
  (void)checked_point_count(grid.dims, "sparse sample grid");
  const double h = grid.spacing.x;
  if (!(h > 0) || !std::isfinite(h) || grid.spacing.y != h || grid.spacing.z != h) {
    throw Error("sparse sample: voxels must be cubes (equal positive spacing on all axes), got " +
                std::to_string(grid.spacing.x) + ", " + std::to_string(grid.spacing.y) + ", " +
                std::to_string(grid.spacing.z));
  }
  if (!is_finite(grid.origin)) throw Error("sparse sample: origin is not finite");
  const openvdb::math::Transform::Ptr xform = vdb_transform(h, grid.origin, "sparse sample");
  for (int a = 0; a < 3; ++a) {
    if (grid.dims[a] > (Index{1} << 30)) throw Error("sparse sample: dims exceed 2^30 voxels per axis");
  }
  if (!(options.half_width > 0) || !std::isfinite(options.half_width)) {
    throw Error("sparse sample: half_width must be positive, got " + std::to_string(options.half_width));
  }
  const double band = options.half_width * h;
  const float background = static_cast<float>(band);
  // Memory scales with the band, i.e. with the surface's area: refuse at once what cannot fit.
  const double voxels = static_cast<double>(grid.dims[0]) * static_cast<double>(grid.dims[1]) *
                        static_cast<double>(grid.dims[2]);
  const double memory = static_cast<double>(physical_memory());
  if (memory > 0 && voxels / 512 * kLeafBytes > memory) {  // could the band exceed memory?
    const double leaves = estimate_band_leaves(f, grid, band, options.half_width);
    require_memory(leaves * kLeafBytes,
                   fmt::format("sparse sample: a narrow band (half width {:g}) of about {:.2g} "
                               "leaves (8³ voxels) in a {} grid",
                               options.half_width, leaves, format_dims(grid.dims)));
  }
  if (voxels / (4096.0 * 4096.0 * 4096.0) > kMaxTopBlocks) {
    throw Error(fmt::format("sparse sample: a {} grid spans more than {:g} blocks of 4096³ voxels, "
                            "each visited: choose a larger voxel size or a smaller box",
                            format_dims(grid.dims), kMaxTopBlocks));
  }

  Descent d{f, grid, band, static_cast<std::size_t>(memory > 0 ? memory / kLeafBytes : 1e18), {}, {}};
  // Top-level blocks covering the domain (4096³ each, aligned like the VDB root's children).
  std::vector<Coord> tops;
  for (Index x = 0; x < grid.dims[0]; x += 4096)
    for (Index y = 0; y < grid.dims[1]; y += 4096)
      for (Index z = 0; z < grid.dims[2]; z += 4096)
        tops.emplace_back(static_cast<int>(x), static_cast<int>(y), static_cast<int>(z));
  for (std::size_t t = 0; t < tops.size(); ++t) {
    d.visit(tops[t], 3);
    report_progress(options.progress, 0.25 * static_cast<double>(t + 1) / static_cast<double>(tops.size()),
                    "sparse sample");
  }

  // Evaluate the leaves in parallel.
  std::vector<SampleLeaf*> leaves(d.leaves.size(), nullptr);
  const auto& node = f.node();
  const Index nx = grid.dims[0], ny = grid.dims[1], nz = grid.dims[2];
  parallel_for_range(leaves.size(), 8, [&](std::size_t begin, std::size_t end) {
    static_assert(implicit_detail::kBlock >= 512, "a leaf is evaluated as one block");
    alignas(64) double x[512], y[512], z[512], v[512];
    for (std::size_t li = begin; li != end; ++li) {
      const Coord o = d.leaves[li];
      auto* leaf = new SampleLeaf(o, background, false);
      // SampleLeaf voxel offset = (i << 6) + (j << 3) + k, the order the values are generated in.
      for (int t = 0; t < 512; ++t) {
        x[t] = grid.coordinate(0, o.x() + (t >> 6));
        y[t] = grid.coordinate(1, o.y() + ((t >> 3) & 7));
        z[t] = grid.coordinate(2, o.z() + (t & 7));
      }
      Bounds box;
      box.min = {x[0], y[0], z[0]};
      box.max = {x[511], y[511], z[511]};
      eval_pruned(node, box, x, y, z, 512, v);
      for (int t = 0; t < 512; ++t) {
        const Index gi = o.x() + (t >> 6), gj = o.y() + ((t >> 3) & 7), gk = o.z() + (t & 7);
        const bool in_domain = gi >= 0 && gi < nx && gj >= 0 && gj < ny && gk >= 0 && gk < nz;
        const auto offset = static_cast<openvdb::Index>(t);
        if (in_domain && std::abs(v[t]) < band) {
          leaf->setValueOn(offset, static_cast<float>(v[t]));
        } else {
          leaf->setValueOff(offset, v[t] < 0 ? -background : background);
        }
      }
      leaves[li] = leaf;
    }
  }, progress_range(options.progress, 0.25, 0.9), "sparse sample");
  report_progress(options.progress, 0.9, "sparse sample");

  auto result = openvdb::FloatGrid::create(background);
  result->setTransform(xform);
  result->setGridClass(openvdb::GRID_LEVEL_SET);
  SampleTree& tree = result->tree();
  for (const Tile& t : d.tiles) tree.addTile(static_cast<openvdb::Index>(t.level), t.origin, -background, false);
  std::size_t kept = 0;
  for (SampleLeaf* leaf : leaves) {
    if (leaf->isEmpty() && all_equal(*leaf)) {
      // All voxels inactive with one sign: a tile says the same in far less memory.
      tree.addTile(1, leaf->origin(), leaf->getFirstValue(), false);
      delete leaf;
      continue;
    }
    tree.addLeaf(leaf);
    ++kept;
  }
  tree.prune();
  report_progress(options.progress, 1.0, "sparse sample");
  SparseSampleResult r{std::move(result), {}};
  r.stats.active_voxels = static_cast<std::size_t>(tree.activeVoxelCount());
  r.stats.leaves = kept;
  r.stats.inside_tiles = d.tiles.size();
  r.stats.evaluated_voxels = d.leaves.size() * 512;
  r.stats.memory_bytes = static_cast<std::size_t>(tree.memUsage());
  return r;
}

}  // namespace isoforge
