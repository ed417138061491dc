// Vertex removal (Schroeder, Zarge and Lorensen 1992, the family of vtkDecimatePro): a vertex is
// classified by its fan — simple (closed, no feature edge), boundary (open fan), interior edge
// (exactly two feature edges); corners and complex vertices stay — and measured by its distance
// to the average plane of its fan (simple) or to the line through its two border or feature
// neighbours. Vertices are removed in order of that distance and the hole is triangulated by
// recursive loop splitting: the split line whose plane (through the line, along the average
// normal) separates the two halves with the best aspect ratio, the feature line first when
// there is one.

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "isoforge/core/parallel.hpp"
#include "reduce/decimate_internal.hpp"

namespace isoforge::reduce {
namespace {

struct RemovalEntry {
  double error;
  Vid v;
  std::uint32_t stamp;
};

struct RemovalLater {
  bool operator()(const RemovalEntry& a, const RemovalEntry& b) const {
    if (a.error != b.error) return a.error > b.error;
    return a.v > b.v;
  }
};

enum class Kind { Simple, Boundary, InteriorEdge, Keep };

// A removable vertex: its fan's faces, the ordered loop of its neighbours, the average plane
// normal, its error and (interior edge) the positions in the loop of the two feature neighbours.
struct Plan {
  Kind kind = Kind::Keep;
  std::vector<Fid> fan;
  std::vector<Vid> loop;
  Vec3 normal;
  double error = 0;
  int feature_a = -1, feature_b = -1;
};

double distance_to_line(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const double l2 = norm2(d);
  if (!(l2 > 0)) return norm(p - a);
  return norm(cross(p - a, d)) / std::sqrt(l2);
}

class Remover {
 public:
  Remover(EditMesh& mesh, const Prepared& prepared, const DecimateOptions& options)
      : mesh_(mesh),
        prepared_(prepared),
        options_(options),
        cos_feature_(std::cos(options.feature_angle * std::numbers::pi / 180)) {}
  DecimateStats run();

 private:
  [[nodiscard]] Plan classify(Vid v) const;
  // Triangulates loop[ids] (a polygon in loop order) into out; false when no split works.
  bool triangulate(const std::vector<Vid>& poly, const Vec3& normal, std::vector<Tri>& out) const;
  void push(Vid v);

