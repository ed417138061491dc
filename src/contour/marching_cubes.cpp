// Marching cubes on 3D images and structured grids: the lattice kernel of marching_cubes.hpp with
// the regular grid's geometry or the grid's own points, for every isovalue.

#include "marching_cubes.hpp"
#include "contour_internal.hpp"

namespace isoforge::contour_detail {

namespace {

/// Contours one isovalue of a lattice (every dimension >= 2): counting is the first 40% of
/// `progress`, generating the rest.
template <class T, class Geometry>
PolyData lattice_value(const Geometry& geometry, const Dims& dims, const T* values, double iso,
                       const Attributes& point_data, const Attributes& cell_data,
                       const ContourOptions& options, ContourStats& stats,
                       const ProgressCallback& progress) {
  LatticeContourer<T, Geometry> c(geometry, dims, values, iso, options);
  const LatticeCounts total = c.count(progress_range(progress, 0.0, 0.4));
  const auto npts = static_cast<std::size_t>(total.x);
  const auto ntris = static_cast<std::size_t>(total.tris);
  PolyData out = triangle_output(npts, ntris);
  out.polys.offsets()[0] = 0;
  ContourArrays arrays(point_data, cell_data, npts, ntris, options);
  c.generate(out.points.floats().data(), out.polys.connectivity().data(),
             out.polys.offsets().data(), arrays, progress_range(progress, 0.4, 1.0));
  arrays.move_into(out);
  stats.points += npts;
  stats.cells += ntris;
  stats.ambiguous_faces += static_cast<std::size_t>(total.ambiguous);
  return out;
}

/// Every isovalue of `options` on a lattice.
template <class Geometry>
PolyData lattice(const Geometry& geometry, const Dims& dims, const DataArray& scalars,
                 const Attributes& point_data, const Attributes& cell_data,
                 const ContourOptions& options, ContourStats& stats) {
  return contour_each_value(options, stats, [&](std::size_t v, const ProgressCallback& progress) {
    return scalars.visit([&](const auto& vec) {
      return lattice_value(geometry, dims, vec.data(), options.values[v], point_data, cell_data,
                           options, stats, progress);
    });
  });
}

}  // namespace

PolyData marching_cubes(const ImageData& image, const DataArray& scalars,
                        const ContourOptions& options, ContourStats& stats) {
  return lattice(ImageGeometry(image), image.dims, scalars, image.point_data, image.cell_data,
                 options, stats);
}

PolyData marching_cubes(const StructuredGrid& grid, const DataArray& scalars,
                        const ContourOptions& options, ContourStats& stats) {
  // Hexahedra read in voxel corner order: the lattice kernel with the grid's own points.
  return lattice(GridGeometry{grid}, grid.dims, scalars, grid.point_data, grid.cell_data, options,
                 stats);
}

}  // namespace isoforge::contour_detail
