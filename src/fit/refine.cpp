// Mesh refinement: the vertex-position optimisation and the edge swaps of
//   H. Hoppe, T. DeRose, T. Duchamp, J. McDonald, W. Stuetzle, "Mesh optimization",
//   SIGGRAPH 1993 —
// without its edge collapses and splits (the triangle count stays). Each outer iteration fixes, for
// every sample x of the original, its closest point on the current mesh (a triangle and barycentric
// coordinates b), and for samples y of the current mesh their closest point on the original (a
// point and the normal of its triangle); the energy
//   Σ |x − Σ b_k v_k|² + Σ (n · (Σ b_k v_k − y'))² + κ Σ_edges |v_i − v_j|²
// is then linear least squares in the vertex positions, solved by Ceres. The second term (point
// to plane, as in
//   Y. Chen, G. Medioni, "Object modelling by registration of multiple range images", 1992)
// pulls the parts of the mesh that no sample of the original reaches, so the Hausdorff distance
// falls too. The error is measured on as many samples of the simplified mesh as of the original;
// the energy's second term uses those dense samples and 4 per triangle in alternate solves (the
// dense ones follow the surface closely, the sparse ones pull less against each other where the
// original is thin). After each solve_positions, moves that turn a face by more than 90° or make
// two faces intersect (exact predicates, core/predicates.hpp) are shortened, then undone, vertex by
// vertex until the neighbourhood is clean, and a step that raises the RMS or Hausdorff error is
// halved, then dropped. Before every other solve, a pass of edge flips (flip_edges) lowers the
// error where a pair of faces is better split along its other diagonal. Method and
// measurements: docs/algorithms/fitting.md.

#include "isoforge/fit/refine.hpp"

#include <ceres/ceres.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <numeric>
#include <optional>
#include <tuple>
#include <vector>

#include "fit/detail/fit_ops.hpp"
#include "fit/robust_constants.hpp"
#include "isoforge/core/closest_point.hpp"
#include "isoforge/core/mesh_topology.hpp"
#include "isoforge/core/parallel.hpp"
#include "isoforge/core/predicates.hpp"
#include "isoforge/spatial/primitive_locator.hpp"
#include "isoforge/spatial/self_intersections.hpp"

