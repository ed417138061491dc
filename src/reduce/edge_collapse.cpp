// Quadric edge collapse (Garland–Heckbert): every vertex carries the area-weighted quadric of
// its faces' planes (plus constraint planes along borders and features); edges are collapsed in
// order of the quadric error at the optimal placement, from a priority queue whose stale entries
// are recognised by per-vertex stamps. Each collapse is checked by EditMesh before it is done.

#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numbers>
#include <optional>
#include <span>

#include "isoforge/core/buffer.hpp"
#include "isoforge/core/parallel.hpp"
#include "isoforge/core/prefetch.hpp"
#include "reduce/decimate_internal.hpp"
#include "reduce/quadric.hpp"
#include "reduce/radix_heap.hpp"

namespace isoforge::reduce {
namespace {

// 16 bytes, so four entries share a cache line. `key` orders the cost (as a float). Stamps only
// grow, so the sum of the two vertices' stamps changes whenever either does: one field tells a
// stale entry.
struct Entry {
  std::uint32_t key;
  Vid u, v;
  std::uint32_t stamps;  // the stamp sum (31 bits), and kExact once `key` is the exact cost
};
// With `preserve_volume` an edge is pushed with its unconstrained cost, a lower bound of the
// volume-preserving one (a minimum under a constraint is never below the free minimum); popped,
// it is evaluated exactly and pushed again with this flag, so edges still come out in the order
// of their exact costs while only the popped ones pay for the constrained placement.
constexpr std::uint32_t kExact = 0x80000000u;

struct Candidate {
  bool valid = false;
  Vid keep = 0, drop = 0;
  Vec3 p;
  double cost = 0;
  double error = 0;  // RMS distance of p to the planes of the merged faces
  double t = 0;      // where p projects on keep→drop, in [0, 1] (for the point arrays)
};

// The quadrics of the vertices (owned by the caller: the parts of a partitioned run fill
// disjoint entries of one set, which the final run then continues from).
using Quadrics = std::vector<VertexQuadric>;

// One run of collapses on a mesh, to `target` faces or until `max_error`.
class Collapser {
 public:
  Collapser(EditMesh& mesh, CarriedAttributes& attributes, Quadrics& quadrics,
            const Prepared& prepared, const DecimateOptions& options, std::size_t target,
            ProgressCallback progress, const std::atomic<bool>* stop_flag = nullptr,
            const MergeLog* replay = nullptr, std::size_t part = 2,
            Buffer<MergeOp>* record = nullptr)
      : mesh_(mesh),
        attributes_(attributes),
        quadric_(quadrics),
        prepared_(prepared),
        target_(target),
        progress_(std::move(progress)),
        stop_flag_(stop_flag),
        replay_(replay != nullptr ? &replay->parts[part] : nullptr),
        record_(record) {
    if (replay != nullptr) {
      replay_tests_ = replay->test[part];
      replay_marked_ = replay->test_marked;
    }
    const double w = options.attribute_weight * prepared.diagonal;
    attribute_scale2_ = attributes.empty() ? 0 : w * w;
    preserve_volume_ = options.preserve_volume;
  }

  DecimateStats run();
  /// Whether the whole replay log was redone (false: a merge in it was refused, or no log).
  [[nodiscard]] bool replayed_all() const { return replayed_all_; }

 private:
  void apply(Vid keep, Vid drop, const Vec3& p, double t, double error, DecimateStats& stats,
             MergeTest test = MergeTest::ByMarks);
  /// Redoes the merges of the replay log up to the first one refused; false if one was.
  bool replay(RunLoop& loop, DecimateStats& stats);
  /// The best collapse of the edge (u, v): with `volume` the volume-preserving placement (which
  /// reads the faces around both ends), otherwise the quadric's own minimum.
  [[nodiscard]] Candidate evaluate(Vid u, Vid v, bool volume = false) const;
  /// The volume-preserving placement of the merged (u, v) next to `mid`, or nullopt where the
  /// constraint is not usable (minimize_on_plane).
  [[nodiscard]] std::optional<Vec3> volume_placement(Vid u, Vid v, const Quadric& q,
                                                     const Vec3& mid) const;
  /// Asks for the records of `vertices` before evaluating their edges: a vertex's neighbours
  /// are scattered, and an evaluation that waits on one cache miss at a time cost 9 % of a run.
  void prefetch_records(std::span<const Vid> vertices) const {
    for (Vid w : vertices) {
      const auto* q = reinterpret_cast<const char*>(&quadric_[w]);
      prefetch(q);
      prefetch(q + 64);
      prefetch(&mesh_.position(w));
    }
  }
  void push_edges_of(Vid v);
  void fill_heap();

