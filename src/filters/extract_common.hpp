#pragma once
// Machinery shared by threshold and extract_surface (private to filters/): fast read access to
// the cells of any dataset, block-wise parallel compaction, and parallel gathers of points and
// attribute tuples. Everything here is deterministic: blocks are fixed by the input size, never
// by the number of threads.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "isoforge/core/dataset.hpp"
#include "isoforge/core/progress.hpp"

namespace isoforge::extract_impl {

/// Cells of any dataset without the per-call dispatch of `cell_point_ids`: structured cells
/// are computed from their index, the others read in place from the connectivity.
class TopologyView {
 public:
  explicit TopologyView(DatasetRef ds);

  [[nodiscard]] std::size_t size() const { return size_; }
  /// Point ids of cell `c`: a view of the dataset's connectivity, or of `buf` (8 entries) for
  /// structured cells.
  [[nodiscard]] std::span<const Index> ids(std::size_t c, Index* buf) const {
    switch (kind_) {
      case Kind::Structured: {
        Index base = 0;
        std::size_t rest = c;
        for (int a = 0; a < dim_; ++a) {
          const std::size_t n = cells_[a];
          base += static_cast<Index>(rest % n) * stride_[a];
          rest /= n;
        }
        for (int i = 0; i < corners_; ++i) buf[i] = base + corner_[i];
        return {buf, static_cast<std::size_t>(corners_)};
      }
      case Kind::Poly: {
        int w = 0;
        while (c >= start_[w + 1]) ++w;
        return arrays_[w]->cell(c - start_[w]);
      }
      case Kind::Unstructured: break;
    }
    return ug_->cells.cell(c);
  }
  [[nodiscard]] CellType type(std::size_t c) const {
    switch (kind_) {
      case Kind::Structured: return stype_;
      case Kind::Poly: {
        int w = 0;
        while (c >= start_[w + 1]) ++w;
        const std::size_t n = arrays_[w]->cell_size(c - start_[w]);
        switch (w) {
          case 0: return n == 1 ? CellType::Vertex : CellType::PolyVertex;
          case 1: return n == 2 ? CellType::Line : CellType::PolyLine;
          case 2: return n == 3 ? CellType::Triangle : (n == 4 ? CellType::Quad : CellType::Polygon);
          default: return CellType::TriangleStrip;
        }
      }
      case Kind::Unstructured: break;
    }
    return ug_->types[c];
  }
  /// Image data or a structured grid (every cell of type `type(0)`).
  [[nodiscard]] bool structured() const { return kind_ == Kind::Structured; }

 private:
  enum class Kind { Structured, Poly, Unstructured };
  Kind kind_ = Kind::Unstructured;
  std::size_t size_ = 0;
  // structured
  int dim_ = 0;
  std::size_t cells_[3] = {1, 1, 1};
  Index stride_[3] = {0, 0, 0};
  Index corner_[8] = {};
  int corners_ = 0;
  CellType stype_ = CellType::Vertex;
  // polygonal data
  const CellArray* arrays_[4] = {};
  std::size_t start_[5] = {};
  // unstructured grid
  const UnstructuredGrid* ug_ = nullptr;
};

/// Cells per block of the block-wise passes (a block is the unit of parallel work and of the
/// prefix sums, so the output never depends on the thread count).
inline constexpr std::size_t kBlock = 16384;
[[nodiscard]] inline std::size_t block_count(std::size_t n) { return (n + kBlock - 1) / kBlock; }

/// Runs body(block, begin, end) over the blocks of [0, n) in parallel, reporting progress.
void for_blocks(std::size_t n, const std::function<void(std::size_t, std::size_t, std::size_t)>& body,
                const ProgressCallback& progress = {}, const char* operation = "");

/// In-place exclusive prefix sum; returns the total.
std::size_t exclusive_scan(std::vector<std::size_t>& v);

/// Marks `used[id] = 1` from several threads (a relaxed atomic store: same value, no race).
inline void mark_used(std::uint8_t* used, Index id) {
  std::atomic_ref<std::uint8_t>(used[id]).store(1, std::memory_order_relaxed);
}

/// The renumbering of the used points: map[id] = new id (increasing original id) for used
/// points (unspecified otherwise), and `kept` = the used ids in increasing order.
void renumber_used(const std::vector<std::uint8_t>& used, Buffer<Index>& map, Buffer<Index>& kept);

/// The points `kept` of `input` (Float64 if the input stores Float64, else Float32).
[[nodiscard]] Points gather_points(DatasetRef input, std::span<const Index> kept);

/// Arrays like `src` holding tuples `from[0], from[1], ...` of it (roles and lookup tables kept).
[[nodiscard]] Attributes gather_attributes(const Attributes& src, std::span<const Index> from);

/// An Int64 array `name` holding `ids`.
[[nodiscard]] DataArray id_array(const char* name, std::span<const Index> ids);

}  // namespace isoforge::extract_impl