namespace isoforge {
namespace {

using Id = std::uint32_t;
using Tri = std::array<Id, 3>;
using Clock = std::chrono::steady_clock;

using fit_detail::kCauchyK;
using fit_detail::kHuberK;
using fit_detail::kMadToSigma;
constexpr int kAutoSamplesPerTriangle = 10;
constexpr double kStepScales[2] = {1, 0.5};  // a worse step is retried at half its length
constexpr int kLocalUndoRounds = 2;  // rounds of undoing the vertices that raise the maximum

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// ---- samples of the simplified mesh (the reverse term) ----

using Bary = std::array<double, 3>;

// The centroids of the n² triangles of the level-n subdivision of a triangle, as barycentric
// coordinates: stratified over the triangle, none on an edge.
std::vector<Bary> subdivision_centroids(int n) {
  std::vector<Bary> out;
  const double inv = 1.0 / n;
  for (int i = 0; i < n; ++i)
    for (int j = 0; i + j < n; ++j) {
      const double u = (i + 1.0 / 3) * inv, v = (j + 1.0 / 3) * inv;
      out.push_back({1 - u - v, u, v});
      if (i + j + 2 <= n) {
        const double u2 = (i + 2.0 / 3) * inv, v2 = (j + 2.0 / 3) * inv;
        out.push_back({1 - u2 - v2, u2, v2});
      }
    }
  return out;
}

// The nodes of the level-n grid of a triangle (i/n, j/n; corners, edge points and interior
// points), with the weights of the composite vertex rule: a node gets a third of the area of
// each small triangle around it (corner 1/3, edge 1, interior 2, scaled to a mean of 1), so the
// weighted samples measure the triangle by area, as far as its corners.
void grid_nodes(int n, std::vector<Bary>& bary, std::vector<double>& weight) {
  const double count = (n + 1.0) * (n + 2.0) / 2;
  const double scale = count / (double(n) * n);  // the raw weights sum to n²
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      const int k = n - i - j;
      const int zeros = (i == 0) + (j == 0) + (k == 0);
      const double raw = zeros >= 2 ? 1.0 / 3 : (zeros == 1 ? 1.0 : 2.0);
      bary.push_back({double(k) / n, double(i) / n, double(j) / n});
      weight.push_back(raw * scale);
    }
}

// The samples of the simplified mesh, the same in every triangle: 4 stratified points for the
// sparse energy, and grid nodes for the error measure and the dense energy, about as many as
// the original has samples (at least 6 per triangle, at most 45), so both directions of the
// error are seen with the same density.
struct ReverseSamples {
  std::vector<Bary> bary;
  std::vector<double> weight;
  std::size_t energy_begin = 0, energy_end = 0;    // the samples of the sparse energy
  std::size_t measure_begin = 0, measure_end = 0;  // the samples of the measure (dense energy)
  std::vector<std::size_t> nearest_node;           // per sparse sample, the nearest measure sample
  std::vector<std::array<int, 3>> nodes;  // per measure sample, its coordinates × the level
};

// The measure samples that neighbouring triangles share — a corner is a vertex, a node on an
// edge lies on both its triangles — for one set of triangles: each such point is queried once.
// The same point comes out of either triangle's formula bit for bit (the weights are the same
// quotients, the third term is a zero and addition commutes), so its answer is the same.
struct SharedNodes {
  static constexpr std::uint32_t kVertex = 0x80000000u;  // `of` holds a vertex id
  std::vector<Tri> tris;                                 // the triangles they were found for
  std::vector<std::uint32_t> of;  // per (triangle, measure sample): kVertex | v, or an owner
  std::vector<std::array<std::uint32_t, 2>> owners;  // (triangle, sample) querying a point
};

SharedNodes shared_nodes(const std::vector<Tri>& tris, const ReverseSamples& rs) {
  SharedNodes sn;
  sn.tris = tris;
  const std::size_t per = rs.measure_end - rs.measure_begin;
  sn.of.resize(tris.size() * per);
  struct EdgeNode {
    Id a, b;
    int ma;
    std::uint32_t at;  // index in `of`
  };
  std::vector<EdgeNode> edge_nodes;
  for (std::size_t f = 0; f < tris.size(); ++f) {
    for (std::size_t j = 0; j < per; ++j) {
      const std::array<int, 3>& c = rs.nodes[j];
      const int zeros = (c[0] == 0) + (c[1] == 0) + (c[2] == 0);
      const auto at = std::uint32_t(f * per + j);
      if (zeros == 2) {
        const int s = c[0] != 0 ? 0 : (c[1] != 0 ? 1 : 2);
        sn.of[at] = SharedNodes::kVertex | tris[f][s];
      } else if (zeros == 1) {
        const int s1 = c[0] == 0 ? 1 : 0, s2 = c[2] == 0 ? 1 : 2;
        Id a = tris[f][s1], b = tris[f][s2];
        int ma = c[s1];
        if (a > b) {
          std::swap(a, b);
          ma = c[s2];
        }
        edge_nodes.push_back({a, b, ma, at});
      } else {
        sn.of[at] = std::uint32_t(sn.owners.size());
        sn.owners.push_back({std::uint32_t(f), std::uint32_t(rs.measure_begin + j)});
      }
    }
  }
  std::sort(edge_nodes.begin(), edge_nodes.end(), [](const EdgeNode& x, const EdgeNode& y) {
    return std::tie(x.a, x.b, x.ma, x.at) < std::tie(y.a, y.b, y.ma, y.at);
  });
  for (std::size_t i = 0; i < edge_nodes.size(); ++i) {
    const EdgeNode& e = edge_nodes[i];
    if (i == 0 || e.a != edge_nodes[i - 1].a || e.b != edge_nodes[i - 1].b ||
        e.ma != edge_nodes[i - 1].ma) {
      sn.owners.push_back(
          {std::uint32_t(e.at / per), std::uint32_t(rs.measure_begin + e.at % per)});
    }
    sn.of[e.at] = std::uint32_t(sn.owners.size() - 1);
  }
  if (sn.owners.size() >= SharedNodes::kVertex || tris.size() * per >= SharedNodes::kVertex) {
    throw Error("refine_mesh: too many samples of the simplified mesh");
  }
  return sn;
}

ReverseSamples reverse_samples(std::size_t forward_samples, std::size_t triangles) {
  const double per = double(forward_samples) / double(std::max<std::size_t>(triangles, 1));
  int level = 2;
  while (level < 8 && (level + 1.0) * (level + 2.0) / 2 < per) ++level;
  ReverseSamples r;
  r.bary = subdivision_centroids(2);
  r.weight.assign(r.bary.size(), 1.0);
  r.energy_end = r.bary.size();
  r.measure_begin = r.bary.size();
  grid_nodes(level, r.bary, r.weight);
  r.measure_end = r.bary.size();
  for (std::size_t k = r.measure_begin; k < r.measure_end; ++k) {
    std::array<int, 3> c{};
    for (int s = 0; s < 3; ++s)
      c[std::size_t(s)] = int(std::lround(r.bary[k][std::size_t(s)] * level));
    r.nodes.push_back(c);
  }
  for (std::size_t k = r.energy_begin; k < r.energy_end; ++k) {
    std::size_t best = r.measure_begin;
    double best_d = 1e300;
    for (std::size_t j = r.measure_begin; j < r.measure_end; ++j) {
      const double d = std::pow(r.bary[k][0] - r.bary[j][0], 2) +
                       std::pow(r.bary[k][1] - r.bary[j][1], 2) +
                       std::pow(r.bary[k][2] - r.bary[j][2], 2);
      if (d < best_d) {
        best_d = d;
        best = j;
      }
    }
    r.nearest_node.push_back(best);
  }
  return r;
}

// ---- inputs ----

std::vector<Vec3> finite_points(const PolyData& pd, const char* what) {
  std::vector<Vec3> v(pd.points.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    v[i] = pd.points[i];
    if (!is_finite(v[i]))
      throw Error(std::string("refine_mesh: ") + what + ": point " + std::to_string(i) +
                  " is not finite");
  }
  return v;
}

std::vector<Tri> original_triangles(const PolyData& pd) {
  pd.validate();
  std::vector<Tri> out;
  for (const auto& t : triangulate_faces(pd)) {
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;  // no area, nothing to sample
    out.push_back({Id(t[0]), Id(t[1]), Id(t[2])});
  }
  if (out.empty()) throw Error("refine_mesh: original: has no triangles");
  return out;
}

std::vector<Tri> simplified_triangles(const PolyData& pd) {
  pd.validate();
  if (pd.strips.size() != 0)
    throw Error("refine_mesh: simplified: has triangle strips; only triangles are refined");
  if (pd.points.size() >= std::size_t(UINT32_MAX))
    throw Error("refine_mesh: simplified: too many points");
  std::vector<Tri> out;
  const Index first = Index(pd.verts.size() + pd.lines.size());
  for (std::size_t c = 0; c < pd.polys.size(); ++c) {
    const auto ids = pd.polys.cell(c);
    if (ids.size() != 3) {
      throw Error("refine_mesh: simplified: cell " + std::to_string(first + Index(c)) + " has " +
                  std::to_string(ids.size()) + " points; only triangles are refined");
    }
    if (ids[0] == ids[1] || ids[1] == ids[2] || ids[0] == ids[2]) {
      throw Error("refine_mesh: simplified: triangle " + std::to_string(first + Index(c)) +
                  " repeats a point");
    }
    out.push_back({Id(ids[0]), Id(ids[1]), Id(ids[2])});
  }
  if (out.empty()) throw Error("refine_mesh: simplified: has no triangles");
  return out;
}

// Vertices that never move: locked by the mask, on the border (keep_boundary), on a non-manifold
// edge. Only vertices of triangles take part at all.
std::vector<char> fixed_vertices(const PolyData& s, const std::vector<Tri>& tris,
                                 const RefineOptions& o) {
  std::vector<char> fixed(s.points.size(), 0);
  if (!o.lock_array.empty()) {
    const DataArray* a = s.point_data.find(o.lock_array);
    if (!a) throw Error("refine_mesh: lock_array '" + o.lock_array + "' is not a point array");
    if (a->components() != 1)
      throw Error("refine_mesh: lock_array '" + o.lock_array + "' has " +
                  std::to_string(a->components()) + " components; it needs 1");
    for (std::size_t i = 0; i < fixed.size(); ++i) fixed[i] = a->get(i) != 0;
  }
  if (o.keep_boundary) {
    std::vector<std::pair<std::uint64_t, int>> edges;  // (key, count) after sorting
    std::vector<std::uint64_t> keys;
    keys.reserve(3 * tris.size());
    for (const Tri& t : tris)
      for (int k = 0; k < 3; ++k) {
        const Id a = std::min(t[k], t[(k + 1) % 3]), b = std::max(t[k], t[(k + 1) % 3]);
        keys.push_back((std::uint64_t(a) << 32) | b);
      }
    std::sort(keys.begin(), keys.end());
    for (std::size_t i = 0; i < keys.size();) {
      std::size_t j = i;
      while (j < keys.size() && keys[j] == keys[i]) ++j;
      if (j - i != 2) {  // a border (1 face) or a non-manifold edge (3 or more)
        fixed[keys[i] >> 32] = 1;
        fixed[keys[i] & 0xffffffffu] = 1;
      }
      i = j;
    }
  }
  return fixed;
}

// ---- samples ----

// `count` points spread over the triangles by area (systematic sampling of the cumulative
// area; inside a triangle, the points of the R2 low-discrepancy sequence folded into it).
void area_samples(const std::vector<Vec3>& v, const std::vector<Tri>& tris, std::size_t count,
                  std::vector<Vec3>& out) {
  if (count == 0) return;
  std::vector<double> cum(tris.size());
  double total = 0;
  for (std::size_t t = 0; t < tris.size(); ++t) {
    const Vec3 &a = v[tris[t][0]], &b = v[tris[t][1]], &c = v[tris[t][2]];
    total += 0.5 * norm(cross(b - a, c - a));
    cum[t] = total;
  }
  if (!(total > 0)) return;
  constexpr double kG = 1.32471795724474602596;  // the plastic number: R2 sequence
  const double a1 = 1 / kG, a2 = 1 / (kG * kG);
  const double step = total / double(count);
  std::size_t t = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const double at = (double(i) + 0.5) * step;
    while (t + 1 < tris.size() && cum[t] < at) ++t;
    double u = std::fmod(0.5 + a1 * double(i + 1), 1.0),
           w = std::fmod(0.5 + a2 * double(i + 1), 1.0);
    if (u + w > 1) {
      u = 1 - u;
      w = 1 - w;
    }
    const Vec3 &a = v[tris[t][0]], &b = v[tris[t][1]], &c = v[tris[t][2]];
    out.push_back(a + u * (b - a) + w * (c - a));
  }
}

// ---- correspondences and the error they measure ----

struct Forward {  // a sample of the original and its closest point on the current mesh
  Id tri = 0;
  double b[3] = {1, 0, 0};
  double dist2 = 0;
};
struct Reverse {  // a sample of the current mesh and its closest point on the original
  Vec3 target;
  Vec3 normal;
  double dist2 = 0;
  Id tri = 0;  // the original's triangle
};
struct Measure {
  std::vector<Forward> fwd;
  std::vector<Reverse> rev;
  std::vector<Reverse> vert;  // each vertex of a triangle and its closest point on the original
  bool sparse = false;        // whether rev holds the sparse energy samples too
  // Each triangle's area over the mean: a triangle's samples weigh by its area, so the
  // reverse term measures the surface by area whatever the triangle sizes.
  std::vector<double> area;
  double rms = 0, hausdorff = 0;
};

// Nearest-triangle queries that start from a nearby answer: the triangles also sit in a grid
// of cells about twice their mean edge long, and a query whose ball (about its candidate) fits
// in a cell looks at the few triangles there instead of walking the tree from its root. The
// answer is the locator's: the lowest (squared distance, id).
// The triangles `ids` of `tris` (over `v`; not empty) in a grid of cells about twice their mean
// edge long.
std::unique_ptr<TriangleGrid> triangle_grid(const std::vector<Vec3>& v,
                                            const std::vector<Tri>& tris,
                                            const std::vector<std::uint32_t>& ids) {
  Bounds b;
  double edge_sum = 0;
  for (std::uint32_t f : ids) {
    for (int k = 0; k < 3; ++k) b.extend(v[tris[f][k]]);
    edge_sum += norm(v[tris[f][1]] - v[tris[f][0]]);
  }
  auto grid = std::make_unique<TriangleGrid>(
      b, triangle_grid_cell_size(b, ids.size(), edge_sum / double(ids.size())));
  for (std::uint32_t f : ids) {
    Bounds tb;
    for (int k = 0; k < 3; ++k) tb.extend(v[tris[f][k]]);
    grid->insert(f, tb.min, tb.max);
  }
  return grid;
}

