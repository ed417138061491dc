// Connectivity segmentation of polygonal data (connectivity.hpp; section 1.5.3, Fig. 1.29; the
// peer is VTK's vtkPolyDataConnectivityFilter): union-find over the points (cells sharing a
// point) or over the cells (cells sharing an edge, edge uses bucketed by their smaller point),
// components numbered by decreasing size, and extraction of the selected components with only
// the points they use and all their attributes.

#include "isoforge/contour/connectivity.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <span>
#include <string>
#include <utility>

#include "isoforge/core/subset.hpp"
#include "isoforge/core/union_find.hpp"

namespace isoforge {

namespace {

constexpr const char* kOp = "connectivity";
constexpr std::int32_t kNone = std::numeric_limits<std::int32_t>::max();
// Progress is reported every 2^20 cells (or points) of a labelling loop.
constexpr std::size_t kProgressMask = (std::size_t{1} << 20) - 1;

enum CellKind : int { kVerts = 0, kLines = 1, kPolys = 2, kStrips = 3 };

std::array<const CellArray*, 4> cell_arrays(const PolyData& pd) {
  return {&pd.verts, &pd.lines, &pd.polys, &pd.strips};
}

// Calls f(cell id, kind, point ids) for every cell, in cell-id order.
template <class F>
void for_each_cell(const PolyData& pd, F&& f) {
  std::size_t id = 0;
  const auto arrays = cell_arrays(pd);
  for (int k = 0; k < 4; ++k) {
    const CellArray& a = *arrays[static_cast<std::size_t>(k)];
    const Index* conn = a.connectivity().data();
    const auto& off = a.offsets();
    for (std::size_t c = 0; c + 1 < off.size(); ++c, ++id) {
      const auto n = static_cast<std::size_t>(off[c + 1] - off[c]);
      f(id, k, std::span<const Index>(conn + off[c], n));
    }
  }
}

// Calls f(a, b) for every edge of a cell (a != b not guaranteed): polyline segments, polygon
// sides, the sides of a strip's triangles; vertex cells have none.
template <class F>
void for_each_edge(int kind, std::span<const Index> ids, F&& f) {
  const std::size_t n = ids.size();
  switch (kind) {
    case kLines:
      for (std::size_t i = 0; i + 1 < n; ++i) f(ids[i], ids[i + 1]);
      break;
    case kPolys:
      for (std::size_t i = 0; i < n; ++i) f(ids[i], ids[i + 1 == n ? 0 : i + 1]);
      break;
    case kStrips:
      for (std::size_t i = 0; i + 1 < n; ++i) f(ids[i], ids[i + 1]);
      for (std::size_t i = 0; i + 2 < n; ++i) f(ids[i], ids[i + 2]);
      break;
    default:
      break;
  }
}

// Provisional labels (connected through shared points), numbered in order of each component's
// smallest cell id. Returns the number of components.
template <class T>
std::size_t label_by_points(const PolyData& pd, std::vector<std::int32_t>& label,
                            const ProgressCallback& progress) {
  UnionFind<T> sets(pd.num_points());
  const double nc = static_cast<double>(pd.num_cells());
  for_each_cell(pd, [&](std::size_t c, int, std::span<const Index> ids) {
    for (std::size_t i = 1; i < ids.size(); ++i) {
      sets.unite(static_cast<T>(ids[i - 1]), static_cast<T>(ids[i]));
    }
    if ((c & kProgressMask) == kProgressMask) report_progress(progress, 0.8 * (static_cast<double>(c) / nc), kOp);
  });
  std::vector<std::int32_t> root_label(pd.num_points(), -1);
  std::int32_t next = 0;
  for_each_cell(pd, [&](std::size_t c, int, std::span<const Index> ids) {
    std::int32_t& l = root_label[sets.find(static_cast<T>(ids[0]))];
    if (l < 0) l = next++;
    label[c] = l;
  });
  return static_cast<std::size_t>(next);
}

// Provisional labels (connected through shared edges), numbered as by label_by_points. The
// edge uses are bucketed by their smaller point (a counting sort), then sorted by the larger
// one within each bucket; the cells of equal edges are united.
template <class T>
std::size_t label_by_edges(const PolyData& pd, std::vector<std::int32_t>& label,
                           const ProgressCallback& progress) {
  const std::size_t np = pd.num_points(), nc = pd.num_cells();
  std::vector<T> start(np + 1, 0);
  for_each_cell(pd, [&](std::size_t, int kind, std::span<const Index> ids) {
    for_each_edge(kind, ids, [&](Index a, Index b) {
      if (a != b) ++start[static_cast<std::size_t>(std::min(a, b)) + 1];
    });
  });
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<std::pair<T, T>> uses(static_cast<std::size_t>(start[np]));  // (larger point, cell)
  for_each_cell(pd, [&](std::size_t c, int kind, std::span<const Index> ids) {
    for_each_edge(kind, ids, [&](Index a, Index b) {
      if (a == b) return;
      if (b < a) std::swap(a, b);
      uses[static_cast<std::size_t>(start[static_cast<std::size_t>(a)]++)] = {static_cast<T>(b),
                                                                           static_cast<T>(c)};
    });
  });
  // start[p] now ends bucket p; shift back so it begins it.
  for (std::size_t p = np; p > 0; --p) start[p] = start[p - 1];
  start[0] = 0;

  report_progress(progress, 0.4, kOp);
  UnionFind<T> sets(nc);
  for (std::size_t p = 0; p < np; ++p) {
    if ((p & kProgressMask) == kProgressMask) {
      report_progress(progress, 0.4 + 0.5 * (static_cast<double>(p) / static_cast<double>(np)), kOp);
    }
    const auto first = uses.begin() + static_cast<std::ptrdiff_t>(start[p]);
    const auto last = uses.begin() + static_cast<std::ptrdiff_t>(start[p + 1]);
    if (last - first < 2) continue;
    std::sort(first, last);
    for (auto it = first + 1; it != last; ++it) {
      if (it->first == (it - 1)->first) sets.unite((it - 1)->second, it->second);
    }
  }
  // The root of a set is its smallest cell, met before every other cell of the set.
  std::int32_t next = 0;
  for (std::size_t c = 0; c < nc; ++c) {
    const std::size_t r = sets.find(static_cast<T>(c));
    label[c] = r == c ? next++ : label[r];
  }
  return static_cast<std::size_t>(next);
}

// Area of one cell: the vector area of a polygon (exact for planar polygons, convex or not),
// the sum of a strip's triangle areas; 0 for verts, lines and non-finite results.
double cell_area(const Points& pts, int kind, std::span<const Index> ids) {
  auto p = [&](std::size_t i) { return pts[static_cast<std::size_t>(ids[i])]; };
  double area = 0;
  if (kind == kPolys) {
    const Vec3 p0 = p(0);
    Vec3 sum{0, 0, 0};
    for (std::size_t i = 1; i + 1 < ids.size(); ++i) sum += cross(p(i) - p0, p(i + 1) - p0);
    area = 0.5 * norm(sum);
  } else if (kind == kStrips) {
    for (std::size_t i = 0; i + 2 < ids.size(); ++i) {
      area += 0.5 * norm(cross(p(i + 1) - p(i), p(i + 2) - p(i)));
    }
  }
  return std::isfinite(area) ? area : 0.0;
}

std::vector<char> select_components(const PolyData& input, const ConnectivityOptions& o,
                                    const std::vector<std::int32_t>& comp, std::size_t ncomp) {
  std::vector<char> sel(ncomp, 0);
  switch (o.mode) {
    case ConnectivityMode::All:
      std::fill(sel.begin(), sel.end(), 1);
      break;
    case ConnectivityMode::Largest:
    case ConnectivityMode::LargestN: {
      const std::size_t n = o.mode == ConnectivityMode::Largest ? 1 : o.count;
      std::fill(sel.begin(), sel.begin() + static_cast<std::ptrdiff_t>(std::min(n, ncomp)), 1);
      break;
    }
    case ConnectivityMode::Specified:
      for (std::size_t id : o.components) {
        if (id >= ncomp) {
          throw Error(std::string(kOp) + ": component " + std::to_string(id) +
                      " is out of range (the input has " + std::to_string(ncomp) +
                      " components)");
        }
        sel[id] = 1;
      }
      break;
    case ConnectivityMode::ClosestToPoint: {
      // The smallest component of every used point (points of one component by point share it).
      std::vector<std::int32_t> point_comp(input.num_points(), kNone);
      for_each_cell(input, [&](std::size_t c, int, std::span<const Index> ids) {
        for (Index id : ids) {
          std::int32_t& pc = point_comp[static_cast<std::size_t>(id)];
          pc = std::min(pc, comp[c]);
        }
      });
      double best = std::numeric_limits<double>::infinity();
      std::size_t best_id = point_comp.size();
      for (std::size_t i = 0; i < point_comp.size(); ++i) {
        if (point_comp[i] == kNone) continue;
        const double d = norm2(input.points[i] - o.point);
        if (d < best) {
          best = d;
          best_id = i;
        }
      }
      if (best_id < point_comp.size()) sel[static_cast<std::size_t>(point_comp[best_id])] = 1;
      break;
    }
    case ConnectivityMode::PointSeeded: {
      std::vector<char> seed(input.num_points(), 0);
      for (Index s : o.seeds) seed[static_cast<std::size_t>(s)] = 1;
      for_each_cell(input, [&](std::size_t c, int, std::span<const Index> ids) {
        for (Index id : ids) {
          if (seed[static_cast<std::size_t>(id)]) sel[static_cast<std::size_t>(comp[c])] = 1;
        }
      });
      break;
    }
    case ConnectivityMode::CellSeeded:
      for (Index s : o.seeds) sel[static_cast<std::size_t>(comp[static_cast<std::size_t>(s)])] = 1;
      break;
  }
  return sel;
}

void check_options(const PolyData& input, const ConnectivityOptions& o) {
  const std::string op(kOp);
  if (o.mode == ConnectivityMode::LargestN && o.count == 0) {
    throw Error(op + ": count must be at least 1 for LargestN");
  }
  if (o.mode == ConnectivityMode::ClosestToPoint && !is_finite(o.point)) {
    throw Error(op + ": the point for ClosestToPoint is not finite");
  }
  if (o.mode == ConnectivityMode::PointSeeded || o.mode == ConnectivityMode::CellSeeded) {
    const bool points = o.mode == ConnectivityMode::PointSeeded;
    const std::size_t n = points ? input.num_points() : input.num_cells();
    for (Index s : o.seeds) {
      if (s < 0 || static_cast<std::size_t>(s) >= n) {
        throw Error(op + ": seed " + (points ? "point " : "cell ") + std::to_string(s) +
                    " is out of range (the input has " + std::to_string(n) +
                    (points ? " points)" : " cells)"));
      }
    }
  }
  if (input.num_cells() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
    throw Error(op + ": " + std::to_string(input.num_cells()) +
                " cells exceed the Int32 range of ComponentId");
  }
}

// The work of both overloads. `donor` is null or the input itself (owned by the caller, who
// discards it afterwards), whose arrays are then moved into the output, each after its last read,
// where the output keeps them whole.
ConnectivityResult run(const PolyData& input, const ConnectivityOptions& options,
                       PolyData* donor) {
  check_options(input, options);
  input.validate();
  report_progress(options.progress, 0.0, kOp);
  const std::size_t np = input.num_points(), nc = input.num_cells();
  constexpr std::size_t k32 = std::numeric_limits<std::uint32_t>::max();

  // 1. Provisional labels, in order of each component's smallest cell.
  std::vector<std::int32_t> comp(nc);
  std::size_t ncomp = 0;
  if (options.connected_by == ConnectedBy::Point) {
    const ProgressCallback labels = progress_range(options.progress, 0.0, 0.5);
    ncomp = np < k32 ? label_by_points<std::uint32_t>(input, comp, labels)
                     : label_by_points<std::uint64_t>(input, comp, labels);
  } else {
    std::size_t ids = 0;
    for (const CellArray* a : cell_arrays(input)) ids += a->connectivity().size();
    const ProgressCallback labels = progress_range(options.progress, 0.0, 0.5);
    ncomp = np < k32 && nc < k32 && 2 * ids < k32
                ? label_by_edges<std::uint32_t>(input, comp, labels)
                : label_by_edges<std::uint64_t>(input, comp, labels);
  }
  report_progress(options.progress, 0.5, kOp);

  // 2. Number by decreasing size; the stable sort keeps the smallest-cell order among ties.
  ConnectivityResult r;
  r.stats.components = ncomp;
  std::vector<std::size_t> sizes(ncomp, 0);
  for (std::int32_t l : comp) ++sizes[static_cast<std::size_t>(l)];
  std::vector<double> areas;
  if (options.size_by == ComponentSize::Area) {
    areas.assign(ncomp, 0.0);
    for_each_cell(input, [&](std::size_t c, int kind, std::span<const Index> ids) {
      areas[static_cast<std::size_t>(comp[c])] += cell_area(input.points, kind, ids);
    });
  }
  std::vector<std::size_t> order(ncomp);
  std::iota(order.begin(), order.end(), std::size_t{0});
  if (options.size_by == ComponentSize::Area) {
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return areas[a] > areas[b]; });
  } else {
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return sizes[a] > sizes[b]; });
  }
  std::vector<std::int32_t> rank(ncomp);
  r.stats.sizes.resize(ncomp);
  if (!areas.empty()) r.stats.areas.resize(ncomp);
  for (std::size_t i = 0; i < ncomp; ++i) {
    rank[order[i]] = static_cast<std::int32_t>(i);
    r.stats.sizes[i] = sizes[order[i]];
    if (!areas.empty()) r.stats.areas[i] = areas[order[i]];
  }
  for (std::int32_t& l : comp) l = rank[static_cast<std::size_t>(l)];

  // 3. Selection.
  const std::vector<char> sel = select_components(input, options, comp, ncomp);
  for (std::size_t i = 0; i < ncomp; ++i) {
    if (sel[i]) r.stats.selected.push_back(i);
  }
  const bool all_cells = r.stats.selected.size() == ncomp;
  report_progress(options.progress, 0.6, kOp);

  // 4. Points of the selected cells, labeled with the smallest component using them.
  std::vector<std::int32_t> point_label(np, kNone);
  std::array<std::size_t, 4> kind_cells{}, kind_ids{};  // output sizes of each cell array
  for_each_cell(input, [&](std::size_t c, int kind, std::span<const Index> ids) {
    const std::int32_t l = comp[c];
    if (!sel[static_cast<std::size_t>(l)]) return;
    ++kind_cells[static_cast<std::size_t>(kind)];
    kind_ids[static_cast<std::size_t>(kind)] += ids.size();
    for (Index id : ids) {
      std::int32_t& pl = point_label[static_cast<std::size_t>(id)];
      pl = std::min(pl, l);
    }
  });
  const std::size_t out_cells = kind_cells[0] + kind_cells[1] + kind_cells[2] + kind_cells[3];
  const auto used = static_cast<std::size_t>(std::count_if(
      point_label.begin(), point_label.end(), [](std::int32_t l) { return l != kNone; }));
  const bool identity = options.keep_unused_points || used == np;  // output point i = input i
  std::vector<Index> new_id;        // input point -> output point (-1: dropped)
  std::vector<std::size_t> old_id;  // output point -> input point
  if (!identity) {
    new_id.assign(np, -1);
    old_id.reserve(used);
    for (std::size_t i = 0; i < np; ++i) {
      if (point_label[i] != kNone) {
        new_id[i] = static_cast<Index>(old_id.size());
        old_id.push_back(i);
      }
    }
  } else if (used < np) {
    // Kept points of no selected cell: the smallest component of the (unselected) cells using
    // them.
    std::vector<char> unlabeled(np, 0);
    for (std::size_t i = 0; i < np; ++i) unlabeled[i] = point_label[i] == kNone;
    for_each_cell(input, [&](std::size_t c, int, std::span<const Index> ids) {
      for (Index id : ids) {
        if (unlabeled[static_cast<std::size_t>(id)]) {
          std::int32_t& pl = point_label[static_cast<std::size_t>(id)];
          pl = std::min(pl, comp[c]);
        }
      }
    });
  }
  for (std::int32_t& pl : point_label) {
    if (pl == kNone) pl = -1;
  }

  // 5. Output cells (input order) with renumbered points.
  PolyData& out = r.output;
  const auto in_arrays = cell_arrays(input);
  const std::array<CellArray*, 4> out_arrays{&out.verts, &out.lines, &out.polys, &out.strips};
  std::array<CellArray*, 4> donor_arrays{};
  if (donor) donor_arrays = {&donor->verts, &donor->lines, &donor->polys, &donor->strips};
  DataArray cell_ids("ComponentId", ScalarType::Int32, 1, options.component_ids ? out_cells : 0);
  const std::span<std::int32_t> cell_label = cell_ids.values<std::int32_t>();
  std::size_t first = 0, next_cell = 0;
  for (std::size_t k = 0; k < 4; ++k) {
    const CellArray& src = *in_arrays[k];
    CellArray& dst = *out_arrays[k];
    const std::size_t n = src.size();
    if (kind_cells[k] == n && identity) {
      if (donor) {
        dst = std::move(*donor_arrays[k]);
      } else {
        dst = src;
      }
      if (options.component_ids) {
        std::copy_n(comp.begin() + static_cast<std::ptrdiff_t>(first), n,
                    cell_label.begin() + static_cast<std::ptrdiff_t>(next_cell));
      }
      next_cell += n;
    } else if (kind_cells[k] > 0) {
      dst.reserve(kind_cells[k], kind_ids[k]);
      auto& offsets = dst.offsets();
      auto& conn = dst.connectivity();
      for (std::size_t c = 0; c < n; ++c) {
        const std::int32_t l = comp[first + c];
        if (!sel[static_cast<std::size_t>(l)]) continue;
        for (Index id : src.cell(c)) {
          conn.push_back(identity ? id : new_id[static_cast<std::size_t>(id)]);
        }
        offsets.push_back(static_cast<Index>(conn.size()));
        if (options.component_ids) cell_label[next_cell] = l;
        ++next_cell;
      }
    }
    first += n;
  }
  report_progress(options.progress, 0.8, kOp);

  // 6. Points and attributes.
  if (identity) {
    out.points = donor ? std::move(donor->points) : input.points;
    out.point_data = donor ? std::move(donor->point_data) : input.point_data;
  } else {
    out.points = Points(old_id.size(), input.points.type());
    const std::size_t bytes = 3 * scalar_size(input.points.type());
    const std::byte* src = input.points.array().bytes();
    std::byte* dst = out.points.array().bytes();
    for (std::size_t i = 0; i < old_id.size(); ++i) {
      std::memcpy(dst + i * bytes, src + old_id[i] * bytes, bytes);
    }
    out.point_data = empty_like(input.point_data, old_id.size());
    if (!input.point_data.empty()) {
      for (std::size_t i = 0; i < old_id.size(); ++i) {
        copy_tuple(input.point_data, old_id[i], out.point_data, i);
      }
    }
  }
  if (all_cells) {
    out.cell_data = donor ? std::move(donor->cell_data) : input.cell_data;
  } else {
    out.cell_data = empty_like(input.cell_data, out_cells);
    if (!input.cell_data.empty()) {
      std::size_t next = 0;
      for (std::size_t c = 0; c < nc; ++c) {
        if (sel[static_cast<std::size_t>(comp[c])]) {
          copy_tuple(input.cell_data, c, out.cell_data, next++);
        }
      }
    }
  }
  out.field_data = donor ? std::move(donor->field_data) : input.field_data;
  if (options.component_ids) {
    DataArray point_ids("ComponentId", ScalarType::Int32, 1, out.points.size());
    const std::span<std::int32_t> labels = point_ids.values<std::int32_t>();
    for (std::size_t i = 0; i < labels.size(); ++i) {
      labels[i] = point_label[identity ? i : old_id[i]];
    }
    out.point_data.add(std::move(point_ids));
    out.cell_data.add(std::move(cell_ids));
  }
  r.stats.cell_component = std::move(comp);
  report_progress(options.progress, 1.0, kOp);
  return r;
}

}  // namespace

ConnectivityResult connectivity(const PolyData& input, const ConnectivityOptions& options) {
  return run(input, options, nullptr);
}

ConnectivityResult connectivity(PolyData&& input, const ConnectivityOptions& options) {
  // Taken over first, so `input` is left empty whatever happens (a sink parameter).
  PolyData local = std::exchange(input, PolyData{});
  return run(local, options, &local);
}

}  // namespace isoforge
