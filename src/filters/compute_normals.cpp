// Surface normals (filters/compute_normals.hpp), after VTK's vtkPolyDataNormals: polygons are
// made consistent by a breadth-first walk over manifold edges (a neighbour that runs along the
// shared edge in the same direction is reversed), each closed surface is turned outward by the
// sign of its volume (divergence theorem: the sum of signed tetrahedra to a fixed point), then
// at each point the polygons around it are grouped across edges no sharper than the feature
// angle and each group beyond the first gets its own copy of the point. Cell normals are
// Newell's normals; point normals are core/normals.hpp's area-weighted sums on the result.

#include "isoforge/filters/compute_normals.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "isoforge/core/normals.hpp"
#include "isoforge/core/parallel.hpp"
#include "isoforge/core/subset.hpp"

namespace isoforge {
namespace {

// Polygons as plain offset/id lists (strips triangulated), with each one's source cell.
struct Polys {
  Buffer<Index> off = Buffer<Index>(1, 0);
  Buffer<Index> ids;
  std::vector<Index> source;  // cell id in the input's cell numbering
  [[nodiscard]] std::size_t size() const { return off.size() - 1; }
  [[nodiscard]] std::size_t len(std::size_t p) const {
    return static_cast<std::size_t>(off[p + 1] - off[p]);
  }
  [[nodiscard]] Index at(std::size_t p, std::size_t k) const {
    return ids[static_cast<std::size_t>(off[p]) + k];
  }
};

Polys gather(const PolyData& in) {
  Polys P;
  const auto first_poly = static_cast<Index>(in.verts.size() + in.lines.size());
  P.ids.assign(in.polys.connectivity().begin(), in.polys.connectivity().end());
  P.off.assign(in.polys.offsets().begin(), in.polys.offsets().end());
  P.source.resize(in.polys.size());
  for (std::size_t c = 0; c < in.polys.size(); ++c) P.source[c] = first_poly + static_cast<Index>(c);
  for (std::size_t s = 0; s < in.strips.size(); ++s) {
    const auto v = in.strips.cell(s);
    for (std::size_t i = 0; i + 2 < v.size(); ++i) {
      if (i % 2 == 0) {
        P.ids.insert(P.ids.end(), {v[i], v[i + 1], v[i + 2]});
      } else {
        P.ids.insert(P.ids.end(), {v[i + 1], v[i], v[i + 2]});
      }
      P.off.push_back(static_cast<Index>(P.ids.size()));
      P.source.push_back(first_poly + static_cast<Index>(in.polys.size() + s));
    }
  }
  return P;
}

// Direction of the edge a-b in polygon p: +1 if p runs a→b, -1 if b→a, 0 if not an edge.
int edge_dir(const Polys& P, std::size_t p, Index a, Index b) {
  const std::size_t n = P.len(p);
  for (std::size_t k = 0; k < n; ++k) {
    if (P.at(p, k) != a) continue;
    if (P.at(p, (k + 1) % n) == b) return 1;
    if (P.at(p, (k + n - 1) % n) == b) return -1;
  }
  return 0;
}

Vec3 newell(const Polys& P, const Points& pts, std::size_t p, bool reversed) {
  const std::size_t n = P.len(p);
  Vec3 s{0, 0, 0};
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3 a = pts[static_cast<std::size_t>(P.at(p, k))];
    const Vec3 b = pts[static_cast<std::size_t>(P.at(p, (k + 1) % n))];
    s.x += (a.y - b.y) * (a.z + b.z);
    s.y += (a.z - b.z) * (a.x + b.x);
    s.z += (a.x - b.x) * (a.y + b.y);
  }
  return reversed ? s * -1.0 : s;
}

}  // namespace

