// Tubes around polylines (filters/tube.hpp), after VTK's vtkTubeFilter. Each ring lies in the
// plane normal to the mean of the adjacent segment directions; the ring's frame is carried
// along the line by projecting the previous normal onto the new plane (a discrete parallel
// transport, Bishop, "There is more than one way to frame a curve", 1975), so a tube does not
// twist. Lines are independent: their rings are written in parallel, each into slots fixed by
// prefix sums, so the output does not depend on the thread count.

#include "isoforge/filters/tube.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "isoforge/core/memory.hpp"
#include "isoforge/core/parallel.hpp"
#include "isoforge/core/subset.hpp"
#include "point_fields.hpp"

namespace isoforge {
namespace {

using filters_detail::perpendicular;
using filters_detail::transport;
using filters_detail::unit_or_zero;

// The point ids of line l without consecutive repeats (by position).
std::vector<Index> distinct_path(const PolyData& lines, std::size_t l) {
  std::vector<Index> path;
  for (const Index id : lines.lines.cell(l)) {
    if (path.empty() || lines.points[static_cast<std::size_t>(id)] !=
                            lines.points[static_cast<std::size_t>(path.back())]) {
      path.push_back(id);
    }
  }
  return path;
}

// The points P of a path of distinct points and their unit tangents T: the mean of the adjacent
// segment directions.
void path_geometry(const PolyData& lines, const std::vector<Index>& ids, std::vector<Vec3>& P,
                   std::vector<Vec3>& T) {
  const std::size_t n = ids.size();
  P.resize(n);
  for (std::size_t i = 0; i < n; ++i) P[i] = lines.points[static_cast<std::size_t>(ids[i])];
  T.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 before = i > 0 ? unit_or_zero(P[i] - P[i - 1]) : Vec3{0, 0, 0};
    const Vec3 after = i + 1 < n ? unit_or_zero(P[i + 1] - P[i]) : Vec3{0, 0, 0};
    Vec3 t = unit_or_zero(before + after);
    if (norm2(t) == 0) t = norm2(before) > 0 ? before : after;  // a reversal: keep going
    T[i] = t;
  }
}


}  // namespace