  EditMesh& mesh_;
  const Prepared& prepared_;
  const DecimateOptions& options_;
  double cos_feature_;
  std::vector<std::uint32_t> stamp_;
  std::vector<double> accumulated_;  // error inherited from removed neighbours
  std::vector<RemovalEntry> heap_;
};

Plan Remover::classify(Vid v) const {
  Plan plan;
  if (mesh_.locked(v)) return plan;
  const auto faces = mesh_.faces_of(v);
  if (faces.empty()) return plan;
  // Link edges x → y of the faces (v, x, y) in their orientation.
  std::vector<std::array<Vid, 2>> link;
  Vec3 normal{0, 0, 0}, center{0, 0, 0};
  double area = 0;
  for (Fid f : faces) {
    const Tri& t = mesh_.face(f);
    const int at = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
    link.push_back({t[(at + 1) % 3], t[(at + 2) % 3]});
    const Vec3 n = cross(mesh_.position(t[1]) - mesh_.position(t[0]),
                         mesh_.position(t[2]) - mesh_.position(t[0]));
    const double a = 0.5 * norm(n);
    normal += n;
    center += a * ((mesh_.position(t[0]) + mesh_.position(t[1]) + mesh_.position(t[2])) / 3.0);
    area += a;
  }
  const double ln = norm(normal);
  if (!(ln > 0) || !(area > 0)) return plan;
  normal = normal / ln;
  center = center / area;
  // Order the loop: each x starts at most one link edge and ends at most one.
  const std::size_t k = link.size();
  auto next_of = [&](Vid x) -> int {
    int found = -1;
    for (std::size_t i = 0; i < k; ++i) {
      if (link[i][0] == x) {
        if (found >= 0) return -2;
        found = static_cast<int>(i);
      }
    }
    return found;
  };
  // Start: a link edge whose start is no edge's end (open fan), else edge 0 (closed fan).
  std::size_t start = 0;
  bool open = false;
  for (std::size_t i = 0; i < k; ++i) {
    bool is_end = false;
    for (std::size_t j = 0; j < k; ++j) is_end = is_end || link[j][1] == link[i][0];
    if (!is_end) {
      if (open) return plan;  // two open ends: more than one fan
      open = true;
      start = i;
    }
  }
  std::vector<Vid>& loop = plan.loop;
  loop.push_back(link[start][0]);
  std::size_t walked = 0;
  int at = static_cast<int>(start);
  while (at >= 0 && walked <= k) {
    const Vid y = link[at][1];
    ++walked;
    if (!open && y == loop.front()) break;
    loop.push_back(y);
    at = next_of(y);
    if (at == -2) return plan;
  }
  if (walked != k) return plan;  // not one fan (inconsistent orientation or non-manifold)
  // Loop vertices must be distinct.
  {
    std::vector<Vid> s = loop;
    std::sort(s.begin(), s.end());
    if (std::adjacent_find(s.begin(), s.end()) != s.end()) return plan;
  }
  const Vec3 p = mesh_.position(v);
  plan.fan.assign(faces.begin(), faces.end());
  plan.normal = normal;
  if (open) {
    // The border moves to the chord between the loop's ends; an ear (one face) stays.
    plan.kind = loop.size() < 3 ? Kind::Keep : Kind::Boundary;
    plan.error = distance_to_line(p, mesh_.position(loop.front()), mesh_.position(loop.back()));
    return plan;
  }
  // Closed fan: features are edges (v, x) whose two faces' normals differ by more than the angle.
  std::vector<int> features;
  if (options_.feature_angle < 180) {
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const Vid x = loop[i];
      Vec3 n[2];
      int m = 0;
      for (Fid f : faces) {
        const Tri& t = mesh_.face(f);
        if ((t[0] == x || t[1] == x || t[2] == x) && m < 2) {
          n[m++] = cross(mesh_.position(t[1]) - mesh_.position(t[0]),
                         mesh_.position(t[2]) - mesh_.position(t[0]));
        }
      }
      if (m == 2) {
        const double l = norm(n[0]) * norm(n[1]);
        if (l > 0 && dot(n[0], n[1]) < cos_feature_ * l) features.push_back(static_cast<int>(i));
      }
    }
  }
  if (features.empty()) {
    plan.kind = Kind::Simple;
    plan.error = std::abs(dot(normal, p - center));
  } else if (features.size() == 2) {
    plan.kind = Kind::InteriorEdge;
    plan.feature_a = features[0];
    plan.feature_b = features[1];
    plan.error = distance_to_line(p, mesh_.position(loop[static_cast<std::size_t>(features[0])]),
                                  mesh_.position(loop[static_cast<std::size_t>(features[1])]));
  } else {
    plan.kind = Kind::Keep;  // a corner
  }
  if (loop.size() < 3) plan.kind = Kind::Keep;
  return plan;
}

bool Remover::triangulate(const std::vector<Vid>& poly, const Vec3& normal,
                          std::vector<Tri>& out) const {
  const std::size_t n = poly.size();
  if (n < 3) return true;
  if (n == 3) {
    out.push_back({poly[0], poly[1], poly[2]});
    return true;
  }
  // The split (i, j) whose plane separates the halves with the largest aspect ratio: the
  // smallest distance of a polygon vertex to the plane over the split line's length.
  double best = 0;
  std::size_t bi = 0, bj = 0;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // adjacent around the loop
      const Vec3 a = mesh_.position(poly[i]), b = mesh_.position(poly[j]);
      const double length = norm(b - a);
      Vec3 sn = cross(b - a, normal);
      const double ls = norm(sn);
      if (!(ls > 0) || !(length > 0)) continue;
      sn = sn / ls;
      // Every vertex strictly inside (i, j) on one side, every other one on the other side.
      double closest = std::numeric_limits<double>::infinity();
      int side_first = 0, side_second = 0;
      bool separates = true;
      for (std::size_t m = 0; m < n && separates; ++m) {
        if (m == i || m == j) continue;
        const double d = dot(sn, mesh_.position(poly[m]) - a);
        const int side = d > 0 ? 1 : (d < 0 ? -1 : 0);
        int& expected = (m > i && m < j) ? side_first : side_second;
        if (side == 0 || (expected != 0 && side != expected)) separates = false;
        expected = side;
        closest = std::min(closest, std::abs(d));
      }
      if (!separates || side_first == side_second) continue;
      const double aspect = closest / length;
      if (aspect > best) {
        best = aspect;
        bi = i;
        bj = j;
      }
    }
  }
  if (!(best > 0)) return false;
  std::vector<Vid> first(poly.begin() + static_cast<std::ptrdiff_t>(bi),
                         poly.begin() + static_cast<std::ptrdiff_t>(bj) + 1);
  std::vector<Vid> second(poly.begin() + static_cast<std::ptrdiff_t>(bj), poly.end());
  second.insert(second.end(), poly.begin(), poly.begin() + static_cast<std::ptrdiff_t>(bi) + 1);
  return triangulate(first, normal, out) && triangulate(second, normal, out);
}

