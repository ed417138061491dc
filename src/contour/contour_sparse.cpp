// Marching cubes (Lorensen & Cline, "Marching cubes: a high resolution 3D surface construction
// algorithm", SIGGRAPH 1987) directly on the sparse tree of an OpenVDB float grid (Museth, "VDB:
// High-resolution sparse volumes with dynamic topology", ACM TOG 32(3), 2013), with the case
// tables, conventions and multi-pass lock-free design of the dense contour (contour_image.cpp,
// after Flying Edges: Schroeder, Maynard & Geveci, LDAV 2015), so both give the same surface.
//   setup   the visited blocks are the 8³ leaf positions and their -x/-y/-z neighbours (the
//           cells whose min corner lies there are exactly those touching leaf voxels), sorted by
//           origin; each records where its values come from (a leaf buffer, or a tile or
//           background value read through an accessor) and the indices of its +x/+y/+z
//           neighbours (binary search, once for all isovalues);
//   pass 1  every block's voxels are classified into a 512-bit mask (SSE compares); then per
//           block, bit rows of the 9³ corners of its cells are assembled from the masks of the
//           block and its neighbours, the crossed edges owned by each voxel (+x, +y, +z) go into
//           three 512-bit masks, and the cells are counted (triangles, cell-interior points);
//   pass 2  prefix sums give every block a contiguous range of points and of triangles;
//   pass 3  blocks generate in parallel, each writing only its ranges: a triangle vertex on an
//           edge owned by voxel v is the point offset of v's block plus the rank of the edge in
//           that block's mask (a popcount), so there is neither hash map nor lock. Values are
//           read only where needed: crossed edges, ambiguous faces, gradients.
// The output does not depend on the number of threads.

#include "isoforge/contour/contour_sparse.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "contour_output.hpp"
#include "isoforge/core/parallel.hpp"
#include "isoforge/sparse/grid.hpp"
#include "tables.hpp"

namespace isoforge {

namespace {

using namespace contour_detail;
using openvdb::Coord;
using Tree = openvdb::FloatTree;
using Leaf = Tree::LeafNodeType;
using Accessor = openvdb::tree::ValueAccessor<const Tree>;
using Word = std::uint64_t;

static_assert(Leaf::DIM == 8, "blocks are the default tree's 8³ leaves");
constexpr int kB = 8;  // voxels per block side
constexpr int kC = 9;  // corner samples per side of a block's cells

/// Voxel edge e of the case table: its axis and corners (c0 the lower one).
struct EdgeInfo {
  int axis;
  int c0, c1;
};

const std::array<EdgeInfo, 12>& edge_info() {
  static const std::array<EdgeInfo, 12> info = [] {
    std::array<EdgeInfo, 12> r{};
    const auto& topo = voxel_table().topology();
    for (std::size_t e = 0; e < 12; ++e) {
      const int lo = std::min(topo.edges[e][0], topo.edges[e][1]);
      const int hi = std::max(topo.edges[e][0], topo.edges[e][1]);
      r[e] = {(hi ^ lo) == 1 ? 0 : ((hi ^ lo) == 2 ? 1 : 2), lo, hi};
    }
    return r;
  }();
  return info;
}

/// Where the values of an 8³ block come from: a leaf's buffer (voxel (x, y, z) at offset
/// 64 x + 8 y + z) or, outside leaves, one tile or background value.
struct SparseSource {
  const float* data = nullptr;
  float value = 0;
  [[nodiscard]] float at(int x, int y, int z) const {
    return data ? data[((x & 7) << 6) | ((y & 7) << 3) | (z & 7)] : value;
  }
};

/// One visited 8³ block of cells (the cells whose min corner lies in it).
struct SparseBlock {
  Coord origin;
  /// Index of the block at origin + 8 (d & 1, (d >> 1) & 1, (d >> 2) & 1) among the visited
  /// blocks, -1 if it is not visited (then it is not a leaf); nb[0] is the block itself.
  std::array<std::int32_t, 8> nb{};
  SparseSource self;
  std::array<float, 8> outside{};  // the value of neighbour d when nb[d] < 0
  // Per isovalue. Bits in leaf offset order: voxel (x, y, z) is bit 8 y + z of word x.
  std::array<Word, 8> above{};  // voxels at or above the isovalue
  /// Crossed edges owned by the block's voxels (from the voxel to its +x, +y or +z neighbour),
  /// axis a in words 8 a .. 8 a + 7. An edge counts when at least one end is a leaf voxel.
  std::array<Word, 24> mask{};
  std::array<std::uint16_t, 24> rank{};  // the block's points before word w's first one
  std::uint32_t edge_points = 0, centers = 0, tris = 0, ambiguous = 0, skipped = 0;
};

constexpr std::array<Word, 8> kAllAbove = {~Word{0}, ~Word{0}, ~Word{0}, ~Word{0},
                                           ~Word{0}, ~Word{0}, ~Word{0}, ~Word{0}};
constexpr std::array<Word, 8> kAllBelow = {};

/// A block's cells with what they read: bit rows over z of the corners [0, 9)³ at or above the
/// isovalue and in leaves, and the sources of the values around the block.
struct Neighbourhood {
  std::array<std::uint16_t, kC * kC> above;  // row (x, y) at 9 x + y, bit z
  std::array<std::uint16_t, kC * kC> leaf;
  std::array<SparseSource, 27> src;  // block d ∈ {-1, 0, 1}³ at (dx + 1) + 3 (dy + 1) + 9 (dz + 1)