Result<PolyData, TubeStats> tube(const PolyData& lines, const TubeOptions& o) {
  if (!(o.radius > 0 && std::isfinite(o.radius))) {
    throw Error("tube: radius must be a finite number > 0, got " + std::to_string(o.radius));
  }
  if (o.sides < 3) throw Error("tube: sides must be >= 3, got " + std::to_string(o.sides));
  if (!(o.max_radius >= 0 && std::isfinite(o.max_radius))) {
    throw Error("tube: max radius must be a finite number > 0, got " + std::to_string(o.max_radius));
  }
  if (o.scalar_range && !((*o.scalar_range)[0] < (*o.scalar_range)[1] &&
                          std::isfinite((*o.scalar_range)[0]) && std::isfinite((*o.scalar_range)[1]))) {
    throw Error("tube: scalar range must be two finite numbers MIN < MAX, got " +
                std::to_string((*o.scalar_range)[0]) + " " + std::to_string((*o.scalar_range)[1]));
  }
  lines.validate();
  const DataArray* radius_array = nullptr;
  double s0 = 0, s1 = 1;
  const double rmin = o.radius, rmax = o.max_radius > 0 ? o.max_radius : 10 * o.radius;
  if (!o.radius_array.empty()) {
    radius_array = lines.point_data.find(o.radius_array);
    if (!radius_array) {
      throw Error("tube: radius by '" + o.radius_array + "': no such point array (point arrays: " +
                  lines.point_data.names() + ")");
    }
    if (radius_array->components() != 1 && radius_array->components() != 3) {
      throw Error("tube: radius by '" + o.radius_array + "': " +
                  std::to_string(radius_array->components()) +
                  " components (1, or 3 for a vector's length)");
    }
    if (o.scalar_range) {
      s0 = (*o.scalar_range)[0];
      s1 = (*o.scalar_range)[1];
    } else {
      const auto r = radius_array->range(radius_array->components() == 3 ? -1 : 0);
      s0 = r.first;
      s1 = r.second;
    }
  }
  const auto radius_at = [&](std::size_t id) {
    if (!radius_array) return rmin;
    const double v = radius_array->components() == 1
                         ? radius_array->get(id, 0)
                         : norm(Vec3{radius_array->get(id, 0), radius_array->get(id, 1), radius_array->get(id, 2)});
    if (!std::isfinite(v) || !(s1 > s0)) return rmin;
    return rmin + (std::clamp(v, s0, s1) - s0) / (s1 - s0) * (rmax - rmin);
  };

  // Each line's points without consecutive repeats (by position), and its output slots.
  const std::size_t nl = lines.lines.size();
  const auto k = static_cast<std::size_t>(o.sides);
  std::vector<std::vector<Index>> path(nl);
  std::vector<std::size_t> first_point(nl + 1, 0), first_tri(nl + 1, 0);
  TubeStats stats;
  for (std::size_t l = 0; l < nl; ++l) {
    path[l] = distinct_path(lines, l);
    const std::size_t n = path[l].size();
    if (n < 2) {
      ++stats.skipped_lines;
      path[l].clear();
    } else {
      ++stats.tubes;
    }
    const std::size_t pts = n < 2 ? 0 : n * k + (o.capping ? 2 * k : 0);
    const std::size_t tris = n < 2 ? 0 : 2 * k * (n - 1) + (o.capping ? 2 * (k - 2) : 0);
    first_point[l + 1] = first_point[l] + pts;
    first_tri[l + 1] = first_tri[l] + tris;
  }
  const std::size_t np = first_point[nl], nt = first_tri[nl];
  double point_bytes = 12.0 + (lines.points.type() == ScalarType::Float64 ? 24.0 : 12.0);
  for (const DataArray& a : lines.point_data) point_bytes += static_cast<double>(scalar_size(a.type())) * a.components();
  require_memory(static_cast<double>(np) * point_bytes + static_cast<double>(nt) * 32.0,
                 "tube: " + std::to_string(stats.tubes) + " tubes of " + std::to_string(k) + " sides");
  report_progress(o.progress, 0.1, "tube");

  PolyData out;
  out.points = Points(np, lines.points.type());
  out.point_data = empty_like(lines.point_data, np);
  DataArray normals = DataArray::uninitialized("Normals", ScalarType::Float32, 3, np);
  float* N = normals.values<float>().data();
  Buffer<Index> offsets(nt + 1), conn(3 * nt);
  for (std::size_t t = 0; t <= nt; ++t) offsets[t] = static_cast<Index>(3 * t);
  const std::size_t first_line_cell = lines.verts.size();
  out.cell_data = empty_like(lines.cell_data, nt);
  std::vector<double> cosines(k), sines(k);
  for (std::size_t j = 0; j < k; ++j) {
    const double a = 2 * std::numbers::pi * static_cast<double>(j) / static_cast<double>(k);
    cosines[j] = std::cos(a);
    sines[j] = std::sin(a);
  }
  double lo = INFINITY, hi = -INFINITY;
  for (std::size_t l = 0; l < nl; ++l) {
    for (const Index id : path[l]) {
      const double r = radius_at(static_cast<std::size_t>(id));
      lo = std::min(lo, r);
      hi = std::max(hi, r);
    }
  }
  if (stats.tubes > 0) {
    stats.min_radius = lo;
    stats.max_radius = hi;
  }

  parallel_for_range(
      nl, 16,
      [&](std::size_t begin, std::size_t end) {
        std::vector<Vec3> P, T;
        for (std::size_t l = begin; l < end; ++l) {
          const std::vector<Index>& ids = path[l];
          const std::size_t n = ids.size();
          if (n < 2) continue;
          path_geometry(lines, ids, P, T);
          std::size_t v = first_point[l];
          Vec3 nrm = perpendicular(T[0]);
          const auto put = [&](std::size_t at, const Vec3& p, const Vec3& normal, std::size_t from) {
            out.points.set(at, p);
            N[3 * at] = static_cast<float>(normal.x);
            N[3 * at + 1] = static_cast<float>(normal.y);
            N[3 * at + 2] = static_cast<float>(normal.z);
            copy_tuple(lines.point_data, from, out.point_data, at);
          };
          const std::size_t rings = v;
          for (std::size_t i = 0; i < n; ++i) {
            if (i > 0) nrm = transport(nrm, T[i]);
            const Vec3 bin = cross(T[i], nrm);
            const auto id = static_cast<std::size_t>(ids[i]);
            const double r = radius_at(id);
            for (std::size_t j = 0; j < k; ++j) {
              const Vec3 d = nrm * cosines[j] + bin * sines[j];
              put(v++, P[i] + d * r, d, id);
            }
          }
          // Caps: copies of the end rings with normals along the line.
          const std::size_t cap0 = v;
          if (o.capping) {
            for (const std::size_t i : {std::size_t{0}, n - 1}) {
              const Vec3 normal = i == 0 ? T[0] * -1.0 : T[n - 1];
              for (std::size_t j = 0; j < k; ++j) {
                const std::size_t src = rings + i * k + j;
                put(v++, out.points[src], normal, static_cast<std::size_t>(ids[i]));
              }
            }
          }
          // Triangles.
          Index* c = conn.data() + 3 * first_tri[l];
          const auto tri = [&](std::size_t a, std::size_t b, std::size_t d) {
            *c++ = static_cast<Index>(a);
            *c++ = static_cast<Index>(b);
            *c++ = static_cast<Index>(d);
          };
          for (std::size_t i = 0; i + 1 < n; ++i) {
            const std::size_t a = rings + i * k, b = a + k;
            for (std::size_t j = 0; j < k; ++j) {
              const std::size_t jn = (j + 1) % k;
              tri(a + j, a + jn, b + jn);
              tri(a + j, b + jn, b + j);
            }
          }
          if (o.capping) {
            for (std::size_t j = 1; j + 1 < k; ++j) tri(cap0, cap0 + j + 1, cap0 + j);
            const std::size_t e = cap0 + k;
            for (std::size_t j = 1; j + 1 < k; ++j) tri(e, e + j, e + j + 1);
          }
          for (std::size_t t = first_tri[l]; t < first_tri[l + 1]; ++t) {
            copy_tuple(lines.cell_data, first_line_cell + l, out.cell_data, t);
          }
        }
      },
      progress_range(o.progress, 0.1, 1.0), "tube");
  out.polys = CellArray(std::move(offsets), std::move(conn));
  out.point_data.add(std::move(normals), AttributeRole::Normals);
  out.field_data = lines.field_data;
  return {std::move(out), stats};
}

