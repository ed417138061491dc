#pragma once
// A triangle mesh under local edits, shared by the three decimation methods: vertex-face
// adjacency, the validity test of an edit (topology, normal turn, exact self-intersection) and
// its application. One kind of edit covers edge and cell collapse: merging a set of vertices
// into one placed at a given point. Vertex removal replaces a vertex's faces by a triangulation
// of its link.

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "isoforge/core/prefetch.hpp"
#include "isoforge/core/vec.hpp"
#include "isoforge/spatial/self_intersections.hpp"

namespace isoforge::reduce {

using Vid = std::uint32_t;
using Fid = std::uint32_t;
using Tri = std::array<Vid, 3>;

/// A face's own plane and the planes through its edges along its normal (outward), for the
/// separating-plane filter in front of the exact face test (edit_mesh.cpp).
struct FacePlanes {
  std::array<Vec3, 3> p;
  Tri id{};
  Vec3 n;
  std::array<Vec3, 3> m;
  double n_scale = 0;               // the magnitude n is computed from (|e1|₁ |e2|₁)
  std::array<double, 3> m_scale{};  // the same for m
  std::array<bool, 3> usable{};
  bool valid = false;
};

/// Why an edit was refused.
enum class Refusal : std::uint8_t { None, Locked, Topology, Flip, Intersection };

struct EditSettings {
  bool preserve_topology = true;
  double max_normal_turn = 90;  ///< degrees
  bool check_intersections = true;
  /// With side_axis 0, 1 or 2, a merge must place its vertex strictly below `side_cut` on that
  /// axis (`side_below`) or at or above it (one half of a partitioned run).
  int side_axis = -1;
  double side_cut = 0;
  bool side_below = true;
  /// Deferred intersection tests (with check_intersections): only merges of a vertex marked in
  /// `check_near` (per vertex; empty = none) are tested when made, and marks spread to the
  /// merged vertex; the faces other merges make are flagged (`face_unchecked`) so the finished
  /// mesh can be tested once and the edits redone where that finds a new intersection
  /// (decimate.cpp, `certify`).
  bool defer_intersections = false;
  std::vector<std::uint8_t> check_near;
  /// Deferred mode: the part of a partitioned run's merge log this mesh's merges go to (0, 1:
  /// the halves; 2: the joined or only run), kept in the faces' writer ids (`face_writer`).
  std::uint32_t log_part = 2;
};

/// Whether a merge is tested for intersections with every face near it: as the vertex marks
/// say (`EditMesh::tests_now`), or told by the caller (a redone merge whose test is known).
enum class MergeTest : std::uint8_t { ByMarks, Now, Deferred };

/// A face's writer id in deferred mode: the log part in the top bits, the merge's 1-based
/// number in that part's log below (0: the face was made by a tested merge or is an input face).
inline constexpr std::uint32_t kWriterPartShift = 30;
inline constexpr std::uint32_t kWriterNumberMask = (1u << kWriterPartShift) - 1;

/// The faces around each vertex, in one pool: each vertex has a slot (start, size, capacity)
/// in it, with room for two more faces than it starts with; a list that outgrows its slot
/// moves to the end of the pool with twice the room. (One vector per vertex cost a heap
/// allocation each: 500 000 per mesh on a 1M-triangle surface, and as many frees.)
class FaceLists {
 public:
  /// The lists of `faces` over `vertices` vertices, each in face order.
  void build(std::size_t vertices, std::span<const Tri> faces);
  [[nodiscard]] std::span<const Fid> operator[](Vid v) const {
    const Slot& s = slots_[v];
    return {pool_.data() + s.start, s.size};
  }
  void push_back(Vid v, Fid f) {
    Slot& s = slots_[v];
    if (s.size == s.capacity) grow(v);
    pool_[slots_[v].start + slots_[v].size++] = f;
  }
  void clear(Vid v) { slots_[v].size = 0; }
  /// Removes f from v's list (the last entry takes its place), if there.
  void erase(Vid v, Fid f);
  /// Gives `into` the larger of its slot and `from`'s (their lists swap with them).
  void take_larger_slot(Vid into, Vid from) {
    if (slots_[from].capacity > slots_[into].capacity) std::swap(slots_[into], slots_[from]);
  }

