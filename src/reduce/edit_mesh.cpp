#include "reduce/edit_mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "isoforge/core/error.hpp"
#include "isoforge/core/predicates.hpp"

namespace isoforge::reduce {
namespace {

bool boxes_overlap(const Vec3& alo, const Vec3& ahi, const Vec3& blo, const Vec3& bhi) {
  return alo.x <= bhi.x && blo.x <= ahi.x && alo.y <= bhi.y && blo.y <= ahi.y && alo.z <= bhi.z &&
         blo.z <= ahi.z;
}

std::array<Index, 3> ids_of(const Tri& t) {
  return {t[0], t[1], t[2]};
}

Vec3 face_normal(const std::array<Vec3, 3>& p) {
  return cross(p[1] - p[0], p[2] - p[0]);
}

// The separating-plane filter. Whether a plane certainly separates two faces except at the
// vertices they share (equal ids: the same point) is decided in double arithmetic with a margin
// (1e-12 relative, about 10^3 times the rounding error of these few operations, with L1 norms,
// which bound the Euclidean ones from above), so a "separated" is never wrong; anything else
// goes to the exact predicates. The candidate planes of a face are its own plane and the planes
// through its edges along its normal, computed once per face (FacePlanes) and tried against
// every face near it. A shared vertex lies on such a plane when it is a vertex of that plane's
// edge (or of the face, for its own plane) and is then skipped: the other face meets the plane
// only there and this face lies on the other side, so they meet only at shared vertices. In a
// mesh, nearby faces — neighbours and coplanar ones included — are almost always told apart
// here without the exact fallback.
constexpr double kSeparationMargin = 1e-12;

// A merge whose test is deferred is still tested against the faces around it when it turns a
// face's normal by more than this (cos 10°): the folds a merge makes next to itself come from
// turning faces, and a merge that turns none by more leaves its fan nearly where it was.
constexpr double kTurnTestedNearby = 0.98480775301220806;

double norm1(const Vec3& v) {
  return std::abs(v.x) + std::abs(v.y) + std::abs(v.z);
}

FacePlanes planes_of(const std::array<Vec3, 3>& p, const Tri& id) {
  FacePlanes f;
  f.p = p;
  f.id = id;
  const Vec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
  f.n = cross(e1, e2);
  if (!(norm1(f.n) > 0)) return f;
  f.valid = true;
  // Rounding errors follow the inputs' magnitudes, not the results': a sliver's normal is
  // small and its direction poorly known, so its bounds are taken from its edges' lengths.
  f.n_scale = norm1(e1) * norm1(e2);
  for (int k = 0; k < 3; ++k) {
    const Vec3& a = p[k];
    const Vec3 r = p[(k + 2) % 3] - a;
    const Vec3 e = p[(k + 1) % 3] - a;
    Vec3 m = cross(e, f.n);
    f.m_scale[k] = norm1(e) * f.n_scale;
    const double inner = dot(m, r);
    const double bound = kSeparationMargin * f.m_scale[k] * norm1(r);
    f.usable[k] = std::abs(inner) > bound;
    f.m[k] = inner > 0 ? -m : m;  // outward
  }
  return f;
}

// Whether all vertices of q not in {skip0, skip1, skip2} are strictly on the positive (sign
// +1) or negative (-1) side of the plane through `origin` with normal w (computed from inputs
// of magnitude `w_scale`: its components are known to a few ulps of that); 0 if not sure.
int side_of(const Vec3& w, double w_scale, const Vec3& origin, const std::array<Vec3, 3>& q,
            const Tri& qid, Vid skip0, Vid skip1, Vid skip2) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo, scale = 0;
  bool any = false;
  for (int k = 0; k < 3; ++k) {
    if (qid[k] == skip0 || qid[k] == skip1 || qid[k] == skip2) continue;
    const Vec3 d = q[k] - origin;
    const double v = dot(w, d);
    lo = std::min(lo, v);
    hi = std::max(hi, v);
    scale = std::max(scale, norm1(d));
    any = true;
  }
  if (!any) return 0;
  const double bound = kSeparationMargin * w_scale * scale;
  return lo > bound ? 1 : (hi < -bound ? -1 : 0);
}

bool separated_by(const FacePlanes& f, const std::array<Vec3, 3>& q, const Tri& qid) {
  if (!f.valid) return false;
  if (side_of(f.n, f.n_scale, f.p[0], q, qid, f.id[0], f.id[1], f.id[2]) != 0) return true;
  constexpr Vid kNoVertex = ~Vid{0};
  for (int k = 0; k < 3; ++k) {
    if (f.usable[k] &&
        side_of(f.m[k], f.m_scale[k], f.p[k], q, qid, f.id[k], f.id[(k + 1) % 3], kNoVertex) > 0) {
      return true;
    }
  }
  return false;
}

}  // namespace

