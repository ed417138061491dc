// Cell collapse (the chapter's "cell deletion"): a triangle is removed by merging its three
// vertices into one, placed where the sum of their quadrics is smallest; the triangle and its
// (up to three) edge neighbours disappear. Triangles are taken in order of that quadric error.

#include <algorithm>
#include <cmath>

#include "isoforge/core/parallel.hpp"
#include "reduce/decimate_internal.hpp"
#include "reduce/quadric.hpp"

namespace isoforge::reduce {
namespace {

struct CellEntry {
  double cost;
  Fid f;
  std::array<std::uint32_t, 3> stamps;
};

struct CellLater {
  bool operator()(const CellEntry& a, const CellEntry& b) const {
    if (a.cost != b.cost) return a.cost > b.cost;
    return a.f > b.f;
  }
};

struct CellCandidate {
  bool valid = false;
  std::array<Vid, 3> group{};  // group[0] survives
  Vec3 p;
  double cost = 0, error = 0;
  std::array<double, 3> weights{};  // barycentric weights of p (point arrays)
};

class CellCollapser {
 public:
  CellCollapser(EditMesh& mesh, CarriedAttributes& attributes, const Prepared& prepared,
                const DecimateOptions& options)
      : mesh_(mesh), attributes_(attributes), prepared_(prepared), options_(options) {}
  DecimateStats run();

 private:
  [[nodiscard]] CellCandidate evaluate(Fid f) const;
  [[nodiscard]] CellEntry entry(Fid f, const CellCandidate& c) const {
    const Tri& t = mesh_.face(f);
    return {c.cost, f, {stamp_[t[0]], stamp_[t[1]], stamp_[t[2]]}};
  }
  void fill_heap();

  EditMesh& mesh_;
  CarriedAttributes& attributes_;
  const Prepared& prepared_;
  const DecimateOptions& options_;
  std::vector<VertexQuadric> quadric_;
  std::vector<std::uint32_t> stamp_;
  std::vector<CellEntry> heap_;
};

CellCandidate CellCollapser::evaluate(Fid f) const {
  CellCandidate c;
  const Tri& t = mesh_.face(f);
  int locked = 0, lock_at = 0;
  for (int k = 0; k < 3; ++k) {
    if (mesh_.locked(t[k])) {
      ++locked;
      lock_at = k;
    }
  }
  if (locked > 1) return c;
  const VertexQuadric sum = quadric_[t[0]] + quadric_[t[1]] + quadric_[t[2]];
  const Quadric q = sum.total();
  const Vec3 a = mesh_.position(t[0]), b = mesh_.position(t[1]), d = mesh_.position(t[2]);
  const int keep = locked == 1 ? lock_at : 0;
  c.group = {t[keep], t[(keep + 1) % 3], t[(keep + 2) % 3]};
  if (locked == 1) {
    c.p = mesh_.position(t[keep]);
  } else {
    const Vec3 centroid = (a + b + d) / 3.0;
    c.p = place(q, centroid, {a, b, d, centroid});
  }
  c.p = prepared_.points->stored(c.p);  // checked and written as stored
  const double geometric = sum.planes(c.p);
  c.cost = q(c.p);
  c.error = sum.area > 0 ? std::sqrt(geometric / sum.area) : 0;
  // Barycentric weights of p's projection on the triangle, clamped to it, for the arrays.
  const Vec3 p0 = mesh_.position(c.group[0]), p1 = mesh_.position(c.group[1]),
             p2 = mesh_.position(c.group[2]);
  const Vec3 e1 = p1 - p0, e2 = p2 - p0, r = c.p - p0;
  const double d11 = dot(e1, e1), d12 = dot(e1, e2), d22 = dot(e2, e2);
  const double det = d11 * d22 - d12 * d12;
  double w1 = 1.0 / 3, w2 = 1.0 / 3;
  if (det > 0) {
    w1 = std::clamp((d22 * dot(r, e1) - d12 * dot(r, e2)) / det, 0.0, 1.0);
    w2 = std::clamp((d11 * dot(r, e2) - d12 * dot(r, e1)) / det, 0.0, 1.0 - w1);
  }
  c.weights = {1 - w1 - w2, w1, w2};
  c.valid = std::isfinite(c.cost);
  return c;
}

void CellCollapser::fill_heap() {
  const std::size_t nf = mesh_.face_count();
  std::vector<CellEntry> entries(nf);
  std::vector<std::uint8_t> ok(nf, 0);
  parallel_for_range(nf, 1024, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const Fid f = static_cast<Fid>(i);
      if (!mesh_.face_alive(f)) continue;
      const CellCandidate c = evaluate(f);
      if (!c.valid) continue;
      entries[i] = entry(f, c);
      ok[i] = 1;
    }
  });
  heap_.clear();
  for (std::size_t i = 0; i < nf; ++i) {
    if (ok[i]) heap_.push_back(entries[i]);
  }
  std::make_heap(heap_.begin(), heap_.end(), CellLater{});
}

DecimateStats CellCollapser::run() {
  DecimateStats stats;
  stats.input_triangles = mesh_.live_faces();
  stats.locked_vertices = prepared_.locked_count;
  vertex_quadrics(mesh_, options_, quadric_,
                  progress_range(options_.progress, 0, 0.05));
  stamp_.assign(mesh_.vertex_count(), 0);
  fill_heap();
  const std::size_t target = prepared_.target;
  RunLoop loop(stats, target, options_.progress);
  for (;;) {
    while (mesh_.live_faces() > target && !heap_.empty()) {
      std::pop_heap(heap_.begin(), heap_.end(), CellLater{});
      const CellEntry e = heap_.back();
      heap_.pop_back();
      if (!mesh_.face_alive(e.f)) continue;
      const Tri& t = mesh_.face(e.f);
      if (stamp_[t[0]] != e.stamps[0] || stamp_[t[1]] != e.stamps[1] ||
          stamp_[t[2]] != e.stamps[2]) {
        continue;
      }
      const CellCandidate c = evaluate(e.f);
      if (!c.valid) continue;
      if (prepared_.max_error > 0 && c.error > prepared_.max_error) {
        loop.skip_for_error();
        continue;
      }
      if (!loop.accept(mesh_.check_merge(c.group, c.p))) continue;
      const VertexQuadric merged =
          quadric_[c.group[0]] + quadric_[c.group[1]] + quadric_[c.group[2]];
      mesh_.merge(c.group, c.p);
      const std::array<std::size_t, 3> from{c.group[0], c.group[1], c.group[2]};
      attributes_.blend(c.group[0], from, c.weights);
      quadric_[c.group[0]] = merged;
      for (Vid v : c.group) ++stamp_[v];
      stats.max_error = std::max(stats.max_error, c.error);
      for (Fid g : mesh_.faces_of(c.group[0])) {
        const CellCandidate n = evaluate(g);
        if (!n.valid) continue;
        heap_.push_back(entry(g, n));
        std::push_heap(heap_.begin(), heap_.end(), CellLater{});
      }
      loop.done(mesh_.live_faces());
    }
    if (!loop.another_round(mesh_.live_faces())) break;
    fill_heap();
  }
  stats.stop = loop.stop(mesh_.live_faces());
  return stats;
}

}  // namespace

MethodRun decimate_cell_collapse(const PolyData& input, const Prepared& prepared,
                                 const DecimateOptions& options, const EditSettings& settings) {
  return run_on_copy(input, prepared, settings, [&](EditMesh& mesh, CarriedAttributes& attributes) {
    CellCollapser collapser(mesh, attributes, prepared, options);
    return collapser.run();
  });
}

}  // namespace isoforge::reduce
