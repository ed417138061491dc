// Appending polygonal data (core/append.hpp).

#include "isoforge/core/append.hpp"

#include <cstring>

namespace isoforge {

namespace {

/// Concatenates the cells of `kind` of every part, shifting ids by each part's point offset.
void append_cells(const std::vector<PolyData>& parts, CellArray PolyData::*kind,
                  const std::vector<Index>& base, CellArray& out) {
  std::size_t cells = 0, ids = 0;
  for (const PolyData& p : parts) {
    cells += (p.*kind).size();
    ids += (p.*kind).connectivity().size();
  }
  Buffer<Index>& offsets = out.offsets();
  Buffer<Index>& conn = out.connectivity();
  offsets.resize(cells + 1);
  conn.resize(ids);
  offsets[0] = 0;
  std::size_t c = 0, at = 0;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const CellArray& src = parts[k].*kind;
    const Index shift = base[k];
    const auto first = static_cast<Index>(at);
    for (std::size_t i = 1; i <= src.size(); ++i) offsets[c + i] = first + src.offsets()[i];
    for (const Index id : src.connectivity()) conn[at++] = id + shift;
    c += src.size();
  }
}

/// The arrays every attribute set of `sets` has with equal type and components, concatenated
/// (tuple counts `counts[k]` per set, in the order of `ranges`: (set, first tuple, tuples)).
struct Range {
  std::size_t set, first, count;
};

Attributes append_arrays(const std::vector<const Attributes*>& sets,
                         const std::vector<Range>& ranges, std::size_t total) {
  Attributes out;
  const Attributes& first = *sets.front();
  for (const DataArray& proto : first) {
    bool common = true;
    for (const Attributes* s : sets) {
      const DataArray* a = s->find(proto.name());
      if (!a || a->type() != proto.type() || a->components() != proto.components()) common = false;
    }
    if (!common) continue;
    DataArray merged =
        DataArray::uninitialized(proto.name(), proto.type(), proto.components(), total);
    merged.set_lookup_table(proto.lookup_table());
    const std::size_t tb = scalar_size(proto.type()) * static_cast<std::size_t>(proto.components());
    std::size_t at = 0;
    for (const Range& r : ranges) {
      const DataArray& src = sets[r.set]->get(proto.name());
      if (r.count > 0)
        std::memcpy(merged.bytes() + at * tb, src.bytes() + r.first * tb, r.count * tb);
      at += r.count;
    }
    out.add(std::move(merged));
  }
  for (std::size_t r = 0; r < kAttributeRoleCount; ++r) {
    const auto role = static_cast<AttributeRole>(r);
    const std::string& name = first.active_name(role);
    if (!name.empty() && out.has(name)) out.set_active(role, name);
  }
  return out;
}

}  // namespace

PolyData append(std::vector<PolyData> parts) {
  if (parts.size() == 1) return std::move(parts.front());
  PolyData out;
  if (parts.empty()) return out;
  std::vector<Index> base(parts.size());
  std::size_t np = 0;
  bool doubles = false;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    base[k] = static_cast<Index>(np);
    np += parts[k].points.size();
    doubles = doubles || parts[k].points.type() == ScalarType::Float64;
  }
  out.points = Points(DataArray::uninitialized(
      "Points", doubles ? ScalarType::Float64 : ScalarType::Float32, 3, np));
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const Points& src = parts[k].points;
    const auto at = static_cast<std::size_t>(base[k]);
    if (src.type() == out.points.type()) {
      if (src.array().size_bytes() > 0) {
        std::memcpy(out.points.array().bytes() + at * 3 * scalar_size(src.type()),
                    src.array().bytes(), src.array().size_bytes());
      }
    } else {
      for (std::size_t i = 0; i < src.size(); ++i) out.points.set(at + i, src[i]);
    }
  }
  append_cells(parts, &PolyData::verts, base, out.verts);
  append_cells(parts, &PolyData::lines, base, out.lines);
  append_cells(parts, &PolyData::polys, base, out.polys);
  append_cells(parts, &PolyData::strips, base, out.strips);

  std::vector<const Attributes*> point_sets, cell_sets;
  std::vector<Range> point_ranges, cell_ranges;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    point_sets.push_back(&parts[k].point_data);
    cell_sets.push_back(&parts[k].cell_data);
    point_ranges.push_back({k, 0, parts[k].points.size()});
  }
  // Cell data: kind by kind, part by part (the order of the appended cells).
  for (int kind = 0; kind < 4; ++kind) {
    for (std::size_t k = 0; k < parts.size(); ++k) {
      const PolyData& p = parts[k];
      const std::size_t sizes[4] = {p.verts.size(), p.lines.size(), p.polys.size(),
                                    p.strips.size()};
      std::size_t first = 0;
      for (int q = 0; q < kind; ++q) first += sizes[q];
      cell_ranges.push_back({k, first, sizes[kind]});
    }
  }
  out.point_data = append_arrays(point_sets, point_ranges, np);
  out.cell_data = append_arrays(cell_sets, cell_ranges, out.num_cells());
  return out;
}

namespace {

/// The summaries of the arrays every set of `sets` has with equal type and components, merged;
/// the first set's active roles (append_arrays's rules).
AttributesSummary append_array_summaries(const std::vector<const AttributesSummary*>& sets) {
  AttributesSummary out;
  const AttributesSummary& first = *sets.front();
  for (const ArraySummary& proto : first.arrays) {
    bool common = true;
    for (const AttributesSummary* s : sets) {
      const ArraySummary* a = s->find(proto.name);
      if (!a || a->type != proto.type || a->components != proto.components) common = false;
    }
    if (!common) continue;
    for (const AttributesSummary* s : sets) out.merge_array(*s->find(proto.name));
  }
  for (std::size_t r = 0; r < kAttributeRoleCount; ++r) {
    if (!first.active[r].empty() && out.find(first.active[r])) out.active[r] = first.active[r];
  }
  return out;
}

}  // namespace

DatasetSummary append_summaries(const std::vector<DatasetSummary>& parts) {
  if (parts.size() == 1) return parts.front();
  if (parts.empty()) return summarize(PolyData{});
  DatasetSummary out;
  out.kind = parts.front().kind;
  std::vector<const AttributesSummary*> point_sets, cell_sets;
  for (const DatasetSummary& p : parts) {
    out.points += p.points;
    out.cells += p.cells;
    for (const auto& [type, count] : p.cell_types) out.cell_types[type] += count;
    out.bounds.merge(p.bounds);
    point_sets.push_back(&p.point_data);
    cell_sets.push_back(&p.cell_data);
  }
  out.point_data = append_array_summaries(point_sets);
  out.cell_data = append_array_summaries(cell_sets);
  return out;
}

}  // namespace isoforge
