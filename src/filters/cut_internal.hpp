#pragma once
// Private to filters/cut*.cpp: the plane fast path of image data.

#include <optional>

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

}  // namespace isoforge::cutting