 private:
  struct Slot {
    std::uint32_t start = 0, size = 0, capacity = 0;
  };
  void grow(Vid v);
  std::vector<Slot> slots_;
  std::vector<Fid> pool_;
};

class EditMesh {
 public:
  /// Takes the mesh (triangles with three distinct ids < positions.size()). `locked` has one
  /// entry per vertex (non-zero = never moved or removed).
  EditMesh(std::vector<Vec3> positions, std::vector<Tri> triangles,
           std::vector<std::uint8_t> locked, const EditSettings& settings);

  [[nodiscard]] std::size_t vertex_count() const { return positions_.size(); }
  [[nodiscard]] std::size_t face_count() const { return faces_.size(); }
  [[nodiscard]] std::size_t live_faces() const { return live_faces_; }
  [[nodiscard]] const Vec3& position(Vid v) const { return positions_[v]; }
  [[nodiscard]] const Tri& face(Fid f) const { return faces_[f]; }
  [[nodiscard]] bool face_alive(Fid f) const { return alive_[f] != 0; }
  [[nodiscard]] bool locked(Vid v) const { return locked_[v] != 0; }
  [[nodiscard]] std::span<const Fid> faces_of(Vid v) const { return vertex_faces_[v]; }
  [[nodiscard]] const std::vector<Vec3>& positions() const { return positions_; }
  /// Whether face f was last made or moved by a merge that was not tested for intersections.
  [[nodiscard]] bool face_unchecked(Fid f) const { return face_writer(f) != 0; }
  /// Whether intersection tests are deferred (merges flag their faces instead).
  [[nodiscard]] bool defers_tests() const { return !writer_.empty(); }
  /// From now on every merge is tested when made (`tests_now` is true), marked or not.
  void test_every_merge() { test_all_ = true; }
  /// The writer id (kWriterPartShift) of the untested merge that last made or moved face f;
  /// 0 if none (deferred mode only).
  [[nodiscard]] std::uint32_t face_writer(Fid f) const { return writer_.empty() ? 0 : writer_[f]; }
  /// Gives face f the writer id of an untested merge (deferred mode; a mesh rebuilt from
  /// another).
  void mark_unchecked(Fid f, std::uint32_t writer) {
    if (!writer_.empty()) writer_[f] = writer;
  }
  /// The vertex v was merged into (v itself while it lives or if it was removed otherwise).
  [[nodiscard]] Vid merged_into(Vid v) const { return merged_into_.empty() ? v : merged_into_[v]; }

  /// Asks for the records of v's faces before an edit around v looks at them (a hint: no
  /// effect on results).
  void prefetch_faces(Vid v) const {
    for (Fid f : vertex_faces_[v]) prefetch(&faces_[f]);
  }
  /// The distinct neighbours of v (vertices sharing a face), appended to `out` after clearing it.
  void neighbours(Vid v, std::vector<Vid>& out) const;
  /// The other ends of v's edges, once per face of the edge, sorted into `out` (cleared first):
  /// an end seen k times is that of an edge with k faces.
  void edge_ends(Vid v, std::vector<Vid>& out) const;
  /// Number of live faces containing the edge (u, v).
  [[nodiscard]] int edge_faces(Vid u, Vid v) const;
  /// Whether v has an edge with exactly one face (computed).
  [[nodiscard]] bool on_border(Vid v) const;
  /// The same, kept up to date by the edits.
  [[nodiscard]] bool border(Vid v) const { return border_[v] != 0; }

  /// Whether merging `group` (distinct vertices; group[0] survives) into one vertex at `p` keeps
  /// the mesh valid: the surviving faces around it form one fan (a cycle, or a path when a member
  /// was on the border) with preserve_topology, no duplicate face or edge of three faces, no face
  /// normal turned by more than the limit or made zero, and no new face intersecting another one
  /// (exact). Locked members must all sit at `p`.
  [[nodiscard]] Refusal check_merge(std::span<const Vid> group, const Vec3& p,
                                    MergeTest test = MergeTest::ByMarks);
  /// Whether a merge of `group` is tested for intersections when it is made (always, unless
  /// the tests are deferred and no member is marked).
  [[nodiscard]] bool tests_now(std::span<const Vid> group) const;
  /// Whether a merge of `group` checked or made as `test` says is tested now.
  [[nodiscard]] bool tests_now(std::span<const Vid> group, MergeTest test) const {
    return test == MergeTest::ByMarks ? tests_now(group) : test == MergeTest::Now;
  }
  /// Applies a merge that `check_merge` accepted (`test`: as it was checked); returns the
  /// number of faces removed.
  std::size_t merge(std::span<const Vid> group, const Vec3& p, MergeTest test = MergeTest::ByMarks);