void FaceLists::build(std::size_t vertices, std::span<const Tri> faces) {
  constexpr std::uint32_t kSlack = 2;
  slots_.assign(vertices, Slot{});
  for (const Tri& t : faces) {
    for (Vid v : t) ++slots_[v].capacity;
  }
  std::size_t total = 0;
  for (Slot& s : slots_) {
    s.start = static_cast<std::uint32_t>(total);
    if (s.capacity > 0) s.capacity += kSlack;
    total += s.capacity;
    if (total > std::numeric_limits<std::uint32_t>::max() / 2) {
      throw Error("decimation: too many faces around the vertices for one list pool");
    }
  }
  pool_.reserve(total + total / 2);
  pool_.resize(total);
  for (Fid f = 0; f < faces.size(); ++f) {
    for (Vid v : faces[f]) pool_[slots_[v].start + slots_[v].size++] = f;
  }
}

void FaceLists::grow(Vid v) {
  Slot& s = slots_[v];
  const std::size_t capacity = std::max<std::size_t>(8, 2 * std::size_t{s.capacity});
  const std::size_t start = pool_.size();
  if (start + capacity > std::numeric_limits<std::uint32_t>::max()) {
    throw Error("decimation: the list pool outgrew 32-bit offsets");
  }
  pool_.resize(start + capacity);
  std::copy_n(pool_.begin() + s.start, s.size, pool_.begin() + static_cast<std::ptrdiff_t>(start));
  s.start = static_cast<std::uint32_t>(start);
  s.capacity = static_cast<std::uint32_t>(capacity);
}

void FaceLists::erase(Vid v, Fid f) {
  Slot& s = slots_[v];
  Fid* list = pool_.data() + s.start;
  Fid* end = list + s.size;
  Fid* it = std::find(list, end, f);
  if (it != end) {
    *it = end[-1];
    --s.size;
  }
}

EditMesh::EditMesh(std::vector<Vec3> positions, std::vector<Tri> triangles,
                   std::vector<std::uint8_t> locked, const EditSettings& settings)
    : positions_(std::move(positions)),
      faces_(std::move(triangles)),
      alive_(faces_.size(), 1),
      locked_(std::move(locked)),
      live_faces_(faces_.size()),
      settings_(settings),
      cos_turn_(std::cos(settings.max_normal_turn * std::numbers::pi / 180)),
      mark_(faces_.size(), 0) {
  vertex_faces_.build(positions_.size(), faces_);
  border_.resize(positions_.size());
  for (std::size_t v = 0; v < positions_.size(); ++v) {
    border_[v] = on_border(static_cast<Vid>(v)) ? 1 : 0;
  }
  if (settings_.check_intersections && settings_.defer_intersections) {
    check_near_ = std::move(settings_.check_near);
    check_near_.resize(positions_.size(), 0);
    writer_.assign(faces_.size(), 0);
    merged_into_.resize(positions_.size());
    for (Vid v = 0; v < positions_.size(); ++v) merged_into_[v] = v;
  }
  settings_.check_near.clear();
  // The grid is built when the first test needs it: a deferred run may test no edit, or
  // only late ones (a redone run testing the merges a finished mesh's test pointed to).
  use_grid_ = settings_.check_intersections && !faces_.empty();
}

// The grid's cells follow the faces' size: as decimation makes faces larger, the grid is rebuilt
// (each time the live faces halve) so a query keeps touching a few cells of a few faces each.
void EditMesh::build_grid() {
  Bounds box;
  double edges = 0;
  for (Fid f = 0; f < faces_.size(); ++f) {
    if (!alive_[f]) continue;
    const Tri& t = faces_[f];
    for (int k = 0; k < 3; ++k) {
      box.extend(positions_[t[k]]);
      edges += norm(positions_[t[(k + 1) % 3]] - positions_[t[k]]);
    }
  }
  const double mean_edge =
      edges / (3.0 * static_cast<double>(std::max<std::size_t>(live_faces_, 1)));
  grid_.emplace(box, triangle_grid_cell_size(box, live_faces_, mean_edge));
  for (Fid f = 0; f < faces_.size(); ++f) {
    if (alive_[f]) grid_insert(f);
  }
  grid_faces_ = live_faces_;
}

