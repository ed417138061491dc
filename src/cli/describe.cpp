#include "describe.hpp"

#include <fmt/core.h>

namespace isoforge::cli {

namespace {

std::string roles_of(const AttributesSummary& at, const std::string& name) {
  std::string s;
  for (std::size_t r = 0; r < kAttributeRoleCount; ++r) {
    if (at.active[r] == name) {
      if (!s.empty()) s += ",";
      s += attribute_role_name(static_cast<AttributeRole>(r));
    }
  }
  return s.empty() ? "" : " [" + s + "]";
}

std::string format_range(const ArraySummary& a) {
  if (a.tuples == 0) return "empty";
  std::string s;
  const int nc = a.components;
  const int shown = nc > 9 ? 9 : nc;
  for (int c = 0; c < shown; ++c) {
    auto [lo, hi] = a.ranges.component(c);
    if (!s.empty()) s += ", ";
    if (lo > hi) {
      s += "all NaN";
    } else {
      s += fmt::format("[{:.6g}, {:.6g}]", lo, hi);
    }
  }
  if (nc > shown) s += ", ...";
  if (nc > 1) {
    auto [lo, hi] = a.ranges.magnitude();
    if (lo <= hi) s += fmt::format("; |v| [{:.6g}, {:.6g}]", lo, hi);
  }
  return s;
}

void describe_attributes(std::string& out, const AttributesSummary& at, const char* what) {
  if (at.arrays.empty()) {
    out += fmt::format("{}: none\n", what);
    return;
  }
  out += fmt::format("{} ({} array{}):\n", what, at.arrays.size(), at.arrays.size() == 1 ? "" : "s");
  for (const auto& a : at.arrays) {
    out += fmt::format("  {:<20} {:<7} x{}{}  {}\n", "'" + a.name + "'", scalar_type_name(a.type),
                       a.components, roles_of(at, a.name), format_range(a));
  }
}

}  // namespace

std::string describe(const DatasetSummary& s) {
  std::string out;
  out += fmt::format("type: {}\n", dataset_kind_name(s.kind));
  if (s.kind == 0 || s.kind == 1) {
    out += fmt::format("dimensions: {} x {} x {}\n", s.dims[0], s.dims[1], s.dims[2]);
  }
  if (s.kind == 0) {
    out += fmt::format("origin: {} {} {}\nspacing: {} {} {}\n", s.origin.x, s.origin.y,
                       s.origin.z, s.spacing.x, s.spacing.y, s.spacing.z);
  }
  out += fmt::format("points: {}\n", s.points);
  std::string hist;
  for (auto [t, n] : s.cell_types) {
    if (!hist.empty()) hist += ", ";
    hist += fmt::format("{} {}", n, cell_type_name(t));
  }
  out += fmt::format("cells: {}{}\n", s.cells, hist.empty() ? "" : " (" + hist + ")");
  const Bounds& b = s.bounds;
  if (b.empty()) {
    out += "bounds: empty\n";
  } else {
    out += fmt::format("bounds: x [{:.6g}, {:.6g}]  y [{:.6g}, {:.6g}]  z [{:.6g}, {:.6g}]\n",
                       b.min.x, b.max.x, b.min.y, b.max.y, b.min.z, b.max.z);
  }
  describe_attributes(out, s.point_data, "point data");
  describe_attributes(out, s.cell_data, "cell data");
  describe_attributes(out, s.field_data, "field data");
  return out;
}

}  // namespace isoforge::cli
