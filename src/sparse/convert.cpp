// Conversion between OpenVDB float grids and image data (sparse/convert.hpp).

#include "isoforge/sparse/convert.hpp"

#include <fmt/format.h>
#include <openvdb/tools/Dense.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "isoforge/sparse/grid.hpp"

namespace isoforge {

ImageData vdb_to_image(const openvdb::FloatGrid& grid, std::size_t max_voxels) {
  const std::string gname = grid.getName().empty() ? std::string("Scalars") : grid.getName();
  const std::string what = "vdb_to_image: grid '" + gname + "'";
  const UniformTransform xf = uniform_transform(grid, what);
  const openvdb::CoordBBox bbox = grid.evalActiveVoxelBoundingBox();
  if (bbox.empty()) throw Error(what + ": the grid has no active voxels");
  const openvdb::Coord dim = bbox.dim();
  std::uint64_t count = 1;
  for (int a = 0; a < 3; ++a) {
    if (__builtin_mul_overflow(count, static_cast<std::uint64_t>(dim[a]), &count)) {
      count = UINT64_MAX;
      break;
    }
  }
  if (count > max_voxels) {
    throw Error(fmt::format(
        "{}: the active bounding box {} x {} x {} = {} voxels exceeds the limit "
        "of {}",
        what, dim[0], dim[1], dim[2],
        count == UINT64_MAX ? std::string("more than 2^64") : std::to_string(count), max_voxels));
  }
  ImageData img;
  img.dims = {dim[0], dim[1], dim[2]};
  const openvdb::Coord lo = bbox.min();
  img.origin = {xf.coordinate(0, lo[0]), xf.coordinate(1, lo[1]), xf.coordinate(2, lo[2])};
  img.spacing = {xf.voxel_size, xf.voxel_size, xf.voxel_size};
  std::vector<float> values(static_cast<std::size_t>(count), grid.background());
  auto index = [&](const openvdb::Coord& c) {
    return static_cast<std::size_t>(c[0] - lo[0]) +
           static_cast<std::size_t>(dim[0]) *
               (static_cast<std::size_t>(c[1] - lo[1]) +
                static_cast<std::size_t>(dim[1]) * static_cast<std::size_t>(c[2] - lo[2]));
  };
  for (auto it = grid.cbeginValueOn(); it; ++it) {
    if (it.isVoxelValue()) {
      values[index(it.getCoord())] = *it;
    } else {
      openvdb::CoordBBox tile;
      it.getBoundingBox(tile);
      tile.intersect(bbox);
      for (int k = tile.min()[2]; k <= tile.max()[2]; ++k) {
        for (int j = tile.min()[1]; j <= tile.max()[1]; ++j) {
          for (int i = tile.min()[0]; i <= tile.max()[0]; ++i) {
            values[index(openvdb::Coord(i, j, k))] = *it;
          }
        }
      }
    }
  }
  img.point_data.add(DataArray::from_vector(gname, 1, std::move(values)), AttributeRole::Scalars);
  return img;
}

openvdb::FloatGrid::Ptr image_to_vdb(const ImageData& image, const ImageToVdbOptions& options) {
  image.validate();
  const DataArray* a = nullptr;
  if (options.array.empty()) {
    a = image.point_data.scalars();
    if (!a) throw Error("image_to_vdb: the image has no active point scalars; name an array");
  } else {
    a = image.point_data.find(options.array);
    if (!a) throw Error("image_to_vdb: the image has no point array '" + options.array + "'");
  }
  const std::string what = "image_to_vdb: array '" + a->name() + "'";
  if (a->components() != 1) {
    throw Error(fmt::format("{} has {} components; a float grid needs 1", what, a->components()));
  }
  if (!std::isfinite(options.background)) throw Error("image_to_vdb: background is not finite");
  if (!std::isfinite(options.tolerance) || options.tolerance < 0) {
    throw Error("image_to_vdb: tolerance must be a finite float32 >= 0");
  }
  const Vec3 sp = image.spacing;
  const double s = sp.x;
  const double tol = 1e-9 * std::max({std::abs(sp.x), std::abs(sp.y), std::abs(sp.z)});
  if (!(s > 0) || std::abs(sp.y - s) > tol || std::abs(sp.z - s) > tol) {
    throw Error(
        fmt::format("image_to_vdb: OpenVDB grids need equal positive spacing on all axes, "
                    "got ({:g}, {:g}, {:g})",
                    sp.x, sp.y, sp.z));
  }
  for (int d = 0; d < 3; ++d) {
    if (image.dims[d] > (Index{1} << 31) - 1) {
      throw Error(
          fmt::format("image_to_vdb: dimension {} = {} exceeds OpenVDB's 32-bit index space", d,
                      image.dims[d]));
    }
  }
  ensure_openvdb_initialized();
  std::vector<float> values(a->size());
  a->visit([&](const auto& v) {
    for (std::size_t i = 0; i < v.size(); ++i) values[i] = static_cast<float>(v[i]);
  });
  auto grid = openvdb::FloatGrid::create(options.background);
  grid->setName(a->name());
  grid->setTransform(vdb_transform(s, image.origin, "image_to_vdb"));
  const openvdb::CoordBBox box(
      openvdb::Coord(0, 0, 0),
      openvdb::Coord(static_cast<int>(image.dims[0] - 1), static_cast<int>(image.dims[1] - 1),
                     static_cast<int>(image.dims[2] - 1)));
  openvdb::tools::Dense<float, openvdb::tools::LayoutXYZ> dense(box, values.data());
  openvdb::tools::copyFromDense(dense, *grid, options.tolerance);
  grid->pruneGrid(0.0f);
  return grid;
}

}  // namespace isoforge