EditMesh::Box EditMesh::face_box(const std::array<Vec3, 3>& p) const {
  Box b{p[0], p[0]};
  for (int k = 1; k < 3; ++k) {
    b.lo = {std::min(b.lo.x, p[k].x), std::min(b.lo.y, p[k].y), std::min(b.lo.z, p[k].z)};
    b.hi = {std::max(b.hi.x, p[k].x), std::max(b.hi.y, p[k].y), std::max(b.hi.z, p[k].z)};
  }
  return b;
}

void EditMesh::grid_insert(Fid f) {
  const Box b = face_box(corners(faces_[f]));
  grid_->insert(f, b.lo, b.hi);
}

void EditMesh::grid_remove(Fid f) {
  const Box b = face_box(corners(faces_[f]));
  grid_->remove(f, b.lo, b.hi);
}

void EditMesh::neighbours(Vid v, std::vector<Vid>& out) const {
  out.clear();
  for (Fid f : vertex_faces_[v]) {
    for (Vid w : faces_[f]) {
      if (w != v && std::find(out.begin(), out.end(), w) == out.end()) out.push_back(w);
    }
  }
}

int EditMesh::edge_faces(Vid u, Vid v) const {
  int n = 0;
  for (Fid f : vertex_faces_[u]) {
    const Tri& t = faces_[f];
    n += (t[0] == v || t[1] == v || t[2] == v) ? 1 : 0;
  }
  return n;
}

void EditMesh::edge_ends(Vid v, std::vector<Vid>& out) const {
  out.clear();
  for (Fid f : vertex_faces_[v]) {
    for (Vid w : faces_[f]) {
      if (w != v) out.push_back(w);
    }
  }
  std::sort(out.begin(), out.end());
}

bool EditMesh::on_border(Vid v) const {
  // An end seen once is a border edge's (cheaper than counting each edge's faces).
  thread_local std::vector<Vid> ends;
  edge_ends(v, ends);
  for (std::size_t i = 0; i < ends.size();) {
    std::size_t j = i + 1;
    while (j < ends.size() && ends[j] == ends[i]) ++j;
    if (j - i == 1) return true;
    i = j;
  }
  return false;
}

