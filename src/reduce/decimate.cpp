#include "isoforge/reduce/decimate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "isoforge/core/mesh_topology.hpp"
#include "isoforge/core/parallel.hpp"
#include "isoforge/core/subset.hpp"
#include "isoforge/spatial/self_intersections.hpp"
#include "reduce/decimate_internal.hpp"

namespace isoforge {
namespace reduce {
namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw Error("decimate: " + what);
}

// Locks the vertices of edges with more than two faces and the vertices whose faces form more
// than one fan: decimation leaves them (and so the non-manifold parts of the input) as they are.
// Each vertex looks at its own faces only (an edge seen from both ends locks both), so the
// vertices are done in parallel.
void lock_non_manifold(const std::vector<Tri>& tris, std::vector<std::uint8_t>& locked) {
  const std::size_t nv = locked.size();
  std::vector<std::uint32_t> start(nv + 1, 0);
  for (const Tri& t : tris) {
    for (Vid v : t) ++start[v + 1];
  }
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<Fid> around(start[nv]);
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (Fid f = 0; f < tris.size(); ++f) {
    for (Vid v : tris[f]) around[fill[v]++] = f;
  }
  parallel_for_range(nv, 4096, [&](std::size_t begin, std::size_t end) {
    std::vector<std::array<Vid, 2>> spokes;  // (other vertex of an edge at v, face at v)
    std::vector<std::uint32_t> parent;
    for (std::size_t v = begin; v < end; ++v) {
      const std::uint32_t b = start[v], e = start[v + 1];
      if (e - b < 2 || locked[v]) continue;
      spokes.clear();
      for (std::uint32_t i = b; i < e; ++i) {
        for (Vid x : tris[around[i]]) {
          if (x != v) spokes.push_back({x, i - b});
        }
      }
      std::sort(spokes.begin(), spokes.end());
      // Runs of one other vertex are the faces of one edge; faces of one edge are in one fan.
      parent.resize(e - b);
      for (std::uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
      auto find = [&](std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
      };
      std::size_t fans = e - b;
      bool lock = false;
      for (std::size_t i = 0; i < spokes.size() && !lock;) {
        std::size_t j = i + 1;
        for (; j < spokes.size() && spokes[j][0] == spokes[i][0]; ++j) {
          const std::uint32_t ri = find(spokes[i][1]), rj = find(spokes[j][1]);
          if (ri != rj) {
            parent[ri] = rj;
            --fans;
          }
        }
        lock = j - i > 2;
        i = j;
      }
      if (lock || fans > 1) locked[v] = 1;
    }
  });
}

}  // namespace

Prepared prepare(const PolyData& input, const DecimateOptions& o) {
  const bool by_count = o.target_triangles > 0;
  const bool by_ratio = o.target_reduction != 0;
  const bool by_error = o.max_error != 0;
  require(std::isfinite(o.target_reduction) && o.target_reduction >= 0 && o.target_reduction < 1,
          fmt::format("target reduction {} is not in [0, 1)", o.target_reduction));
  require(std::isfinite(o.max_error) && o.max_error >= 0,
          fmt::format("maximum error {} is not a finite value >= 0", o.max_error));
  require(!(by_count && by_ratio), "a target triangle count and a target reduction contradict");
  require(by_count || by_ratio || by_error,
          "no stop is set (a target triangle count, a target reduction or a maximum error)");
  require(std::isfinite(o.boundary_weight) && o.boundary_weight >= 0,
          fmt::format("boundary weight {} is not a finite value >= 0", o.boundary_weight));
  require(std::isfinite(o.feature_angle) && o.feature_angle > 0 && o.feature_angle <= 180,
          fmt::format("feature angle {} is not in (0, 180] degrees", o.feature_angle));
  require(std::isfinite(o.max_normal_turn) && o.max_normal_turn > 0 && o.max_normal_turn <= 180,
          fmt::format("maximum normal turn {} is not in (0, 180] degrees", o.max_normal_turn));
  require(std::isfinite(o.attribute_weight) && o.attribute_weight >= 0,
          fmt::format("attribute weight {} is not a finite value >= 0", o.attribute_weight));
  input.validate();
  require(input.num_points() < std::numeric_limits<Vid>::max(),
          fmt::format("{} points is more than decimation supports", input.num_points()));

  Prepared p;
  const auto faces = triangulate_faces(input);
  p.triangles.reserve(faces.size());
  for (const auto& t : faces) {
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;  // degenerate by ids
    p.triangles.push_back({static_cast<Vid>(t[0]), static_cast<Vid>(t[1]), static_cast<Vid>(t[2])});
  }
  require(!p.triangles.empty(), "the input has no triangle (polygons or strips)");
  require(p.triangles.size() < std::numeric_limits<Fid>::max() / 2,
          fmt::format("{} triangles is more than decimation supports", p.triangles.size()));
  const std::size_t n = input.num_points();
  p.positions.resize(n);
  Bounds box;
  std::vector<std::uint8_t> used(n, 0);
  for (const Tri& t : p.triangles) {
    for (Vid v : t) used[v] = 1;
  }
  for (std::size_t i = 0; i < n; ++i) {
    p.positions[i] = input.points[i];
    if (!used[i]) continue;
    require(is_finite(p.positions[i]), fmt::format("point {} is not finite", i));
    box.extend(p.positions[i]);
  }
  p.diagonal = norm(box.max - box.min);
  p.points = &input.points;
  p.locked.assign(n, 0);
  if (!o.lock_array.empty()) {
    const DataArray* mask = input.point_data.find(o.lock_array);
    require(mask != nullptr,
            fmt::format("lock array '{}' is not a point array of the input", o.lock_array));
    require(mask->components() == 1, fmt::format("lock array '{}' has {} components, not 1",
                                                 o.lock_array, mask->components()));
    for (std::size_t i = 0; i < n; ++i) p.locked[i] = mask->get(i) != 0 ? 1 : 0;
  }
  lock_non_manifold(p.triangles, p.locked);
  for (std::size_t i = 0; i < n; ++i) p.locked_count += (p.locked[i] && used[i]) ? 1 : 0;
  const std::size_t count = p.triangles.size();
  if (by_count) p.target = std::min(o.target_triangles, count);
  if (by_ratio) {
    p.target = static_cast<std::size_t>(
        std::llround(static_cast<double>(count) * (1 - o.target_reduction)));
  }
  p.max_error = o.max_error_relative ? o.max_error * p.diagonal : o.max_error;
  return p;
}

CarriedAttributes::CarriedAttributes(const Attributes& point_data) : source_(&point_data) {
  for (const DataArray& a : point_data) width_ += static_cast<std::size_t>(a.components());
  if (width_ == 0) return;
  const std::size_t n = point_data[0].tuples();
  values_.resize(n * width_);
  changed_.assign(n, 0);
  std::size_t column = 0;
  for (const DataArray& a : point_data) {
    for (int c = 0; c < a.components(); ++c, ++column) {
      const auto [lo, hi] = a.range(c);
      const double span = hi - lo;
      inverse_range2_.push_back(std::isfinite(span) && span > 0 ? 1 / (span * span) : 0.0);
      for (std::size_t i = 0; i < n; ++i) values_[i * width_ + column] = a.get(i, c);
    }
  }
}

double CarriedAttributes::scaled_distance2(std::size_t a, std::size_t b) const {
  const double* x = row(a);
  const double* y = row(b);
  double s = 0;
  for (std::size_t c = 0; c < width_; ++c) {
    const double d = x[c] - y[c];
    if (std::isfinite(d)) s += d * d * inverse_range2_[c];
  }
  return s;
}

void CarriedAttributes::blend(std::size_t into, std::span<const std::size_t> from,
                              std::span<const double> weights) {
  if (width_ == 0) return;
  double sum[64];
  std::vector<double> big;
  double* out = sum;
  if (width_ > 64) {
    big.resize(width_);
    out = big.data();
  }
  for (std::size_t c = 0; c < width_; ++c) {
    double s = 0;
    for (std::size_t i = 0; i < from.size(); ++i) s += weights[i] * row(from[i])[c];
    out[c] = s;
  }
  std::copy(out, out + width_, values_.data() + into * width_);
  changed_[into] = 1;
}

Attributes CarriedAttributes::output(const std::vector<Vid>& kept) const {
  Attributes out = empty_like(*source_, kept.size());
  if (width_ == 0) return out;
  const std::string& normals = source_->active_name(AttributeRole::Normals);
  for (std::size_t i = 0; i < kept.size(); ++i) {
    const Vid v = kept[i];
    if (!changed_[v]) {
      copy_tuple(*source_, v, out, i);
      continue;
    }
    std::size_t column = 0;
    for (std::size_t k = 0; k < source_->size(); ++k) {
      const DataArray& in = (*source_)[k];
      DataArray& a = out[k];
      const int nc = in.components();
      const double* r = row(v) + column;
      double scale = 1;
      if (nc == 3 && in.name() == normals) {
        const double l = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
        scale = l > 0 ? 1 / l : 1;
      }
      const bool integral = !is_floating(in.type());
      for (int c = 0; c < nc; ++c) {
        const double x = r[c] * scale;
        a.set(i, c, integral ? std::round(x) : x);
      }
      column += static_cast<std::size_t>(nc);
    }
  }
  return out;
}

CellArray live_cells(const EditMesh& mesh, const std::vector<Vid>* map, std::vector<Fid>* face_of) {
  Buffer<Index> offsets, connectivity;
  offsets.reserve(mesh.live_faces() + 1);
  connectivity.reserve(3 * mesh.live_faces());
  offsets.push_back(0);
  for (Fid f = 0; f < mesh.face_count(); ++f) {
    if (!mesh.face_alive(f)) continue;
    if (face_of != nullptr) face_of->push_back(f);
    for (Vid v : mesh.face(f)) connectivity.push_back(map != nullptr ? (*map)[v] : v);
    offsets.push_back(static_cast<Index>(connectivity.size()));
  }
  return CellArray(std::move(offsets), std::move(connectivity));
}

PolyData assemble(const EditMesh& mesh, const CarriedAttributes& attributes,
                  ScalarType point_type) {
  const std::size_t nv = mesh.vertex_count();
  std::vector<Vid> kept;
  std::vector<Vid> map(nv, std::numeric_limits<Vid>::max());
  for (Vid v = 0; v < nv; ++v) {
    if (!mesh.faces_of(v).empty()) {
      map[v] = static_cast<Vid>(kept.size());
      kept.push_back(v);
    }
  }
  PolyData out;
  out.points = Points(kept.size(), point_type);
  for (std::size_t i = 0; i < kept.size(); ++i) out.points.set(i, mesh.position(kept[i]));
  out.polys = live_cells(mesh, &map);
  out.point_data = attributes.output(kept);
  return out;
}

EditSettings edit_settings(const DecimateOptions& options) {
  EditSettings settings;
  settings.preserve_topology = options.preserve_topology;
  settings.max_normal_turn = options.max_normal_turn;
  settings.check_intersections = options.check_self_intersections;
  return settings;
}

bool RunLoop::accept(Refusal r) {
  switch (r) {
    case Refusal::None:
      return true;
    case Refusal::Locked:
    case Refusal::Topology:
      ++stats_.refused_topology;
      break;
    case Refusal::Flip:
      ++stats_.refused_flip;
      break;
    case Refusal::Intersection:
      ++stats_.refused_intersection;
      break;
  }
  ++refused_since_fill_;
  return false;
}

void RunLoop::done(std::size_t live, const std::atomic<bool>* stop) {
  ++stats_.operations;
  ++since_fill_;
  if ((stats_.operations & 2047) != 0) return;
  if (stop != nullptr && stop->load(std::memory_order_relaxed)) throw Cancelled("decimate");
  const std::size_t from = stats_.input_triangles;
  if (from > target_) {
    const double f =
        static_cast<double>(from - std::min(live, from)) / static_cast<double>(from - target_);
    report_progress(progress_, 0.1 + 0.9 * std::min(f, 1.0), "decimate");
  }
}

bool RunLoop::another_round(std::size_t live) {
  if (live <= target_ || since_fill_ == 0 || refused_since_fill_ == 0 || ++rounds_ > kMaxRounds) {
    return false;
  }
  refused_since_fill_ = 0;
  since_fill_ = 0;
  skipped_error_ = 0;
  return true;
}

DecimateStop RunLoop::stop(std::size_t live) const {
  if (live <= target_) return DecimateStop::Target;
  return skipped_error_ > 0 ? DecimateStop::MaxError : DecimateStop::Exhausted;
}

DecimateResult finish(const EditMesh& mesh, const CarriedAttributes& attributes,
                      const PolyData& input, DecimateStats stats, const DecimateOptions& options) {
  PolyData output = assemble(mesh, attributes, input.points.type());
  stats.output_triangles = mesh.live_faces();
  stats.output_points = output.num_points();
  report_progress(options.progress, 1.0, "decimate");
  return {std::move(output), stats};
}

}  // namespace reduce