class NearTriangles {
 public:
  /// `locator` over `set`, or null: then one is built when a query first needs it.
  NearTriangles(const PrimitiveSet& set, const PrimitiveLocator* locator,
                const std::vector<Vec3>& v, const std::vector<Tri>& tris)
      : set_(set), locator_(locator) {
    if (tris.empty()) return;
    std::vector<std::uint32_t> all(tris.size());
    std::iota(all.begin(), all.end(), 0u);
    grid_ = triangle_grid(v, tris, all);
  }

  /// The nearest triangle to y given a candidate `c` (an id and its squared distance).
  void nearest(const Vec3& y, ClosestPrimitive& c) const {
    // (Enlarged a little: the rounding of the root must not shrink the ball.)
    const double r = std::sqrt(c.dist2) * (1 + 1e-9) + 1e-300;
    if (!grid_ || !(r <= grid_->cell_size())) {
      locator().nearest(y, c.dist2, c);
      return;
    }
    const std::size_t tb = set_.triangle_begin();
    const Vec3 d{r, r, r};
    grid_->for_each_candidate(y - d, y + d, [&](std::uint32_t f) {
      const auto id = PrimitiveSet::Id(tb + f);
      const double d2 = set_.dist2(id, y);
      if (d2 < c.dist2 || (d2 == c.dist2 && id < c.id)) {
        c.dist2 = d2;
        c.id = id;
      }
    });
  }

 private:
  const PrimitiveLocator& locator() const {
    if (locator_) return *locator_;
    std::call_once(built_, [this] { own_ = std::make_unique<PrimitiveLocator>(set_); });
    return *own_;
  }

  const PrimitiveSet& set_;
  const PrimitiveLocator* locator_;
  mutable std::once_flag built_;
  mutable std::unique_ptr<PrimitiveLocator> own_;
  std::unique_ptr<TriangleGrid> grid_;
};

struct Original {
  PrimitiveSet set;
  std::unique_ptr<PrimitiveLocator> locator;
  std::unique_ptr<NearTriangles> near;
  std::vector<Vec3> normals;  // unit normal of each triangle (0 if degenerate)

  /// The closest point to y on the original, starting from triangle `*start` when given.
  [[nodiscard]] Reverse closest(const Vec3& y, const Id* start) const {
    const std::size_t tb = set.triangle_begin();
    ClosestPrimitive c;
    if (start) {
      c.id = PrimitiveSet::Id(tb + *start);
      c.dist2 = set.dist2(c.id, y);
      near->nearest(y, c);
    } else {
      c = locator->closest(y);
    }
    const auto& ot = set.triangles()[c.id - tb];
    const auto& ov = set.vertices();
    const TriangleClosest q = closest_on_triangle(y, ov[ot[0]], ov[ot[1]], ov[ot[2]]);
    return {q.point, normals[c.id - tb], q.dist2, Id(c.id - tb)};
  }
};

// The correspondences and errors for positions `pos`. With `prev` (the correspondences of
// nearby positions), each query starts from its previous answer, which prunes most of the tree.
// With `prev_pos` and `prev_tris` too (the positions and triangles `prev` was measured at), the
// answers that cannot have changed are taken over: those of the samples of a triangle whose
// corners are the same points, of a vertex that stayed, and of an original's sample whose
// closest triangle stayed, unless a changed triangle (looked up in a grid of those alone) now
// comes closer. The result is the one a full measure gives (the same (distance, id) order).
// `shared` holds the shared measure samples of `tris` (made again when the triangles differ).
Measure measure(const std::vector<Vec3>& pos, const std::vector<Tri>& tris,
                const std::vector<Vec3>& samples, const ReverseSamples& rs, SharedNodes& shared,
                const std::vector<char>& used, const Original& orig, bool sparse,
                const Measure* prev = nullptr, const std::vector<Vec3>* prev_pos = nullptr,
                const std::vector<Tri>* prev_tris = nullptr) {
  const std::vector<Bary>& rb = rs.bary;
  Measure m;
  m.sparse = sparse;
  m.area.resize(tris.size());
  double area_sum = 0;
  for (std::size_t f = 0; f < tris.size(); ++f) {
    const Vec3 &a = pos[tris[f][0]], &b = pos[tris[f][1]], &c = pos[tris[f][2]];
    m.area[f] = norm(cross(b - a, c - a));
    area_sum += m.area[f];
  }
  if (area_sum > 0)
    for (double& a : m.area) a *= double(tris.size()) / area_sum;
  // Which triangles changed since `prev` (all of them without its positions).
  const bool reuse = prev && prev_pos && prev_tris;
  std::vector<char> changed(tris.size(), 1);
  std::vector<std::uint32_t> changed_ids;
  if (reuse) {
    for (std::size_t f = 0; f < tris.size(); ++f) {
      const Tri& t = tris[f];
      changed[f] = t != (*prev_tris)[f] || pos[t[0]] != (*prev_pos)[t[0]] ||
                   pos[t[1]] != (*prev_pos)[t[1]] || pos[t[2]] != (*prev_pos)[t[2]];
      if (changed[f]) changed_ids.push_back(std::uint32_t(f));
    }
  }
  std::vector<std::array<PrimitiveSet::Id, 3>> t(tris.begin(), tris.end());
  const PrimitiveSet set(pos, {}, {}, std::move(t));
  // From a previous answer through the grid (a tree only if a query needs it), else the tree.
  std::optional<PrimitiveLocator> loc;
  std::optional<NearTriangles> near;
  if (prev) {
    near.emplace(set, nullptr, pos, tris);
  } else {
    loc.emplace(set);
  }
  // The changed triangles alone, for the samples whose closest triangle stayed.
  std::unique_ptr<TriangleGrid> moved;
  if (reuse && !changed_ids.empty()) moved = triangle_grid(pos, tris, changed_ids);
  const std::size_t tb = set.triangle_begin();
  m.fwd.resize(samples.size());
  parallel_for_range(samples.size(), 1024, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      ClosestPrimitive c;
      if (reuse && !changed[prev->fwd[i].tri]) {
        if (changed_ids.empty()) {
          m.fwd[i] = prev->fwd[i];
          continue;
        }
        const Forward& old = prev->fwd[i];
        c.id = PrimitiveSet::Id(tb + old.tri);
        c.dist2 = set.dist2(c.id, samples[i]);  // as the full query compares it
        const double r = std::sqrt(c.dist2) * (1 + 1e-9) + 1e-300;
        const Vec3 d{r, r, r};
        bool closer = false;
        moved->for_each_candidate(samples[i] - d, samples[i] + d, [&](std::uint32_t f) {
          const auto id = PrimitiveSet::Id(tb + f);
          const double d2 = set.dist2(id, samples[i]);
          if (d2 < c.dist2 || (d2 == c.dist2 && id < c.id)) {
            c.dist2 = d2;
            c.id = id;
            closer = true;
          }
        });
        if (!closer) {
          m.fwd[i] = old;
          continue;
        }
      } else if (prev) {
        c.id = tb + prev->fwd[i].tri;
        c.dist2 = set.dist2(c.id, samples[i]);
        near->nearest(samples[i], c);
      } else {
        c = loc->closest(samples[i]);
      }
      const Id f = c.id - tb;
      const Tri& tr = tris[f];
      const TriangleClosest q = closest_on_triangle(samples[i], pos[tr[0]], pos[tr[1]], pos[tr[2]]);
      m.fwd[i] = {f, {1 - q.s - q.t, q.s, q.t}, q.dist2};
    }
  });
  // The vertices (which are the triangles' corner samples too), then each point shared by
  // triangles once, then every triangle's samples.
  m.vert.resize(pos.size());
  parallel_for_range(pos.size(), 1024, [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) {
      if (!used[v]) continue;
      if (reuse && pos[v] == (*prev_pos)[v]) {
        m.vert[v] = prev->vert[v];
        continue;
      }
      m.vert[v] = orig.closest(pos[v], prev ? &prev->vert[v].tri : nullptr);
    }
  });
  if (shared.tris != tris) shared = shared_nodes(tris, rs);
  const std::size_t nr = rb.size(), per = rs.measure_end - rs.measure_begin;
  std::vector<char> needed(shared.owners.size(), reuse ? 0 : 1);
  if (reuse) {
    for (std::uint32_t f : changed_ids) {
      for (std::size_t j = 0; j < per; ++j) {
        const std::uint32_t o = shared.of[f * per + j];
        if ((o & SharedNodes::kVertex) == 0) needed[o] = 1;
      }
    }
  }
  std::vector<Reverse> points(shared.owners.size());
  parallel_for_range(shared.owners.size(), 1024, [&](std::size_t b, std::size_t e) {
    for (std::size_t u = b; u < e; ++u) {
      if (!needed[u]) continue;
      const auto [f, k] = shared.owners[u];
      const Bary& w = rb[k];
      const Vec3 y = w[0] * pos[tris[f][0]] + w[1] * pos[tris[f][1]] + w[2] * pos[tris[f][2]];
      points[u] = orig.closest(y, prev ? &prev->rev[nr * f + k].tri : nullptr);
    }
  });
  m.rev.resize(nr * tris.size());
  parallel_for_range(tris.size(), 256, [&](std::size_t b, std::size_t e) {
    for (std::size_t f = b; f < e; ++f) {
      const std::size_t k0 = sparse ? rs.energy_begin : rs.measure_begin;
      if (reuse && !changed[f] && (!sparse || prev->sparse)) {
        std::copy(prev->rev.begin() + std::ptrdiff_t(nr * f + k0),
                  prev->rev.begin() + std::ptrdiff_t(nr * f + rs.measure_end),
                  m.rev.begin() + std::ptrdiff_t(nr * f + k0));
        continue;
      }
      for (std::size_t k = k0; k < rs.measure_begin; ++k) {  // the sparse samples
        const Bary& w = rb[k];
        const Vec3 y = w[0] * pos[tris[f][0]] + w[1] * pos[tris[f][1]] + w[2] * pos[tris[f][2]];
        m.rev[nr * f + k] = orig.closest(y, prev ? &prev->rev[nr * f + k].tri : nullptr);
      }
      for (std::size_t j = 0; j < per; ++j) {
        const std::uint32_t o = shared.of[f * per + j];
        m.rev[nr * f + rs.measure_begin + j] =
            (o & SharedNodes::kVertex) != 0 ? m.vert[o & ~SharedNodes::kVertex] : points[o];
      }
    }
  });
  double sum = 0, mx = 0;
  for (const Forward& f : m.fwd) {
    sum += f.dist2;
    mx = std::max(mx, f.dist2);
  }
  for (std::size_t f = 0; f < tris.size(); ++f)
    for (std::size_t k = rs.measure_begin; k < rs.measure_end; ++k) {
      const double d2 = m.rev[nr * f + k].dist2;
      sum += m.area[f] * rs.weight[k] * d2;
      mx = std::max(mx, d2);
    }
  m.rms = std::sqrt(sum / double(m.fwd.size() + tris.size() * (rs.measure_end - rs.measure_begin)));
  // The vertices count in the maximum (not in the RMS, which is by area): a vertex pushed off
  // the surface is where a sampled maximum misses the true one.
  for (const Reverse& r : m.vert) mx = std::max(mx, r.dist2);
  m.hausdorff = std::sqrt(mx);
  return m;
}

