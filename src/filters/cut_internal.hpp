#pragma once
// Private to filters/cut*.cpp: the plane fast path of image data.

#include <optional>
#include <span>
#include <vector>

#include "isoforge/core/buffer.hpp"
#include "isoforge/core/dataset.hpp"
#include "isoforge/filters/cut.hpp"

namespace isoforge::cutting {

/// F(p) = a + g · p, the linear function of a plane.
struct LinearField {
  double a = 0;
  Vec3 g{};
};

/// The cut of 3D image data by the plane `field` = c (value number `value_index`), visiting only
/// the voxels it crosses. nullopt when a grid point lies exactly on the plane (F = c): the caller
/// then takes the general path, which merges the cut points there.
[[nodiscard]] std::optional<PolyData> cut_image_plane(const ImageData& image,
                                                      const LinearField& field, double c,
                                                      int value_index, const CutOptions& options);

/// The cut of a 3D structured grid by the plane `field` = c (one value): exactly the general
/// path's output, from one pass over the points and the rows of cells the plane crosses. nullopt
/// when a point has F = c exactly or F is not finite somewhere (the general path handles those).
[[nodiscard]] std::optional<PolyData> cut_structured_plane(const StructuredGrid& sg,
                                                           const LinearField& field, double c,
                                                           const CutOptions& options,
                                                           CutStats& stats);

/// Calls fn(cell, type, ids) for the cells [c0, c1) of `ds`; structured 3D cells without
/// going through the generic accessors.
/// `row_ok(r)` (structured 3D only) may skip whole rows of cells along i (row r = j + (ny−1) k).
template <class Fn, class RowOk>
void visit_cells(DatasetRef ds, std::size_t c0, std::size_t c1, Fn&& fn, RowOk&& row_ok) {
  const Dims* dims = nullptr;
  bool image = false;
  if (const auto* im = ds.get_if<ImageData>()) {
    dims = &im->dims;
    image = true;
  } else if (const auto* sg = ds.get_if<StructuredGrid>()) {
    dims = &sg->dims;
  }
  if (dims != nullptr && structured_dimension(*dims) == 3) {
    const Index nx = (*dims)[0], ny = (*dims)[1];
    const Index cx = nx - 1, cy = (*dims)[1] - 1;
    const Index dy = nx, dz = nx * ny;
    const CellType type = image ? CellType::Voxel : CellType::Hexahedron;
    Index ids[8];
    for (std::size_t c = c0; c < c1; ++c) {
      const auto ci = static_cast<Index>(c);
      if (!row_ok(static_cast<std::size_t>(ci / cx))) {
        c = static_cast<std::size_t>((ci / cx + 1) * cx) - 1;  // to the end of the row
        continue;
      }
      const Index i = ci % cx, j = (ci / cx) % cy, k = ci / (cx * cy);
      const Index p = i + nx * (j + ny * k);
      if (image) {
        ids[0] = p, ids[1] = p + 1, ids[2] = p + dy, ids[3] = p + dy + 1;
      } else {
        ids[0] = p, ids[1] = p + 1, ids[2] = p + dy + 1, ids[3] = p + dy;
      }
      for (int q = 0; q < 4; ++q) ids[q + 4] = ids[q] + dz;
      fn(ci, type, std::span<const Index>(ids, 8));
    }
    return;
  }
  std::vector<Index> ids;
  for (std::size_t c = c0; c < c1; ++c) {
    const auto ci = static_cast<Index>(c);
    cell_point_ids(ds, ci, ids);
    fn(ci, cell_type(ds, ci), std::span<const Index>(ids));
  }
}

template <class Fn>
void visit_cells(DatasetRef ds, std::size_t c0, std::size_t c1, Fn&& fn) {
  visit_cells(ds, c0, c1, std::forward<Fn>(fn), [](std::size_t) { return true; });
}

/// Values of F at the points of `ds`: `plane` (when given) evaluated directly, else `f` in
/// blocks of points. Parallel, deterministic.
[[nodiscard]] Buffer<double> evaluate_at_points(DatasetRef ds, const ImplicitFunction& f,
                                                const LinearField* plane,
                                                const ProgressCallback& progress);

/// The edge parameter t in [0, 1] of the root of F − c between pa (t = 0, F − c = ga) and pb
/// (t = 1, gb of the other sign), by the Illinois method from the linear estimate t0.
[[nodiscard]] double refine_root(const ImplicitFunction& f, const Vec3& pa, const Vec3& pb,
                                 double ga, double gb, double c, double t0);

}  // namespace isoforge::cutting
