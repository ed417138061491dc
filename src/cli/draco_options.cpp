// The Draco options of the isoforge command (see draco_options.hpp).

#include "draco_options.hpp"

#include <fmt/core.h>

#include <malloc.h>

#include <cmath>
#include <cstdlib>

#include "common.hpp"

namespace isoforge::cli {

void add_draco_options(CLI::App& cmd, DracoCli& d) {
  d.max_error_opt = cmd.add_option("--max-error", d.max_error,
                                   "Draco: largest distance a point may move, in data units "
                                   "(> 0; the quantization is chosen to meet it)")
                        ->check(positive_number());
  d.max_error_rel_opt =
      cmd.add_option("--max-error-rel", d.max_error_rel,
                     "Draco: the same as a fraction of the bounding-box diagonal (> 0)")
          ->check(positive_number());
  auto* array_opt = cmd.add_option("--array-error", d.array_errors,
                                   "Draco: NAME=E, largest error of a float point array in its "
                                   "units (repeatable; other arrays use the *-bits)");
  d.bits_opt = cmd.add_option("--bits", d.bits,
                              "Draco: position quantization bits (1-30, "
                              "default 11)")
                   ->check(integer_in(1, 30));
  auto* nb = cmd.add_option("--normal-bits", d.normal_bits, "Draco: normal bits (1-30, default 8)")
                 ->check(integer_in(1, 30));
  auto* cb =
      cmd.add_option("--color-bits", d.color_bits, "Draco: float colour bits (1-30, default 8)")
          ->check(integer_in(1, 30));
  auto* tb = cmd.add_option("--texcoord-bits", d.texcoord_bits,
                            "Draco: texture coordinate bits (1-30, default 10)")
                 ->check(integer_in(1, 30));
  auto* gb = cmd.add_option("--generic-bits", d.generic_bits,
                            "Draco: bits of other float arrays (1-30, default 8)")
                 ->check(integer_in(1, 30));
  // Shared with VTK XML output (add_xml_compression_options): checked per output format.
  d.level_opt = cmd.add_option("--level", d.level,
                               "Compression level: Draco 0 (fastest) to 10 (smallest), default "
                               "7; VTK XML output 1 to 12 (default 5 for zlib, 1 for lz4)")
                    ->check(integer_in(0, 12));
  auto* seq = cmd.add_flag("--sequential", d.sequential,
                           "Draco: sequential coding, which keeps the order of points and faces "
                           "(larger than the default Edgebreaker)");
  d.options = {
      d.max_error_opt, d.max_error_rel_opt, array_opt, d.bits_opt, nb, cb, tb, gb, seq};
}

void check_draco_options(const DracoCli& d, bool meaningful, const std::string& why) {
  for (const CLI::Option* o : d.options) require_meaningful(o, meaningful, why);
  if (meaningful && d.level_opt->count() > 0 && d.level > 10) {
    throw UsageError("--level", "must be an integer in [0, 10], got " + std::to_string(d.level));
  }
  exclude_each_other({d.max_error_opt, d.max_error_rel_opt});
  exclude_each_other({d.bits_opt, d.max_error_opt});
  exclude_each_other({d.bits_opt, d.max_error_rel_opt});
}

DracoWriteOptions draco_write_options(const DracoCli& d) {
  DracoWriteOptions o;
  o.bits = {d.bits, d.normal_bits, d.color_bits, d.texcoord_bits, d.generic_bits};
  o.level = d.level;
  o.method = d.sequential ? DracoMethod::Sequential : DracoMethod::Edgebreaker;
  o.max_position_error = d.max_error;
  o.max_position_error_relative = d.max_error_rel;
  for (const std::string& a : d.array_errors) {
    const auto eq = a.rfind('=');
    const std::string name = eq == std::string::npos ? "" : a.substr(0, eq);
    const std::string value = eq == std::string::npos ? "" : a.substr(eq + 1);
    char* end = nullptr;
    const double e = value.empty() ? NAN : std::strtod(value.c_str(), &end);
    if (name.empty() || value.empty() || *end != '\0' || !std::isfinite(e) || e <= 0) {
      throw UsageError("--array-error", "must be NAME=E with a finite E > 0, got '" + a + "'");
    }
    for (const auto& b : o.max_array_errors) {
      if (b.name == name) throw UsageError("--array-error", "array '" + name + "' given twice");
    }
    o.max_array_errors.push_back({name, e});
  }
  return o;
}

void keep_freed_memory() {
#if defined(__GLIBC__)
  // glibc starts with a 128 KiB mmap threshold that grows only as large blocks are freed, so
  // the first Draco encoding of a run maps, faults in and unmaps each large vector it grows:
  // measured on the bunny, 95 ms against 60 ms for the same encoding later in the process
  // (docs/algorithms/draco.md). A short-lived command keeps freed memory for reuse instead.
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
#endif
}

namespace {

// One line per attribute: its grid, the measured error and the budget.
void print_attributes(const std::vector<DracoAttributeStats>& attributes, const char* prefix) {
  for (const auto& a : attributes) {
    std::string grid = a.bits == 0 ? "exact" : fmt::format("{} bits", a.bits);
    if (a.step > 0) grid += fmt::format(", step {:.3g}", a.step);
    const std::string budget = a.budget > 0 ? fmt::format(" (budget {:.3g})", a.budget) : "";
    fmt::print(stderr, "  {}{}: {}, measured max error {:.3g}{}\n", prefix, a.name, grid,
               a.max_error, budget);
  }
}

}  // namespace

void print_draco_stats(const DracoStats& st, const std::string& path) {
  fmt::print(stderr,
             "wrote {} ({} points, {} triangles): {} bytes, ratio {:.1f} to raw float32/int32 "
             "({} bytes)\n",
             path, st.points, st.triangles, st.bytes, st.ratio, st.raw_bytes);
  print_attributes(st.attributes, "");
  fmt::print(stderr, "  decoded: {} points, {} triangles; lost triangles: {}", st.decoded_points,
             st.decoded_triangles, st.lost_triangles);
  if (st.unreferenced_points > 0) {
    fmt::print(stderr, "; {} points in no triangle left out", st.unreferenced_points);
  }
  fmt::print(stderr, "\n");
  fmt::print(stderr,
             "  encoded in {:.0f} ms; with the verifying decode and measurement {:.0f} ms "
             "({} encoding{})\n",
             1e3 * st.encode_seconds, 1e3 * st.total_seconds, st.encodes,
             st.encodes > 1 ? "s" : "");
  if (!st.note.empty()) fmt::print(stderr, "  note: {}\n", st.note);
  for (const auto& d : st.dropped) fmt::print(stderr, "  not stored (Draco has no place): {}\n", d);
}

void print_gltf_stats(const GltfWriteStats& st, const std::string& path) {
  std::string counts =
      fmt::format("{} mesh{}, {} points", st.meshes, st.meshes == 1 ? "" : "es", st.vertices);
  if (st.triangles) counts += fmt::format(", {} triangles", st.triangles);
  if (st.segments) counts += fmt::format(", {} line segments", st.segments);
  if (st.points) counts += fmt::format(", {} points drawn", st.points);
  fmt::print(stderr, "wrote {} ({}): {} bytes, ratio {:.2f} to plain glTF buffers ({} bytes)\n",
             path, counts, st.bytes,
             st.bytes ? static_cast<double>(st.raw_bytes) / static_cast<double>(st.bytes) : 0.0,
             st.raw_bytes);
  for (const auto& d : st.draco) {
    print_attributes(d.attributes, "draco ");
    fmt::print(stderr, "  draco decoded: {} points, {} triangles; lost triangles: {}\n",
               d.decoded_points, d.decoded_triangles, d.lost_triangles);
    if (!d.note.empty()) fmt::print(stderr, "  note: {}\n", d.note);
  }
  if (st.normals_replaced > 0) {
    fmt::print(stderr, "  {} zero normals written as (0, 0, 1)\n", st.normals_replaced);
  }
  for (const auto& s : st.arrays_skipped) fmt::print(stderr, "  not stored: {}\n", s);
}

}  // namespace isoforge::cli