// Adds the sparse energy samples' correspondences to `m`, measured without them at the same
// positions (what measure(..., true) would add: the rest is the same). Each query starts from
// the triangle of the face's nearest dense sample.
void add_sparse(Measure& m, const std::vector<Vec3>& pos, const std::vector<Tri>& tris,
                const ReverseSamples& rs, const Original& orig) {
  const std::size_t nr = rs.bary.size();
  parallel_for_range(tris.size(), 256, [&](std::size_t b, std::size_t e) {
    for (std::size_t f = b; f < e; ++f) {
      for (std::size_t k = rs.energy_begin; k < rs.energy_end; ++k) {
        const Bary& w = rs.bary[k];
        const Vec3 y = w[0] * pos[tris[f][0]] + w[1] * pos[tris[f][1]] + w[2] * pos[tris[f][2]];
        const Id start = m.rev[nr * f + rs.nearest_node[k - rs.energy_begin]].tri;
        m.rev[nr * f + k] = orig.closest(y, &start);
      }
    }
  });
  m.sparse = true;
}

std::vector<std::array<Id, 2>> unique_edges(const std::vector<Tri>& tris) {
  std::vector<std::array<Id, 2>> edges;
  edges.reserve(3 * tris.size());
  for (const Tri& t : tris)
    for (int k = 0; k < 3; ++k) {
      const Id a = t[k], b = t[(k + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b)});
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

// ---- edge flips (the edge swap of Hoppe et al.) ----
//
// A pass proposes, for every interior edge (a, b) between faces (a, b, c) and (b, a, d), the
// pair (c, a, d), (d, b, c) in the same two slots, and scores it by the change of the measured
// error over the two faces: the original's samples whose closest face is one of them (their
// distance to the nearer new face: an upper bound, a closer third face only lowers it) and the
// measure's samples of the faces themselves (to the original). The flips that lower it, best
// first and at most one per face, are made; a flip that folds (a new face turning more than
// kFlipTurn from the faces it replaces, or a dihedral angle between the new faces beyond it) or
// whose edge (c, d) exists is not proposed, and a flipped face that intersects another face
// (exact) is flipped back.

constexpr double kFlipTurnCos = 0.5;  // 60°
constexpr int kFlipPasses = 1;
// Pairs of faces whose fourth point lies within this fraction of the RMS error of the plane of
// the other three are not proposed.
constexpr double kFlipFlat = 0.1;  // passes in a row at most, each kept only if it helps

struct FlipCandidate {
  double gain = 0;  // error before − after over the two faces (weighted squared distances)
  Id f1 = 0, f2 = 0;
  Tri g1{}, g2{};
};

// Whether the faces `tris` of `pos` have a pair that intersects (exact) with at least one face
// in `touched`; those faces' ids go to `bad`.
void intersecting_touched(const std::vector<Vec3>& pos, const std::vector<Tri>& tris,
                          const std::vector<char>& touched, std::vector<char>& bad) {
  PolyData pd;
  pd.points = Points(pos.size(), ScalarType::Float64);
  for (std::size_t i = 0; i < pos.size(); ++i) pd.points.set(i, pos[i]);
  for (const Tri& t : tris) pd.polys.add({Index(t[0]), Index(t[1]), Index(t[2])});
  for (const auto& [i, j] : self_intersections(pd)) {
    if (touched[std::size_t(i)]) bad[std::size_t(i)] = 1;
    if (touched[std::size_t(j)]) bad[std::size_t(j)] = 1;
  }
}

// One pass over the edges; returns the flips made (in `tris` and `faces_of`).
// Whether some face around c uses d: the edge (c, d) exists.
bool has_edge(const std::vector<Tri>& tris, const std::vector<std::vector<Id>>& faces_of, Id c,
              Id d) {
  for (Id g : faces_of[c]) {
    const Tri& t = tris[g];
    if (t[0] == d || t[1] == d || t[2] == d) return true;
  }
  return false;
}

// Puts `t` in slot f, keeping `faces_of` in step.
void set_face(std::vector<Tri>& tris, std::vector<std::vector<Id>>& faces_of, Id f, const Tri& t) {
  for (Id v : tris[f]) {
    auto& list = faces_of[v];
    list.erase(std::remove(list.begin(), list.end(), f), list.end());
  }
  tris[f] = t;
  for (Id v : t) faces_of[v].push_back(f);
}

std::size_t flip_edges(const std::vector<Vec3>& pos, std::vector<Tri>& tris,
                       std::vector<std::vector<Id>>& faces_of, const std::vector<Vec3>& samples,
                       const ReverseSamples& rs, const Measure& m, const Original& orig) {
  const double flat = kFlipFlat * m.rms;
  const std::size_t nf = tris.size(), nr = rs.bary.size();
  // The original's samples by the face they are closest to.
  std::vector<std::uint32_t> first(nf + 1, 0), order(samples.size());
  for (const Forward& f : m.fwd) ++first[f.tri + 1];
  for (std::size_t f = 0; f < nf; ++f) first[f + 1] += first[f];
  {
    std::vector<std::uint32_t> at(first.begin(), first.end() - 1);
    for (std::size_t i = 0; i < samples.size(); ++i) order[at[m.fwd[i].tri]++] = std::uint32_t(i);
  }
  // Interior edges: (face, corner) of the edge from corner k to k + 1 and its twin face.
  std::vector<std::array<Id, 3>> pairs;  // f1, k1 (edge tris[f1][k1] → tris[f1][k1 + 1]), f2
  for (std::size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const Id a = tris[f][k], b = tris[f][(k + 1) % 3];
      if (a > b) continue;  // each edge once, from the face where it runs up
      Id twin = Id(-1);
      int count = 0;
      for (Id g : faces_of[a]) {
        if (g == f) continue;
        const Tri& t = tris[g];
        for (int q = 0; q < 3; ++q)
          if (t[q] == b && t[(q + 1) % 3] == a) {
            twin = g;
            ++count;
          }
        for (int q = 0; q < 3; ++q)
          if (t[q] == a && t[(q + 1) % 3] == b) count += 2;  // inconsistent: leave it
      }
      if (count == 1) pairs.push_back({Id(f), Id(k), twin});
    }
  const double area_scale = [&] {  // m.area is the area over the mean
    for (std::size_t f = 0; f < nf; ++f) {
      const double a =
          norm(cross(pos[tris[f][1]] - pos[tris[f][0]], pos[tris[f][2]] - pos[tris[f][0]]));
      if (a > 0 && m.area[f] > 0) return m.area[f] / a;
    }
    return 0.0;
  }();
  std::vector<FlipCandidate> cand(pairs.size());
  parallel_for_range(pairs.size(), 64, [&](std::size_t b0, std::size_t b1) {
    for (std::size_t e = b0; e < b1; ++e) {
      const auto [f1, k1, f2] = pairs[e];
      const Id a = tris[f1][k1], b = tris[f1][(k1 + 1) % 3], c = tris[f1][(k1 + 2) % 3];
      Id d = 0;
      for (Id v : tris[f2])
        if (v != a && v != b) d = v;
      FlipCandidate& fc = cand[e];
      fc.gain = 0;
      if (c == d) continue;
      if (has_edge(tris, faces_of, c, d)) continue;  // it would become non-manifold
      const Vec3 n1 = cross(pos[b] - pos[a], pos[c] - pos[a]);
      const Vec3 n2 = cross(pos[a] - pos[b], pos[d] - pos[b]);
      const Tri g1{c, a, d}, g2{d, b, c};
      const Vec3 m1 = cross(pos[a] - pos[c], pos[d] - pos[c]);
      const Vec3 m2 = cross(pos[b] - pos[d], pos[c] - pos[d]);
      const double l1 = norm(n1), l2 = norm(n2), k1n = norm(m1), k2n = norm(m2);
      if (!(l1 > 0 && l2 > 0 && k1n > 0 && k2n > 0)) continue;
      // A flat pair: the two splits are nearly the same surface (apart by at most d's distance
      // from the plane of a, b, c), so the flip cannot change the error by much.
      if (std::abs(dot(pos[d] - pos[a], n1)) < flat * l1) continue;
      const auto cosine = [](const Vec3& u, double lu, const Vec3& v, double lv) {
        return dot(u, v) / (lu * lv);
      };
      if (cosine(m1, k1n, m2, k2n) < kFlipTurnCos) continue;
      bool fold = false;
      for (const auto& [u, lu] : {std::pair{m1, k1n}, std::pair{m2, k2n}})
        for (const auto& [v, lv] : {std::pair{n1, l1}, std::pair{n2, l2}})
          fold = fold || cosine(u, lu, v, lv) < kFlipTurnCos;
      if (fold) continue;
      // The error before and after over the two faces.
      double before = 0, after = 0;
      for (const Id f : {f1, f2})
        for (std::uint32_t q = first[f]; q < first[f + 1]; ++q) {
          const std::uint32_t i = order[q];
          before += m.fwd[i].dist2;
          const Vec3& x = samples[i];
          after += std::min(closest_on_triangle(x, pos[g1[0]], pos[g1[1]], pos[g1[2]]).dist2,
                            closest_on_triangle(x, pos[g2[0]], pos[g2[1]], pos[g2[2]]).dist2);
        }
      for (const Id f : {f1, f2})
        for (std::size_t k = rs.measure_begin; k < rs.measure_end; ++k) {
          before += m.area[f] * rs.weight[k] * m.rev[nr * f + k].dist2;
        }
      // The reverse part only adds to `after`: a pair already worse without it is not scored.
      if (!(after < before * (1 - 1e-6))) continue;
      for (const auto& [g, area] : {std::pair{g1, k1n}, std::pair{g2, k2n}})
        for (std::size_t k = rs.measure_begin; k < rs.measure_end; ++k) {
          const Bary& w = rs.bary[k];
          const Vec3 y = w[0] * pos[g[0]] + w[1] * pos[g[1]] + w[2] * pos[g[2]];
          // Each query starts from the original's triangle of the nearer of the old faces'
          // samples with the same coordinates (the new faces cover the old ones' quad).
          const Reverse& r1 = m.rev[nr * f1 + k];
          const Reverse& r2 = m.rev[nr * f2 + k];
          const Vec3 y1 =
              w[0] * pos[tris[f1][0]] + w[1] * pos[tris[f1][1]] + w[2] * pos[tris[f1][2]];
          const Vec3 y2 =
              w[0] * pos[tris[f2][0]] + w[1] * pos[tris[f2][1]] + w[2] * pos[tris[f2][2]];
          const Id hint = norm2(y - y1) <= norm2(y - y2) ? r1.tri : r2.tri;
          after += area * area_scale * rs.weight[k] * orig.closest(y, &hint).dist2;
          if (!(after < before * (1 - 1e-6))) break;
        }
      if (after < before * (1 - 1e-6)) fc = {before - after, f1, f2, g1, g2};
    }
  });
  std::vector<std::size_t> best;
  for (std::size_t e = 0; e < cand.size(); ++e)
    if (cand[e].gain > 0) best.push_back(e);
  std::sort(best.begin(), best.end(), [&](std::size_t x, std::size_t y) {
    return cand[x].gain != cand[y].gain ? cand[x].gain > cand[y].gain : x < y;
  });
  const std::vector<Tri> before = tris;
  std::vector<char> touched(nf, 0);
  std::vector<std::size_t> made;
  for (std::size_t e : best) {
    const FlipCandidate& fc = cand[e];
    if (touched[fc.f1] || touched[fc.f2]) continue;
    // The edge (c, d) may have been made by an earlier flip of this pass.
    if (has_edge(tris, faces_of, fc.g1[0], fc.g1[2])) continue;
    touched[fc.f1] = touched[fc.f2] = 1;
    set_face(tris, faces_of, fc.f1, fc.g1);
    set_face(tris, faces_of, fc.f2, fc.g2);
    made.push_back(e);
  }
  if (made.empty()) return 0;
  // Flipped faces that intersect another face go back, with their partner.
  std::vector<char> bad(nf, 0);
  intersecting_touched(pos, tris, touched, bad);
  std::size_t undone = 0;
  for (std::size_t e : made) {
    const FlipCandidate& fc = cand[e];
    if (!bad[fc.f1] && !bad[fc.f2]) continue;
    ++undone;
    set_face(tris, faces_of, fc.f1, before[fc.f1]);
    set_face(tris, faces_of, fc.f2, before[fc.f2]);
  }
  if (undone > 0) {  // what is left must be clean too, or nothing is kept
    std::fill(bad.begin(), bad.end(), 0);
    intersecting_touched(pos, tris, touched, bad);
    if (std::find(bad.begin(), bad.end(), 1) != bad.end()) {
      for (std::size_t f = 0; f < nf; ++f)
        if (touched[f]) set_face(tris, faces_of, Id(f), before[f]);
      return 0;
    }
  }
  return made.size() - undone;
}

// ---- the linear least-squares terms (analytic derivatives) ----
//
// The energy is quadratic, so the sample terms of one triangle are gathered into one residual
// block of 9 rows before Ceres sees them, and a solve costs the same whatever the sampling
// density. Point to point: for the samples x_s with barycentric coordinates b_s (weights w_s),
// per coordinate c, Σ w_s (b_sᵀ v_c − x_sc)² = v_cᵀ M v_c − 2 g_cᵀ v_c + const with
// M = Σ w_s b_s b_sᵀ and g_c = Σ w_s b_s x_sc. With M = Q Λ Qᵀ, the rows
// √λ_k q_kᵀ v_c − q_kᵀ g_c / √λ_k (λ_k > 0) have the same squared sum up to a constant: 9
// rows, each coordinate on its own. Point to plane: each sample is a row √w (aᵀ V − n · y)
// over V = (v_0, v_1, v_2) ∈ R⁹ with a[3j + c] = b_j n_c. The Householder QR factorization of
// all these rows [a | rhs] gives at most 9 rows [R | Qᵀ rhs] with the same squared sum up to a
// constant. One block of 9 rows instead of one per kind halves the Jacobian the conjugate
// gradients multiply by (the solves of the 100k → 10k case: 1.05 s → 0.66 s). Householder
// reflections keep a column that is zero zero, so a coordinate no row touches stays exactly
// where it was.

struct Gathered {  // the samples of one triangle, gathered
  double m[3][3] = {};
  double g[3][3] = {};  // g[c][k]
  bool any = false;
};

// Writes the 9 rows [√λ_k q_kᵀ (column 3j + c: vertex j, coordinate c) | q_kᵀ g_c / √λ_k] of the
// eigenpairs k with λ_k > 0 and coordinates c at `first` (row 3k + c); the others are zero.
void gathered_rows(const Gathered& s, Eigen::Matrix<double, Eigen::Dynamic, 10>& rows,
                   Eigen::Index first) {
  rows.middleRows(first, 9).setZero();
  if (!s.any) return;
  Eigen::Matrix3d m;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) m(a, b) = s.m[a][b];
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> e(m);
  const double top = std::max(e.eigenvalues()(2), 0.0);
  for (int k = 0; k < 3; ++k) {
    const double lam = e.eigenvalues()(k);
    if (!(lam > 1e-14 * top)) continue;  // no sample constrains this combination
    const double sq = std::sqrt(lam);
    for (int c = 0; c < 3; ++c) {
      const Eigen::Index row = first + 3 * k + c;
      double qg = 0;
      for (int j = 0; j < 3; ++j) {
        rows(row, 3 * j + c) = sq * e.eigenvectors()(j, k);
        qg += e.eigenvectors()(j, k) * s.g[c][j];
      }
      rows(row, 9) = qg / sq;
    }
  }
}

