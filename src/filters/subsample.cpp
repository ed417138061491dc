// Subsampling structured data (filters/subsample.hpp): every n-th point of a volume of
// interest, as VTK's vtkExtractVOI (image data) and vtkExtractGrid (structured grids) do.

#include "isoforge/filters/subsample.hpp"

#include <fmt/format.h>

#include <cstring>
#include <vector>

namespace isoforge {

namespace {

/// The kept indices along each axis.
struct Selection {
  std::array<std::vector<Index>, 3> index;
  [[nodiscard]] Dims dims() const {
    return {Index(index[0].size()), Index(index[1].size()), Index(index[2].size())};
  }
};

Selection select(const Dims& dims, const SubsampleOptions& o, bool boundary_allowed) {
  const char* axis = "ijk";
  if (o.include_boundary && !boundary_allowed) {
    throw Error("subsample: include_boundary applies to structured grids, not image data "
                "(its points must stay evenly spaced)");
  }
  const Voi voi = o.voi.value_or(Voi{0, dims[0] - 1, 0, dims[1] - 1, 0, dims[2] - 1});
  Selection s;
  for (int a = 0; a < 3; ++a) {
    const Index r = o.rate[std::size_t(a)], lo = voi[std::size_t(2 * a)],
                hi = voi[std::size_t(2 * a + 1)];
    if (r < 1) throw Error(fmt::format("subsample: rate along {} must be >= 1, got {}", axis[a], r));
    if (lo < 0 || hi >= dims[std::size_t(a)]) {
      throw Error(fmt::format("subsample: VOI {} {}..{} is out of range 0..{}", axis[a], lo, hi,
                              dims[std::size_t(a)] - 1));
    }
    if (lo > hi) {
      throw Error(fmt::format("subsample: VOI {} {}..{} is inverted", axis[a], lo, hi));
    }
    for (Index i = lo; i <= hi; i += r) s.index[std::size_t(a)].push_back(i);
    if (o.include_boundary && s.index[std::size_t(a)].back() != hi) {
      s.index[std::size_t(a)].push_back(hi);
    }
  }
  return s;
}

/// Copies tuples of every array of `src` into an array of `dst` (made here) at the ids `ids`.
void gather_tuples(const Attributes& src, const std::vector<std::size_t>& ids, Attributes& dst) {
  for (const DataArray& a : src) {
    DataArray d = DataArray::uninitialized(a.name(), a.type(), a.components(), ids.size());
    d.set_lookup_table(a.lookup_table());
    const std::size_t bytes = scalar_size(a.type()) * std::size_t(a.components());
    const std::byte* from = a.bytes();
    std::byte* to = d.bytes();
    for (std::size_t i = 0; i < ids.size(); ++i) std::memcpy(to + i * bytes, from + ids[i] * bytes, bytes);
    dst.add(std::move(d));
  }
  for (std::size_t r = 0; r < kAttributeRoleCount; ++r) {
    const auto role = static_cast<AttributeRole>(r);
    if (!src.active_name(role).empty()) dst.set_active(role, src.active_name(role));
  }
}

/// Input point ids of the kept points, and input cell ids of the output cells (the input cell
/// at each output cell's first point, clamped to the input's cells).
void kept_ids(const Dims& dims, const Selection& s, std::vector<std::size_t>& points,
              std::vector<std::size_t>& cells) {
  const Dims od = s.dims();
  points.clear();
  for (Index k : s.index[2])
    for (Index j : s.index[1])
      for (Index i : s.index[0]) points.push_back(std::size_t(i + dims[0] * (j + dims[1] * k)));
  const Index ci = dims[0] > 1 ? dims[0] - 1 : 1, cj = dims[1] > 1 ? dims[1] - 1 : 1;
  auto cell_index = [&](const std::vector<Index>& idx, Index a, Index n) {
    return n > 1 ? std::min(idx[std::size_t(a)], n - 2) : Index{0};
  };
  cells.clear();
  const Index oci = od[0] > 1 ? od[0] - 1 : 1, ocj = od[1] > 1 ? od[1] - 1 : 1,
              ock = od[2] > 1 ? od[2] - 1 : 1;
  for (Index c = 0; c < ock; ++c)
    for (Index b = 0; b < ocj; ++b)
      for (Index a = 0; a < oci; ++a) {
        const Index i = cell_index(s.index[0], a, dims[0]);
        const Index j = cell_index(s.index[1], b, dims[1]);
        const Index k = cell_index(s.index[2], c, dims[2]);
        cells.push_back(std::size_t(i + ci * (j + cj * k)));
      }
}

}  // namespace

ImageData subsample(const ImageData& input, const SubsampleOptions& options) {
  input.validate();
  const Selection s = select(input.dims, options, false);
  ImageData out;
  out.dims = s.dims();
  out.origin = input.point(s.index[0][0], s.index[1][0], s.index[2][0]);
  for (int a = 0; a < 3; ++a) out.spacing[a] = input.spacing[a] * double(options.rate[std::size_t(a)]);
  std::vector<std::size_t> points, cells;
  kept_ids(input.dims, s, points, cells);
  gather_tuples(input.point_data, points, out.point_data);
  gather_tuples(input.cell_data, cells, out.cell_data);
  out.field_data = input.field_data;
  out.validate();
  return out;
}

StructuredGrid extract_voi(const StructuredGrid& input, const SubsampleOptions& options) {
  input.validate();
  const Selection s = select(input.dims, options, true);
  StructuredGrid out;
  out.dims = s.dims();
  std::vector<std::size_t> points, cells;
  kept_ids(input.dims, s, points, cells);
  Attributes coords;
  coords.add(input.points.array());
  Attributes kept;
  gather_tuples(coords, points, kept);
  out.points = Points(std::move(kept[0]));
  gather_tuples(input.point_data, points, out.point_data);
  gather_tuples(input.cell_data, cells, out.cell_data);
  out.field_data = input.field_data;
  out.validate();
  return out;
}

Dataset subsample(DatasetRef input, const SubsampleOptions& options) {
  if (const auto* img = input.get_if<ImageData>()) return subsample(*img, options);
  if (const auto* g = input.get_if<StructuredGrid>()) return extract_voi(*g, options);
  throw Error(fmt::format("subsample: {} has no i, j, k structure (image data or structured "
                          "grids only)",
                          dataset_type_name(input)));
}

}  // namespace isoforge