  EditMesh& mesh_;
  CarriedAttributes& attributes_;
  Quadrics& quadric_;
  const Prepared& prepared_;
  std::size_t target_;
  ProgressCallback progress_;
  const std::atomic<bool>* stop_flag_;
  const Buffer<MergeOp>* replay_;
  std::span<const std::uint32_t> replay_tests_;  // positions in replay_ to test (ascending)
  bool replay_marked_ = false;                   // also test the merges of marked vertices
  Buffer<MergeOp>* record_;
  bool replayed_all_ = false;
  double attribute_scale2_ = 0;
  bool preserve_volume_ = false;
  Entry last_{0, 0, 0, 0};  // the last entry pushed back with its exact cost, and its evaluation
  Candidate last_candidate_;
  std::size_t last_faces_ = 0;
  std::vector<std::uint32_t> stamp_;
  RadixHeap<Entry> heap_;
  std::vector<Vid> scratch_;
};

std::optional<Vec3> Collapser::volume_placement(Vid u, Vid v, const Quadric& q,
                                                const Vec3& mid) const {
  // The collapse replaces the faces around both ends (each once) by a fan around p; the volume
  // between the two surfaces is the sum of the tetrahedra from p to the old faces,
  // (p·n − s) / 6 with n = Σ (b − a) × (c − a) and s = Σ a·((b − a) × (c − a)). It is zero, and
  // the enclosed volume unchanged, on the plane n·p = s.
  Vec3 n{0, 0, 0};
  double s = 0, scale = 0;
  const auto add = [&](Fid f) {
    const Tri& t = mesh_.face(f);
    const Vec3& a = mesh_.position(t[0]);
    const Vec3 m = cross(mesh_.position(t[1]) - a, mesh_.position(t[2]) - a);
    n = n + m;
    s += dot(a, m);
    scale += norm(m);
  };
  for (Fid f : mesh_.faces_of(u)) add(f);
  for (Fid f : mesh_.faces_of(v)) {
    const Tri& t = mesh_.face(f);
    if (t[0] != u && t[1] != u && t[2] != u) add(f);
  }
  return minimize_on_plane(q, mid, n, s, scale, norm(mesh_.position(v) - mesh_.position(u)));
}

Candidate Collapser::evaluate(Vid u, Vid v, bool volume) const {
  Candidate c;
  const bool lu = mesh_.locked(u), lv = mesh_.locked(v);
  if (lu && lv) return c;
  const VertexQuadric sum = quadric_[u] + quadric_[v];
  const Quadric q = sum.total();
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
    const std::optional<Vec3> p = volume ? volume_placement(u, v, q, mid) : std::nullopt;
    c.p = p ? *p : place(q, mid, {pu, pv, mid});
  }
  c.p = prepared_.points->stored(c.p);  // checked and written as stored
  const double geometric = sum.planes(c.p);
  c.cost = q(c.p);
  if (attribute_scale2_ > 0) {
    c.cost += attribute_scale2_ * attributes_.scaled_distance2(u, v) * sum.area;
  }
  c.error = sum.area > 0 ? std::sqrt(geometric / sum.area) : 0;
  const Vec3 e = mesh_.position(c.drop) - mesh_.position(c.keep);
  const double l2 = norm2(e);
  c.t = l2 > 0 ? std::clamp(dot(c.p - mesh_.position(c.keep), e) / l2, 0.0, 1.0) : 0.5;
  c.valid = std::isfinite(c.cost);
  return c;
}

void Collapser::push_edges_of(Vid v) {
  mesh_.neighbours(v, scratch_);
  prefetch_records(scratch_);
  for (Vid w : scratch_) {
    const Vid a = std::min(v, w), b = std::max(v, w);
    const Candidate c = evaluate(a, b);
    if (!c.valid) continue;
    heap_.push({order_key(static_cast<float>(c.cost)), a, b, (stamp_[a] + stamp_[b]) & ~kExact});
  }
}

void Collapser::fill_heap() {
  // Every live edge once (from its smaller end), evaluated in parallel, in a fixed order.
  const std::size_t nv = mesh_.vertex_count();
  Buffer<std::uint32_t> start(nv + 1);  // every entry written
  start[0] = 0;
  {
    std::vector<Vid> nb;
    for (Vid v = 0; v < nv; ++v) {
      mesh_.neighbours(v, nb);
      std::uint32_t k = 0;
      for (Vid w : nb) k += w > v ? 1 : 0;
      start[v + 1] = start[v] + k;
    }
  }
  Buffer<Entry> entries(start[nv]);  // every entry written
  Buffer<std::uint8_t> ok(start[nv]);
  parallel_for_range(nv, 512, [&](std::size_t begin, std::size_t end) {
    std::vector<Vid> nb;
    for (std::size_t i = begin; i < end; ++i) {
      const Vid v = static_cast<Vid>(i);
      mesh_.neighbours(v, nb);
      std::sort(nb.begin(), nb.end());
      prefetch_records(nb);
      std::uint32_t at = start[v];
      for (Vid w : nb) {
        if (w <= v) continue;
        const Candidate c = evaluate(v, w);
        entries[at] = {order_key(static_cast<float>(c.cost)), v, w,
                       (stamp_[v] + stamp_[w]) & ~kExact};
        ok[at] = c.valid ? 1 : 0;
        ++at;
      }
    }
  });
  std::size_t kept = 0;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (ok[i]) entries[kept++] = entries[i];
  }
  entries.resize(kept);
  heap_.assign(entries);
}