bool EditMesh::single_chain(bool cycle) {
  // chain_ holds undirected edges. One cycle: every node has degree 2 and the edges connect;
  // one path: two nodes of degree 1, the others 2, connected. O(k log k) in the fan size.
  chain_nodes_.clear();
  for (const auto& e : chain_) {
    chain_nodes_.push_back(e[0]);
    chain_nodes_.push_back(e[1]);
  }
  std::sort(chain_nodes_.begin(), chain_nodes_.end());
  std::size_t ends = 0;
  for (std::size_t i = 0; i < chain_nodes_.size();) {
    std::size_t j = i;
    while (j < chain_nodes_.size() && chain_nodes_[j] == chain_nodes_[i]) ++j;
    const std::size_t degree = j - i;
    if (degree > 2) return false;
    if (degree == 1) ++ends;
    i = j;
  }
  if (ends != (cycle ? 0u : 2u)) return false;
  chain_nodes_.erase(std::unique(chain_nodes_.begin(), chain_nodes_.end()), chain_nodes_.end());
  // Connected: union-find over the nodes; a connected graph with these degrees is one chain.
  auto index = [&](Vid v) {
    return static_cast<std::uint32_t>(
        std::lower_bound(chain_nodes_.begin(), chain_nodes_.end(), v) - chain_nodes_.begin());
  };
  auto& parent = walk_parent_;
  parent.resize(chain_nodes_.size());
  for (std::uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::size_t components = chain_nodes_.size();
  for (const auto& e : chain_) {
    const std::uint32_t a = find(index(e[0])), b = find(index(e[1]));
    if (a != b) {
      parent[a] = b;
      --components;
    }
  }
  return components == 1;
}

bool EditMesh::intersects(std::span<const Tri> faces, std::span<const std::array<Vec3, 3>> pos,
                          bool local) {
  // The new faces' planes, once; then every live face near the new ones (one grid query over
  // their common box), its planes computed when first needed.
  std::vector<FacePlanes>& planes = new_planes_;
  planes.clear();
  Box all = face_box(pos[0]);
  std::vector<Box>& boxes = new_boxes_;
  boxes.clear();
  for (std::size_t i = 0; i < faces.size(); ++i) {
    planes.push_back(planes_of(pos[i], faces[i]));
    boxes.push_back(face_box(pos[i]));
    all.lo = {std::min(all.lo.x, boxes[i].lo.x), std::min(all.lo.y, boxes[i].lo.y),
              std::min(all.lo.z, boxes[i].lo.z)};
    all.hi = {std::max(all.hi.x, boxes[i].hi.x), std::max(all.hi.y, boxes[i].hi.y),
              std::max(all.hi.z, boxes[i].hi.z)};
  }
  auto pair_intersects = [&](std::size_t i, const FacePlanes& other) {
    if (separated_by(planes[i], other.p, other.id) || separated_by(other, pos[i], faces[i])) {
      return false;
    }
    return faces_intersect(pos[i], ids_of(faces[i]), other.p, ids_of(other.id));
  };
  for (std::size_t i = 0; i < faces.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (boxes_overlap(boxes[i].lo, boxes[i].hi, boxes[j].lo, boxes[j].hi) &&
          pair_intersects(i, planes[j])) {
        return true;
      }
    }
  }
  bool hit = false;
  auto test = [&](std::uint32_t g) {
    if (hit || mark_[g] == stamp_) return;
    const Tri& gid = faces_[g];
    const auto q = corners(gid);
    const Box c = face_box(q);
    bool planes_ready = false;
    FacePlanes other;
    for (std::size_t i = 0; i < faces.size() && !hit; ++i) {
      if (!boxes_overlap(boxes[i].lo, boxes[i].hi, c.lo, c.hi)) continue;
      // The new face's planes first (made once per edit); the other face's only when needed.
      if (separated_by(planes[i], q, gid)) continue;
      if (!planes_ready) {
        other = planes_of(q, gid);
        planes_ready = true;
      }
      if (separated_by(other, pos[i], faces[i])) continue;
      hit = faces_intersect(pos[i], ids_of(faces[i]), q, ids_of(gid));
    }
  };
  if (local) {
    // The faces around the new ones' vertices (the second ring of the merged vertex).
    ++seen_stamp_;
    if (seen_.size() < faces_.size()) seen_.resize(faces_.size(), 0);
    for (const Tri& t : faces) {
      for (Vid v : t) {
        for (Fid g : vertex_faces_[v]) {
          if (seen_[g] == seen_stamp_) continue;
          seen_[g] = seen_stamp_;
          test(g);
          if (hit) return true;
        }
      }
    }
    return false;
  }
  if (!use_grid_) return false;
  if (!grid_) build_grid();
  grid_->for_each_candidate(all.lo, all.hi, test);
  return hit;
}

bool EditMesh::tests_now(std::span<const Vid> group) const {
  if (!settings_.check_intersections) return false;
  if (check_near_.empty() || test_all_) return true;
  for (Vid v : group) {
    if (check_near_[v] != 0) return true;
  }
  return false;
}

void EditMesh::gather_faces(std::span<const Vid> group) {
  ++stamp_;
  touched_.clear();
  for (Vid s : group) {
    for (Fid f : vertex_faces_[s]) {
      if (mark_[f] != stamp_) {
        mark_[f] = stamp_;
        touched_.push_back(f);
      }
    }
  }
}