Result<PolyData, RibbonStats> ribbon(const PolyData& lines, const RibbonOptions& o) {
  if (!(o.width > 0 && std::isfinite(o.width))) {
    throw Error("ribbon: width must be a finite number > 0, got " + std::to_string(o.width));
  }
  if (!std::isfinite(o.angle)) throw Error("ribbon: the angle must be finite");
  lines.validate();
  const DataArray* normals = nullptr;
  if (!o.normals.empty()) {
    normals = lines.point_data.find(o.normals);
    if (!normals) {
      throw Error("ribbon: normals '" + o.normals + "': no such point array (point arrays: " +
                  lines.point_data.names() + ")");
    }
  } else {
    normals = lines.point_data.normals();
  }
  if (normals && normals->components() != 3) {
    throw Error("ribbon: normals '" + normals->name() + "' have " +
                std::to_string(normals->components()) + " components, 3 needed");
  }
  RibbonStats stats;
  stats.oriented = normals != nullptr;
  const std::size_t nl = lines.lines.size();
  std::vector<std::vector<Index>> path(nl);
  std::vector<std::size_t> first_point(nl + 1, 0), first_tri(nl + 1, 0);
  for (std::size_t l = 0; l < nl; ++l) {
    path[l] = distinct_path(lines, l);
    const std::size_t n = path[l].size();
    if (n < 2) {
      ++stats.skipped_lines;
      path[l].clear();
    } else {
      ++stats.ribbons;
    }
    first_point[l + 1] = first_point[l] + (n < 2 ? 0 : 2 * n);
    first_tri[l + 1] = first_tri[l] + (n < 2 ? 0 : 2 * (n - 1));
  }
  const std::size_t np = first_point[nl], nt = first_tri[nl];
  double point_bytes = 12.0 + (lines.points.type() == ScalarType::Float64 ? 24.0 : 12.0);
  for (const DataArray& a : lines.point_data) point_bytes += static_cast<double>(scalar_size(a.type())) * a.components();
  require_memory(static_cast<double>(np) * point_bytes + static_cast<double>(nt) * 32.0,
                 "ribbon: " + std::to_string(stats.ribbons) + " ribbons");

  PolyData out;
  out.points = Points(np, lines.points.type());
  out.point_data = empty_like(lines.point_data, np);  // copy_tuple pairs arrays by position
  DataArray surface_normals = DataArray::uninitialized("Normals", ScalarType::Float32, 3, np);
  float* N = surface_normals.values<float>().data();
  Buffer<Index> offsets(nt + 1), conn(3 * nt);
  for (std::size_t t = 0; t <= nt; ++t) offsets[t] = static_cast<Index>(3 * t);
  out.cell_data = empty_like(lines.cell_data, nt);
  const std::size_t first_line_cell = lines.verts.size();
  const double ca = std::cos(o.angle * std::numbers::pi / 180), sa = std::sin(o.angle * std::numbers::pi / 180);
  const double half = o.width / 2;
  parallel_for_range(
      nl, 16,
      [&](std::size_t begin, std::size_t end) {
        std::vector<Vec3> P, T;
        for (std::size_t l = begin; l < end; ++l) {
          const std::vector<Index>& ids = path[l];
          const std::size_t n = ids.size();
          if (n < 2) continue;
          path_geometry(lines, ids, P, T);
          Vec3 nrm = perpendicular(T[0]);
          std::size_t v = first_point[l];
          for (std::size_t i = 0; i < n; ++i) {
            const auto id = static_cast<std::size_t>(ids[i]);
            if (normals) {
              const Vec3 given{normals->get(id, 0), normals->get(id, 1), normals->get(id, 2)};
              const Vec3 projected = given - T[i] * dot(given, T[i]);
              // A normal along the line (or zero) orients nothing: keep the carried frame.
              nrm = norm2(projected) > 1e-24 ? unit_or_zero(projected) : transport(nrm, T[i]);
            } else if (i > 0) {
              nrm = transport(nrm, T[i]);
            }
            const Vec3 turned = nrm * ca + cross(T[i], nrm) * sa;
            const Vec3 across = cross(T[i], turned);
            for (const double side : {-1.0, 1.0}) {
              out.points.set(v, P[i] + across * (side * half));
              N[3 * v] = static_cast<float>(turned.x);
              N[3 * v + 1] = static_cast<float>(turned.y);
              N[3 * v + 2] = static_cast<float>(turned.z);
              copy_tuple(lines.point_data, id, out.point_data, v);
              ++v;
            }
          }
          // Triangles (a, b on the left, c, d on the right), facing along the normal.
          Index* c = conn.data() + 3 * first_tri[l];
          for (std::size_t i = 0; i + 1 < n; ++i) {
            const auto a = static_cast<Index>(first_point[l] + 2 * i);
            const Index b = a + 1, d = a + 2, e = a + 3;
            *c++ = a, *c++ = b, *c++ = e;
            *c++ = a, *c++ = e, *c++ = d;
          }
          for (std::size_t t = first_tri[l]; t < first_tri[l + 1]; ++t) {
            copy_tuple(lines.cell_data, first_line_cell + l, out.cell_data, t);
          }
        }
      },
      o.progress, "ribbon");
  out.polys = CellArray(std::move(offsets), std::move(conn));
  out.point_data.add(std::move(surface_normals), AttributeRole::Normals);  // replaces the lines'
  out.field_data = lines.field_data;
  return {std::move(out), stats};
}

}  // namespace isoforge
