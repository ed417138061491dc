// Point location in a mesh of tetrahedra by walking (probe_tets.hpp).
//
// References implemented:
// - O. Devillers, S. Pion, M. Teillaud, "Walking in a triangulation", IJFCS 13 (2002): the
//   visibility walk (here: across the face opposite the most negative barycentric coordinate,
//   with a step cap instead of randomisation, the exact locator taking over when it is hit).

#include "probe_tets.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>

namespace isoforge::probe_detail {

namespace {
/// The walk gives up after this many tetrahedra (a cycle, or a start far away).
constexpr int kMaxSteps = 512;
}  // namespace

bool TetWalker::applicable(const UnstructuredGrid& ug) {
  // 4 ids per cell must fit the 32-bit point-to-cells table.
  if (ug.types.empty() || ug.cells.size() >= (std::size_t(1) << 30) ||
      ug.num_points() >= std::size_t(UINT32_MAX)) {
    return false;
  }
  return std::all_of(ug.types.begin(), ug.types.end(),
                     [](CellType t) { return t == CellType::Tetra; });
}

inline Vec3 TetWalker::pt(Index id) const {
  if (pf_) {
    const float* q = pf_ + 3 * id;
    return {q[0], q[1], q[2]};
  }
  const double* q = pd_ + 3 * id;
  return {q[0], q[1], q[2]};
}

TetWalker::TetWalker(const UnstructuredGrid& ug, std::span<const std::uint8_t> cell_ok,
                     double tolerance)
    : conn_(ug.cells.connectivity().data()), cell_ok_(cell_ok), tol_(tolerance) {
  if (ug.points.type() == ScalarType::Float32) {
    pf_ = ug.points.floats().data();
  } else {
    pd_ = ug.points.array().values<double>().data();
  }
  const std::size_t nc = ug.types.size(), np = ug.num_points();
  // Cells of each point, in increasing cell id (counting sort).
  point_start_.assign(np + 1, 0);
  for (std::size_t i = 0; i < 4 * nc; ++i) ++point_start_[std::size_t(conn_[i]) + 1];
  for (std::size_t i = 0; i < np; ++i) point_start_[i + 1] += point_start_[i];
  point_cells_.resize(4 * nc);
  neighbours_.resize(4 * nc, 0);
  std::vector<std::uint32_t> fill(point_start_.begin(), point_start_.end() - 1);
  for (std::size_t c = 0; c < nc; ++c) {
    for (int k = 0; k < 4; ++k) point_cells_[fill[std::size_t(conn_[4 * c + std::size_t(k)])]++] = std::uint32_t(c);
  }
  // Seeds: bins of about 4 centroids each over the mesh's bounds.
  const Bounds b = ug.bounds();
  double ext[3], vol = 1;
  for (int a = 0; a < 3; ++a) {
    ext[a] = std::max(b.max[a] - b.min[a], 1e-30);
    vol *= ext[a];
  }
  const double h = std::cbrt(vol / (double(nc) / 4 + 1));
  std::size_t total = 1;
  for (int a = 0; a < 3; ++a) {
    bins_[std::size_t(a)] = std::clamp(Index(std::ceil(ext[a] / h)), Index{1}, Index{512});
    bin_lo_[a] = b.min[a];
    bin_inv_[a] = double(bins_[std::size_t(a)]) / ext[a];
    total *= std::size_t(bins_[std::size_t(a)]);
  }
  bin_seed_.assign(total, -1);
  for (std::size_t c = nc; c-- > 0;) {  // downward: the smallest id wins
    if (!cell_ok_.empty() && !cell_ok_[c]) continue;
    const Vec3 centre =
        (pt(conn_[4 * c]) + pt(conn_[4 * c + 1]) + pt(conn_[4 * c + 2]) + pt(conn_[4 * c + 3])) * 0.25;
    Index i[3];
    for (int a = 0; a < 3; ++a) {
      i[a] = std::clamp(Index((centre[a] - bin_lo_[a]) * bin_inv_[a]), Index{0}, bins_[std::size_t(a)] - 1);
    }
    bin_seed_[std::size_t(i[0] + bins_[0] * (i[1] + bins_[1] * i[2]))] = std::int32_t(c);
  }
  // Empty bins borrow a neighbour's seed: sweeps forward and back along x, then y, then z.
  const std::size_t stride[3] = {1, std::size_t(bins_[0]), std::size_t(bins_[0] * bins_[1])};
  for (int a = 0; a < 3; ++a) {
    const std::size_t len = std::size_t(bins_[std::size_t(a)]);
    for (std::size_t start = 0; start < total; ++start) {
      if ((start / stride[a]) % len != 0) continue;  // the first bin of a line along a
      for (std::size_t k = 1; k < len; ++k) {
        auto& cur = bin_seed_[start + k * stride[a]];
        if (cur < 0) cur = bin_seed_[start + (k - 1) * stride[a]];
      }
      for (std::size_t k = len - 1; k-- > 0;) {
        auto& cur = bin_seed_[start + k * stride[a]];
        if (cur < 0) cur = bin_seed_[start + (k + 1) * stride[a]];
      }
    }
  }
}

Index TetWalker::seed(const Vec3& p) const {
  Index i[3];
  for (int a = 0; a < 3; ++a) {
    // Clamped: a point outside the bins starts from the nearest ones (any start is valid).
    const double u = (p[a] - bin_lo_[a]) * bin_inv_[a];
    if (!std::isfinite(u)) return -1;
    i[a] = std::clamp(Index(std::clamp(u, -1.0, double(bins_[std::size_t(a)]))), Index{0},
                      bins_[std::size_t(a)] - 1);
  }
  return bin_seed_[std::size_t(i[0] + bins_[0] * (i[1] + bins_[1] * i[2]))];
}

Index TetWalker::neighbour(Index cell, int f) const {
  std::atomic_ref<std::int32_t> memo(neighbours_[4 * std::size_t(cell) + std::size_t(f)]);
  const std::int32_t known = memo.load(std::memory_order_relaxed);
  if (known != 0) return known - 1;
  const Index* v = conn_ + 4 * cell;
  Index a = v[(f + 1) % 4], b = v[(f + 2) % 4], c = v[(f + 3) % 4];
  // Scan the cells of the face's point with the fewest.
  const auto degree = [&](Index q) {
    return point_start_[std::size_t(q) + 1] - point_start_[std::size_t(q)];
  };
  if (degree(b) < degree(a)) std::swap(a, b);
  if (degree(c) < degree(a)) std::swap(a, c);
  Index found = -1;
  for (std::uint32_t e = point_start_[std::size_t(a)]; e < point_start_[std::size_t(a) + 1]; ++e) {
    const Index n = Index(point_cells_[e]);
    if (n == cell) continue;
    const Index* u = conn_ + 4 * n;
    const bool has_b = u[0] == b || u[1] == b || u[2] == b || u[3] == b;
    const bool has_c = u[0] == c || u[1] == c || u[2] == c || u[3] == c;
    if (has_b && has_c) {
      if (found >= 0) {
        found = -2;
        break;
      }
      found = n;
    }
  }
  memo.store(std::int32_t(found + 1), std::memory_order_relaxed);
  return found;
}

bool TetWalker::walk(const Vec3& p, Index& cell, std::array<double, 4>& w) const {
  Index prev = -1;
  for (int step = 0; step < kMaxSteps; ++step) {
    const Index* v = conn_ + 4 * cell;
    const Vec3 p0 = pt(v[0]);
    const Vec3 e1 = pt(v[1]) - p0, e2 = pt(v[2]) - p0, e3 = pt(v[3]) - p0, d = p - p0;
    const Vec3 c23 = cross(e2, e3);
    const double det = dot(e1, c23);
    if (!(std::abs(det) > 1e-300)) return false;  // degenerate: the locator decides
    const double inv = 1.0 / det;
    const double r = dot(d, c23) * inv;
    const double s = dot(e1, cross(d, e3)) * inv;
    const double t = dot(e1, cross(e2, d)) * inv;
    const double l[4] = {1 - r - s - t, r, s, t};
    int worst = 0;  // the smallest coordinate (the first of equal ones)
    for (int f = 1; f < 4; ++f) {
      if (l[f] < l[worst]) worst = f;
    }
    if (l[worst] >= -tol_) {
      if (!cell_ok_.empty() && !cell_ok_[std::size_t(cell)]) return false;
      w = {l[0], l[1], l[2], l[3]};
      return true;
    }
    // Across the face opposite the most negative coordinate, or the next negative one when
    // that face is on the boundary (or leads back): the other cell holding the face's points.
    Index next = neighbour(cell, worst);
    if (next < -1 || next == prev) next = -1;
    if (next < 0) {
      int order[4] = {0, 1, 2, 3};  // faces by increasing barycentric coordinate
      std::sort(order, order + 4,
                [&](int x, int y) { return l[x] < l[y] || (l[x] == l[y] && x < y); });
      for (int f = 0; f < 4 && next < 0 && l[order[f]] < -tol_; ++f) {
        const Index n = neighbour(cell, order[f]);
        if (n >= 0) {
          if (n != prev) next = n;
          continue;
        }
        if (n == -1) continue;
        // Several cells share this face (an invalid mesh): the first other than prev.
        const Index* u0 = v;
        const Index a = u0[(order[f] + 1) % 4], b = u0[(order[f] + 2) % 4],
                    c = u0[(order[f] + 3) % 4];
        for (std::uint32_t e = point_start_[std::size_t(a)]; e < point_start_[std::size_t(a) + 1];
             ++e) {
          const Index m = Index(point_cells_[e]);
          if (m == cell || m == prev) continue;
          const Index* u = conn_ + 4 * m;
          const bool has_b = u[0] == b || u[1] == b || u[2] == b || u[3] == b;
          const bool has_c = u[0] == c || u[1] == c || u[2] == c || u[3] == c;
          if (has_b && has_c) {
            next = m;
            break;
          }
        }
      }
    }
    if (next < 0) return false;  // p beyond the boundary here (or only back the way we came)
    prev = cell;
    cell = next;
  }
  return false;
}

}  // namespace isoforge::probe_detail