namespace reduce {
namespace {

// Deferred runs before one with every edit tested (docs/algorithms/decimation.md,
// "Deferred tests and certification").
constexpr int kDeferredRuns = 4;

// The pairs of live faces of `mesh` that intersect (exact) where one face was made by an
// untested merge: the only pairs that can be new (a tested edit met no face it intersects, and
// the faces it made kept their place until a later edit made them again).
std::vector<std::array<Fid, 2>> untested_intersections(const EditMesh& mesh,
                                                       const ProgressCallback& progress) {
  PolyData live;
  live.points = Points(mesh.vertex_count(), ScalarType::Float64);
  for (Vid v = 0; v < mesh.vertex_count(); ++v) live.points.set(v, mesh.position(v));
  std::vector<Fid> face_of;
  face_of.reserve(mesh.live_faces());
  live.polys = live_cells(mesh, nullptr, &face_of);
  SelfIntersectionOptions si;
  si.progress = progress;
  std::vector<std::array<Fid, 2>> out;
  for (const auto& [i, j] : self_intersections(live, si)) {
    const Fid a = face_of[static_cast<std::size_t>(i)], b = face_of[static_cast<std::size_t>(j)];
    if (mesh.face_unchecked(a) || mesh.face_unchecked(b)) out.push_back({a, b});
  }
  return out;
}

// Marks, in `near`, every input vertex merged into a vertex of the faces in `pairs` or of
// their neighbours: the next run tests the merges that made those faces.
void mark_near(const MethodRun& run, const std::vector<std::array<Fid, 2>>& pairs,
               std::vector<std::uint8_t>& near) {
  const EditMesh& mesh = *run.mesh;
  const std::size_t nv = mesh.vertex_count();
  std::vector<std::uint8_t> hit(nv, 0);
  std::vector<Vid> ring;
  for (const auto& pair : pairs) {
    for (Fid f : pair) {
      for (Vid v : mesh.face(f)) {
        hit[v] = 1;
        mesh.neighbours(v, ring);
        for (Vid w : ring) hit[w] = 1;
      }
    }
  }
  std::vector<Vid> merged = run.merged_into;
  for (Vid v = 0; v < nv; ++v) {
    if (hit[find_root(merged, v)] != 0) near[v] = 1;
  }
}

// Fills log.test with the merges a redone run tests. For each pair the finished mesh's test
// found, with a the face made earlier and b the later one: the merge that made b as it is (a
// then stood as it does, so tested it is refused); with `wide`, or when a was made by no untested
// merge (an input face, which b's earlier forms may all cut: the input's own intersections),
// also every merge between the two whose vertex ends in a vertex of a or b — the ones that made
// b's earlier forms around there, which stand again when that merge is refused. The first redone
// run tests the last merges only: tests need the grid of faces, which the run then builds late,
// when it reaches the first of them, and most finished meshes are clean after it (the head's skin
// to 2 %: the redone run 0.05 s instead of 0.25 s wide). The third also tests the merges of the
// vertices marked around every pair found so far (MergeLog::test_marked), as all redone runs once
// did: dearer, but it refuses early merges whose faces would stand again; so does the first when
// the pairs are everywhere (decimate()). Faces of the two halves of a partitioned run cannot meet;
// the joined run's merges come after both halves'.
void mark_tests(const MethodRun& run, const std::vector<std::array<Fid, 2>>& pairs, bool wide,
                MergeLog& log) {
  const EditMesh& mesh = *run.mesh;
  std::vector<Vid> merged = run.merged_into;
  for (auto& t : log.test) t.clear();
  const auto part_of = [](std::uint32_t w) { return w >> kWriterPartShift; };
  const auto number_of = [](std::uint32_t w) { return w & kWriterNumberMask; };
  // Scans positions [from, to) of a part for merges into the pair's vertices.
  const auto scan = [&](std::size_t part, std::size_t from, std::size_t to,
                        const std::array<Vid, 6>& ends) {
    const Buffer<MergeOp>& ops = log.parts[part];
    to = std::min(to, ops.size());
    for (std::size_t i = from; i < to; ++i) {
      const Vid root = find_root(merged, ops[i].keep);
      if (std::find(ends.begin(), ends.end(), root) != ends.end()) {
        log.test[part].push_back(static_cast<std::uint32_t>(i));
      }
    }
  };
  for (auto [a, b] : pairs) {
    std::uint32_t wa = mesh.face_writer(a), wb = mesh.face_writer(b);
    // Order: input faces (0) first, then by part (the halves before the joined run), number.
    if (wa > wb) {
      std::swap(a, b);
      std::swap(wa, wb);
    }
    if (wb == 0 || number_of(wb) == kWriterNumberMask || part_of(wb) >= log.parts.size()) continue;
    const Tri& ta = mesh.face(a);
    const Tri& tb = mesh.face(b);
    const std::array<Vid, 6> ends{ta[0], ta[1], ta[2], tb[0], tb[1], tb[2]};
    const std::size_t pb = part_of(wb), nb = number_of(wb);
    if (!wide && wa != 0) {
      log.test[pb].push_back(static_cast<std::uint32_t>(nb - 1));
      continue;
    }
    if (wa == 0) {
      // b's earlier forms may go back to the start: before it, the halves (for the joined run).
      for (std::size_t p = 0; p < pb && pb == 2; ++p) scan(p, 0, log.parts[p].size(), ends);
      scan(pb, 0, nb, ends);
      continue;
    }
    const std::size_t pa = part_of(wa), na = number_of(wa);
    if (pa == pb) {
      scan(pb, na - 1, nb, ends);
    } else if (pb == 2) {
      scan(pa, na - 1, log.parts[pa].size(), ends);
      scan(pb, 0, nb, ends);
    } else {
      log.test[pa].push_back(static_cast<std::uint32_t>(na - 1));
      log.test[pb].push_back(static_cast<std::uint32_t>(nb - 1));
    }
  }
  for (auto& t : log.test) {
    std::sort(t.begin(), t.end());
    t.erase(std::unique(t.begin(), t.end()), t.end());
  }
}

}  // namespace
}  // namespace reduce