void Collapser::apply(Vid keep, Vid drop, const Vec3& p, double t, double error,
                      DecimateStats& stats, MergeTest test) {
  const std::array<Vid, 2> group{keep, drop};
  mesh_.merge(group, p, test);
  const std::array<std::size_t, 2> from{keep, drop};
  const std::array<double, 2> weights{1 - t, t};
  attributes_.blend(keep, from, weights);
  quadric_[keep] += quadric_[drop];
  ++stamp_[keep];
  ++stamp_[drop];
  stats.max_error = std::max(stats.max_error, error);
  if (record_ != nullptr) record_->push_back({keep, drop, p, t, error});
}

bool Collapser::replay(RunLoop& loop, DecimateStats& stats) {
  // Until a merge is refused the mesh is the one the logged run had at the same step, so the
  // merges are valid as they were, except where the finished mesh's test found an intersection:
  // the later merge of each pair of faces found is tested now (and, when this run defers no
  // test, every merge). The merges of marked vertices were all tested here before: nearly all
  // of them early merges whose faces later merges remade, a quarter of a deep run's merges and
  // half its time.
  auto next_test = replay_tests_.begin();
  for (std::size_t i = 0; i < replay_->size(); ++i) {
    if (mesh_.live_faces() <= target_) break;
    const MergeOp& op = (*replay_)[i];
    const std::array<Vid, 2> group{op.keep, op.drop};
    while (next_test != replay_tests_.end() && *next_test < i) ++next_test;
    const bool test = (next_test != replay_tests_.end() && *next_test == i) ||
                      ((replay_marked_ || !mesh_.defers_tests()) && mesh_.tests_now(group));
    if (test && !loop.accept(mesh_.check_merge(group, op.p, MergeTest::Now))) return false;
    apply(op.keep, op.drop, op.p, op.t, op.error, stats,
          test ? MergeTest::Now : MergeTest::Deferred);
    loop.done(mesh_.live_faces(), stop_flag_);
  }
  return true;
}

