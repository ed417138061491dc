// Dense sampling of implicit functions (vtkSampleFunction's role): rows of points are evaluated
// in blocks by the function tree (function_node.hpp), rows in parallel with TBB.

#include "isoforge/implicit/sample.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <vector>

#include "function_node.hpp"
#include "isoforge/core/memory.hpp"

namespace isoforge {

using implicit_detail::eval_block;
using implicit_detail::eval_pruned;
using implicit_detail::kBlock;

namespace {


// One brick of at most kBx x kBy x kBz samples at (i0, j0, kk0) of a slab: coordinates filled,
// evaluated with eval_pruned over the brick's box (boolean branches that cannot matter there are
// skipped), values stored. Inlined into the clones below, so fills and stores use the CPU's
// widest vectors.
constexpr Index kBx = 16, kBy = 8, kBz = static_cast<Index>(kBlock) / (kBx * kBy);
static_assert(kBx * kBy * kBz == static_cast<Index>(kBlock));

struct SlabAxes {
  const double* xs;  // coordinates of the slab's columns, rows and slices
  const double* ys;
  const double* zs;
  Index nx, ny, nk;
};

template <class T>
[[gnu::always_inline]] inline void sample_brick_impl(const ImplicitFunction::Node& node, const SlabAxes& a,
                                                     Index i0, Index j0, Index kk0, T* out) {
  alignas(64) double x[kBlock], y[kBlock], z[kBlock], v[kBlock];
  const Index ni = std::min(kBx, a.nx - i0), nj = std::min(kBy, a.ny - j0), nkk = std::min(kBz, a.nk - kk0);
  const double* xr = a.xs + i0;
  std::size_t n = 0;
  if (ni == kBx && nj == kBy && nkk == kBz) {
    // A full brick: fixed trip counts, so the fills and stores vectorize.
    for (Index k = 0; k < kBz; ++k) {
      const double zk = a.zs[kk0 + k];
      for (Index j = 0; j < kBy; ++j) {
        const double yj = a.ys[j0 + j];
        for (Index i = 0; i < kBx; ++i) {
          x[n + static_cast<std::size_t>(i)] = xr[i];
          y[n + static_cast<std::size_t>(i)] = yj;
          z[n + static_cast<std::size_t>(i)] = zk;
        }
        n += static_cast<std::size_t>(kBx);
      }
    }
  } else {
    for (Index k = kk0; k < kk0 + nkk; ++k) {
      const double zk = a.zs[k];
      for (Index j = j0; j < j0 + nj; ++j) {
        const double yj = a.ys[j];
        for (Index i = 0; i < ni; ++i) {
          x[n + static_cast<std::size_t>(i)] = xr[i];
          y[n + static_cast<std::size_t>(i)] = yj;
          z[n + static_cast<std::size_t>(i)] = zk;
        }
        n += static_cast<std::size_t>(ni);
      }
    }
  }
  Bounds box;
  box.min = {xr[0], a.ys[j0], a.zs[kk0]};
  box.max = {xr[ni - 1], a.ys[j0 + nj - 1], a.zs[kk0 + nkk - 1]};
  eval_pruned(node, box, x, y, z, n, v);
  n = 0;
  if (ni == kBx) {
    for (Index k = kk0; k < kk0 + nkk; ++k) {
      for (Index j = j0; j < j0 + nj; ++j) {
        T* dst = out + (k * a.ny + j) * a.nx + i0;
        const double* src = v + n;
        for (Index i = 0; i < kBx; ++i) dst[i] = static_cast<T>(src[i]);
        n += static_cast<std::size_t>(kBx);
      }
    }
  } else {
    for (Index k = kk0; k < kk0 + nkk; ++k) {
      for (Index j = j0; j < j0 + nj; ++j) {
        T* dst = out + (k * a.ny + j) * a.nx + i0;
        for (Index i = 0; i < ni; ++i) dst[i] = static_cast<T>(v[n + static_cast<std::size_t>(i)]);
        n += static_cast<std::size_t>(ni);
      }
    }
  }
}

// Cloned as eval_block (ISOFORGE_SIMD_CLONES, src/CMakeLists.txt).
ISOFORGE_SIMD_CLONES
void sample_brick(const ImplicitFunction::Node& node, const SlabAxes& a, Index i0, Index j0, Index kk0,
                  float* out) {
  sample_brick_impl(node, a, i0, j0, kk0, out);
}

ISOFORGE_SIMD_CLONES
void sample_brick(const ImplicitFunction::Node& node, const SlabAxes& a, Index i0, Index j0, Index kk0,
                  double* out) {
  sample_brick_impl(node, a, i0, j0, kk0, out);
}

// Samples z-slices [k0, k0 + nk) of the grid into `out` (the values of slice k0 first), in
// bricks of kBx x kBy x kBz samples, bricks in parallel.
// Coordinates always come from GridSpec::coordinate on the whole grid, so every sampler
// (dense or sparse, any slab split, any thread count) computes bit-identical values.
template <class T>
void sample_slab(const ImplicitFunction::Node& node, const GridSpec& g, Index k0, Index nk, T* out) {
  const Index nx = g.dims[0], ny = g.dims[1];
  std::vector<double> xs(static_cast<std::size_t>(nx)), ys(static_cast<std::size_t>(ny)),
      zs(static_cast<std::size_t>(nk));
  for (Index i = 0; i < nx; ++i) xs[static_cast<std::size_t>(i)] = g.coordinate(0, i);
  for (Index j = 0; j < ny; ++j) ys[static_cast<std::size_t>(j)] = g.coordinate(1, j);
  for (Index k = 0; k < nk; ++k) zs[static_cast<std::size_t>(k)] = g.coordinate(2, k0 + k);
  const SlabAxes axes{xs.data(), ys.data(), zs.data(), nx, ny, nk};
  const Index bx = (nx + kBx - 1) / kBx, by = (ny + kBy - 1) / kBy, bz = (nk + kBz - 1) / kBz;
  tbb::parallel_for(tbb::blocked_range<Index>(0, bx * by * bz, 4), [&](const tbb::blocked_range<Index>& r) {
    for (Index b = r.begin(); b != r.end(); ++b) {
      sample_brick(node, axes, (b % bx) * kBx, ((b / bx) % by) * kBy, (b / (bx * by)) * kBz, out);
    }
  });
}

}  // namespace

ImageData sample_image(const ImplicitFunction& f, const GridSpec& grid, const SampleOptions& options) {
  grid.validate("sample grid");
  if (options.type != ScalarType::Float32 && options.type != ScalarType::Float64) {
    throw Error("sample: value type must be Float32 or Float64");
  }
  if (options.name.empty()) throw Error("sample: the array name is empty");
  require_volume_memory("sample", grid.dims, scalar_type_name(options.type),
                        static_cast<double>(scalar_size(options.type)) + (options.normals ? 12 : 0) +
                            (options.gradients ? 12 : 0));
  ImageData img;
  img.dims = grid.dims;
  img.origin = grid.origin;
  img.spacing = grid.spacing;
  const std::size_t np = img.num_points();
  DataArray values = DataArray::uninitialized(options.name, options.type, 1, np);  // all written

  // Slabs of z-slices, so progress is reported (and cancellation honoured) from this thread.
  const Index nz = grid.dims[2];
  const Index slab = std::max<Index>(1, nz / 32);
  const std::size_t slice = static_cast<std::size_t>(grid.dims[0] * grid.dims[1]);
  for (Index k0 = 0; k0 < nz; k0 += slab) {
    const Index nk = std::min(slab, nz - k0);
    const std::size_t offset = static_cast<std::size_t>(k0) * slice;
    if (options.type == ScalarType::Float32) {
      sample_slab(f.node(), grid, k0, nk, values.values<float>().data() + offset);
    } else {
      sample_slab(f.node(), grid, k0, nk, values.values<double>().data() + offset);
    }
    report_progress(options.progress, static_cast<double>(k0 + nk) / static_cast<double>(nz), "sample");
  }
  img.point_data.add(std::move(values), AttributeRole::Scalars);

  if (options.normals || options.gradients) {
    DataArray normals("Normals", ScalarType::Float32, 3, options.normals ? np : 0);
    DataArray gradients("Gradient", ScalarType::Float32, 3, options.gradients ? np : 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, np, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t id = r.begin(); id != r.end(); ++id) {
        const auto i = static_cast<Index>(id) % grid.dims[0];
        const auto j = (static_cast<Index>(id) / grid.dims[0]) % grid.dims[1];
        const auto k = static_cast<Index>(id) / (grid.dims[0] * grid.dims[1]);
        const Vec3 g = f.gradient({grid.coordinate(0, i), grid.coordinate(1, j), grid.coordinate(2, k)});
        if (options.gradients) {
          float* d = gradients.values<float>().data() + 3 * id;
          d[0] = static_cast<float>(g.x);
          d[1] = static_cast<float>(g.y);
          d[2] = static_cast<float>(g.z);
        }
        if (options.normals) {
          const double len = norm(g);
          const Vec3 u = len > 0 ? g / len : Vec3{0, 0, 0};
          float* d = normals.values<float>().data() + 3 * id;
          d[0] = static_cast<float>(u.x);
          d[1] = static_cast<float>(u.y);
          d[2] = static_cast<float>(u.z);
        }
      }
    });
    if (options.normals) img.point_data.add(std::move(normals), AttributeRole::Normals);
    if (options.gradients) img.point_data.add(std::move(gradients), AttributeRole::Vectors);
  }
  return img;
}

DataArray sample_points(const ImplicitFunction& f, DatasetRef ds, const std::string& name,
                        ScalarType type) {
  if (type != ScalarType::Float32 && type != ScalarType::Float64) {
    throw Error("sample_points: value type must be Float32 or Float64");
  }
  const std::size_t np = num_points(ds);
  DataArray out(name, type, 1, np);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, np, kBlock * 8), [&](const tbb::blocked_range<std::size_t>& r) {
    double x[kBlock], y[kBlock], z[kBlock], v[kBlock];
    for (std::size_t b = r.begin(); b < r.end(); b += kBlock) {
      const std::size_t n = std::min(kBlock, r.end() - b);
      for (std::size_t t = 0; t < n; ++t) {
        const Vec3 p = point(ds, static_cast<Index>(b + t));
        x[t] = p.x;
        y[t] = p.y;
        z[t] = p.z;
      }
      eval_block(f.node(), x, y, z, n, v);
      for (std::size_t t = 0; t < n; ++t) out.set(b + t, 0, v[t]);
    }
  });
  return out;
}

}  // namespace isoforge
