// Shared contouring pieces: option checks, attribute interpolation, appending, normals.

#include <algorithm>
#include <cmath>
#include <cstring>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "contour_internal.hpp"

namespace isoforge::contour_detail {

const DataArray& contour_scalars(const Attributes& point_data, const ContourOptions& options,
                                 const char* who) {
  if (options.values.empty()) throw Error(std::string(who) + ": no isovalues given");
  for (double v : options.values) {
    if (!std::isfinite(v)) throw Error(std::string(who) + ": isovalue " + std::to_string(v) + " is not finite");
  }
  const DataArray* a = options.array.empty() ? point_data.scalars() : point_data.find(options.array);
  if (!a) {
    if (options.array.empty()) {
      throw Error(std::string(who) + ": the input has no active point scalars (name an array)");
    }
    throw Error(std::string(who) + ": no point array named '" + options.array + "'");
  }
  if (a->components() != 1) {
    throw Error(std::string(who) + ": array '" + a->name() + "' has " + std::to_string(a->components()) +
                " components; contouring needs one");
  }
  return *a;
}

namespace {

template <class T>
void interp_typed(const DataArray& src, DataArray& dst, std::size_t out,
                  std::span<const InterpolatedArrays::Term> terms) {
  const auto nc = static_cast<std::size_t>(src.components());
  const T* s = src.values<T>().data();
  T* d = dst.values<T>().data();
  for (std::size_t c = 0; c < nc; ++c) {
    double v = 0;
    for (const auto& [id, w] : terms) v += w * static_cast<double>(s[id * nc + c]);
    if constexpr (std::is_floating_point_v<T>) {
      d[out * nc + c] = static_cast<T>(v);
    } else {
      d[out * nc + c] = static_cast<T>(std::nearbyint(v));
    }
  }
}

void copy_tuple_raw(const DataArray& src, DataArray& dst, std::size_t out, std::size_t in) {
  const std::size_t bytes = scalar_size(src.type()) * static_cast<std::size_t>(src.components());
  std::memcpy(dst.bytes() + out * bytes, src.bytes() + in * bytes, bytes);
}

}  // namespace

InterpolatedArrays::InterpolatedArrays(const Attributes& point_data, const Attributes& cell_data,
                                       std::size_t points, std::size_t cells, bool attributes,
                                       bool normals) {
  if (attributes) {
    src_points_ = &point_data;
    src_cells_ = &cell_data;
    for (const auto& a : point_data) {
      DataArray d = DataArray::uninitialized(a.name(), a.type(), a.components(), points);
      d.set_lookup_table(a.lookup_table());
      points_.add(std::move(d));
      interp_.push_back(a.visit([](const auto& v) -> InterpFn {
        using T = typename std::decay_t<decltype(v)>::value_type;
        return &interp_typed<T>;
      }));
    }
    for (std::size_t r = 0; r < kAttributeRoleCount; ++r) {
      const auto role = static_cast<AttributeRole>(r);
      if (!point_data.active_name(role).empty()) points_.set_active(role, point_data.active_name(role));
    }
    for (const auto& a : cell_data) {
      cells_.add(DataArray::uninitialized(a.name(), a.type(), a.components(), cells));
      copy_.push_back(&copy_tuple_raw);
    }
    for (std::size_t r = 0; r < kAttributeRoleCount; ++r) {
      const auto role = static_cast<AttributeRole>(r);
      if (!cell_data.active_name(role).empty()) cells_.set_active(role, cell_data.active_name(role));
    }
    this->cell_data = !cells_.empty();
  }
  if (normals) {
    normal_array_ = DataArray::uninitialized("Normals", ScalarType::Float32, 3, points);
    this->normals = normal_array_.values<float>().data();
    has_normals_ = true;
  }
}

void InterpolatedArrays::interpolate(std::size_t out, std::size_t a, std::size_t b, double t) const {
  const Term terms[2] = {{a, 1.0 - t}, {b, t}};
  combine(out, terms);
}

void InterpolatedArrays::combine(std::size_t out, std::span<const Term> terms) const {
  for (std::size_t i = 0; i < interp_.size(); ++i) {
    interp_[i]((*src_points_)[i], const_cast<DataArray&>(points_[i]), out, terms);
  }
}

void InterpolatedArrays::copy_cell(std::size_t out, std::size_t in) const {
  for (std::size_t i = 0; i < copy_.size(); ++i) {
    copy_[i]((*src_cells_)[i], const_cast<DataArray&>(cells_[i]), out, in);
  }
}

void InterpolatedArrays::move_into(Attributes& point_data, Attributes& cell_data) {
  for (std::size_t i = 0; i < points_.size(); ++i) point_data.add(std::move(points_[i]));
  for (std::size_t r = 0; r < kAttributeRoleCount; ++r) {
    const auto role = static_cast<AttributeRole>(r);
    if (!points_.active_name(role).empty()) point_data.set_active(role, points_.active_name(role));
  }
  for (std::size_t i = 0; i < cells_.size(); ++i) cell_data.add(std::move(cells_[i]));
  for (std::size_t r = 0; r < kAttributeRoleCount; ++r) {
    const auto role = static_cast<AttributeRole>(r);
    if (!cells_.active_name(role).empty()) cell_data.set_active(role, cells_.active_name(role));
  }
  if (has_normals_) point_data.add(std::move(normal_array_), AttributeRole::Normals);
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

PolyData append_polydata(std::vector<PolyData> parts) {
  if (parts.size() == 1) return std::move(parts.front());
  PolyData out;
  if (parts.empty()) return out;
  std::size_t np = 0;
  for (const auto& p : parts) np += p.points.size();
  out.points = Points(0, parts.front().points.type());
  out.points.reserve(np);
  for (const auto& p : parts) {
    const Index base = static_cast<Index>(out.points.size());
    for (std::size_t i = 0; i < p.points.size(); ++i) out.points.push_back(p.points[i]);
    auto append_cells = [base](CellArray& dst, const CellArray& src) {
      for (std::size_t c = 0; c < src.size(); ++c) {
        auto ids = src.cell(c);
        std::vector<Index> shifted(ids.begin(), ids.end());
        for (Index& id : shifted) id += base;
        dst.add(shifted);
      }
    };
    append_cells(out.verts, p.verts);
    append_cells(out.lines, p.lines);
    append_cells(out.polys, p.polys);
    append_cells(out.strips, p.strips);
  }
  // Point data: concatenate arrays by name (every part has the same layout).
  const PolyData& first = parts.front();
  for (std::size_t a = 0; a < first.point_data.size(); ++a) {
    DataArray merged(first.point_data[a].name(), first.point_data[a].type(),
                     first.point_data[a].components(), np);
    std::size_t at = 0;
    const std::size_t tb = scalar_size(merged.type()) * static_cast<std::size_t>(merged.components());
    for (const auto& p : parts) {
      const DataArray& src = p.point_data.get(merged.name());
      if (src.size_bytes() > 0) std::memcpy(merged.bytes() + at * tb, src.bytes(), src.size_bytes());  // empty: null data
      at += src.tuples();
    }
    out.point_data.add(std::move(merged));
  }
  for (std::size_t r = 0; r < kAttributeRoleCount; ++r) {
    const auto role = static_cast<AttributeRole>(r);
    if (!first.point_data.active_name(role).empty()) out.point_data.set_active(role, first.point_data.active_name(role));
  }
  // Cell data in verts, lines, polys, strips order of the result.
  const std::size_t nc = out.num_cells();
  for (std::size_t a = 0; a < first.cell_data.size(); ++a) {
    const DataArray& proto = first.cell_data[a];
    DataArray merged(proto.name(), proto.type(), proto.components(), nc);
    const std::size_t tb = scalar_size(merged.type()) * static_cast<std::size_t>(merged.components());
    std::size_t at = 0;
    for (int kind = 0; kind < 4; ++kind) {
      for (const auto& p : parts) {
        const DataArray& src = p.cell_data.get(proto.name());
        std::size_t start = 0, count = 0;
        const std::size_t sizes[4] = {p.verts.size(), p.lines.size(), p.polys.size(), p.strips.size()};
        for (int q = 0; q < kind; ++q) start += sizes[q];
        count = sizes[kind];
        if (count > 0) std::memcpy(merged.bytes() + at * tb, src.bytes() + start * tb, count * tb);
        at += count;
      }
    }
    out.cell_data.add(std::move(merged));
  }
  return out;
}

void finish_output(PolyData& pd, const ContourOptions& options) {
  if (options.flip) {
    for (CellArray* ca : {&pd.lines, &pd.polys}) {
      for (std::size_t c = 0; c < ca->size(); ++c) {
        auto ids = ca->cell(c);
        std::reverse(ids.begin(), ids.end());
      }
    }
  }
  if (options.normals != ContourNormals::Triangles) return;
  const std::size_t np = pd.points.size();
  std::vector<double> acc(3 * np, 0.0);
  for (std::size_t c = 0; c < pd.polys.size(); ++c) {
    auto ids = pd.polys.cell(c);
    for (std::size_t k = 1; k + 1 < ids.size(); ++k) {
      const Vec3 a = pd.points[static_cast<std::size_t>(ids[0])];
      const Vec3 b = pd.points[static_cast<std::size_t>(ids[k])];
      const Vec3 d = pd.points[static_cast<std::size_t>(ids[k + 1])];
      const Vec3 n = cross(b - a, d - a);  // twice the area, along the normal
      for (Index id : {ids[0], ids[k], ids[k + 1]}) {
        for (int i = 0; i < 3; ++i) acc[3 * static_cast<std::size_t>(id) + static_cast<std::size_t>(i)] += n[i];
      }
    }
  }
  DataArray normals("Normals", ScalarType::Float32, 3, np);
  float* out = normals.values<float>().data();
  for (std::size_t i = 0; i < np; ++i) {
    const Vec3 n{acc[3 * i], acc[3 * i + 1], acc[3 * i + 2]};
    const double len = norm(n);
    const Vec3 u = len > 0 ? n / len : Vec3{0, 0, 0};
    out[3 * i] = static_cast<float>(u.x);
    out[3 * i + 1] = static_cast<float>(u.y);
    out[3 * i + 2] = static_cast<float>(u.z);
  }
  pd.point_data.add(std::move(normals), AttributeRole::Normals);
}

}  // namespace isoforge::contour_detail