  /// Value of local voxel (x, y, z), each in [-1, 10) (the -1 side only when it was gathered).
  [[nodiscard]] float value(int x, int y, int z) const {
    return src[static_cast<std::size_t>((x >> 3) + 1 + 3 * ((y >> 3) + 1) + 9 * ((z >> 3) + 1))].at(
        x, y, z);
  }

  /// Fills the rows from the above masks and leaf flags of the blocks d ∈ {0, 1}³.
  void fill_rows(const std::array<const Word*, 8>& ab, const std::array<bool, 8>& is_leaf) {
    for (int x = 0; x < kC; ++x) {
      for (int y = 0; y < kC; ++y) {
        const int d = (x >> 3) | (y >> 3) << 1;
        const int sh = 8 * (y & 7);
        const std::size_t w = static_cast<std::size_t>(x & 7);
        const auto i = static_cast<std::size_t>(kC * x + y);
        above[i] =
            static_cast<std::uint16_t>(((ab[static_cast<std::size_t>(d)][w] >> sh) & 0xFFu) |
                                       ((ab[static_cast<std::size_t>(d | 4)][w] >> sh) & 1u) << 8);
        leaf[i] =
            static_cast<std::uint16_t>((is_leaf[static_cast<std::size_t>(d)] ? 0xFFu : 0u) |
                                       (is_leaf[static_cast<std::size_t>(d | 4)] ? 0x100u : 0u));
      }
    }
  }