Refusal EditMesh::check_merge(std::span<const Vid> group, const Vec3& p, MergeTest test) {
  const Vid keep = group[0];
  auto member = [&](Vid v) { return std::find(group.begin(), group.end(), v) != group.end(); };
  bool border = false;
  for (Vid s : group) {
    if (locked_[s] && positions_[s] != p) return Refusal::Locked;
  }
  if (settings_.side_axis >= 0) {
    const double x = p[settings_.side_axis];
    if (settings_.side_below ? !(x < settings_.side_cut) : !(x >= settings_.side_cut)) {
      return Refusal::Locked;
    }
  }
  if (settings_.preserve_topology) {
    for (Vid s : group) border = border || border_[s] != 0;
  }
  gather_faces(group);
  new_faces_.clear();
  new_pos_.clear();
  chain_.clear();
  Refusal flip = Refusal::None;
  bool turns = false;  // some face turns by more than kTurnTestedNearby
  for (Fid f : touched_) {
    const Tri& t = faces_[f];
    int members = 0, at = 0;
    for (int k = 0; k < 3; ++k) {
      if (member(t[k])) {
        ++members;
        at = k;
      }
    }
    if (members >= 2) continue;  // collapses to an edge: removed
    Tri nt = t;
    nt[at] = keep;
    std::array<Vec3, 3> np = corners(t);
    const Vec3 n0 = face_normal(np);
    np[at] = p;
    const Vec3 n1 = face_normal(np);
    const double l1 = norm2(n1);
    if (l1 == 0 || triangle_degenerate(np[0], np[1], np[2])) {
      flip = Refusal::Flip;
    } else {
      const double l0 = norm2(n0);
      if (l0 > 0 && dot(n0, n1) <= cos_turn_ * std::sqrt(l0 * l1)) flip = Refusal::Flip;
      if (l0 > 0 && dot(n0, n1) <= kTurnTestedNearby * std::sqrt(l0 * l1)) turns = true;
    }
    chain_.push_back({t[(at + 1) % 3], t[(at + 2) % 3]});
    new_faces_.push_back(nt);
    new_pos_.push_back(np);
  }
  if (new_faces_.empty()) return Refusal::Topology;
  // No duplicate faces (the same opposite edge twice) and at most two faces per new edge.
  for (auto& e : chain_) {
    if (e[0] > e[1]) std::swap(e[0], e[1]);
  }
  sorted_chain_.assign(chain_.begin(), chain_.end());
  std::sort(sorted_chain_.begin(), sorted_chain_.end());
  if (std::adjacent_find(sorted_chain_.begin(), sorted_chain_.end()) != sorted_chain_.end()) {
    return Refusal::Topology;
  }
  if (settings_.preserve_topology) {
    if (!single_chain(!border)) return Refusal::Topology;
  } else {
    chain_nodes_.clear();
    for (const auto& e : chain_) {
      chain_nodes_.push_back(e[0]);
      chain_nodes_.push_back(e[1]);
    }
    std::sort(chain_nodes_.begin(), chain_nodes_.end());
    for (std::size_t i = 2; i < chain_nodes_.size(); ++i) {
      if (chain_nodes_[i] == chain_nodes_[i - 2]) return Refusal::Topology;
    }
  }
  if (flip != Refusal::None) return flip;
  // A merge whose test is deferred is still tested against the faces around it if it turns
  // a face: nearly every intersection a merge can make is there, so a test of the finished mesh
  // rarely finds one to redo.
  if (!settings_.check_intersections) return Refusal::None;
  const bool now = tests_now(group, test);
  if ((now || turns) && intersects(new_faces_, new_pos_, /*local=*/!now)) {
    return Refusal::Intersection;
  }
  return Refusal::None;
}

void EditMesh::detach(Fid f, Vid v) {
  vertex_faces_.erase(v, f);
}

std::size_t EditMesh::merge(std::span<const Vid> group, const Vec3& p, MergeTest test) {
  const Vid keep = group[0];
  auto member = [&](Vid v) { return std::find(group.begin(), group.end(), v) != group.end(); };
  const bool tested = tests_now(group, test);
  merges_ = std::min(merges_ + 1, kWriterNumberMask);  // saturated: no longer a log position
  const std::uint32_t writer = tested ? 0 : (settings_.log_part << kWriterPartShift) | merges_;
  gather_faces(group);
  if (grid_) {
    for (Fid f : touched_) grid_remove(f);
  }
  positions_[keep] = p;
  std::size_t removed = 0;
  // The merged fan is larger than either: it takes the largest slot.
  for (std::size_t i = 1; i < group.size(); ++i) vertex_faces_.take_larger_slot(keep, group[i]);
  vertex_faces_.clear(keep);
  for (Fid f : touched_) {
    Tri& t = faces_[f];
    int members = 0;
    for (Vid v : t) members += member(v) ? 1 : 0;
    if (members >= 2) {
      alive_[f] = 0;
      --live_faces_;
      ++removed;
      for (Vid v : t) {
        if (!member(v)) detach(f, v);
      }
      continue;
    }
    for (Vid& v : t) {
      if (member(v)) v = keep;
    }
    vertex_faces_.push_back(keep, f);
    if (!writer_.empty()) writer_[f] = writer;
  }
  for (std::size_t i = 1; i < group.size(); ++i) vertex_faces_.clear(group[i]);
  if (!merged_into_.empty()) {
    for (std::size_t i = 1; i < group.size(); ++i) {
      merged_into_[group[i]] = keep;
      check_near_[keep] |= check_near_[group[i]];
    }
  }
  if (locked_[keep] == 0) {
    for (Vid s : group) locked_[keep] |= locked_[s];
  }
  if (settings_.preserve_topology) {
    // Borders stay borders and interiors interiors: the merged vertex is on one if a member was.
    for (Vid s : group) border_[keep] |= border_[s];
  } else {
    border_[keep] = on_border(keep) ? 1 : 0;
    for (Fid f : vertex_faces_[keep]) {
      for (Vid v : faces_[f]) border_[v] = on_border(v) ? 1 : 0;
    }
  }
  if (grid_) {
    for (Fid f : vertex_faces_[keep]) grid_insert(f);
    if (2 * live_faces_ < grid_faces_ && live_faces_ > 0) build_grid();
  }
  return removed;
}

