// What every contour kernel shares to build its output (contour_output.hpp).

#include "contour_output.hpp"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <tuple>

#include "isoforge/core/normals.hpp"
#include "isoforge/core/subset.hpp"

namespace isoforge::contour_detail {

void check_values(const ContourOptions& options, const char* who) {
  if (options.values.empty()) throw Error(fmt::format("{}: no isovalues given", who));
  for (double v : options.values) {
    if (!std::isfinite(v)) throw Error(fmt::format("{}: isovalue {} is not finite", who, v));
  }
}

const DataArray& contour_scalars(const Attributes& point_data, const ContourOptions& options,
                                 const char* who) {
  check_values(options, who);
  const DataArray* a =
      options.array.empty() ? point_data.scalars() : point_data.find(options.array);
  if (!a) {
    if (options.array.empty()) {
      throw Error(fmt::format("{}: the input has no active point scalars (name an array)", who));
    }
    throw Error(fmt::format("{}: no point array named '{}'", who, options.array));
  }
  if (a->components() != 1) {
    throw Error(fmt::format("{}: array '{}' has {} components; contouring needs one", who,
                            a->name(), a->components()));
  }
  return *a;
}

ContourArrays::ContourArrays(const Attributes& point_data, const Attributes& cell_data,
                             std::size_t points, std::size_t cells, const ContourOptions& options) {
  if (options.interpolate_attributes) {
    attributes = AttributeInterpolator(point_data, cell_data, points, cells);
    this->cell_data = attributes.has_cell_arrays();
  }
  if (options.normals == ContourNormals::Gradient) {
    normal_array_ = DataArray::uninitialized("Normals", ScalarType::Float32, 3, points);
    normals = normal_array_.values<float>().data();
  }
}

void ContourArrays::move_into(PolyData& out) {
  attributes.move_into(out.point_data, out.cell_data);
  if (normals) out.point_data.add(std::move(normal_array_), AttributeRole::Normals);
  normals = nullptr;
}

PolyData triangle_output(std::size_t points, std::size_t triangles) {
  PolyData pd;
  pd.points = Points(DataArray::uninitialized("Points", ScalarType::Float32, 3, points));
  pd.polys.offsets().resize(triangles + 1);
  pd.polys.connectivity().resize(3 * triangles);
  return pd;
}

void add_isovalue_index(PolyData& pd, int index) {
  DataArray a = DataArray::uninitialized("IsovalueIndex", ScalarType::Int32, 1, pd.points.size());
  std::int32_t* v = a.values<std::int32_t>().data();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pd.points.size(), 1 << 16),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      std::fill(v + r.begin(), v + r.end(), static_cast<std::int32_t>(index));
                    });
  pd.point_data.add(std::move(a));
}

namespace {

/// Removes the points that are not finite (crossings of edges with an undefined, NaN, end) and
/// the cells using them: a vertex or polygon goes, a polyline is split into its runs of
/// defined points (runs of one point go). Unused points go too; attributes follow. Subtracts
/// the points and the vertices, segments and triangles removed from `stats`.
void drop_undefined(PolyData& pd, ContourStats& stats) {
  const std::size_t np = pd.points.size();
  const auto xyz = pd.points.floats();
  std::vector<char> bad(np, 0);
  bool any = false;
  for (std::size_t p = 0; p < np; ++p) {
    if (!std::isfinite(xyz[3 * p]) || !std::isfinite(xyz[3 * p + 1]) || !std::isfinite(xyz[3 * p + 2])) {
      bad[p] = 1;
      any = true;
    }
  }
  if (!any) return;
  // The cells kept, as (source cell, ids); cell ids count verts, lines, polys, strips in turn.
  std::vector<Index> used(np, -1);
  Index next = 0;
  std::vector<std::size_t> source;
  auto keep_ids = [&](CellArray& out, std::span<const Index> ids) {
    std::vector<Index> mapped(ids.size());
    for (std::size_t k = 0; k < ids.size(); ++k) {
      Index& u = used[static_cast<std::size_t>(ids[k])];
      if (u < 0) u = next++;
      mapped[k] = u;
    }
    out.add(mapped);
  };
  std::size_t cell = 0;
  PolyData out;
  for (auto [in, dst, split] : {std::tuple{&pd.verts, &out.verts, false}, std::tuple{&pd.lines, &out.lines, true},
                                 std::tuple{&pd.polys, &out.polys, false}, std::tuple{&pd.strips, &out.strips, false}}) {
    for (std::size_t c = 0; c < in->size(); ++c, ++cell) {
      const auto ids = in->cell(c);
      if (!split) {
        if (std::none_of(ids.begin(), ids.end(), [&](Index id) { return bad[static_cast<std::size_t>(id)] != 0; })) {
          keep_ids(*dst, ids);
          source.push_back(cell);
        }
        continue;
      }
      std::size_t start = 0;
      for (std::size_t k = 0; k <= ids.size(); ++k) {
        if (k < ids.size() && !bad[static_cast<std::size_t>(ids[k])]) continue;
        if (k - start >= 2) {
          keep_ids(*dst, ids.subspan(start, k - start));
          source.push_back(cell);
        }
        start = k + 1;
      }
    }
  }
  const auto kept = static_cast<std::size_t>(next);
  out.points = Points(DataArray::uninitialized("Points", pd.points.type(), 3, kept));
  out.point_data = empty_like(pd.point_data, kept);
  for (std::size_t p = 0; p < np; ++p) {
    if (used[p] < 0) continue;
    const auto to = static_cast<std::size_t>(used[p]);
    out.points.set(to, pd.points[p]);
    copy_tuple(pd.point_data, p, out.point_data, to);
  }
  out.cell_data = empty_like(pd.cell_data, source.size());
  for (std::size_t c = 0; c < source.size(); ++c) copy_tuple(pd.cell_data, source[c], out.cell_data, c);
  out.field_data = std::move(pd.field_data);
  // Cells in the units of ContourStats: vertices, segments, triangles (one per polygon here).
  auto units = [](const PolyData& d) {
    std::size_t n = d.verts.size() + d.polys.size();
    for (std::size_t c = 0; c < d.lines.size(); ++c) n += d.lines.cell_size(c) - 1;
    for (std::size_t c = 0; c < d.strips.size(); ++c) n += d.strips.cell_size(c) - 2;
    return n;
  };
  stats.points -= std::min(stats.points, np - kept);
  stats.cells -= std::min(stats.cells, units(pd) - units(out));
  pd = std::move(out);
}

}  // namespace

void finish_output(PolyData& pd, const ContourOptions& options, ContourStats& stats) {
  drop_undefined(pd, stats);
  if (options.flip) {
    for (CellArray* ca : {&pd.lines, &pd.polys}) {
      for (std::size_t c = 0; c < ca->size(); ++c) {
        auto ids = ca->cell(c);
        std::reverse(ids.begin(), ids.end());
      }
    }
  }
  if (options.normals == ContourNormals::Triangles) {
    pd.point_data.add(point_normals(pd), AttributeRole::Normals);
  }
}

}  // namespace isoforge::contour_detail
