#pragma once
// Private to filters/cut*.cpp: the plane fast path of image data.

#include <optional>

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