Refusal EditMesh::check_replace(std::span<const Fid> old_faces, std::span<const Tri> new_faces,
                                const Vec3& reference_normal) {
  ++stamp_;
  for (Fid f : old_faces) mark_[f] = stamp_;
  new_faces_.assign(new_faces.begin(), new_faces.end());
  new_pos_.clear();
  const double lr = norm2(reference_normal);
  for (const Tri& t : new_faces) {
    const auto np = corners(t);
    const Vec3 n = face_normal(np);
    const double l = norm2(n);
    if (l == 0 || triangle_degenerate(np[0], np[1], np[2])) return Refusal::Flip;
    if (lr > 0 && dot(n, reference_normal) <= cos_turn_ * std::sqrt(l * lr)) return Refusal::Flip;
    new_pos_.push_back(np);
  }
  // Topology: a new face must not duplicate a remaining face, and each of its edges may have
  // at most two faces among the remaining and new ones.
  auto same = [](const Tri& a, const Tri& b) {
    std::array<Vid, 3> x = a, y = b;
    std::sort(x.begin(), x.end());
    std::sort(y.begin(), y.end());
    return x == y;
  };
  for (std::size_t i = 0; i < new_faces.size(); ++i) {
    const Tri& t = new_faces[i];
    for (int k = 0; k < 3; ++k) {
      const Vid a = t[k], b = t[(k + 1) % 3];
      int count = 0;
      for (Fid f : vertex_faces_[a]) {
        if (mark_[f] == stamp_) continue;
        const Tri& s = faces_[f];
        if (s[0] == b || s[1] == b || s[2] == b) ++count;
        if (k == 0 && same(s, t)) return Refusal::Topology;
      }
      for (const Tri& s : new_faces) {
        const bool has_a = s[0] == a || s[1] == a || s[2] == a;
        const bool has_b = s[0] == b || s[1] == b || s[2] == b;
        if (has_a && has_b) ++count;
      }
      if (count > 2) return Refusal::Topology;
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (same(new_faces[i], new_faces[j])) return Refusal::Topology;
    }
  }
  if (settings_.check_intersections && intersects(new_faces_, new_pos_)) {
    return Refusal::Intersection;
  }
  return Refusal::None;
}

void EditMesh::replace(std::span<const Fid> old_faces, std::span<const Tri> new_faces) {
  for (Fid f : old_faces) {
    if (grid_) grid_remove(f);
    alive_[f] = 0;
    --live_faces_;
    for (Vid v : faces_[f]) detach(f, v);
  }
  for (const Tri& t : new_faces) {
    const Fid f = static_cast<Fid>(faces_.size());
    faces_.push_back(t);
    alive_.push_back(1);
    mark_.push_back(0);
    if (!writer_.empty()) writer_.push_back(0);
    ++live_faces_;
    for (Vid v : t) vertex_faces_.push_back(v, f);
    if (grid_) grid_insert(f);
  }
  for (const Tri& t : new_faces) {
    for (Vid v : t) border_[v] = on_border(v) ? 1 : 0;
  }
  if (grid_ && 2 * live_faces_ < grid_faces_ && live_faces_ > 0) build_grid();
}

}  // namespace isoforge::reduce