  /// Calls fn(x, y, z, case, variant) for every cell of the block that has crossings and touches
  /// a leaf voxel, in x, y, z order (z fastest); returns the number of cells left out because
  /// the surface crosses one of their edges between two voxels outside leaves.
  template <class Fn>
  std::uint32_t for_each_cell(double iso, Fn&& fn) const {
    const CaseTable& table = voxel_table();
    const auto& faces = table.topology().faces;
    const auto& edges = edge_info();
    std::uint32_t skipped = 0;
    for (int x = 0; x < kB; ++x) {
      for (int y = 0; y < kB; ++y) {
        // Corner c of cell (x, y, z) is in row q[c & 3] at z + (c >> 2).
        const auto r = static_cast<std::size_t>(kC * x + y);
        const unsigned q[4] = {above[r], above[r + kC], above[r + 1], above[r + kC + 1]};
        const unsigned any =
            q[0] | q[0] >> 1 | q[1] | q[1] >> 1 | q[2] | q[2] >> 1 | q[3] | q[3] >> 1;
        const unsigned all =
            q[0] & q[0] >> 1 & q[1] & q[1] >> 1 & q[2] & q[2] >> 1 & q[3] & q[3] >> 1;
        unsigned mixed = any & ~all & 0xFFu;
        if (!mixed) continue;
        const unsigned l[4] = {leaf[r], leaf[r + kC], leaf[r + 1], leaf[r + kC + 1]};
        const unsigned touch =
            l[0] | l[0] >> 1 | l[1] | l[1] >> 1 | l[2] | l[2] >> 1 | l[3] | l[3] >> 1;
        const unsigned full =
            l[0] & l[0] >> 1 & l[1] & l[1] >> 1 & l[2] & l[2] >> 1 & l[3] & l[3] >> 1;
        mixed &= touch;
        while (mixed) {
          const int z = std::countr_zero(mixed);
          mixed &= mixed - 1;
          auto corners = [z](const unsigned* rows) {
            unsigned bits = 0;
            for (int c = 0; c < 4; ++c) {
              bits |= ((rows[c] >> z) & 1u) << c | ((rows[c] >> (z + 1)) & 1u) << (c + 4);
            }
            return bits;
          };
          const unsigned cs = corners(q);
          if (!((full >> z) & 1u)) {
            const unsigned lc = corners(l);
            bool bad = false;
            for (const EdgeInfo& e : edges) {
              bad = bad ||
                    ((((cs >> e.c0) ^ (cs >> e.c1)) & 1u) && !(((lc >> e.c0) | (lc >> e.c1)) & 1u));
            }
            if (bad) {
              ++skipped;
              continue;
            }
          }
          const CaseTable::Case& c = table.at(cs);
          unsigned vb = 0;
          if (c.ambiguous) {
            double cv[8];
            for (int k = 0; k < 8; ++k) {
              cv[k] =
                  static_cast<double>(value(x + (k & 1), y + ((k >> 1) & 1), z + ((k >> 2) & 1)));
            }
            for (unsigned a = 0; a < c.ambiguous; ++a) {
              const auto& f = faces[c.faces[a]];
              if (above_connected(cv[f[0]], cv[f[1]], cv[f[2]], cv[f[3]], iso)) vb |= 1u << a;
            }
          }
          fn(x, y, z, c, table.variant(c, vb));
        }
      }
    }
    return skipped;
  }
};

/// SparseBlock origins as integers ordered like (x, y, z) lexicographically, so that offsets by whole
/// blocks are additions (the coordinates are multiples of 8 in int32, biased to unsigned).
__extension__ typedef unsigned __int128 CoordKey;

CoordKey key_of(const Coord& c) {
  auto u = [](int v) { return static_cast<CoordKey>(static_cast<std::uint32_t>(v) ^ 0x80000000u); };
  return u(c.x()) << 64 | u(c.y()) << 32 | u(c.z());
}

Coord coord_of(CoordKey k) {
  auto s = [](CoordKey v) { return static_cast<int>(static_cast<std::uint32_t>(v) ^ 0x80000000u); };
  return {s(k >> 64), s(k >> 32), s(k)};
}

/// CoordKey offset of the block at +8 (d & 1, (d >> 1) & 1, (d >> 2) & 1). Adding or subtracting it
/// never carries between the fields while the coordinates stay within int32.
constexpr CoordKey neighbour_key(std::size_t d) {
  return static_cast<CoordKey>(8 * (d & 1)) << 64 | static_cast<CoordKey>(8 * ((d >> 1) & 1)) << 32 |
         static_cast<CoordKey>(8 * ((d >> 2) & 1));
}
constexpr std::array<CoordKey, 8> kNeighbour = {neighbour_key(0), neighbour_key(1), neighbour_key(2),
                                           neighbour_key(3), neighbour_key(4), neighbour_key(5),
                                           neighbour_key(6), neighbour_key(7)};

class VdbContourer {
 public:
  VdbContourer(const openvdb::FloatGrid& grid, const UniformTransform& map, const ContourOptions& options)
      : tree_(grid.tree()), map_(map), opt_(options) {}

