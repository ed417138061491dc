#pragma once
// What the three decimation methods share: the prepared input (triangles, double positions,
// locks, the stop), the point arrays carried as doubles while vertices merge, and the output.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "isoforge/core/buffer.hpp"
#include "isoforge/reduce/decimate.hpp"
#include "reduce/edit_mesh.hpp"

namespace isoforge::reduce {

struct Prepared {
  std::vector<Vec3> positions;
  std::vector<Tri> triangles;
  std::vector<std::uint8_t> locked;  ///< by mask or on a non-manifold edge/vertex
  std::size_t locked_count = 0;
  double diagonal = 0;
  std::size_t target = 0;  ///< stop at or below this many triangles (0: only the error stops)
  double max_error = 0;    ///< absolute; 0 = none
  /// The input's points: placements are rounded to their precision (`Points::stored`)
  /// before they are checked, so the checks decide on the coordinates that are written.
  const Points* points = nullptr;
};

/// Validates `options`, triangulates `input`, locks vertices (mask, non-manifold) and turns the
/// stops into a triangle count and an absolute error. \throw Error as `decimate`.
[[nodiscard]] Prepared prepare(const PolyData& input, const DecimateOptions& options);

/// The point arrays of the input as doubles, one row per vertex, merged as vertices merge.
class CarriedAttributes {
 public:
  explicit CarriedAttributes(const Attributes& point_data);
  [[nodiscard]] bool empty() const { return width_ == 0; }
  [[nodiscard]] std::size_t width() const { return width_; }
  [[nodiscard]] const double* row(std::size_t v) const { return values_.data() + v * width_; }
  /// Squared difference of two rows, each array scaled by its range (arrays of constant value
  /// count nothing).
  [[nodiscard]] double scaled_distance2(std::size_t a, std::size_t b) const;
  /// Row `into` = Σ w_i row(from_i); marks `into` as changed.
  void blend(std::size_t into, std::span<const std::size_t> from, std::span<const double> weights);
  /// The output point data: rows of `kept` (old ids in output order); unchanged rows are copied
  /// exactly, changed ones converted (integers rounded, unit normals renormalised).
  [[nodiscard]] Attributes output(const std::vector<Vid>& kept) const;

 private:
  const Attributes* source_ = nullptr;
  std::size_t width_ = 0;
  std::vector<double> values_;
  std::vector<double> inverse_range2_;  ///< per column
  std::vector<std::uint8_t> changed_;
};

/// The live faces of `mesh` as polygonal data with compacted points (in old-id order) and the
/// carried point arrays.
[[nodiscard]] PolyData assemble(const EditMesh& mesh, const CarriedAttributes& attributes,
                                ScalarType point_type);

/// The edit settings `options` ask for.
[[nodiscard]] EditSettings edit_settings(const DecimateOptions& options);

/// The bookkeeping every method's loop shares: refusals, rounds over every candidate after the
/// queue runs dry (refusals may have been lifted by later edits: at most kMaxRounds, and only
/// while a round still edits something), the stop reason and progress.
class RunLoop {
 public:
  static constexpr int kMaxRounds = 8;
  RunLoop(DecimateStats& stats, std::size_t target, const ProgressCallback& progress)
      : stats_(stats), target_(target), progress_(progress) {}
  /// Counts a refusal; true when the edit may go ahead.
  bool accept(Refusal r);
  /// Counts a candidate skipped for its error.
  void skip_for_error() { ++skipped_error_; }
  /// Counts an edit done, reports progress now and then (`live` faces left; cancels by
  /// throwing `Cancelled`, also when `stop` is set).
  void done(std::size_t live, const std::atomic<bool>* stop = nullptr);
  /// Whether to fill the queue again after it ran dry with `live` faces left.
  bool another_round(std::size_t live);
  [[nodiscard]] DecimateStop stop(std::size_t live) const;

 private:
  DecimateStats& stats_;
  std::size_t target_;
  const ProgressCallback& progress_;
  std::size_t skipped_error_ = 0, since_fill_ = 0, refused_since_fill_ = 0;
  int rounds_ = 0;
};

/// One merge of an edge collapse run, as done: enough to redo it without choosing it again.
struct MergeOp {
  Vid keep = 0, drop = 0;
  Vec3 p;
  double t = 0;      ///< where p projects on keep→drop (for the point arrays)
  double error = 0;  ///< its error (for the stats)
};

/// The merges of an edge collapse run, per part: the two halves of a partitioned run and the
/// joined (or only) run. A later run redoes them in order, testing those in `test`, up to the
/// first one refused, and chooses afresh from there on (testing the merges of marked vertices).
struct MergeLog {
  std::array<Buffer<MergeOp>, 3> parts;  // Buffers: their growth reuses mapped blocks
  /// Per part, ascending: the 0-based positions of the merges to test when redone — each the
  /// later of the two merges that made a pair of faces the finished mesh's test found
  /// intersecting.
  std::array<std::vector<std::uint32_t>, 3> test;
  /// Also test the merges of marked vertices (EditSettings::check_near) when redone.
  bool test_marked = false;
};

/// A method's finished run: the edited mesh, the carried point arrays and the counts.
struct MethodRun {
  std::optional<EditMesh> mesh;
  std::optional<CarriedAttributes> attributes;
  DecimateStats stats;
  /// Per input vertex, the vertex it was merged into (itself if none); filled by runs with
  /// deferred intersection tests.
  std::vector<Vid> merged_into;
  /// The merges done (edge collapse, deferred runs only).
  MergeLog log;
};

/// The vertex that `v` ended in, following `merged_into` (compressing the paths it walks).
inline Vid find_root(std::vector<Vid>& merged_into, Vid v) {
  while (merged_into[v] != v) {
    merged_into[v] = merged_into[merged_into[v]];
    v = merged_into[v];
  }
  return v;
}

/// A method's run on a fresh editable copy of `prepared`: `run(mesh, attributes)` returns
/// its counts.
template <class Run>
MethodRun run_on_copy(const PolyData& input, const Prepared& prepared, const EditSettings& settings,
                      Run&& run) {
  MethodRun out;
  out.mesh.emplace(prepared.positions, prepared.triangles, prepared.locked, settings);
  out.attributes.emplace(input.point_data);
  out.stats = run(*out.mesh, *out.attributes);
  return out;
}

/// The live faces of `mesh` as a cell array, vertex ids through `map` (none: as they are);
/// `face_of`, if given, gets the face id of each cell.
[[nodiscard]] CellArray live_cells(const EditMesh& mesh, const std::vector<Vid>* map,
                                   std::vector<Fid>* face_of = nullptr);

/// The three methods. Each runs on a copy of `prepared` with `settings` (edit_settings, plus
/// the deferred-test marks of `decimate`'s certification loop); `options.progress` covers the run.
MethodRun decimate_quadric(const PolyData& input, const Prepared& prepared,
                           const DecimateOptions& options, const EditSettings& settings,
                           const MergeLog* replay = nullptr);
MethodRun decimate_vertex_removal(const PolyData& input, const Prepared& prepared,
                                  const DecimateOptions& options, const EditSettings& settings);
MethodRun decimate_cell_collapse(const PolyData& input, const Prepared& prepared,
                                 const DecimateOptions& options, const EditSettings& settings);

}  // namespace isoforge::reduce