Result<PolyData, NormalsStats> compute_normals(const PolyData& input, const NormalsOptions& o) {
  if (!(o.feature_angle >= 0 && o.feature_angle <= 180)) {
    throw Error("compute normals: feature angle must be in [0, 180] degrees, got " +
                std::to_string(o.feature_angle));
  }
  input.validate();
  NormalsStats stats;
  const std::size_t np = input.num_points();
  Polys P = gather(input);
  const std::size_t npoly = P.size();

  // Point → polygon incidence (the star of each point), in increasing polygon order; each
  // corner remembers its slot in its point's star.
  std::vector<Index> star_off(np + 1, 0);
  for (const Index v : P.ids) ++star_off[static_cast<std::size_t>(v) + 1];
  for (std::size_t i = 0; i < np; ++i) star_off[i + 1] += star_off[i];
  Buffer<Index> star(P.ids.size()), corner_slot(P.ids.size());  // every slot written below
  {
    std::vector<Index> fill(star_off.begin(), star_off.end() - 1);
    for (std::size_t p = 0; p < npoly; ++p) {
      for (auto c = static_cast<std::size_t>(P.off[p]); c < static_cast<std::size_t>(P.off[p + 1]); ++c) {
        const Index s = fill[static_cast<std::size_t>(P.ids[c])]++;
        star[static_cast<std::size_t>(s)] = static_cast<Index>(p);
        corner_slot[c] = s;
      }
    }
  }
  report_progress(o.progress, 0.1, "compute normals");

  // The polygon across each half-edge (corner c of p: the edge from its point to the next),
  // found in parallel through the star of its first point: kBorder, kNonManifold, or the one
  // other polygon, with whether it runs the edge the same way.
  constexpr Index kBorder = -1, kNonManifold = -2;
  Buffer<Index> across(P.ids.size());
  std::vector<char> same_way(P.ids.size(), 0), first_of_fan(P.ids.size(), 0);
  parallel_for_range(npoly, 2048, [&](std::size_t begin, std::size_t end) {
    for (std::size_t p = begin; p < end; ++p) {
      const std::size_t n = P.len(p);
      const auto c0 = static_cast<std::size_t>(P.off[p]);
      for (std::size_t k = 0; k < n; ++k) {
        const Index a = P.at(p, k), b = P.at(p, (k + 1) % n);
        Index found = kBorder, smallest = static_cast<Index>(p);
        int count = 0, dir = 0;
        if (a != b) {
          const auto sa = static_cast<std::size_t>(a);
          Index last = -1;
          for (auto t = static_cast<std::size_t>(star_off[sa]); t < static_cast<std::size_t>(star_off[sa + 1]); ++t) {
            const Index q = star[t];
            if (q == static_cast<Index>(p) || q == last) continue;
            last = q;
            const int d = edge_dir(P, static_cast<std::size_t>(q), a, b);
            if (d == 0) continue;
            ++count;
            found = q;
            dir = d;
            smallest = std::min(smallest, q);
          }
        }
        across[c0 + k] = count == 0 ? kBorder : (count == 1 ? found : kNonManifold);
        same_way[c0 + k] = dir == 1 ? 1 : 0;
        first_of_fan[c0 + k] = count >= 2 && smallest == static_cast<Index>(p) ? 1 : 0;
      }
    }
  });
  for (const char f : first_of_fan) stats.non_manifold_edges += f ? 1 : 0;
  report_progress(o.progress, 0.2, "compute normals");

  // Breadth-first walk over manifold edges: components, orientation, closedness.
  std::vector<char> flip(npoly, 0);
  std::vector<Index> comp(npoly, -1);
  std::vector<char> comp_open;
  std::vector<Index> queue;
  for (std::size_t seed = 0; seed < npoly; ++seed) {
    if (comp[seed] >= 0) continue;
    const auto c = static_cast<Index>(comp_open.size());
    comp_open.push_back(0);
    comp[seed] = c;
    queue.assign(1, static_cast<Index>(seed));
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const auto p = static_cast<std::size_t>(queue[head]);
      for (auto e = static_cast<std::size_t>(P.off[p]); e < static_cast<std::size_t>(P.off[p + 1]); ++e) {
        const Index q = across[e];
        if (q < 0) {
          comp_open[static_cast<std::size_t>(c)] = 1;
          continue;
        }
        // Neighbours agree when they run the shared edge opposite ways as written.
        const auto qi = static_cast<std::size_t>(q);
        const char want = same_way[e] ? static_cast<char>(!flip[p]) : flip[p];
        if (comp[qi] < 0) {
          comp[qi] = c;
          flip[qi] = o.consistency ? want : 0;
          queue.push_back(q);
        } else if (p < qi && flip[qi] != want) {
          ++stats.inconsistent_edges;
        }
      }
    }
    // Orientation of the whole component.
    if (o.consistency && o.auto_orient) {
      bool reverse = false;
      if (!comp_open[static_cast<std::size_t>(c)]) {
        const Vec3 origin = input.points[static_cast<std::size_t>(P.at(static_cast<std::size_t>(queue[0]), 0))];
        double volume = 0;
        for (const Index pi : queue) {
          const auto p = static_cast<std::size_t>(pi);
          const std::size_t n = P.len(p);
          const Vec3 a = input.points[static_cast<std::size_t>(P.at(p, 0))] - origin;
          for (std::size_t k = 1; k + 1 < n; ++k) {
            const Vec3 b = input.points[static_cast<std::size_t>(P.at(p, k))] - origin;
            const Vec3 d = input.points[static_cast<std::size_t>(P.at(p, k + 1))] - origin;
            volume += (flip[p] ? -1.0 : 1.0) * dot(a, cross(b, d));
          }
        }
        reverse = volume < 0;
      } else {
        std::size_t flipped = 0;
        for (const Index p : queue) flipped += flip[static_cast<std::size_t>(p)] ? 1 : 0;
        reverse = 2 * flipped > queue.size();
      }
      if (reverse) {
        for (const Index p : queue) flip[static_cast<std::size_t>(p)] ^= 1;
      }
    }
  }
  if (o.flip) {
    for (auto& f : flip) f ^= 1;
  }
  stats.surfaces = comp_open.size();
  for (const char op : comp_open) stats.closed_surfaces += op ? 0 : 1;
  for (const char f : flip) stats.flipped_polygons += f ? 1 : 0;
  report_progress(o.progress, 0.3, "compute normals");

  // Oriented polygons: a reversed polygon keeps its first point and runs the others backwards.
  for (std::size_t p = 0; p < npoly; ++p) {
    if (!flip[p]) continue;
    std::reverse(P.ids.begin() + P.off[p] + 1, P.ids.begin() + P.off[p + 1]);
    std::reverse(corner_slot.begin() + P.off[p] + 1, corner_slot.begin() + P.off[p + 1]);
  }
  std::vector<Vec3> unit(npoly);
  parallel_for_range(npoly, 4096, [&](std::size_t begin, std::size_t end) {
    for (std::size_t p = begin; p < end; ++p) {
      const Vec3 n = newell(P, input.points, p, false);
      const double len = norm(n);
      unit[p] = len > 0 ? n / len : Vec3{0, 0, 0};
    }
  });
  report_progress(o.progress, 0.4, "compute normals");

  // Splitting: group the polygons around each point across smooth manifold edges.
  std::vector<Index> group(star.size(), 0);  // per star slot: 0 = the point itself, g = copy g
  std::vector<Index> extra(np + 1, 0);
  if (o.split && o.feature_angle < 180) {
    const double cos_feature = std::cos(o.feature_angle * std::numbers::pi / 180);
    parallel_for_range(np, 1024, [&](std::size_t begin, std::size_t end) {
      std::vector<std::pair<Index, Index>> spokes;  // (other point, local slot)
      std::vector<Index> parent, label;
      for (std::size_t v = begin; v < end; ++v) {
        const auto s0 = static_cast<std::size_t>(star_off[v]);
        const std::size_t k = static_cast<std::size_t>(star_off[v + 1]) - s0;
        if (k < 2) continue;
        spokes.clear();
        for (std::size_t i = 0; i < k; ++i) {
          const auto p = static_cast<std::size_t>(star[s0 + i]);
          const std::size_t n = P.len(p);
          for (std::size_t j = 0; j < n; ++j) {
            if (P.at(p, j) != static_cast<Index>(v)) continue;
            spokes.emplace_back(P.at(p, (j + 1) % n), static_cast<Index>(i));
            spokes.emplace_back(P.at(p, (j + n - 1) % n), static_cast<Index>(i));
          }
        }
        std::sort(spokes.begin(), spokes.end());
        parent.resize(k);
        for (std::size_t i = 0; i < k; ++i) parent[i] = static_cast<Index>(i);
        const auto find = [&](Index x) {
          while (parent[static_cast<std::size_t>(x)] != x) {
            x = parent[static_cast<std::size_t>(x)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
          }
          return x;
        };
        for (std::size_t a = 0; a < spokes.size();) {
          std::size_t b = a;
          while (b < spokes.size() && spokes[b].first == spokes[a].first) ++b;
          if (b - a == 2 && spokes[a].second != spokes[a + 1].second) {
            const auto i = spokes[a].second, j = spokes[a + 1].second;
            const Vec3& ni = unit[static_cast<std::size_t>(star[s0 + static_cast<std::size_t>(i)])];
            const Vec3& nj = unit[static_cast<std::size_t>(star[s0 + static_cast<std::size_t>(j)])];
            if (dot(ni, nj) >= cos_feature) {
              const Index ri = find(i), rj = find(j);
              if (ri != rj) parent[static_cast<std::size_t>(std::max(ri, rj))] = std::min(ri, rj);
            }
          }
          a = b;
        }
        // Groups numbered by their first slot: the group of slot 0 keeps the point.
        label.assign(k, -1);
        Index groups = 0;
        for (std::size_t i = 0; i < k; ++i) {
          const auto r = static_cast<std::size_t>(find(static_cast<Index>(i)));
          if (label[r] < 0) label[r] = groups++;
          group[s0 + i] = label[r];
        }
        extra[v + 1] = groups - 1;
      }
    });
  }
  for (std::size_t i = 0; i < np; ++i) extra[i + 1] += extra[i];
  const auto added = static_cast<std::size_t>(extra[np]);
  stats.split_points = added;
  report_progress(o.progress, 0.7, "compute normals");

  PolyData out;
  out.points = input.points;
  out.point_data = input.point_data;
  if (added > 0) {
    out.points.resize(np + added);
    for (auto& a : out.point_data) a.resize(np + added);
    for (std::size_t v = 0; v < np; ++v) {
      const auto s0 = static_cast<std::size_t>(star_off[v]), s1 = static_cast<std::size_t>(star_off[v + 1]);
      for (std::size_t s = s0; s < s1; ++s) {
        const Index g = group[s];
        if (g == 0) continue;
        const auto id = np + static_cast<std::size_t>(extra[v] + g - 1);
        out.points.set(id, input.points[v]);
        copy_tuple(input.point_data, v, out.point_data, id);
      }
    }
    for (std::size_t c = 0; c < P.ids.size(); ++c) {
      const auto v = static_cast<std::size_t>(P.ids[c]);
      const Index g = group[static_cast<std::size_t>(corner_slot[c])];
      if (g > 0) P.ids[c] = static_cast<Index>(np) + extra[v] + g - 1;
    }
  }
  out.verts = input.verts;
  out.lines = input.lines;
  out.polys = CellArray(std::move(P.off), std::move(P.ids));
  out.field_data = input.field_data;
  const std::size_t nfixed = input.verts.size() + input.lines.size();
  if (input.strips.empty()) {
    out.cell_data = input.cell_data;
  } else {
    out.cell_data = empty_like(input.cell_data, nfixed + npoly);
    for (std::size_t c = 0; c < nfixed; ++c) copy_tuple(input.cell_data, c, out.cell_data, c);
    for (std::size_t p = 0; p < npoly; ++p) {
      copy_tuple(input.cell_data, static_cast<std::size_t>(P.source[p]), out.cell_data, nfixed + p);
    }
  }
  if (o.cell_normals) {
    DataArray cn("Normals", ScalarType::Float32, 3, nfixed + npoly);
    float* w = cn.values<float>().data() + 3 * nfixed;
    for (std::size_t p = 0; p < npoly; ++p) {
      w[3 * p] = static_cast<float>(unit[p].x);
      w[3 * p + 1] = static_cast<float>(unit[p].y);
      w[3 * p + 2] = static_cast<float>(unit[p].z);
    }
    out.cell_data.add(std::move(cn), AttributeRole::Normals);
  }
  report_progress(o.progress, 0.8, "compute normals");
  if (o.point_normals) out.point_data.add(point_normals(out), AttributeRole::Normals);
  report_progress(o.progress, 1.0, "compute normals");
  return {std::move(out), stats};
}

}  // namespace isoforge
