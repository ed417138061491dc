// Quadric edge collapse (Garland–Heckbert): every vertex carries the area-weighted quadric of
// its faces' planes (plus constraint planes along borders and features); edges are collapsed in
// order of the quadric error at the optimal placement, from a priority queue whose stale entries
// are recognised by per-vertex stamps. Each collapse is checked by EditMesh before it is done.

#include <algorithm>
#include <cmath>
#include <numbers>

#include "isoforge/core/parallel.hpp"
#include "reduce/decimate_internal.hpp"
#include "reduce/quadric.hpp"

namespace isoforge::reduce {
namespace {

// Rounds over every candidate after the queue runs dry (refusals may have been lifted).
constexpr int kMaxRounds = 8;

// 16 bytes, so four entries share a cache line. Stamps only grow, so the sum of the two
// vertices' stamps changes whenever either does: one field tells a stale entry.
struct Entry {
  float cost;
  Vid u, v;
  std::uint32_t stamps;
};

// Heap order: the smallest cost first, ties by vertex ids (deterministic).
struct Later {
  bool operator()(const Entry& a, const Entry& b) const {
    if (a.cost != b.cost) return a.cost > b.cost;
    if (a.u != b.u) return a.u > b.u;
    return a.v > b.v;
  }
};

struct Candidate {
  bool valid = false;
  Vid keep = 0, drop = 0;
  Vec3 p;
  double cost = 0;
  double error = 0;  // RMS distance of p to the planes of the merged faces
  double t = 0;      // where p projects on keep→drop, in [0, 1] (for the point arrays)
};

class Collapser {
 public:
  Collapser(EditMesh& mesh, CarriedAttributes& attributes, const Prepared& prepared,
            const DecimateOptions& options)
      : mesh_(mesh), attributes_(attributes), prepared_(prepared), options_(options) {
    const double w = options.attribute_weight * prepared.diagonal;
    attribute_scale2_ = attributes.empty() ? 0 : w * w;
  }

  DecimateStats run();

 private:
  void build_quadrics();
  [[nodiscard]] Candidate evaluate(Vid u, Vid v) const;
  void push_edges_of(Vid v);
  void fill_heap();

