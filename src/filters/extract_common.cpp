// Machinery shared by threshold and extract_surface (extract_common.hpp).

#include "extract_common.hpp"

#include <cstring>

#include "isoforge/core/parallel.hpp"

namespace isoforge::extract_impl {

TopologyView::TopologyView(DatasetRef ds) {
  size_ = num_cells(ds);
  if (const auto* ug = ds.get_if<UnstructuredGrid>()) {
    kind_ = Kind::Unstructured;
    ug_ = ug;
    return;
  }
  if (const auto* pd = ds.get_if<PolyData>()) {
    kind_ = Kind::Poly;
    arrays_[0] = &pd->verts;
    arrays_[1] = &pd->lines;
    arrays_[2] = &pd->polys;
    arrays_[3] = &pd->strips;
    for (int w = 0; w < 4; ++w) start_[w + 1] = start_[w] + arrays_[w]->size();
    return;
  }
  kind_ = Kind::Structured;
  const bool voxel_order = ds.get_if<ImageData>() != nullptr;
  const Dims dims = ds.visit([](const auto& d) -> Dims {
    if constexpr (requires { d.dims; }) {
      return d.dims;
    } else {
      return Dims{1, 1, 1};
    }
  });
  const Index point_stride[3] = {1, dims[0], dims[0] * dims[1]};
  Index axis_stride[3] = {0, 0, 0};  // point stride of the a-th varying axis
  for (int a = 0; a < 3; ++a) {
    if (dims[a] > 1) {
      cells_[dim_] = static_cast<std::size_t>(dims[a] - 1);
      stride_[dim_] = point_stride[a];
      axis_stride[dim_] = point_stride[a];
      ++dim_;
    }
  }
  // Local corners in VTK order (as core's structured_cell_ids gives them).
  const auto at = [&](int di, int dj, int dk) {
    return di * axis_stride[0] + dj * axis_stride[1] + dk * axis_stride[2];
  };
  switch (dim_) {
    case 0:
      stype_ = CellType::Vertex;
      corners_ = 1;
      corner_[0] = 0;
      break;
    case 1:
      stype_ = CellType::Line;
      corners_ = 2;
      corner_[0] = 0;
      corner_[1] = at(1, 0, 0);
      break;
    case 2: {
      stype_ = voxel_order ? CellType::Pixel : CellType::Quad;
      corners_ = 4;
      const Index pix[4] = {at(0, 0, 0), at(1, 0, 0), at(0, 1, 0), at(1, 1, 0)};
      const Index quad[4] = {at(0, 0, 0), at(1, 0, 0), at(1, 1, 0), at(0, 1, 0)};
      for (int i = 0; i < 4; ++i) corner_[i] = voxel_order ? pix[i] : quad[i];
      break;
    }
    default: {
      stype_ = voxel_order ? CellType::Voxel : CellType::Hexahedron;
      corners_ = 8;
      const Index vox[8] = {at(0, 0, 0), at(1, 0, 0), at(0, 1, 0), at(1, 1, 0),
                            at(0, 0, 1), at(1, 0, 1), at(0, 1, 1), at(1, 1, 1)};
      const Index hex[8] = {at(0, 0, 0), at(1, 0, 0), at(1, 1, 0), at(0, 1, 0),
                            at(0, 0, 1), at(1, 0, 1), at(1, 1, 1), at(0, 1, 1)};
      for (int i = 0; i < 8; ++i) corner_[i] = voxel_order ? vox[i] : hex[i];
    }
  }
}

void for_blocks(std::size_t n,
                const std::function<void(std::size_t, std::size_t, std::size_t)>& body,
                const ProgressCallback& progress, const char* operation) {
  parallel_for_range(
      block_count(n), 1,
      [&](std::size_t b0, std::size_t b1) {
        for (std::size_t b = b0; b < b1; ++b) body(b, b * kBlock, std::min(n, (b + 1) * kBlock));
      },
      progress, operation);
}

std::size_t exclusive_scan(std::vector<std::size_t>& v) {
  std::size_t sum = 0;
  for (auto& x : v) {
    const std::size_t c = x;
    x = sum;
    sum += c;
  }
  return sum;
}

void renumber_used(const std::vector<std::uint8_t>& used, Buffer<Index>& map, Buffer<Index>& kept) {
  const std::size_t np = used.size();
  std::vector<std::size_t> counts(block_count(np));
  for_blocks(np, [&](std::size_t b, std::size_t begin, std::size_t end) {
    std::size_t c = 0;
    for (std::size_t i = begin; i < end; ++i) c += used[i];
    counts[b] = c;
  });
  const std::size_t total = exclusive_scan(counts);
  map.resize(np);
  kept.resize(total);
  for_blocks(np, [&](std::size_t b, std::size_t begin, std::size_t end) {
    std::size_t next = counts[b];
    for (std::size_t i = begin; i < end; ++i) {
      map[i] = static_cast<Index>(next);
      if (used[i]) kept[next++] = static_cast<Index>(i);
    }
  });
}

Points gather_points(DatasetRef input, std::span<const Index> kept) {
  const std::size_t n = kept.size();
  if (const auto* img = input.get_if<ImageData>()) {
    DataArray a = DataArray::uninitialized("Points", ScalarType::Float32, 3, n);
    float* dst = a.values<float>().data();
    parallel_for_range(n, 8192, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) {
        const Vec3 p = img->point(kept[i]);
        dst[3 * i] = static_cast<float>(p.x);
        dst[3 * i + 1] = static_cast<float>(p.y);
        dst[3 * i + 2] = static_cast<float>(p.z);
      }
    });
    return Points(std::move(a));
  }
  const Points& src = input.visit([](const auto& d) -> const Points& {
    if constexpr (requires { d.points; }) {
      return d.points;
    } else {
      static const Points none;
      return none;
    }
  });
  const DataArray& a = src.array();
  DataArray b = DataArray::uninitialized("Points", a.type(), 3, n);
  b.visit([&](auto& dst) {
    using T = typename std::decay_t<decltype(dst)>::value_type;
    const T* s = a.values<T>().data();
    T* d = dst.data();
    parallel_for_range(n, 8192, [&](std::size_t lo, std::size_t hi) {
      for (std::size_t i = lo; i < hi; ++i) {
        const T* p = s + 3 * static_cast<std::size_t>(kept[i]);
        d[3 * i] = p[0];
        d[3 * i + 1] = p[1];
        d[3 * i + 2] = p[2];
      }
    });
  });
  return Points(std::move(b));
}