// The rows of one triangle (point to point and point to plane), compressed by QR into 9 (zero
// rows pad them).
class TriangleCost final : public ceres::SizedCostFunction<9, 3, 3, 3> {
 public:
  // `rows`: [coefficients of V | right-hand side]: the 9 point-to-point rows (gathered_rows),
  // then one row per point-to-plane sample, [√w a | √w n · y].
  explicit TriangleCost(Eigen::Matrix<double, Eigen::Dynamic, 10>& rows) {
    const Eigen::HouseholderQR<Eigen::Ref<Eigen::Matrix<double, Eigen::Dynamic, 10>>> qr(rows);
    const auto& r = qr.matrixQR();
    const Eigen::Index n = std::min<Eigen::Index>(r.rows(), 9);
    for (Eigen::Index k = 0; k < n; ++k) {
      for (Eigen::Index j = k; j < 9; ++j) row_[k][j] = r(k, j);
      rhs_[k] = r(k, 9);
    }
  }
  bool Evaluate(double const* const* v, double* r, double** jac) const override {
    for (int k = 0; k < 9; ++k) {
      double sum = -rhs_[k];
      for (int j = 0; j < 3; ++j)
        for (int c = 0; c < 3; ++c) sum += row_[k][3 * j + c] * v[j][c];
      r[k] = sum;
    }
    if (jac) {
      for (int j = 0; j < 3; ++j) {
        if (!jac[j]) continue;
        for (int k = 0; k < 9; ++k)  // 9 rows x 3 columns, row-major
          for (int c = 0; c < 3; ++c) jac[j][3 * k + c] = row_[k][3 * j + c];
      }
    }
    return true;
  }