DecimateStats Collapser::run() {
  DecimateStats stats;
  stats.input_triangles = mesh_.live_faces();
  stamp_.assign(mesh_.vertex_count(), 0);
  const std::size_t target = target_;
  RunLoop loop(stats, target, progress_);
  // Past the first merge refused, the run chooses afresh: those merges are tested as they are
  // made, so the test of the finished mesh finds nothing new there (faces the log's merges made
  // can still meet where the merges that remade them in the logged run are not redone).
  if (replay_ != nullptr) {
    replayed_all_ = replay(loop, stats);
    if (!replayed_all_) mesh_.test_every_merge();
  }
  if (mesh_.live_faces() <= target) {
    stats.stop = loop.stop(mesh_.live_faces());
    return stats;
  }
  fill_heap();
  report_progress(progress_, 0.1, "decimate");
  for (;;) {
    while (mesh_.live_faces() > target && !heap_.empty()) {
      const Entry e = heap_.pop();
      if (((stamp_[e.u] + stamp_[e.v]) & ~kExact) != (e.stamps & ~kExact)) continue;
      // The merge's check reads the faces around both ends: asked for now, they arrive while
      // the edge is evaluated.
      mesh_.prefetch_faces(e.u);
      mesh_.prefetch_faces(e.v);
      // An edge pushed back with its exact cost usually comes out next: its evaluation is kept
      // if no merge has changed the faces around it since.
      const bool again = (e.stamps & kExact) != 0 && e.u == last_.u && e.v == last_.v &&
                         e.stamps == last_.stamps && mesh_.live_faces() == last_faces_;
      const Candidate c = again ? last_candidate_ : evaluate(e.u, e.v, preserve_volume_);
      if (!c.valid) continue;
      if (preserve_volume_ && (e.stamps & kExact) == 0) {
        // The key was a lower bound: back in the queue with the exact cost, unless that is it.
        const std::uint32_t key = order_key(static_cast<float>(c.cost));
        if (key > e.key) {
          last_ = {key, e.u, e.v, e.stamps | kExact};
          last_candidate_ = c;
          last_faces_ = mesh_.live_faces();
          heap_.push(last_);
          continue;
        }
      }
      if (prepared_.max_error > 0 && c.error > prepared_.max_error) {
        loop.skip_for_error();
        continue;
      }
      const std::array<Vid, 2> group{c.keep, c.drop};
      if (!loop.accept(mesh_.check_merge(group, c.p))) continue;
      apply(c.keep, c.drop, c.p, c.t, c.error, stats);
      push_edges_of(c.keep);
      loop.done(mesh_.live_faces(), stop_flag_);
    }
    if (!loop.another_round(mesh_.live_faces())) break;
    fill_heap();
  }
  stats.stop = loop.stop(mesh_.live_faces());
  return stats;
}

// Runs below this many triangles are not partitioned (the second core would not pay).
constexpr std::size_t kPartitionMinFaces = 150'000;
// Nor runs to fewer triangles than this many times the faces crossing the cut: those stay fine
// (locked) until the joined run, so on a deep target they crowd the output. The 1M-triangle
// surface (1 680 crossing faces) to 2 % (12.5 times) was slower partitioned, with a rerun for
// an intersection, and worse (RMS 3.30e-5 against 3.15e-5); to 10 % (63 times) the halves pay.
constexpr std::size_t kPartitionMinTargetPerCrossing = 20;

void add_stats(DecimateStats& into, const DecimateStats& s) {
  into.operations += s.operations;
  into.max_error = std::max(into.max_error, s.max_error);
  into.refused_topology += s.refused_topology;
  into.refused_flip += s.refused_flip;
  into.refused_intersection += s.refused_intersection;
}

// The partitioned first phase on large meshes (docs/algorithms/decimation.md, "Two cores"): the
// vertices are split at the median of the longest axis; each half is decimated on its own with
// the vertices of the faces that cross the cut locked and every moved vertex kept strictly on its
// side, so the halves' new faces can never meet; then one sequential run over the joined mesh,
// the cut unlocked, goes to the target. The split does not depend on the thread count, and the
// halves run on the calling thread and one task (one after the other with one thread), so the
// result does not either.
struct Partitioned {
  std::vector<Vec3> positions;
  std::vector<Tri> triangles;
  Quadrics quadrics;
  DecimateStats stats;
  std::vector<Vid> merged_into;
  std::vector<std::uint32_t> writers;   // per triangle: EditMesh::face_writer
  bool replayed_all = false;            // both halves redid their whole logs
};