  /// Whether replacing the live faces `old_faces` by `new_faces` (over existing vertices; the
  /// vertices only in old faces disappear) keeps the mesh valid: no new face duplicates a
  /// remaining one or gives an edge three faces, no new face is degenerate or turned by more
  /// than the limit from `reference_normal`, and none intersects another face (exact).
  [[nodiscard]] Refusal check_replace(std::span<const Fid> old_faces,
                                      std::span<const Tri> new_faces, const Vec3& reference_normal);
  /// Applies a replacement that `check_replace` accepted.
  void replace(std::span<const Fid> old_faces, std::span<const Tri> new_faces);

 private:
  struct Box {
    Vec3 lo, hi;
  };
  [[nodiscard]] Box face_box(const std::array<Vec3, 3>& p) const;
  [[nodiscard]] std::array<Vec3, 3> corners(const Tri& t) const {
    return {positions_[t[0]], positions_[t[1]], positions_[t[2]]};
  }
  void build_grid();
  void grid_insert(Fid f);
  void grid_remove(Fid f);
  void detach(Fid f, Vid v);
  /// The faces of `group`'s vertices into touched_, each once, marked with a new stamp_.
  void gather_faces(std::span<const Vid> group);
  /// Whether any of `faces` (with positions `pos`) intersects another of them or a live face
  /// outside `excluded` (faces being removed or rewritten, marked with `mark_`): every such
  /// face, or with `local` only those sharing a vertex with `faces`.
  [[nodiscard]] bool intersects(std::span<const Tri> faces,
                                std::span<const std::array<Vec3, 3>> pos, bool local = false);
  /// Whether the undirected edges (a, b) form one cycle (`cycle`) or one path.
  [[nodiscard]] bool single_chain(bool cycle);

  std::vector<Vec3> positions_;
  std::vector<Tri> faces_;
  std::vector<std::uint8_t> alive_;
  std::vector<std::uint8_t> locked_;
  std::vector<std::uint8_t> border_;
  std::vector<std::uint8_t> check_near_;  // deferred mode: per vertex, test its merges now
  std::vector<std::uint32_t> writer_;     // deferred mode: per face (face_writer)
  std::uint32_t merges_ = 0;              // merges made (deferred mode: the writer numbers)
  bool test_all_ = false;                 // test_every_merge
  std::vector<Vid> merged_into_;          // deferred mode: per vertex
  FaceLists vertex_faces_;
  std::size_t live_faces_ = 0;
  EditSettings settings_;
  double cos_turn_ = 0;
  bool use_grid_ = false;
  std::optional<TriangleGrid> grid_;
  std::size_t grid_faces_ = 0;  // live faces when the grid was built (rebuilt at half)
  // Scratch (the edits run on one thread).
  std::vector<std::uint32_t> mark_;  // per face: == stamp_ when excluded from the current test
  std::vector<std::uint32_t> seen_;  // per face: == seen_stamp_ when tested (local tests)
  std::uint32_t seen_stamp_ = 0;
  std::uint32_t stamp_ = 0;
  std::vector<Fid> touched_;
  std::vector<Tri> new_faces_;
  std::vector<std::array<Vec3, 3>> new_pos_;
  std::vector<std::array<Vid, 2>> chain_;
  std::vector<Vid> chain_nodes_;
  std::vector<std::uint32_t> walk_parent_;
  std::vector<FacePlanes> new_planes_;
  std::vector<Box> new_boxes_;
  std::vector<std::array<Vid, 2>> sorted_chain_;
};

}  // namespace isoforge::reduce