  EditMesh& mesh_;
  CarriedAttributes& attributes_;
  const Prepared& prepared_;
  const DecimateOptions& options_;
  double attribute_scale2_ = 0;
  std::vector<Quadric> quadric_;
  std::vector<PointQuadric> point_;
  std::vector<double> area_;
  std::vector<std::uint32_t> stamp_;
  std::vector<Entry> heap_;
  std::vector<Vid> scratch_;
};

void Collapser::build_quadrics() {
  vertex_quadrics(mesh_, options_, quadric_, point_, area_, progress_range(options_.progress, 0, 0.05));
}

Candidate Collapser::evaluate(Vid u, Vid v) const {
  Candidate c;
  const bool lu = mesh_.locked(u), lv = mesh_.locked(v);
  if (lu && lv) return c;
  const Quadric planes = quadric_[u] + quadric_[v];
  const Quadric q = (point_[u] + point_[v]).added_to(planes);
  const Vec3& pu = mesh_.position(u);
  const Vec3& pv = mesh_.position(v);
  if (lu || lv) {
    c.keep = lu ? u : v;
    c.drop = lu ? v : u;
    c.p = mesh_.position(c.keep);
  } else {
    c.keep = u;
    c.drop = v;
    const Vec3 mid = 0.5 * (pu + pv);
    c.p = minimize(q, mid);
    double best = q(c.p);
    for (const Vec3& x : {pu, pv, mid}) {
      const double e = q(x);
      if (e < best) {
        best = e;
        c.p = x;
      }
    }
  }
  const double geometric = planes(c.p);
  c.cost = q(c.p);
  if (attribute_scale2_ > 0) {
    c.cost += attribute_scale2_ * attributes_.scaled_distance2(u, v) * (area_[u] + area_[v]);
  }
  const double area = area_[u] + area_[v];
  c.error = area > 0 ? std::sqrt(geometric / area) : 0;
  const Vec3 e = mesh_.position(c.drop) - mesh_.position(c.keep);
  const double l2 = norm2(e);
  c.t = l2 > 0 ? std::clamp(dot(c.p - mesh_.position(c.keep), e) / l2, 0.0, 1.0) : 0.5;
  c.valid = std::isfinite(c.cost);
  return c;
}

void Collapser::push_edges_of(Vid v) {
  mesh_.neighbours(v, scratch_);
  for (Vid w : scratch_) {
    const Vid a = std::min(v, w), b = std::max(v, w);
    const Candidate c = evaluate(a, b);
    if (!c.valid) continue;
    heap_.push_back({static_cast<float>(c.cost), a, b, stamp_[a] + stamp_[b]});
    std::push_heap(heap_.begin(), heap_.end(), Later{});
  }
}

void Collapser::fill_heap() {
  // Every live edge once (from its smaller end), evaluated in parallel, in a fixed order.
  const std::size_t nv = mesh_.vertex_count();
  std::vector<std::uint32_t> start(nv + 1, 0);
  {
    std::vector<Vid> nb;
    for (Vid v = 0; v < nv; ++v) {
      mesh_.neighbours(v, nb);
      std::uint32_t k = 0;
      for (Vid w : nb) k += w > v ? 1 : 0;
      start[v + 1] = start[v] + k;
    }
  }
  std::vector<Entry> entries(start[nv]);
  std::vector<std::uint8_t> ok(start[nv], 0);
  parallel_for_range(nv, 512, [&](std::size_t begin, std::size_t end) {
    std::vector<Vid> nb;
    for (std::size_t i = begin; i < end; ++i) {
      const Vid v = static_cast<Vid>(i);
      mesh_.neighbours(v, nb);
      std::sort(nb.begin(), nb.end());
      std::uint32_t at = start[v];
      for (Vid w : nb) {
        if (w <= v) continue;
        const Candidate c = evaluate(v, w);
        entries[at] = {static_cast<float>(c.cost), v, w, stamp_[v] + stamp_[w]};
        ok[at] = c.valid ? 1 : 0;
        ++at;
      }
    }
  });
  heap_.clear();
  heap_.reserve(entries.size() + entries.size() / 2);
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (ok[i]) heap_.push_back(entries[i]);
  }
  std::make_heap(heap_.begin(), heap_.end(), Later{});
}

DecimateStats Collapser::run() {
  DecimateStats stats;
  stats.input_triangles = mesh_.live_faces();
  stats.locked_vertices = prepared_.locked_count;
  build_quadrics();
  stamp_.assign(mesh_.vertex_count(), 0);
  fill_heap();
  report_progress(options_.progress, 0.1, "decimate");
  const std::size_t target = prepared_.target;
  const std::size_t to_remove = stats.input_triangles > target ? stats.input_triangles - target : 0;
  std::size_t skipped_error = 0, since_fill = 0, refused_since_fill = 0, rounds = 0;
  for (;;) {
    while (mesh_.live_faces() > target && !heap_.empty()) {
      std::pop_heap(heap_.begin(), heap_.end(), Later{});
      const Entry e = heap_.back();
      heap_.pop_back();
      if (stamp_[e.u] + stamp_[e.v] != e.stamps) continue;
      const Candidate c = evaluate(e.u, e.v);
      if (!c.valid) continue;
      if (prepared_.max_error > 0 && c.error > prepared_.max_error) {
        ++skipped_error;
        continue;
      }
      const std::array<Vid, 2> group{c.keep, c.drop};
      switch (mesh_.check_merge(group, c.p)) {
        case Refusal::None: break;
        case Refusal::Locked:
        case Refusal::Topology: ++stats.refused_topology; ++refused_since_fill; continue;
        case Refusal::Flip: ++stats.refused_flip; ++refused_since_fill; continue;
        case Refusal::Intersection: ++stats.refused_intersection; ++refused_since_fill; continue;
      }
      const Quadric q = quadric_[c.keep] + quadric_[c.drop];
      const PointQuadric pq = point_[c.keep] + point_[c.drop];
      mesh_.merge(group, c.p);
      const std::array<std::size_t, 2> from{c.keep, c.drop};
      const std::array<double, 2> weights{1 - c.t, c.t};
      attributes_.blend(c.keep, from, weights);
      quadric_[c.keep] = q;
      point_[c.keep] = pq;
      area_[c.keep] += area_[c.drop];
      ++stamp_[c.keep];
      ++stamp_[c.drop];
      ++stats.operations;
      ++since_fill;
      stats.max_error = std::max(stats.max_error, c.error);
      push_edges_of(c.keep);
      if ((stats.operations & 4095) == 0 && to_remove > 0) {
        const double done = static_cast<double>(stats.input_triangles - mesh_.live_faces()) /
                            static_cast<double>(to_remove);
        report_progress(options_.progress, 0.1 + 0.85 * std::min(done, 1.0), "decimate");
      }
    }
    // Refused candidates may have become possible as their neighbourhoods changed: another
    // round over every edge, while rounds still collapse something (at most kMaxRounds).
    if (mesh_.live_faces() <= target || since_fill == 0 || refused_since_fill == 0 ||
        ++rounds > kMaxRounds) {
      break;
    }
    refused_since_fill = 0;
    since_fill = 0;
    skipped_error = 0;
    fill_heap();
  }
  if (mesh_.live_faces() <= target) {
    stats.stop = DecimateStop::Target;
  } else if (skipped_error > 0) {
    stats.stop = DecimateStop::MaxError;
  } else {
    stats.stop = DecimateStop::Exhausted;
  }
  return stats;
}

}  // namespace

DecimateResult decimate_quadric(const PolyData& input, Prepared prepared,
                                const DecimateOptions& options) {
  EditSettings settings;
  settings.preserve_topology = options.preserve_topology;
  settings.max_normal_turn = options.max_normal_turn;
  settings.check_intersections = options.check_self_intersections;
  EditMesh mesh(std::move(prepared.positions), std::move(prepared.triangles),
                std::move(prepared.locked), settings);
  CarriedAttributes attributes(input.point_data);
  Collapser collapser(mesh, attributes, prepared, options);
  DecimateStats stats = collapser.run();
  PolyData output = assemble(mesh, attributes, input.points.type());
  stats.output_triangles = mesh.live_faces();
  stats.output_points = output.num_points();
  report_progress(options.progress, 1.0, "decimate");
  return {std::move(output), stats};
}

}  // namespace isoforge::reduce