 private:
  double row_[9][9] = {};
  double rhs_[9] = {};
};

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  const auto mid = v.begin() + std::ptrdiff_t(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// Weights of residuals of size sqrt(dist2) under the robust loss (iteratively reweighted least
// squares: w = ρ'(r²) with the scale from the median |r| of all sample residuals), 1 without.
constexpr double kEmphasisMax = 16;

struct Weights {
  RobustLoss loss = RobustLoss::None;
  double a2 = 0;    // squared scale
  double rms2 = 0;  // mean squared residual: large residuals weigh more (see below)
  [[nodiscard]] double operator()(double dist2) const {
    // Without a robust loss, a residual above the RMS weighs 1 + (r / rms)², up to 16: the
    // solve_positions then leans on the largest distances (an L4-like energy), so the Hausdorff distance
    // falls with the RMS instead of being traded for it.
    if (loss == RobustLoss::None || a2 == 0) {
      return rms2 > 0 ? std::min(1 + dist2 / rms2, kEmphasisMax) : 1;
    }
    if (loss == RobustLoss::Huber) return dist2 <= a2 ? 1 : std::sqrt(a2 / dist2);
    return 1 / (1 + dist2 / a2);  // Cauchy
  }
};

Weights weights_for(const Measure& m, RobustLoss loss) {
  Weights w;
  w.loss = loss;
  if (loss == RobustLoss::None) {
    w.rms2 = m.rms * m.rms;
    return w;
  }
  std::vector<double> d;
  d.reserve(m.fwd.size() + m.rev.size());
  for (const Forward& f : m.fwd) d.push_back(std::sqrt(f.dist2));
  for (const Reverse& r : m.rev) d.push_back(std::sqrt(r.dist2));
  const double a = (loss == RobustLoss::Huber ? kHuberK : kCauchyK) * kMadToSigma * median(d);
  w.a2 = a * a;
  return w;
}

// One solve_positions of the energy for fixed correspondences; returns the new positions.
std::vector<Vec3> solve_positions(const std::vector<Vec3>& pos, const std::vector<Tri>& tris,
                        const std::vector<std::array<Id, 2>>& edges,
                        const std::vector<Vec3>& samples, const ReverseSamples& rs,
                        const Measure& m, const std::vector<char>& fixed,
                        const RefineOptions& o, bool sparse, bool plain) {
  const std::vector<Bary>& rb = rs.bary;
  const std::size_t eb = sparse ? rs.energy_begin : rs.measure_begin;
  const std::size_t ee = sparse ? rs.energy_end : rs.measure_end;
  std::vector<double> x(3 * pos.size());
  for (std::size_t i = 0; i < pos.size(); ++i)
    for (int c = 0; c < 3; ++c) x[3 * i + c] = pos[i][c];
  Weights weight = weights_for(m, o.loss);
  if (plain) weight.rms2 = 0;
  std::vector<Gathered> gathered(tris.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Forward& f = m.fwd[i];
    const double w = weight(f.dist2);
    Gathered& gt = gathered[f.tri];
    gt.any = true;
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) gt.m[a][b] += w * f.b[a] * f.b[b];
      for (int c = 0; c < 3; ++c) gt.g[c][a] += w * f.b[a] * samples[i][c];
    }
  }
  const std::size_t nr = rb.size();
  // The springs join the triangles' blocks: an edge's rows go to each of its k triangles with
  // weight 1/√k (the same squared sum), and the QR below folds them in with the samples' rows.
  const double spring_w =
      std::sqrt(o.spring * double(samples.size() + (ee - eb) * tris.size()) / double(edges.size()));
  std::vector<std::array<Id, 2>> sides;  // every triangle's edges, sorted: k copies of an edge
  if (spring_w > 0) {
    sides.reserve(3 * tris.size());
    for (const Tri& t : tris)
      for (int k = 0; k < 3; ++k)
        sides.push_back({std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])});
    std::sort(sides.begin(), sides.end());
  }
  const Eigen::Index spring_rows = spring_w > 0 ? 9 : 0;
  std::vector<std::unique_ptr<TriangleCost>> costs(tris.size());
  parallel_for_range(tris.size(), 256, [&](std::size_t b, std::size_t e) {
    Eigen::Matrix<double, Eigen::Dynamic, 10> rows(Eigen::Index(9 + ee - eb) + spring_rows, 10);
    for (std::size_t f = b; f < e; ++f) {
      gathered_rows(gathered[f], rows, 0);
      for (std::size_t k = eb; k < ee; ++k) {
        const Reverse& r = m.rev[nr * f + k];
        const double sw = std::sqrt(m.area[f] * rs.weight[k] * weight(r.dist2));
        const Eigen::Index row = Eigen::Index(9 + k - eb);
        for (int j = 0; j < 3; ++j)
          for (int c = 0; c < 3; ++c) rows(row, 3 * j + c) = sw * rb[k][j] * r.normal[c];
        rows(row, 9) = sw * dot(r.normal, r.target);
      }
      if (spring_rows > 0) {
        rows.bottomRows(spring_rows).setZero();
        const Tri& t = tris[f];
        for (int k = 0; k < 3; ++k) {
          const int j = (k + 1) % 3;
          const std::array<Id, 2> side{std::min(t[k], t[j]), std::max(t[k], t[j])};
          const auto run = std::equal_range(sides.begin(), sides.end(), side);
          const double w = spring_w / std::sqrt(double(run.second - run.first));
          for (int c = 0; c < 3; ++c) {
            const Eigen::Index row = Eigen::Index(9 + ee - eb) + 3 * k + c;
            rows(row, 3 * k + c) = w;
            rows(row, 3 * j + c) = -w;
          }
        }
      }
      costs[f] = std::make_unique<TriangleCost>(rows);
    }
  });
  ceres::Problem::Options po;
  po.enable_fast_removal = false;
  ceres::Problem problem(po);
  const auto block = [&](Id v) { return &x[3 * std::size_t(v)]; };
  for (std::size_t f = 0; f < tris.size(); ++f) {
    const Tri& t = tris[f];
    problem.AddResidualBlock(costs[f].release(), nullptr, block(t[0]), block(t[1]), block(t[2]));
  }
  for (std::size_t i = 0; i < pos.size(); ++i)
    if (fixed[i] && problem.HasParameterBlock(block(Id(i))))
      problem.SetParameterBlockConstant(block(Id(i)));

  ceres::Solver::Options so;
  // Conjugate gradients on the normal equations with a block-Jacobi preconditioner: the start
  // (the current positions) is close to the solution and the springs keep the system well
  // conditioned, so a few dozen iterations reach the cost a sparse Cholesky factorization
  // (SPARSE_NORMAL_CHOLESKY with SuiteSparse or Eigen) reaches, in a tenth of its time
  // (docs/algorithms/fitting.md).
  so.linear_solver_type = ceres::CGNR;
  so.preconditioner_type = ceres::JACOBI;
  so.max_linear_solver_iterations = 500;
  // The energy is quadratic (the weights are fixed for the solve_positions): Levenberg-Marquardt with a
  // huge trust region takes Gauss-Newton steps; a few suffice (the inner solve_positions is inexact).
  so.initial_trust_region_radius = 1e12;
  so.max_num_iterations = 4;
  so.num_threads = 1;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  std::vector<Vec3> out(pos.size());
  for (std::size_t i = 0; i < pos.size(); ++i) out[i] = {x[3 * i], x[3 * i + 1], x[3 * i + 2]};
  return out;
}