DecimateResult decimate(const PolyData& input, const DecimateOptions& options) {
  using namespace reduce;
  const Prepared prepared = prepare(input, options);
  MergeLog log;  // the previous run's merges (edge collapse), redone by the next one
  std::size_t reruns = 0;
  auto method = [&](const DecimateOptions& o, const EditSettings& settings) {
    switch (options.method) {
      case DecimateMethod::Quadric:
        return decimate_quadric(input, prepared, o, settings, reruns > 0 ? &log : nullptr);
      case DecimateMethod::VertexRemoval:
        return decimate_vertex_removal(input, prepared, o, settings);
      case DecimateMethod::CellCollapse:
        return decimate_cell_collapse(input, prepared, o, settings);
    }
    throw Error("decimate: unknown method");
  };
  // Merges are tested for intersections once, on the finished mesh, and redone with the test
  // where that finds one (vertex removal tests as it goes).
  const bool defer =
      options.check_self_intersections && options.method != DecimateMethod::VertexRemoval;
  std::vector<std::uint8_t> near;
  double from = 0, width = defer ? 0.9 : 1.0;
  for (int attempt = 0;; ++attempt) {
    EditSettings settings = edit_settings(options);
    settings.defer_intersections = defer && attempt < kDeferredRuns;
    if (settings.defer_intersections) settings.check_near = near;
    DecimateOptions o = options;
    o.progress = progress_range(options.progress, from, from + width);
    MethodRun run = method(o, settings);
    run.stats.intersection_reruns = reruns;
    if (settings.defer_intersections) {
      const auto pairs = untested_intersections(
          *run.mesh, progress_range(options.progress, from + width, from + 1.05 * width));
      if (!pairs.empty()) {
        if (run.merged_into.empty()) {
          run.merged_into.resize(run.mesh->vertex_count());
          for (Vid v = 0; v < run.merged_into.size(); ++v) {
            run.merged_into[v] = run.mesh->merged_into(v);
          }
        }
        near.resize(run.mesh->vertex_count(), 0);
        mark_near(run, pairs, near);
        log = std::move(run.log);
        // Intersections everywhere (as many pairs as a quarter of the faces: two shells closer
        // than the faces grow) are not a few merges to refuse: marks from the first redone run.
        const bool widespread = 4 * pairs.size() >= run.mesh->live_faces();
        mark_tests(run, pairs, /*wide=*/reruns > 0 || widespread, log);
        log.test_marked = reruns > 1 || widespread;
        ++reruns;
        from += 1.05 * width;
        width = 0.5 * (1 - from);
        continue;
      }
    }
    return finish(*run.mesh, *run.attributes, input, run.stats, options);
  }
}

const char* to_string(DecimateMethod method) {
  switch (method) {
    case DecimateMethod::Quadric:
      return "quadric";
    case DecimateMethod::VertexRemoval:
      return "vertex-removal";
    case DecimateMethod::CellCollapse:
      return "cell-collapse";
  }
  return "unknown";
}

const char* to_string(DecimateStop stop) {
  switch (stop) {
    case DecimateStop::Target:
      return "target reached";
    case DecimateStop::MaxError:
      return "maximum error reached";
    case DecimateStop::Exhausted:
      return "no further operation is allowed";
  }
  return "unknown";
}

}  // namespace isoforge
