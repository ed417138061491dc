#include "isoforge/core/summary.hpp"

#include <algorithm>
#include <limits>
#include <utility>

#include "core/detail/ranges.hpp"
#include "isoforge/core/parallel.hpp"

namespace isoforge {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

void widen(std::pair<double, double>& r, std::pair<double, double> by) {
  r.first = std::min(r.first, by.first);
  r.second = std::max(r.second, by.second);
}

AttributesSummary summarize(const Attributes& at) {
  AttributesSummary s;
  for (const DataArray& a : at) s.arrays.push_back(summarize(a));
  for (std::size_t r = 0; r < kAttributeRoleCount; ++r) {
    s.active[r] = at.active_name(static_cast<AttributeRole>(r));
  }
  return s;
}

}  // namespace

ValueRanges::ValueRanges(int components)
    : component_(static_cast<std::size_t>(std::max(components, 1)), {kInf, -kInf}),
      magnitude_{kInf, -kInf} {}

void ValueRanges::add(ScalarType type, const void* values, std::size_t tuples) {
  const std::size_t nc = component_.size();
  visit_scalar_type(type, [&](auto tag) {
    using T = decltype(tag);
    const T* v = static_cast<const T*>(values);
    // Pieces of 64k tuples on all threads, each giving every component's range and the
    // magnitude's; min and max do not depend on the order.
    constexpr std::size_t kPiece = std::size_t{1} << 16;
    const std::size_t pieces = (tuples + kPiece - 1) / kPiece;
    const std::size_t width = nc + (nc > 1 ? 1 : 0);
    std::vector<std::pair<double, double>> r(pieces * width);
    const auto piece = [&](std::size_t p) {
      const std::size_t b = p * kPiece, e = std::min(tuples, b + kPiece);
      for (std::size_t c = 0; c < nc; ++c) r[p * width + c] = core_detail::column_range(v + c, nc, b, e);
      if (nc > 1) r[p * width + nc] = core_detail::magnitude_range(v, nc, b, e);
    };
    if (pieces == 1) {
      piece(0);
    } else if (pieces > 1) {
      parallel_for_range(pieces, 1, [&](std::size_t b, std::size_t e) {
        for (std::size_t p = b; p < e; ++p) piece(p);
      });
    }
    for (std::size_t p = 0; p < pieces; ++p) {
      for (std::size_t c = 0; c < nc; ++c) widen(component_[c], r[p * width + c]);
      if (nc > 1) widen(magnitude_, r[p * width + nc]);
    }
  });
}

void ValueRanges::merge(const ValueRanges& other) {
  for (std::size_t c = 0; c < component_.size() && c < other.component_.size(); ++c) {
    widen(component_[c], other.component_[c]);
  }
  widen(magnitude_, other.magnitude_);
}

const ArraySummary* AttributesSummary::find(const std::string& name) const {
  for (const ArraySummary& a : arrays) {
    if (a.name == name) return &a;
  }
  return nullptr;
}

ArraySummary* AttributesSummary::find(const std::string& name) {
  return const_cast<ArraySummary*>(std::as_const(*this).find(name));
}

void AttributesSummary::merge_array(ArraySummary a) {
  if (ArraySummary* s = find(a.name)) {
    s->tuples += a.tuples;
    s->ranges.merge(a.ranges);
  } else {
    arrays.push_back(std::move(a));
  }
}

std::string_view dataset_kind_name(std::size_t kind) {
  static constexpr std::string_view kNames[] = {"image data", "structured grid", "polygonal data",
                                                "unstructured grid"};
  return kind < 4 ? kNames[kind] : "unknown";
}

ArraySummary summarize(const DataArray& a) {
  ArraySummary s{a.name(), a.type(), a.components(), a.tuples(), ValueRanges(a.components())};
  s.ranges.add(a.type(), a.bytes(), a.tuples());
  return s;
}

DatasetSummary summarize(DatasetRef ds) {
  DatasetSummary s;
  s.kind = ds.index();
  if (const auto* img = ds.get_if<ImageData>()) {
    s.dims = img->dims;
    s.origin = img->origin;
    s.spacing = img->spacing;
  } else if (const auto* sg = ds.get_if<StructuredGrid>()) {
    s.dims = sg->dims;
  }
  s.points = num_points(ds);
  s.cells = num_cells(ds);
  // Structured datasets have one cell type, so they cost O(1) whatever the dimensions claim;
  // the others hold their cells in memory and are counted one by one.
  if (ds.get_if<ImageData>() || ds.get_if<StructuredGrid>()) {
    if (s.cells > 0) s.cell_types[cell_type(ds, 0)] = s.cells;
  } else if (const auto* pd = ds.get_if<PolyData>()) {
    const CellArray* sections[4] = {&pd->verts, &pd->lines, &pd->polys, &pd->strips};
    for (int k = 0; k < 4; ++k) {
      for (std::size_t c = 0; c < sections[k]->size(); ++c) {
        ++s.cell_types[poly_cell_type(k, sections[k]->cell_size(c))];
      }
    }
  } else if (const auto* ug = ds.get_if<UnstructuredGrid>()) {
    std::array<std::uint64_t, 256> count{};
    for (CellType t : ug->types) ++count[static_cast<std::uint8_t>(t)];
    for (std::size_t t = 0; t < count.size(); ++t) {
      if (count[t] > 0) s.cell_types[static_cast<CellType>(t)] = count[t];
    }
  }
  s.bounds = bounds(ds);
  s.point_data = summarize(point_data(ds));
  s.cell_data = summarize(cell_data(ds));
  s.field_data = summarize(field_data(ds));
  return s;
}

}  // namespace isoforge