// ---- rejection of flips and self-intersections ----

constexpr int kShortenings = 3;  // a refused move is tried at 1/2 and 1/4 before it is undone

struct Rejector {
  const std::vector<Tri>& tris;
  const std::vector<std::vector<Id>>& faces_of;  // faces around each vertex
  const Points& storage;                         // positions are rounded as it stores them

  std::array<Vec3, 3> corners(const std::vector<Vec3>& p, Id f) const {
    return {p[tris[f][0]], p[tris[f][1]], p[tris[f][2]]};
  }
  static Vec3 face_normal(const std::array<Vec3, 3>& c) { return cross(c[1] - c[0], c[2] - c[0]); }
  static void box(const std::array<Vec3, 3>& c, Vec3& lo, Vec3& hi) {
    lo = hi = c[0];
    for (int k = 1; k < 3; ++k)
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], c[k][a]);
        hi[a] = std::max(hi[a], c[k][a]);
      }
  }
  std::array<Index, 3> ids(Id f) const { return {tris[f][0], tris[f][1], tris[f][2]}; }

  // Shortens moves of `pos` (relative to `old`) until no face turns by more than 90° and no face
  // pair intersects that did not before: a vertex of an offending face moves half as far, then
  // a quarter, then not at all. Returns the number of vertex moves undone or shortened.
  std::size_t run(const std::vector<Vec3>& old, std::vector<Vec3>& pos) const {
    const std::vector<Vec3> want = pos;
    std::vector<std::uint8_t> level(pos.size(), 0);  // the move is want-old scaled by 2^-level
    const std::size_t nv = pos.size();
    std::vector<char> moved(nv, 0);
    for (std::size_t i = 0; i < nv; ++i) moved[i] = !(pos[i] == old[i]);
    Bounds b;
    for (std::size_t i = 0; i < nv; ++i) {
      b.extend(old[i]);
      b.extend(pos[i]);
    }
    double edge_sum = 0;
    for (const Tri& t : tris) edge_sum += norm(pos[t[1]] - pos[t[0]]);
    TriangleGrid grid(b, triangle_grid_cell_size(b, tris.size(), edge_sum / double(tris.size())));
    std::vector<std::array<Vec3, 2>> boxes(tris.size());
    for (std::size_t f = 0; f < tris.size(); ++f) {
      box(corners(pos, Id(f)), boxes[f][0], boxes[f][1]);
      grid.insert(Id(f), boxes[f][0], boxes[f][1]);
    }
    std::vector<Id> dirty;
    for (std::size_t f = 0; f < tris.size(); ++f)
      for (Id v : tris[f])
        if (moved[v]) {
          dirty.push_back(Id(f));
          break;
        }
    std::size_t undone = 0;
    std::vector<char> revert(nv, 0);
    std::vector<std::uint8_t> is_dirty(tris.size(), 0);  // 1: dirty, 2: dirty and turned
    while (!dirty.empty()) {
      // A dirty face that turned by 90° or more (or collapsed) offends; one that did not is
      // tested against the faces near it, in parallel, each pair once: a pair of two such
      // faces from the smaller id. Offending faces are flagged (a relaxed store of 1, from
      // any thread) and then marked in order.
      for (Id f : dirty) is_dirty[f] = 1;
      std::vector<std::atomic<std::uint8_t>> offends(tris.size());
      for (auto& x : offends) x.store(0, std::memory_order_relaxed);
      parallel_for_range(dirty.size(), 256, [&](std::size_t b0, std::size_t b1) {
        for (std::size_t i = b0; i < b1; ++i) {
          const Id f = dirty[i];
          const Vec3 nn = face_normal(corners(pos, f)), no = face_normal(corners(old, f));
          if (dot(nn, no) <= 0 && norm2(no) > 0) is_dirty[f] = 2;
        }
      });
      parallel_for_range(dirty.size(), 64, [&](std::size_t b0, std::size_t b1) {
        for (std::size_t i = b0; i < b1; ++i) {
          const Id f = dirty[i];
          if (is_dirty[f] == 2) {
            offends[f].store(1, std::memory_order_relaxed);
            continue;
          }
          const auto cn = corners(pos, f), co = corners(old, f);
          const auto fid = ids(f);
          grid.for_each_candidate(boxes[f][0], boxes[f][1], [&](std::uint32_t g) {
            if (g == f || (is_dirty[g] == 1 && g < f)) return;
            const auto gid = ids(Id(g));
            if (faces_intersect(cn, fid, corners(pos, Id(g)), gid) &&
                !faces_intersect(co, fid, corners(old, Id(g)), gid)) {
              offends[f].store(1, std::memory_order_relaxed);
              offends[g].store(1, std::memory_order_relaxed);
            }
          });
        }
      });
      for (Id f : dirty) is_dirty[f] = 0;
      std::vector<Id> to_revert;
      const auto mark = [&](Id f) {
        for (Id v : tris[f])
          if (moved[v] && !revert[v]) {
            revert[v] = 1;
            to_revert.push_back(v);
          }
      };
      for (std::size_t f = 0; f < tris.size(); ++f)
        if (offends[f].load(std::memory_order_relaxed)) mark(Id(f));
      if (to_revert.empty()) break;
      std::sort(to_revert.begin(), to_revert.end());
      dirty.clear();
      for (Id v : to_revert) {
        revert[v] = 0;
        ++undone;
        if (++level[v] >= kShortenings) {
          pos[v] = old[v];
          moved[v] = 0;
        } else {
          const Vec3 p = storage.stored(old[v] + std::ldexp(1.0, -level[v]) * (want[v] - old[v]));
          if (p == old[v]) moved[v] = 0;
          pos[v] = p;
        }
        for (Id f : faces_of[v]) dirty.push_back(f);
      }
      std::sort(dirty.begin(), dirty.end());
      dirty.erase(std::unique(dirty.begin(), dirty.end()), dirty.end());
      for (Id f : dirty) {
        grid.remove(f, boxes[f][0], boxes[f][1]);
        box(corners(pos, f), boxes[f][0], boxes[f][1]);
        grid.insert(f, boxes[f][0], boxes[f][1]);
      }
    }
    return undone;
  }
};

}  // namespace