  // Setup: the visited blocks, their neighbours and value sources.
  void build_blocks() {
    std::vector<CoordKey> leaves;
    leaves.reserve(static_cast<std::size_t>(tree_.leafCount()));
    for (auto it = tree_.cbeginLeaf(); it; ++it) leaves.push_back(key_of(it->origin()));
    leaves_ = leaves.size();
    std::vector<CoordKey> keys(8 * leaves.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 1024),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t l = r.begin(); l != r.end(); ++l) {
                          for (std::size_t d = 0; d < 8; ++d)
                            keys[8 * l + d] = leaves[l] - kNeighbour[d];
                        }
                      });
    std::vector<CoordKey>().swap(leaves);
    tbb::parallel_sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    blocks_.resize(keys.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, keys.size(), 256),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        Accessor acc(tree_);
                        for (std::size_t b = r.begin(); b != r.end(); ++b) {
                          SparseBlock& blk = blocks_[b];
                          blk.origin = coord_of(keys[b]);
                          blk.self = source(acc, blk.origin);
                          blk.nb[0] = static_cast<std::int32_t>(b);
                          for (std::size_t d = 1; d < 8; ++d) {
                            // Neighbours come later in the order; +z is usually the next block.
                            const CoordKey k = keys[b] + kNeighbour[d];
                            auto it = keys.begin() + static_cast<std::ptrdiff_t>(b) + 1;
                            if (it != keys.end() && *it != k)
                              it = std::lower_bound(it, keys.end(), k);
                            const bool found = it != keys.end() && *it == k;
                            blk.nb[d] = found ? static_cast<std::int32_t>(it - keys.begin()) : -1;
                            blk.outside[d] = found ? 0.0f : acc.getValue(coord_of(k));
                          }
                        }
                      });
  }

  [[nodiscard]] std::size_t leaves() const { return leaves_; }
  [[nodiscard]] std::size_t blocks() const { return blocks_.size(); }

  void set_isovalue(double iso) {
    iso_ = iso;
    float f = static_cast<float>(iso);
    if (static_cast<double>(f) < iso) f = std::nextafter(f, std::numeric_limits<float>::infinity());
    threshold_ = f;  // v >= threshold_ exactly when double(v) >= iso
  }

  // Pass 1: classification of every block's voxels, then edge masks and counts per block.
  void count(const ProgressCallback& progress) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks_.size(), 64),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t b = r.begin(); b != r.end(); ++b) classify(blocks_[b]);
                      });
    parallel_for_range(blocks_.size(), 16, [&](std::size_t begin, std::size_t end) {
      Neighbourhood nh;
      for (std::size_t b = begin; b != end; ++b) count_block(nh, b);
    }, progress, "contour");
  }

  struct Totals {
    Index points = 0, tris = 0;
    std::size_t ambiguous = 0, skipped = 0;
  };

  // Pass 2: prefix sums.
  Totals offsets() {
    point_offset_.resize(blocks_.size() + 1);
    tri_offset_.resize(blocks_.size() + 1);
    Totals t;
    for (std::size_t b = 0; b < blocks_.size(); ++b) {
      const SparseBlock& blk = blocks_[b];
      point_offset_[b] = t.points;
      tri_offset_[b] = t.tris;
      t.points += static_cast<Index>(blk.edge_points + blk.centers);
      t.tris += static_cast<Index>(blk.tris);
      t.ambiguous += blk.ambiguous;
      t.skipped += blk.skipped;
    }
    point_offset_.back() = t.points;
    tri_offset_.back() = t.tris;
    return t;
  }

  // Pass 3: points, attributes and triangles.
  void generate(float* pts, float* scalars, float* normals, Index* conn,
                const ProgressCallback& progress) {
    pts_ = pts;
    scalars_ = scalars;
    normals_ = normals;
    conn_ = conn;
    parallel_for_range(blocks_.size(), 16, [&](std::size_t begin, std::size_t end) {
      Accessor acc(tree_);
      Neighbourhood nh;
      for (std::size_t b = begin; b != end; ++b) generate_block(acc, nh, b);
    }, progress, "contour");
  }

 private:
  static SparseSource source(Accessor& acc, const Coord& origin) {
    if (const Leaf* leaf = acc.probeConstLeaf(origin)) return {leaf->buffer().data(), 0.0f};
    return {nullptr, acc.getValue(origin)};  // a tile's or the background value
  }

  void classify(SparseBlock& blk) const {
    if (!blk.self.data) {
      blk.above = blk.self.value >= threshold_ ? kAllAbove : kAllBelow;
      return;
    }
    const float* v = blk.self.data;
#if defined(__SSE2__)
    const __m128 t = _mm_set1_ps(threshold_);
    for (std::size_t w = 0; w < 8; ++w, v += 64) {
      Word bits = 0;
      for (int q = 0; q < 16; ++q) {  // ordered compare: NaN is below
        bits |= static_cast<Word>(_mm_movemask_ps(_mm_cmpge_ps(_mm_loadu_ps(v + 4 * q), t)))
                << (4 * q);
      }
      blk.above[w] = bits;
    }
#else
    for (std::size_t w = 0; w < 8; ++w, v += 64) {
      Word bits = 0;
      for (int q = 0; q < 64; ++q) bits |= static_cast<Word>(v[q] >= threshold_) << q;
      blk.above[w] = bits;
    }
#endif
  }

  // The neighbourhood of block b: rows, and sources for d ∈ {0, 1}³ (and d ∈ {-1, 0, 1}³ with
  // a margin, read through the accessor).
  void neighbourhood(std::size_t b, Neighbourhood& nh, Accessor* margin) const {
    const SparseBlock& blk = blocks_[b];
    std::array<const Word*, 8> ab;
    std::array<bool, 8> is_leaf;
    for (std::size_t d = 0; d < 8; ++d) {
      const std::int32_t n = blk.nb[d];
      SparseSource s;
      if (n >= 0) {
        const SparseBlock& nbk = blocks_[static_cast<std::size_t>(n)];
        s = nbk.self;
        ab[d] = nbk.above.data();
      } else {
        s = {nullptr, blk.outside[d]};
        ab[d] = s.value >= threshold_ ? kAllAbove.data() : kAllBelow.data();
      }
      is_leaf[d] = s.data != nullptr;
      nh.src[(d & 1) + 1 + 3 * (((d >> 1) & 1) + 1) + 9 * (((d >> 2) & 1) + 1)] = s;
    }
    nh.fill_rows(ab, is_leaf);
    if (!margin) return;
    for (int dz = -1; dz <= 1; ++dz) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          if (dx >= 0 && dy >= 0 && dz >= 0) continue;
          nh.src[static_cast<std::size_t>(dx + 1 + 3 * (dy + 1) + 9 * (dz + 1))] =
              source(*margin, blk.origin.offsetBy(kB * dx, kB * dy, kB * dz));
        }
      }
    }
  }

  void count_block(Neighbourhood& nh, std::size_t b) {
    SparseBlock& blk = blocks_[b];
    blk.mask.fill(0);
    blk.edge_points = blk.centers = blk.tris = blk.ambiguous = blk.skipped = 0;
    // Nothing crosses when every corner is on one side.
    bool uniform = true;
    const Word first = blk.above[0] & 1u ? ~Word{0} : 0;
    for (std::size_t d = 0; d < 8 && uniform; ++d) {
      const std::int32_t n = blk.nb[d];
      if (n >= 0) {
        for (const Word w : blocks_[static_cast<std::size_t>(n)].above)
          uniform = uniform && w == first;
      } else {
        uniform = uniform && (blk.outside[d] >= threshold_) == (first != 0);
      }
    }
    if (uniform) {
      blk.rank.fill(0);
      return;
    }
    neighbourhood(b, nh, nullptr);
    for (int x = 0; x < kB; ++x) {
      for (int y = 0; y < kB; ++y) {
        const auto r = static_cast<std::size_t>(kC * x + y);
        const unsigned a = nh.above[r], l = nh.leaf[r];
        const unsigned ex = (a ^ nh.above[r + kC]) & (l | nh.leaf[r + kC]) & 0xFFu;
        const unsigned ey = (a ^ nh.above[r + 1]) & (l | nh.leaf[r + 1]) & 0xFFu;
        const unsigned ez = (a ^ a >> 1) & (l | l >> 1) & 0xFFu;
        const int sh = kB * y;
        blk.mask[static_cast<std::size_t>(x)] |= static_cast<Word>(ex) << sh;
        blk.mask[static_cast<std::size_t>(8 + x)] |= static_cast<Word>(ey) << sh;
        blk.mask[static_cast<std::size_t>(16 + x)] |= static_cast<Word>(ez) << sh;
      }
    }
    std::uint32_t p = 0;
    for (std::size_t w = 0; w < 24; ++w) {
      blk.rank[w] = static_cast<std::uint16_t>(p);
      p += static_cast<std::uint32_t>(std::popcount(blk.mask[w]));
    }
    blk.edge_points = p;
    blk.skipped = nh.for_each_cell(
        iso_, [&](int, int, int, const CaseTable::Case& c, const CaseTable::Variant& var) {
          blk.tris += var.triangles;
          blk.centers += var.centers;
          blk.ambiguous += c.ambiguous;
        });
  }

  // Central differences in world units at local voxel (x, y, z) (needs the margin).
  Vec3 gradient(const Neighbourhood& nh, int x, int y, int z) const {
    const double d = 2.0 * map_.voxel_size;
    return {
        (static_cast<double>(nh.value(x + 1, y, z)) - static_cast<double>(nh.value(x - 1, y, z))) /
            d,
        (static_cast<double>(nh.value(x, y + 1, z)) - static_cast<double>(nh.value(x, y - 1, z))) /
            d,
        (static_cast<double>(nh.value(x, y, z + 1)) - static_cast<double>(nh.value(x, y, z - 1))) /
            d};
  }

  void write_normal(Index id, Vec3 g) const {
    const double len = norm(g);
    g = len > 0 ? g / len : Vec3{0, 0, 0};
    if (opt_.flip) g = -g;
    float* n = normals_ + 3 * id;
    n[0] = static_cast<float>(g.x);
    n[1] = static_cast<float>(g.y);
    n[2] = static_cast<float>(g.z);
  }

  void generate_block(Accessor& acc, Neighbourhood& nh, std::size_t b) const {
    const SparseBlock& blk = blocks_[b];
    const Index base = point_offset_[b];
    const Index tri_begin = tri_offset_[b], tri_end = tri_offset_[b + 1];
    if (point_offset_[b + 1] == base && tri_end == tri_begin) return;
    neighbourhood(b, nh, normals_ ? &acc : nullptr);
    const Coord& o = blk.origin;
    // Points on the crossed edges owned by the block's voxels.
    Index p = base;
    for (int a = 0; a < 3; ++a) {
      for (int x = 0; x < kB; ++x) {
        Word mk = blk.mask[static_cast<std::size_t>(8 * a + x)];
        while (mk) {
          const int bit = std::countr_zero(mk);
          mk &= mk - 1;
          const int y = bit >> 3, z = bit & 7;
          const int x1 = x + (a == 0), y1 = y + (a == 1), z1 = z + (a == 2);
          const double v0 = static_cast<double>(nh.value(x, y, z));
          const double v1 = static_cast<double>(nh.value(x1, y1, z1));
          const double t = crossing(v0, v1, iso_);
          const std::int64_t g[3] = {static_cast<std::int64_t>(o.x()) + x,
                                     static_cast<std::int64_t>(o.y()) + y,
                                     static_cast<std::int64_t>(o.z()) + z};
          float* q = pts_ + 3 * p;
          for (int c = 0; c < 3; ++c) {
            // As the dense contour: coordinate(i) + t * h along the edge.
            const double w =
                c == a ? map_.coordinate(c, g[c]) + t * map_.voxel_size : map_.coordinate(c, g[c]);
            q[c] = static_cast<float>(w);
          }
          if (scalars_) {
            double v = 0;  // the sums of AttributeInterpolator
            v += (1.0 - t) * v0;
            v += t * v1;
            scalars_[p] = static_cast<float>(v);
          }
          if (normals_) {
            const Vec3 ga = gradient(nh, x, y, z), gb = gradient(nh, x1, y1, z1);
            write_normal(p, ga + (gb - ga) * t);
          }
          ++p;
        }
      }
    }
    check_invariant(p == base + static_cast<Index>(blk.edge_points), "block edge points = count");
    // Cell-interior points and triangles.
    const CaseTable& table = voxel_table();
    const auto& edges = edge_info();
    Index center = p;
    Index tri = tri_begin;
    (void)nh.for_each_cell(iso_, [&](int x, int y, int z, const CaseTable::Case&,
                                     const CaseTable::Variant& var) {
      for (unsigned q = 0; q < var.centers; ++q) {
        emit_center(nh, o, center + static_cast<Index>(q), table.center_edges(var, q), x, y, z);
      }
      const auto tri_edges = table.triangles(var);
      Index* out = conn_ + 3 * tri;
      for (std::size_t e = 0; e < tri_edges.size(); ++e) {
        const unsigned edge = tri_edges[e];
        if (edge >= 12) {
          out[e] = center + static_cast<Index>(edge - 12);
          continue;
        }
        const EdgeInfo& ei = edges[edge];
        // The voxel owning the edge (its lower end) and the block it lies in.
        const int vx = x + (ei.c0 & 1), vy = y + ((ei.c0 >> 1) & 1), vz = z + ((ei.c0 >> 2) & 1);
        const int d = (vx >> 3) | (vy >> 3) << 1 | (vz >> 3) << 2;
        const std::int32_t ob = blk.nb[static_cast<std::size_t>(d)];
        check_invariant(ob >= 0, "the owner block of an edge exists");
        const SparseBlock& owner = blocks_[static_cast<std::size_t>(ob)];
        const auto w = static_cast<std::size_t>(8 * ei.axis + (vx & 7));
        const int bit = 8 * (vy & 7) + (vz & 7);
        out[e] = point_offset_[static_cast<std::size_t>(ob)] + owner.rank[w] +
                 std::popcount(owner.mask[w] & ((Word{1} << bit) - 1));
      }
      tri += var.triangles;
      center += var.centers;
    });
    check_invariant(tri == tri_end, "block triangles = count");
    check_invariant(center == point_offset_[b + 1], "block points = count");
  }

  // A point inside cell (x, y, z): the mean of the crossings on `edges`, computed exactly like
  // the dense contour's.
  void emit_center(const Neighbourhood& nh, const Coord& o, Index id,
                   std::span<const std::uint8_t> edges, int x, int y, int z) const {
    const auto& topo = voxel_table().topology();
    Vec3 p{0, 0, 0}, g{0, 0, 0};
    double v = 0;
    const double w = 1.0 / static_cast<double>(edges.size());
    for (const std::uint8_t e : edges) {
      const int c0 = topo.edges[e][0], c1 = topo.edges[e][1];
      const int x0 = x + (c0 & 1), y0 = y + ((c0 >> 1) & 1), z0 = z + ((c0 >> 2) & 1);
      const int x1 = x + (c1 & 1), y1 = y + ((c1 >> 1) & 1), z1 = z + ((c1 >> 2) & 1);
      const double v0 = static_cast<double>(nh.value(x0, y0, z0));
      const double v1 = static_cast<double>(nh.value(x1, y1, z1));
      const double t = crossing(v0, v1, iso_);
      const Vec3 a = point(o, x0, y0, z0), b = point(o, x1, y1, z1);
      p += (a + (b - a) * t) * w;
      v += (1 - t) * w * v0;
      v += t * w * v1;
      if (normals_) {
        const Vec3 ga = gradient(nh, x0, y0, z0), gb = gradient(nh, x1, y1, z1);
        g += (ga + (gb - ga) * t) * w;
      }
    }
    float* q = pts_ + 3 * id;
    q[0] = static_cast<float>(p.x);
    q[1] = static_cast<float>(p.y);
    q[2] = static_cast<float>(p.z);
    if (scalars_) scalars_[id] = static_cast<float>(v);
    if (normals_) write_normal(id, g);
  }

  [[nodiscard]] Vec3 point(const Coord& o, int x, int y, int z) const {
    return {map_.coordinate(0, static_cast<std::int64_t>(o.x()) + x),
            map_.coordinate(1, static_cast<std::int64_t>(o.y()) + y),
            map_.coordinate(2, static_cast<std::int64_t>(o.z()) + z)};
  }

  const Tree& tree_;
  UniformTransform map_;
  const ContourOptions& opt_;
  std::vector<SparseBlock> blocks_;
  std::vector<Index> point_offset_, tri_offset_;
  std::size_t leaves_ = 0;
  double iso_ = 0;
  float threshold_ = 0;
  float* pts_ = nullptr;
  float* scalars_ = nullptr;
  float* normals_ = nullptr;
  Index* conn_ = nullptr;
};

}  // namespace

