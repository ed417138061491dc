#include "describe.hpp"

#include <fmt/core.h>

#include <map>

namespace isoforge::cli {

namespace {

std::string roles_of(const Attributes& at, const std::string& name) {
  std::string s;
  for (std::size_t r = 0; r < kAttributeRoleCount; ++r) {
    auto role = static_cast<AttributeRole>(r);
    if (at.active_name(role) == name) {
      if (!s.empty()) s += ",";
      s += attribute_role_name(role);
    }
  }
  return s.empty() ? "" : " [" + s + "]";
}

std::string format_range(const DataArray& a) {
  if (a.tuples() == 0) return "empty";
  std::string s;
  const int nc = a.components();
  const int shown = nc > 9 ? 9 : nc;
  for (int c = 0; c < shown; ++c) {
    auto [lo, hi] = a.range(c);
    if (!s.empty()) s += ", ";
    if (lo > hi) {
      s += "all NaN";
    } else {
      s += fmt::format("[{:.6g}, {:.6g}]", lo, hi);
    }
  }
  if (nc > shown) s += ", ...";
  if (nc > 1) {
    auto [lo, hi] = a.range(-1);
    if (lo <= hi) s += fmt::format("; |v| [{:.6g}, {:.6g}]", lo, hi);
  }
  return s;
}

void describe_attributes(std::string& out, const Attributes& at, const char* what) {
  if (at.empty()) {
    out += fmt::format("{}: none\n", what);
    return;
  }
  out += fmt::format("{} ({} array{}):\n", what, at.size(), at.size() == 1 ? "" : "s");
  for (const auto& a : at) {
    out += fmt::format("  {:<20} {:<7} x{}{}  {}\n", "'" + a.name() + "'",
                       scalar_type_name(a.type()), a.components(), roles_of(at, a.name()),
                       format_range(a));
  }
}

}  // namespace

std::string describe(DatasetRef ds) {
  std::string out;
  out += fmt::format("type: {}\n", dataset_type_name(ds));
  if (const auto* img = ds.get_if<ImageData>()) {
    out += fmt::format("dimensions: {} x {} x {}\n", img->dims[0], img->dims[1], img->dims[2]);
    out += fmt::format("origin: {} {} {}\nspacing: {} {} {}\n", img->origin.x, img->origin.y,
                       img->origin.z, img->spacing.x, img->spacing.y, img->spacing.z);
  } else if (const auto* sg = ds.get_if<StructuredGrid>()) {
    out += fmt::format("dimensions: {} x {} x {}\n", sg->dims[0], sg->dims[1], sg->dims[2]);
  }
  out += fmt::format("points: {}\n", num_points(ds));
  const std::size_t nc = num_cells(ds);
  // Cell-type histogram: structured datasets have one cell type, so they cost O(1) whatever the
  // dimensions claim (a 100000^3 image header must not mean 10^15 visits); the others hold their
  // cells in memory and are counted one by one.
  std::map<int, std::size_t> histogram;
  if (ds.get_if<ImageData>() || ds.get_if<StructuredGrid>()) {
    if (nc > 0) histogram[static_cast<int>(cell_type(ds, 0))] = nc;
  } else {
    for (std::size_t c = 0; c < nc; ++c) ++histogram[static_cast<int>(cell_type(ds, static_cast<Index>(c)))];
  }
  std::string hist;
  for (auto [t, n] : histogram) {
    if (!hist.empty()) hist += ", ";
    hist += fmt::format("{} {}", n, cell_type_name(static_cast<CellType>(t)));
  }
  out += fmt::format("cells: {}{}\n", nc, hist.empty() ? "" : " (" + hist + ")");
  const Bounds b = bounds(ds);
  if (b.empty()) {
    out += "bounds: empty\n";
  } else {
    out += fmt::format("bounds: x [{:.6g}, {:.6g}]  y [{:.6g}, {:.6g}]  z [{:.6g}, {:.6g}]\n", b.min.x,
                       b.max.x, b.min.y, b.max.y, b.min.z, b.max.z);
  }
  describe_attributes(out, point_data(ds), "point data");
  describe_attributes(out, cell_data(ds), "cell data");
  describe_attributes(out, field_data(ds), "field data");
  return out;
}

}  // namespace isoforge::cli