RefineResult fit_detail::refine_mesh(const PolyData& original, const PolyData& simplified,
                                     const RefineOptions& options) {
  const auto t_start = Clock::now();
  const RefineOptions& o = options;
  if (o.outer_iterations < 1)
    throw Error("refine_mesh: outer_iterations must be >= 1, got " +
                std::to_string(o.outer_iterations));
  if (!std::isfinite(o.spring) || o.spring < 0)
    throw Error("refine_mesh: spring must be a finite number >= 0, got " +
                std::to_string(o.spring));
  if (static_cast<unsigned>(o.loss) > static_cast<unsigned>(RobustLoss::Cauchy))
    throw Error("refine_mesh: unknown robust loss");

  const std::vector<Tri> otris = original_triangles(original);
  const std::vector<Vec3> overts = finite_points(original, "original");
  std::vector<Tri> tris = simplified_triangles(simplified);
  std::vector<Vec3> pos = finite_points(simplified, "simplified");
  const std::vector<char> fixed = fixed_vertices(simplified, tris, o);
  report_progress(o.progress, 0, "refine_mesh");

  // The original: locator, triangle normals, samples.
  Original orig;
  {
    std::vector<std::array<PrimitiveSet::Id, 3>> t(otris.begin(), otris.end());
    orig.set = PrimitiveSet(overts, {}, {}, std::move(t));
    orig.locator = std::make_unique<PrimitiveLocator>(orig.set);
    orig.near = std::make_unique<NearTriangles>(orig.set, orig.locator.get(), overts, otris);
    orig.normals.resize(otris.size());
    for (std::size_t f = 0; f < otris.size(); ++f) {
      const Vec3 n = cross(overts[otris[f][1]] - overts[otris[f][0]],
                           overts[otris[f][2]] - overts[otris[f][0]]);
      const double len = norm(n);
      orig.normals[f] = len > 0 ? n / len : Vec3{};
    }
  }
  std::vector<Vec3> samples;
  if (o.samples == 0) {
    std::vector<char> used(overts.size(), 0);
    for (const Tri& t : otris)
      for (Id v : t) used[v] = 1;
    for (std::size_t i = 0; i < overts.size(); ++i)
      if (used[i]) samples.push_back(overts[i]);
    const std::size_t want = kAutoSamplesPerTriangle * tris.size();
    area_samples(overts, otris, want > samples.size() ? want - samples.size() : 0, samples);
  } else {
    area_samples(overts, otris, o.samples, samples);
  }

  // Topology of the simplified mesh: faces around each vertex, unique edges.
  std::vector<std::vector<Id>> faces_of(pos.size());
  for (std::size_t f = 0; f < tris.size(); ++f)
    for (int k = 0; k < 3; ++k) faces_of[tris[f][k]].push_back(Id(f));
  std::vector<std::array<Id, 2>> edges = unique_edges(tris);
  const std::vector<Tri> input_tris = tris;
  // Flips rewrite the triangles, so not with cell arrays (they would no longer fit).
  const bool flips = o.flip_edges && simplified.cell_data.size() == 0;
  const Rejector rejector{tris, faces_of, simplified.points};

  RefineStats stats;
  const ReverseSamples rsamples = reverse_samples(samples.size(), tris.size());
  SharedNodes shared;
  std::vector<char> used(pos.size(), 0);
  for (const Tri& t : tris)
    for (Id v : t) used[v] = 1;
  Measure current = measure(pos, tris, samples, rsamples, shared, used, orig, true);
  stats.rms_before = current.rms;
  stats.hausdorff_before = current.hausdorff;
  const std::vector<Vec3> input = pos;
  // The schedule: solves alternate between the sparse reverse samples (even iterations) and the
  // dense ones. The solves lean on the largest distances and may not raise the maximum above
  // the input's, until the last quarter of the solves or until one of them finds no step; from
  // then on they weigh every sample alike (plain least squares, lowering the RMS) and may not
  // raise the maximum reached so far, and two of them in a row finding no step end the fit.
  const int plain_from = o.outer_iterations - o.outer_iterations / 4;
  bool plain = false;
  int failures = 0;  // consecutive plain solves whose step was not taken
  for (int it = 0; it < o.outer_iterations; ++it) {
    report_progress(o.progress, double(it) / o.outer_iterations, "refine_mesh");
    plain = plain || it >= plain_from;
    const double hlimit = plain ? current.hausdorff : stats.hausdorff_before;
    const bool sparse = it % 2 == 0;
    for (int pass = 0; flips && it > 0 && it % 2 == 0 && pass < kFlipPasses; ++pass) {
      // Edge flips that lower the error, kept if the whole measure agrees.
      const std::vector<Tri> kept = tris;
      const std::vector<std::vector<Id>> kept_faces = faces_of;
      if (flip_edges(pos, tris, faces_of, samples, rsamples, current, orig) > 0) {
        Measure m =
            measure(pos, tris, samples, rsamples, shared, used, orig, false, &current, &pos, &kept);
        if (m.rms < current.rms && m.hausdorff <= hlimit) {
          current = std::move(m);
          edges = unique_edges(tris);
          ++stats.flip_passes;
          stats.flips = 0;
          for (std::size_t f = 0; f < tris.size(); ++f) stats.flips += tris[f] != input_tris[f];
          continue;
        }
        tris = kept;
        faces_of = kept_faces;
      }
      break;
    }
    // Trial positions are measured on the dense samples only; the sparse ones when needed.
    if (sparse && !current.sparse) add_sparse(current, pos, tris, rsamples, orig);
    const auto t0 = Clock::now();
    const std::vector<Vec3> solved =
        solve_positions(pos, tris, edges, samples, rsamples, current, fixed, o, sparse, plain);
    stats.seconds += seconds_since(t0);
    ++stats.solves;
    bool accepted = false;
    for (const double scale : kStepScales) {
      std::vector<Vec3> trial(pos.size());
      for (std::size_t i = 0; i < pos.size(); ++i) {
        Vec3 p = fixed[i] ? pos[i] : pos[i] + scale * (solved[i] - pos[i]);
        p = simplified.points.stored(p);
        trial[i] = is_finite(p) ? p : pos[i];
      }
      stats.rejected_moves += rejector.run(pos, trial);
      Measure m = measure(trial, tris, samples, rsamples, shared, used, orig, false, &current);
      // Where the step pushed a sample beyond the input's Hausdorff distance, the vertices of
      // the triangles involved go back (a few rounds): least squares may trade a little of the
      // maximum for the RMS, and this keeps the trade local instead of refusing the whole step.
      for (int round = 0; round < kLocalUndoRounds && m.hausdorff > hlimit; ++round) {
        const double limit2 = hlimit * hlimit;
        std::vector<char> undo(pos.size(), 0);
        for (const Forward& f : m.fwd) {
          if (f.dist2 > limit2) {
            for (Id v : tris[f.tri]) undo[v] = 1;
          }
        }
        for (std::size_t f = 0; f < tris.size(); ++f) {
          for (std::size_t k = rsamples.measure_begin; k < rsamples.measure_end; ++k) {
            if (m.rev[rsamples.bary.size() * f + k].dist2 > limit2) {
              for (Id v : tris[f]) undo[v] = 1;
            }
          }
        }
        for (std::size_t v = 0; v < pos.size(); ++v) {
          if (m.vert[v].dist2 > limit2) undo[v] = 1;
        }
        const std::vector<Vec3> measured = trial;
        bool changed = false;
        for (std::size_t i = 0; i < pos.size(); ++i) {
          if (undo[i] && trial[i] != pos[i]) {
            trial[i] = pos[i];
            changed = true;
          }
        }
        if (!changed) break;
        stats.rejected_moves += rejector.run(pos, trial);
        m = measure(trial, tris, samples, rsamples, shared, used, orig, false, &m, &measured,
                    &tris);
      }
      if (m.rms <= current.rms && m.hausdorff <= hlimit) {
        pos = std::move(trial);
        current = std::move(m);
        accepted = true;
        break;
      }
    }
    // No shorter step helps either: on to the plain solves; when the other sample set failed
    // too there, the fit has converged.
    if (accepted) {
      failures = 0;
    } else if (!plain) {
      plain = true;
    } else if (++failures == 2) {
      break;
    }
  }
  stats.rms_after = current.rms;
  stats.hausdorff_after = current.hausdorff;
  PolyData out = simplified;
  for (std::size_t i = 0; i < pos.size(); ++i) {
    if (pos[i] == input[i]) continue;
    ++stats.moved_vertices;
    out.points.set(i, pos[i]);
  }
  if (stats.flips > 0) {
    out.polys.clear();
    for (const Tri& t : tris) out.polys.add({Index(t[0]), Index(t[1]), Index(t[2])});
  }
  report_progress(o.progress, 1, "refine_mesh");
  stats.total_seconds = seconds_since(t_start);
  return {std::move(out), stats};
}

}  // namespace isoforge