// nullopt, having done nothing, when the target is too deep for the cut
// (kPartitionMinTargetPerCrossing).
std::optional<Partitioned> decimate_halves(const Prepared& prepared, CarriedAttributes& attributes,
                                           const DecimateOptions& options, const EditSettings& base,
                                           const MergeLog* replay, MergeLog* record,
                                           const ProgressCallback& progress) {
  const std::size_t nv = prepared.positions.size();
  Bounds box;
  for (const Tri& t : prepared.triangles) {
    for (Vid v : t) box.extend(prepared.positions[v]);
  }
  const Vec3 extent = box.max - box.min;
  const int axis =
      extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  std::vector<std::uint8_t> used(nv, 0);
  for (const Tri& t : prepared.triangles) {
    for (Vid v : t) used[v] = 1;
  }
  std::vector<double> coordinate;
  for (std::size_t v = 0; v < nv; ++v) {
    if (used[v]) coordinate.push_back(prepared.positions[v][axis]);
  }
  std::nth_element(coordinate.begin(), coordinate.begin() + coordinate.size() / 2,
                   coordinate.end());
  const double cut = coordinate[coordinate.size() / 2];
  std::vector<std::uint8_t> sides(nv);
  for (std::size_t v = 0; v < nv; ++v) sides[v] = prepared.positions[v][axis] < cut ? 0 : 1;
  auto side = [&](Vid v) { return static_cast<int>(sides[v]); };

  // The faces of each side and those crossing the cut, counted first: a target too deep for the
  // cut is known before anything is copied.
  std::array<std::size_t, 2> own{0, 0};
  std::size_t crossing = 0;
  for (const Tri& t : prepared.triangles) {
    const int s0 = side(t[0]), s1 = side(t[1]), s2 = side(t[2]);
    if (s0 == s1 && s1 == s2) {
      ++own[static_cast<std::size_t>(s0)];
    } else {
      ++crossing;
    }
  }
  if (prepared.target > 0 && prepared.target < kPartitionMinTargetPerCrossing * crossing) {
    return std::nullopt;
  }
  std::array<std::vector<Tri>, 2> faces;
  for (std::size_t h = 0; h < 2; ++h) faces[h].reserve(own[h] + crossing);
  std::array<std::vector<std::uint8_t>, 2> locks{prepared.locked, prepared.locked};
  for (const Tri& t : prepared.triangles) {
    const int s0 = side(t[0]), s1 = side(t[1]), s2 = side(t[2]);
    if (s0 == s1 && s1 == s2) {
      faces[static_cast<std::size_t>(s0)].push_back(t);
      continue;
    }
    for (int h = 0; h < 2; ++h) {
      faces[static_cast<std::size_t>(h)].push_back(t);
      for (Vid v : t) locks[static_cast<std::size_t>(h)][v] = 1;
    }
  }
  // Each half goes a little above its share of the target, so the joined run still has work
  // to do along the cut.
  const double total = static_cast<double>(prepared.triangles.size());
  std::array<std::size_t, 2> targets{};
  for (int h = 0; h < 2; ++h) {
    const double own = static_cast<double>(faces[static_cast<std::size_t>(h)].size() - crossing);
    const double share = prepared.target > 0
                             ? 1.03 * static_cast<double>(prepared.target) *
                                   (own + 0.5 * static_cast<double>(crossing)) / total
                             : 0.0;
    targets[static_cast<std::size_t>(h)] = static_cast<std::size_t>(share) + crossing;
  }

  // One set of quadrics: a half computes and changes only those of its side's vertices (it never
  // reads the others': a vertex of the other side is on a crossing face, locked, and an edge
  // to it has a locked end on this side too, so it is never evaluated).
  Partitioned out;
  out.merged_into.resize(nv);
  out.quadrics.resize(nv);
  std::array<std::optional<EditMesh>, 2> meshes;
  std::array<DecimateStats, 2> stats;
  std::array<bool, 2> replayed{false, false};
  std::atomic<bool> stop{false};
  auto run_half = [&](int h, const ProgressCallback& report) {
    const auto i = static_cast<std::size_t>(h);
    EditSettings settings = base;
    settings.side_axis = axis;
    settings.side_cut = cut;
    settings.side_below = h == 0;
    settings.log_part = static_cast<std::uint32_t>(h);
    meshes[i].emplace(prepared.positions, std::move(faces[i]), std::move(locks[i]), settings);
    vertex_quadrics(*meshes[i], options, out.quadrics, {}, sides, static_cast<std::uint8_t>(h));
    Collapser collapser(*meshes[i], attributes, out.quadrics, prepared, options, targets[i], report,
                        &stop, replay, i, record != nullptr ? &record->parts[i] : nullptr);
    stats[i] = collapser.run();
    replayed[i] = collapser.replayed_all();
  };
  tbb::task_group group;
  group.run([&] {
    try {
      run_half(1, {});
    } catch (...) {
      stop = true;
      throw;
    }
  });
  try {
    run_half(0, progress);
  } catch (...) {
    stop = true;
    try {
      group.wait();
    } catch (...) {
    }
    throw;
  }
  group.wait();

  // Join: each vertex from the half of its side; the crossing faces (unchanged, in both) once.
  out.positions = prepared.positions;
  for (Vid v = 0; v < nv; ++v) {
    const auto h = static_cast<std::size_t>(side(v));
    out.positions[v] = meshes[h]->position(v);
    out.merged_into[v] = meshes[h]->merged_into(v);
  }
  out.replayed_all = replayed[0] && replayed[1];
  for (int h = 0; h < 2; ++h) {
    const EditMesh& m = *meshes[static_cast<std::size_t>(h)];
    for (Fid f = 0; f < m.face_count(); ++f) {
      if (!m.face_alive(f)) continue;
      const Tri& t = m.face(f);
      const bool crosses = side(t[0]) != side(t[1]) || side(t[1]) != side(t[2]);
      if (crosses && h == 1) continue;
      out.triangles.push_back(t);
      out.writers.push_back(m.face_writer(f));
    }
    add_stats(out.stats, stats[static_cast<std::size_t>(h)]);
  }
  return out;
}

}  // namespace

