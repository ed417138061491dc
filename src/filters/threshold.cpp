// Thresholding (VTK's vtkThreshold): the cells whose values of one array lie in a range.
//
// Method (docs/algorithms/threshold.md): one parallel pass classifies every value of the array
// (in the range, below, above, NaN) into a byte; a block-wise pass decides each cell from the
// bytes of its points (or its own byte), counts kept cells and connectivity per block and marks
// the used points; after prefix sums over the blocks and the points, a second block-wise pass
// writes the cells with renumbered ids, and the points and every point/cell array are gathered in
// parallel. Blocks are fixed by the input size, so the output does not depend on the threads.

#include "isoforge/filters/threshold.hpp"

#include <fmt/core.h>

#include <cmath>

#include "extract_common.hpp"
#include "isoforge/core/parallel.hpp"

namespace isoforge {

namespace {

using namespace extract_impl;

// Classification of one value against [lower, upper].
enum Code : std::uint8_t { kIn = 0, kBelow = 1, kAbove = 2, kNaN = 3 };

// The codes of every tuple of `a` (component `component`, or the magnitude when -1).
Buffer<std::uint8_t> classify(const DataArray& a, int component, double lower, double upper,
                              const ProgressCallback& progress) {
  const std::size_t n = a.tuples();
  const auto nc = static_cast<std::size_t>(a.components());
  Buffer<std::uint8_t> codes(n);
  const auto code = [lower, upper](double v) -> std::uint8_t {
    if (v >= lower) return v <= upper ? kIn : kAbove;
    return v < lower ? kBelow : kNaN;
  };
  a.visit([&](const auto& values) {
    const auto* p = values.data();
    parallel_for_range(
        n, 65536,
        [&](std::size_t lo, std::size_t hi) {
          if (component >= 0) {
            const auto c = static_cast<std::size_t>(component);
            for (std::size_t t = lo; t < hi; ++t) codes[t] = code(static_cast<double>(p[t * nc + c]));
          } else {
            for (std::size_t t = lo; t < hi; ++t) {
              double s = 0;
              for (std::size_t c = 0; c < nc; ++c) {
                const auto v = static_cast<double>(p[t * nc + c]);
                s += v * v;
              }
              codes[t] = code(std::sqrt(s));
            }
          }
        },
        progress, "threshold");
  });
  return codes;
}

}  // namespace

ThresholdResult threshold(DatasetRef input, const ThresholdOptions& o) {
  if (std::isnan(o.lower) || std::isnan(o.upper)) {
    throw Error(fmt::format("threshold: the range [{}, {}] has a NaN bound", o.lower, o.upper));
  }
  if (o.lower > o.upper) {
    throw Error(fmt::format("threshold: lower bound {} exceeds upper bound {}", o.lower, o.upper));
  }
  validate(input);
  const Attributes& pd = point_data(input);
  const Attributes& cd = cell_data(input);
  using Assoc = ThresholdArrayAssociation;
  const DataArray* array = nullptr;
  bool on_points = true;
  const auto lookup = [&](const Attributes& a, bool points) {
    if (array) return;
    array = o.array.empty() ? a.scalars() : a.find(o.array);
    on_points = points;
  };
  if (o.association != Assoc::Cells) lookup(pd, true);
  if (o.association != Assoc::Points) lookup(cd, false);
  if (!array) {
    const std::string what = o.array.empty() ? std::string("no active scalars")
                                             : fmt::format("no array '{}'", o.array);
    throw Error(fmt::format(
        "threshold: {}{} (point arrays: {}; cell arrays: {})", what,
        o.association == Assoc::Points  ? " in the point data"
        : o.association == Assoc::Cells ? " in the cell data"
                                        : "",
        pd.names(), cd.names()));
  }
  if (o.component < -1 || o.component >= array->components()) {
    throw Error(fmt::format("threshold: component {} of '{}', which has {} component{} (-1: "
                            "magnitude)",
                            o.component, array->name(), array->components(),
                            array->components() == 1 ? "" : "s"));
  }

  const TopologyView cells(input);
  const std::size_t nc = cells.size();
  const std::size_t np = num_points(input);
  const Buffer<std::uint8_t> codes =
      classify(*array, o.component, o.lower, o.upper, progress_range(o.progress, 0, 0.2));

  // Pass 1: decide, count per block, mark used points.
  const std::size_t nb = block_count(nc);
  std::vector<std::size_t> block_cells(nb), block_ids(nb);
  Buffer<std::uint8_t> keep(nc);
  std::vector<std::uint8_t> used(np, 0);
  const ThresholdMode mode = o.mode;
  for_blocks(
      nc,
      [&](std::size_t b, std::size_t begin, std::size_t end) {
        Index buf[8];
        std::size_t kept = 0, ids_total = 0;
        for (std::size_t c = begin; c < end; ++c) {
          const auto ids = cells.ids(c, buf);
          bool k;
          if (!on_points) {
            k = codes[c] == kIn;
          } else {
            unsigned seen = 0;  // bit per code
            for (Index id : ids) seen |= 1u << codes[static_cast<std::size_t>(id)];
            switch (mode) {
              case ThresholdMode::AllPoints: k = seen == (1u << kIn); break;
              case ThresholdMode::AnyPoint: k = (seen & (1u << kIn)) != 0; break;
              default:
                k = !(seen & (1u << kNaN)) &&
                    ((seen & (1u << kIn)) || (seen & (1u << kBelow) && seen & (1u << kAbove)));
            }
          }
          keep[c] = k;
          if (k) {
            ++kept;
            ids_total += ids.size();
            for (Index id : ids) mark_used(used.data(), id);
          }
        }
        block_cells[b] = kept;
        block_ids[b] = ids_total;
      },
      progress_range(o.progress, 0.2, 0.5), "threshold");
  const std::size_t out_cells = exclusive_scan(block_cells);
  const std::size_t out_ids = exclusive_scan(block_ids);
  Buffer<Index> map, kept_points;
  renumber_used(used, map, kept_points);
  used = {};

  // Pass 2: write the kept cells.
  UnstructuredGrid out;
  out.types.resize(out_cells);
  Buffer<Index> offsets(out_cells + 1), conn(out_ids);
  Buffer<Index> kept_cells(out_cells);
  offsets[out_cells] = static_cast<Index>(out_ids);
  for_blocks(
      nc,
      [&](std::size_t b, std::size_t begin, std::size_t end) {
        Index buf[8];
        std::size_t next = block_cells[b], at = block_ids[b];
        for (std::size_t c = begin; c < end; ++c) {
          if (!keep[c]) continue;
          const auto ids = cells.ids(c, buf);
          out.types[next] = cells.type(c);
          offsets[next] = static_cast<Index>(at);
          kept_cells[next] = static_cast<Index>(c);
          for (Index id : ids) conn[at++] = map[static_cast<std::size_t>(id)];
          ++next;
        }
      },
      progress_range(o.progress, 0.5, 0.8), "threshold");
  out.cells = CellArray(std::move(offsets), std::move(conn));
  out.points = gather_points(input, kept_points);
  out.point_data = gather_attributes(pd, kept_points);
  out.cell_data = gather_attributes(cd, kept_cells);
  out.field_data = field_data(input);
  if (o.original_ids) {
    out.point_data.add(id_array("OriginalPointIds", kept_points));
    out.cell_data.add(id_array("OriginalCellIds", kept_cells));
  }
  report_progress(o.progress, 1.0, "threshold");
  ThresholdStats stats;
  stats.cells_in = nc;
  stats.cells_kept = out_cells;
  stats.points_kept = kept_points.size();
  stats.point_array = on_points;
  return {std::move(out), stats};
}

}  // namespace isoforge
