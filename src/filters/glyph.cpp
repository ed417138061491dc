// Glyphs (filters/glyph.hpp), after VTK's vtkGlyph3D: the masked points are chosen first, then
// every glyph's rotation and size, then all output points, normals, cells and point arrays are
// written in parallel, each glyph into its own fixed slot, so the output does not depend on the
// thread count. The rotation taking +x to a unit direction d is the half-turn about the bisector
// b of +x and d, R = 2 b bᵀ − I (a proper rotation: the source's normals turn with it).

#include "isoforge/filters/glyph.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

#include "isoforge/core/memory.hpp"
#include "isoforge/core/parallel.hpp"
#include "point_fields.hpp"

namespace isoforge {
namespace {

constexpr std::size_t kGrain = 2048;  // glyphs per parallel task

// The array named `name`, or the active one of `role`; nullptr if neither (`name` must exist).
const DataArray* pick(const Attributes& pd, const std::string& name, AttributeRole role,
                      const char* what, int components) {
  const DataArray* a = name.empty() ? pd.active(role) : pd.find(name);
  if (!name.empty() && !a) {
    throw Error(std::string("glyph: ") + what + ": no point array '" + name +
                "' (point arrays: " + pd.names() + ")");
  }
  if (a && components > 0 && a->components() != components) {
    throw Error(std::string("glyph: ") + what + ": point array '" + a->name() + "' has " +
                std::to_string(a->components()) + " components, not " +
                std::to_string(components));
  }
  return a;
}

double ptype_bytes(DatasetRef input) {
  return input.visit([](const auto& d) -> double {
    if constexpr (requires { d.points; }) return d.points.type() == ScalarType::Float64 ? 8.0 : 4.0;
    return 4.0;
  });
}

const DataArray* require(const DataArray* a, const Attributes& pd, const char* what,
                         const char* role) {
  if (!a) {
    throw Error(std::string("glyph: ") + what + ": the input has no active " + role +
                " (point arrays: " + pd.names() + ")");
  }
  return a;
}

using filters_detail::tuple3;

// Row-major 3x3 matrix taking +x to the unit direction of v (identity for zero or non-finite v).
std::array<double, 9> rotation_to(const Vec3& v) {
  const Vec3 d = unit_direction(v);
  if (d == Vec3{}) return {1, 0, 0, 0, 1, 0, 0, 0, 1};
  if (d.x < -1 + 1e-12) return {-1, 0, 0, 0, -1, 0, 0, 0, 1};  // half-turn about z
  Vec3 b{1 + d.x, d.y, d.z};
  b = b / norm(b);
  return {2 * b.x * b.x - 1, 2 * b.x * b.y,     2 * b.x * b.z,
          2 * b.y * b.x,     2 * b.y * b.y - 1, 2 * b.y * b.z,
          2 * b.z * b.x,     2 * b.z * b.y,     2 * b.z * b.z - 1};
}

// Copies the `cells` of the source once per glyph, shifting ids by m per glyph.
CellArray replicate(const CellArray& cells, std::size_t glyphs, std::size_t m) {
  if (cells.empty() || glyphs == 0) return {};
  const std::size_t nc = cells.size(), nid = cells.connectivity().size();
  Buffer<Index> offsets(glyphs * nc + 1), conn(glyphs * nid);
  const auto& so = cells.offsets();
  const auto& sc = cells.connectivity();
  parallel_for_range(glyphs, kGrain, [&](std::size_t begin, std::size_t end) {
    for (std::size_t g = begin; g < end; ++g) {
      const auto shift = static_cast<Index>(g * m);
      const auto base = static_cast<Index>(g * nid);
      for (std::size_t c = 0; c < nc; ++c) offsets[g * nc + c] = base + so[c];
      Index* out = conn.data() + g * nid;
      for (std::size_t k = 0; k < nid; ++k) out[k] = sc[k] + shift;
    }
  });
  offsets[glyphs * nc] = static_cast<Index>(glyphs * nid);
  return CellArray(std::move(offsets), std::move(conn));
}

// The glyphs; `hedgehog`: the source is the unit line, written directly as p, p + size d.
Result<PolyData, GlyphStats> glyph_impl(DatasetRef input, const PolyData& source,
                                        const GlyphOptions& o, bool hedgehog) {
  if (!std::isfinite(o.factor)) {
    throw Error("glyph: factor must be finite, got " + std::to_string(o.factor));
  }
  if (o.range && !((*o.range)[0] < (*o.range)[1] && std::isfinite((*o.range)[0]) &&
                   std::isfinite((*o.range)[1]))) {
    throw Error("glyph: range must be two finite numbers MIN < MAX, got " +
                std::to_string((*o.range)[0]) + " " + std::to_string((*o.range)[1]));
  }
  source.validate();
  const Attributes& pd = point_data(input);
  GlyphStats stats;

  // Orientation, scale and colour arrays.
  const DataArray* orient = nullptr;
  switch (o.orient) {
    case GlyphOrient::Auto:
      orient = pick(pd, o.vectors, AttributeRole::Vectors, "orient by vectors", 3);
      if (!orient) orient = pick(pd, o.normals, AttributeRole::Normals, "orient by normals", 3);
      break;
    case GlyphOrient::Vectors:
      orient = require(pick(pd, o.vectors, AttributeRole::Vectors, "orient by vectors", 3), pd,
                       "orient by vectors", "vectors");
      break;
    case GlyphOrient::Normals:
      orient = require(pick(pd, o.normals, AttributeRole::Normals, "orient by normals", 3), pd,
                       "orient by normals", "normals");
      break;
    case GlyphOrient::None: break;
  }
  const DataArray* scale = nullptr;
  if (o.scale == GlyphScale::Scalar) {
    scale = require(pick(pd, o.scalars, AttributeRole::Scalars, "scale by scalar", 0), pd,
                    "scale by scalar", "scalars");
  } else if (o.scale == GlyphScale::Vector) {
    scale = require(pick(pd, o.vectors, AttributeRole::Vectors, "scale by vector", 3), pd,
                    "scale by vector", "vectors");
  }
  const DataArray* color = nullptr;
  if (o.color == GlyphColor::Scalar) {
    color = require(pick(pd, o.scalars, AttributeRole::Scalars, "colour by scalar", 0), pd,
                    "colour by scalar", "scalars");
  } else if (o.color == GlyphColor::Magnitude) {
    color = require(pick(pd, o.vectors, AttributeRole::Vectors, "colour by magnitude", 3), pd,
                    "colour by magnitude", "vectors");
  }
  const auto value_of = [](const DataArray& a, std::size_t i) {
    if (a.components() == 1) return a.get(i, 0);
    if (a.components() == 3) return norm(tuple3(a, i));
    return a.get(i, 0);
  };
  double r0 = 0, r1 = 1;
  if (scale && o.clamp) {
    if (o.range) {
      r0 = (*o.range)[0];
      r1 = (*o.range)[1];
    } else {
      const auto rg = scale->range(scale->components() == 3 ? -1 : 0);
      r0 = rg.first;
      r1 = rg.second;
    }
  }

  // The glyphed points: all of them (no id list) unless a mask is set.
  const MaskOptions& mk = o.mask;
  const bool all_points = mk.every <= 1 && mk.random == 0 && mk.voxel == 0 && mk.max_points == 0;
  const std::vector<Index> ids = all_points ? std::vector<Index>{} : mask_point_ids(input, mk);
  const std::size_t n = all_points ? num_points(input) : ids.size();
  const auto id_of = [&](std::size_t g) {
    return all_points ? g : static_cast<std::size_t>(ids[g]);
  };
  const std::size_t m = source.num_points();
  stats.glyphs = n;
  stats.source_points = m;
  stats.source_cells = source.num_cells();
  stats.orient_array = orient ? orient->name() : "";
  stats.scale_array = scale ? scale->name() : "";

  // Input positions without a dispatch per point where the points are stored.
  const Points* in_points = input.visit([](const auto& d) -> const Points* {
    if constexpr (requires { d.points; }) return &d.points;
    return nullptr;
  });
  const float* in_float = in_points && in_points->type() == ScalarType::Float32
                              ? in_points->floats().data() : nullptr;
  const auto position = [&](std::size_t id) {
    if (in_float) return Vec3{in_float[3 * id], in_float[3 * id + 1], in_float[3 * id + 2]};
    return in_points ? (*in_points)[id] : point(input, static_cast<Index>(id));
  };
  // A glyph's size (factor included; 0 if not finite).
  const auto size_of = [&](std::size_t id) {
    double s = 1;
    if (scale) {
      const double v = value_of(*scale, id);
      s = o.clamp ? (r1 > r0 ? (std::clamp(v, r0, r1) - r0) / (r1 - r0) : 1.0) : std::abs(v);
    }
    s *= std::abs(o.factor);
    return std::isfinite(s) ? s : 0.0;
  };
  constexpr std::array<double, 9> kIdentity{1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::mutex range_mutex;
  double lo = INFINITY, hi = -INFINITY;
  const auto merge_range = [&](double l, double h) {
    const std::lock_guard<std::mutex> lock(range_mutex);
    lo = std::min(lo, l);
    hi = std::max(hi, h);
  };
  report_progress(o.progress, 0.05, "glyph");

  // Refuse at once an output that cannot fit (e.g. a large source at millions of points).
  {
    double per_point = (ptype_bytes(input) * 3.0) + (o.point_ids ? 8.0 : 0.0) + 12.0 + 4.0;
    if (o.carry_point_data) {
      for (const DataArray& a : pd) per_point += static_cast<double>(scalar_size(a.type())) * a.components();
    }
    double per_glyph = static_cast<double>(m) * per_point;
    for (const CellArray* c : {&source.verts, &source.lines, &source.polys, &source.strips}) {
      per_glyph += 8.0 * static_cast<double>(c->size() + c->connectivity().size());
    }
    require_memory(static_cast<double>(n) * per_glyph,
                   "glyph: " + std::to_string(n) + " glyphs of " + std::to_string(m) + " points");
  }
  PolyData out;
  const std::size_t total = n * m;
  const ScalarType ptype = in_points ? in_points->type() : ScalarType::Float32;
  DataArray pts = DataArray::uninitialized("Points", ptype, 3, total);
  const DataArray* snormals = hedgehog ? nullptr : source.point_data.normals();
  if (snormals && snormals->components() != 3) snormals = nullptr;
  DataArray normals;
  if (snormals) normals = DataArray::uninitialized("Normals", ScalarType::Float32, 3, total);
  std::vector<double> sp(3 * m), sn(snormals ? 3 * m : 0);
  for (std::size_t j = 0; j < m; ++j) {
    const Vec3 p = source.points[j];
    for (int c = 0; c < 3; ++c) sp[3 * j + static_cast<std::size_t>(c)] = p[c];
    if (snormals) {
      for (int c = 0; c < 3; ++c) sn[3 * j + static_cast<std::size_t>(c)] = snormals->get(j, c);
    }
  }
  pts.visit([&](auto& buf) {
    using T = typename std::decay_t<decltype(buf)>::value_type;
    if constexpr (std::is_floating_point_v<T>) {
      T* P = buf.data();
      float* N = snormals ? normals.values<float>().data() : nullptr;
      parallel_for_range(
          n, kGrain,
          [&](std::size_t begin, std::size_t end) {
            double l = INFINITY, h = -INFINITY;
            for (std::size_t g = begin; g < end; ++g) {
              const std::size_t id = id_of(g);
              const Vec3 c = position(id);
              const double s = size_of(id);
              l = std::min(l, s);
              h = std::max(h, s);
              T* q = P + 3 * g * m;
              if (hedgehog) {
                Vec3 d{1, 0, 0};
                if (orient) {
                  const Vec3 u = unit_direction(tuple3(*orient, id));
                  if (u != Vec3{}) d = u;
                }
                const Vec3 e = c + d * s;
                q[0] = static_cast<T>(c.x), q[1] = static_cast<T>(c.y), q[2] = static_cast<T>(c.z);
                q[3] = static_cast<T>(e.x), q[4] = static_cast<T>(e.y), q[5] = static_cast<T>(e.z);
                continue;
              }
              const std::array<double, 9> R = orient ? rotation_to(tuple3(*orient, id)) : kIdentity;
              for (std::size_t j = 0; j < m; ++j) {
                const double x = sp[3 * j], y = sp[3 * j + 1], z = sp[3 * j + 2];
                q[3 * j] = static_cast<T>(c.x + s * (R[0] * x + R[1] * y + R[2] * z));
                q[3 * j + 1] = static_cast<T>(c.y + s * (R[3] * x + R[4] * y + R[5] * z));
                q[3 * j + 2] = static_cast<T>(c.z + s * (R[6] * x + R[7] * y + R[8] * z));
              }
              if (N) {
                float* w = N + 3 * g * m;
                for (std::size_t j = 0; j < m; ++j) {
                  const double x = sn[3 * j], y = sn[3 * j + 1], z = sn[3 * j + 2];
                  w[3 * j] = static_cast<float>(R[0] * x + R[1] * y + R[2] * z);
                  w[3 * j + 1] = static_cast<float>(R[3] * x + R[4] * y + R[5] * z);
                  w[3 * j + 2] = static_cast<float>(R[6] * x + R[7] * y + R[8] * z);
                }
              }
            }
            if (end > begin) merge_range(l, h);
          },
          progress_range(o.progress, 0.05, 0.6), "glyph");
    }
  });
  if (n > 0) {
    stats.min_scale = lo;
    stats.max_scale = hi;
  }
  out.points = Points(std::move(pts));
  report_progress(o.progress, 0.6, "glyph");

  // Cells.
  if (hedgehog) {
    Buffer<Index> offsets(n + 1), conn(2 * n);
    parallel_for_range(n, 8 * kGrain, [&](std::size_t begin, std::size_t end) {
      for (std::size_t g = begin; g < end; ++g) {
        offsets[g] = static_cast<Index>(2 * g);
        conn[2 * g] = static_cast<Index>(2 * g);
        conn[2 * g + 1] = static_cast<Index>(2 * g + 1);
      }
    });
    offsets[n] = static_cast<Index>(2 * n);
    out.lines = CellArray(std::move(offsets), std::move(conn));
  } else {
    out.verts = replicate(source.verts, n, m);
    out.lines = replicate(source.lines, n, m);
    out.polys = replicate(source.polys, n, m);
    out.strips = replicate(source.strips, n, m);
  }
  report_progress(o.progress, 0.8, "glyph");

  // Point arrays: the glyph's normals, input point ids, colour, then the input's arrays.
  if (snormals) out.point_data.add(std::move(normals), AttributeRole::Normals);
  if (o.point_ids) {
    DataArray a = DataArray::uninitialized("InputPointIds", ScalarType::Int64, 1, total);
    std::int64_t* w = a.values<std::int64_t>().data();
    parallel_for_range(n, kGrain, [&](std::size_t begin, std::size_t end) {
      for (std::size_t g = begin; g < end; ++g) std::fill_n(w + g * m, m, static_cast<std::int64_t>(id_of(g)));
    });
    out.point_data.add(std::move(a));
  }
  if (o.color != GlyphColor::None) {
    DataArray a = DataArray::uninitialized("GlyphColor", ScalarType::Float32, 1, total);
    float* w = a.values<float>().data();
    parallel_for_range(n, kGrain, [&](std::size_t begin, std::size_t end) {
      for (std::size_t g = begin; g < end; ++g) {
        const std::size_t id = id_of(g);
        const double v = o.color == GlyphColor::Index ? static_cast<double>(g)
                         : o.color == GlyphColor::Magnitude ? norm(tuple3(*color, id))
                                                            : color->get(id, 0);
        std::fill_n(w + g * m, m, static_cast<float>(v));
      }
    });
    out.point_data.add(std::move(a), AttributeRole::Scalars);
  }
  if (o.carry_point_data) {
    for (const DataArray& a : pd) {
      if (out.point_data.has(a.name())) continue;  // the glyph's own arrays win
      const std::size_t bytes = scalar_size(a.type()) * static_cast<std::size_t>(a.components());
      DataArray b = DataArray::uninitialized(a.name(), a.type(), a.components(), total);
      b.set_lookup_table(a.lookup_table());
      const std::byte* from = a.bytes();
      std::byte* to = b.bytes();
      parallel_for_range(n, kGrain, [&](std::size_t begin, std::size_t end) {
        for (std::size_t g = begin; g < end; ++g) {
          const std::byte* t = from + id_of(g) * bytes;
          std::byte* w = to + g * m * bytes;
          for (std::size_t j = 0; j < m; ++j) std::memcpy(w + j * bytes, t, bytes);
        }
      });
      out.point_data.add(std::move(b));
    }
    for (std::size_t r = 0; r < kAttributeRoleCount; ++r) {
      const auto role = static_cast<AttributeRole>(r);
      const std::string& name = pd.active_name(role);
      if (!name.empty() && out.point_data.active_name(role).empty() && out.point_data.has(name) &&
          !(role == AttributeRole::Normals && snormals)) {
        out.point_data.set_active(role, name);
      }
    }
  }
  report_progress(o.progress, 1.0, "glyph");
  return {std::move(out), stats};
}

}  // namespace

Result<PolyData, GlyphStats> glyph(DatasetRef input, const PolyData& source,
                                   const GlyphOptions& o) {
  return glyph_impl(input, source, o, false);
}

Result<PolyData, GlyphStats> glyph(DatasetRef input, GlyphShape shape, const GlyphOptions& o,
                                   int resolution) {
  return glyph_impl(input, glyph_source(shape, resolution), o, shape == GlyphShape::Line);
}

}  // namespace isoforge