void Remover::push(Vid v) {
  const Plan plan = classify(v);
  if (plan.kind == Kind::Keep) return;
  heap_.push_back({plan.error + accumulated_[v], v, stamp_[v]});
  std::push_heap(heap_.begin(), heap_.end(), RemovalLater{});
}

DecimateStats Remover::run() {
  DecimateStats stats;
  stats.input_triangles = mesh_.live_faces();
  stats.locked_vertices = prepared_.locked_count;
  const std::size_t nv = mesh_.vertex_count();
  stamp_.assign(nv, 0);
  accumulated_.assign(nv, 0.0);
  std::vector<RemovalEntry> entries(nv);
  std::vector<std::uint8_t> ok(nv, 0);
  parallel_for_range(
      nv, 1024,
      [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
          const Plan plan = classify(static_cast<Vid>(i));
          if (plan.kind == Kind::Keep) continue;
          entries[i] = {plan.error, static_cast<Vid>(i), 0};
          ok[i] = 1;
        }
      },
      progress_range(options_.progress, 0, 0.1), "decimate");
  for (std::size_t i = 0; i < nv; ++i) {
    if (ok[i]) heap_.push_back(entries[i]);
  }
  std::make_heap(heap_.begin(), heap_.end(), RemovalLater{});
  const std::size_t target = prepared_.target;
  RunLoop loop(stats, target, options_.progress);
  std::vector<Tri> triangles;
  for (;;) {
    while (mesh_.live_faces() > target && !heap_.empty()) {
      std::pop_heap(heap_.begin(), heap_.end(), RemovalLater{});
      const RemovalEntry e = heap_.back();
      heap_.pop_back();
      if (stamp_[e.v] != e.stamp) continue;
      const Plan plan = classify(e.v);
      if (plan.kind == Kind::Keep) continue;
      const double error = plan.error + accumulated_[e.v];
      if (prepared_.max_error > 0 && error > prepared_.max_error) {
        loop.skip_for_error();
        continue;
      }
      triangles.clear();
      bool made = false;
      if (plan.kind == Kind::InteriorEdge) {
        // Split along the feature line first.
        const auto a = static_cast<std::size_t>(plan.feature_a);
        const auto b = static_cast<std::size_t>(plan.feature_b);
        std::vector<Vid> first(plan.loop.begin() + static_cast<std::ptrdiff_t>(a),
                               plan.loop.begin() + static_cast<std::ptrdiff_t>(b) + 1);
        std::vector<Vid> second(plan.loop.begin() + static_cast<std::ptrdiff_t>(b),
                                plan.loop.end());
        second.insert(second.end(), plan.loop.begin(),
                      plan.loop.begin() + static_cast<std::ptrdiff_t>(a) + 1);
        made = first.size() >= 3 && second.size() >= 3 &&
               triangulate(first, plan.normal, triangles) &&
               triangulate(second, plan.normal, triangles);
      } else {
        made = triangulate(plan.loop, plan.normal, triangles);
      }
      if (!made && !loop.accept(Refusal::Topology)) continue;
      if (!loop.accept(mesh_.check_replace(plan.fan, triangles, plan.normal))) continue;
      mesh_.replace(plan.fan, triangles);
      ++stamp_[e.v];
      stats.max_error = std::max(stats.max_error, error);
      // The surface near the hole has moved by up to `error`: its vertices inherit it, so
      // errors add up where removals pile up (vtkDecimatePro's accumulated error).
      for (Vid x : plan.loop) accumulated_[x] = std::max(accumulated_[x], error);
      for (Vid x : plan.loop) {
        ++stamp_[x];
        push(x);
      }
      loop.done(mesh_.live_faces());
    }
    if (!loop.another_round(mesh_.live_faces())) break;
    heap_.clear();
    for (Vid v = 0; v < nv; ++v) push(v);
  }
  stats.stop = loop.stop(mesh_.live_faces());
  return stats;
}

}  // namespace

MethodRun decimate_vertex_removal(const PolyData& input, const Prepared& prepared,
                                  const DecimateOptions& options, const EditSettings& settings) {
  return run_on_copy(input, prepared, settings, [&](EditMesh& mesh, CarriedAttributes& attributes) {
    Remover remover(mesh, prepared, options);
    return remover.run();
  });
}

}  // namespace isoforge::reduce