MethodRun decimate_quadric(const PolyData& input, const Prepared& prepared,
                           const DecimateOptions& options, const EditSettings& settings,
                           const MergeLog* replay) {
  MethodRun run;
  run.attributes.emplace(input.point_data);
  CarriedAttributes& attributes = *run.attributes;
  DecimateStats& stats = run.stats;
  stats.input_triangles = prepared.triangles.size();
  stats.locked_vertices = prepared.locked_count;
  Quadrics quadrics;
  std::vector<Vec3> positions;
  std::vector<Tri> triangles;
  std::vector<std::uint32_t> halves_writers;
  MergeLog* record = settings.defer_intersections ? &run.log : nullptr;
  double from = 0;
  std::optional<Partitioned> partitioned;
  bool test_all = false;
  if (prepared.triangles.size() >= kPartitionMinFaces &&
      (prepared.target == 0 || static_cast<double>(prepared.target) <
                                   0.7 * static_cast<double>(prepared.triangles.size()))) {
    partitioned = decimate_halves(prepared, attributes, options, settings, replay, record,
                                  progress_range(options.progress, 0, 0.85));
  }
  const bool split = partitioned.has_value();
  if (split) {
    Partitioned& halves = *partitioned;
    // The joined run's log continues from the halves' results: only valid if they are the same;
    // otherwise the joined run is new, and tests every merge (as a run past its first refusal).
    if (!halves.replayed_all && replay != nullptr) {
      replay = nullptr;
      test_all = true;
    }
    positions = std::move(halves.positions);
    triangles = std::move(halves.triangles);
    quadrics = std::move(halves.quadrics);
    run.merged_into = std::move(halves.merged_into);
    halves_writers = std::move(halves.writers);
    add_stats(stats, halves.stats);
    from = 0.85;
  } else {
    positions = prepared.positions;
    triangles = prepared.triangles;
  }
  // The joined run keeps the marks the halves spread (a merged vertex is marked if a member was).
  EditSettings joined = settings;
  if (split && !joined.check_near.empty()) {
    for (Vid v = 0; v < joined.check_near.size(); ++v) {
      if (joined.check_near[v] != 0) joined.check_near[find_root(run.merged_into, v)] = 1;
    }
  }
  const std::vector<std::uint32_t> writers = std::move(halves_writers);
  run.mesh.emplace(std::move(positions), std::move(triangles), prepared.locked, joined);
  EditMesh& mesh = *run.mesh;
  if (test_all) mesh.test_every_merge();
  for (Fid f = 0; f < writers.size(); ++f) {
    if (writers[f] != 0) mesh.mark_unchecked(f, writers[f]);
  }
  if (!split) {
    vertex_quadrics(mesh, options, quadrics, progress_range(options.progress, 0, 0.05));
  }
  Collapser collapser(mesh, attributes, quadrics, prepared, options, prepared.target,
                      progress_range(options.progress, from, 1.0), nullptr, replay, 2,
                      record != nullptr ? &record->parts[2] : nullptr);
  const DecimateStats last = collapser.run();
  add_stats(stats, last);
  stats.stop = last.stop;
  if (split) {
    for (Vid v = 0; v < run.merged_into.size(); ++v) {
      if (run.merged_into[v] == v) run.merged_into[v] = mesh.merged_into(v);
    }
  }
  return run;
}

}  // namespace isoforge::reduce