VdbContourResult contour_vdb(const openvdb::FloatGrid& grid, const ContourOptions& options) {
  ensure_openvdb_initialized();
  const std::string name = grid.getName().empty() ? std::string("Scalars") : grid.getName();
  const std::string what = "contour_vdb: grid '" + name + "'";
  check_values(options, what.c_str());
  if (!options.array.empty() && options.array != name) {
    throw Error(what + ": no point array named '" + options.array + "' (the grid's values are '" +
                name + "')");
  }
  const UniformTransform map = uniform_transform(grid, what);

  VdbContourer c(grid, map, options);
  c.build_blocks();
  VdbContourResult r;
  VdbContourStats& local = r.stats;
  local.leaves = c.leaves();
  local.blocks = c.blocks();
  const bool gradient = options.normals == ContourNormals::Gradient;
  r.output = contour_each_value(options, local, [&](std::size_t v, const ProgressCallback& progress) {
    c.set_isovalue(options.values[v]);
    c.count(progress_range(progress, 0.0, 0.4));
    const auto totals = c.offsets();
    const auto npts = static_cast<std::size_t>(totals.points);
    const auto ntris = static_cast<std::size_t>(totals.tris);
    PolyData part = triangle_output(npts, ntris);
    Index* offsets = part.polys.offsets().data();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, ntris + 1, std::size_t{1} << 16),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t t = r.begin(); t != r.end(); ++t) {
                          offsets[t] = static_cast<Index>(3 * t);
                        }
                      });
    DataArray scalars, normals;
    if (options.interpolate_attributes) {
      scalars = DataArray::uninitialized(name, ScalarType::Float32, 1, npts);
    }
    if (gradient) normals = DataArray::uninitialized("Normals", ScalarType::Float32, 3, npts);
    c.generate(part.points.floats().data(),
               options.interpolate_attributes ? scalars.values<float>().data() : nullptr,
               gradient ? normals.values<float>().data() : nullptr,
               part.polys.connectivity().data(), progress_range(progress, 0.4, 1.0));
    if (options.interpolate_attributes)
      part.point_data.add(std::move(scalars), AttributeRole::Scalars);
    if (gradient) part.point_data.add(std::move(normals), AttributeRole::Normals);
    local.points += npts;
    local.cells += ntris;
    local.ambiguous_faces += totals.ambiguous;
    local.skipped_cells += totals.skipped;
    return part;
  });
  return r;
}

}  // namespace isoforge