namespace {

template <std::size_t Bytes>
void gather_fixed(const std::byte* src, std::byte* dst, std::span<const Index> from) {
  parallel_for_range(from.size(), 8192, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t i = lo; i < hi; ++i)
      std::memcpy(dst + i * Bytes, src + static_cast<std::size_t>(from[i]) * Bytes, Bytes);
  });
}

}  // namespace

Attributes gather_attributes(const Attributes& src, std::span<const Index> from) {
  Attributes out;
  for (const DataArray& a : src) {
    DataArray b = DataArray::uninitialized(a.name(), a.type(), a.components(), from.size());
    b.set_lookup_table(a.lookup_table());
    const std::size_t bytes = scalar_size(a.type()) * static_cast<std::size_t>(a.components());
    const std::byte* s = a.bytes();
    std::byte* d = b.bytes();
    switch (bytes) {
      case 1: gather_fixed<1>(s, d, from); break;
      case 2: gather_fixed<2>(s, d, from); break;
      case 4: gather_fixed<4>(s, d, from); break;
      case 8: gather_fixed<8>(s, d, from); break;
      case 12: gather_fixed<12>(s, d, from); break;
      case 16: gather_fixed<16>(s, d, from); break;
      case 24: gather_fixed<24>(s, d, from); break;
      default:
        parallel_for_range(from.size(), 8192, [&](std::size_t lo, std::size_t hi) {
          for (std::size_t i = lo; i < hi; ++i)
            std::memcpy(d + i * bytes, s + static_cast<std::size_t>(from[i]) * bytes, bytes);
        });
    }
    out.add(std::move(b));
  }
  for (std::size_t r = 0; r < kAttributeRoleCount; ++r) {
    const auto role = static_cast<AttributeRole>(r);
    if (!src.active_name(role).empty()) out.set_active(role, src.active_name(role));
  }
  return out;
}

DataArray id_array(const char* name, std::span<const Index> ids) {
  Buffer<std::int64_t> v(ids.size());
  parallel_for_range(ids.size(), 65536, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t i = lo; i < hi; ++i) v[i] = ids[i];
  });
  return DataArray::from_buffer<std::int64_t>(name, 1, std::move(v));
}

}  // namespace isoforge::extract_impl
