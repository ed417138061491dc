// Object File Format (Geomview OFF: "OFF" / "COFF" / "NOFF" / "STOFF" headers, `nv nf ne`
// counts, vertices, faces `n i j k ...` with optional trailing colour ignored, '#' comments) —
// reader and writer; and the Wavefront OBJ geometry subset (v, vn, vt, f v/vt/vn, l, p;
// 1-based indices) — writer only.

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "detail/progress.hpp"
#include "detail/scanner.hpp"
#include "detail/summaries.hpp"
#include "isoforge/core/cell.hpp"
#include "isoforge/core/summary.hpp"
#include "isoforge/io/atomic_file.hpp"
#include "isoforge/io/io.hpp"
#include "isoforge/io/off_obj.hpp"

namespace isoforge {

namespace {

using io_detail::Scanner;
using io_detail::split_words;

/// Appends `v` in the shortest form that reads back to the same value.
using io_detail::append_number;

void append_coord(std::string& out, double v, bool single) {
  if (single) {
    append_number(out, static_cast<float>(v));
  } else {
    append_number(out, v);
  }
}

/// Strips '#' comments and splits on whitespace.
std::vector<std::string_view> split_rest(std::string_view line) {
  if (auto h = line.find('#'); h != std::string_view::npos) line = line.substr(0, h);
  return split_words(line);
}

/// Number of significant digits in a decimal number token (to tell float32 text from float64).
int significant_digits(std::string_view t) {
  int n = 0;
  bool leading = true;
  for (char c : t) {
    if (c == 'e' || c == 'E') break;
    if (c < '0' || c > '9') continue;
    if (leading && c == '0') continue;
    leading = false;
    ++n;
  }
  return n;
}

class OffReader {
 public:
  OffReader(std::span<const std::byte> data, std::string_view name,
            io_detail::Progress* progress = nullptr, std::uint64_t progress_base = 0)
      : sc_(data, std::string(name)) {
    sc_.track(progress, progress_base);
  }

  /// The summary of the file (`info`): parsed and checked as by read(), but the coordinates,
  /// normals and texture coordinates go into ranges a block of vertices at a time and the
  /// faces are counted by size, not stored (colours are still read: 4 bytes a vertex).
  DatasetSummary summarize() {
    summary_.emplace();
    const PolyData mesh = read();  // points and faces empty, normals and tcoords too
    DatasetSummary s = isoforge::summarize(mesh);
    s.streamed = true;
    s.points = summary_->points;
    s.cells = summary_->cells;
    s.cell_types = summary_->cell_types;
    if (s.points > 0) {
      for (int a = 0; a < 3; ++a) {
        s.bounds.min[a] = summary_->xyz.component(a).first;
        s.bounds.max[a] = summary_->xyz.component(a).second;
      }
    }
    for (ArraySummary& a : s.point_data.arrays) {
      if (a.name == kNormals) a = {a.name, a.type, 3, s.points, summary_->normals};
      if (a.name == kTCoords) a = {a.name, a.type, 2, s.points, summary_->tcoords};
    }
    return s;
  }

  PolyData read() {
    // ---- header keyword: [ST][C][N]OFF, after a UTF-8 byte order mark (Windows editors) ----
    const auto d = sc_.data();
    if (sc_.offset() == 0 && d.size() >= 3 && d[0] == std::byte{0xEF} && d[1] == std::byte{0xBB} &&
        d[2] == std::byte{0xBF}) {
      sc_.seek(3);
    }
    const std::string_view magic = next();
    if (magic.empty()) sc_.fail_line("empty file, expected the OFF header keyword");
    std::string_view m = magic;
    if (m.starts_with("ST")) {
      texture_ = true;
      m.remove_prefix(2);
    }
    if (m.starts_with("C")) {
      color_ = true;
      m.remove_prefix(1);
    }
    if (m.starts_with("N")) {
      normals_ = true;
      m.remove_prefix(1);
    }
    if (texture_ && color_)
      sc_.fail_line(io_detail::quoted(magic) + " (texture and colour) is not supported");
    if (m == "4OFF" || m == "nOFF") {
      sc_.fail_line(io_detail::quoted(magic) + " (4D or n-dimensional OFF) is not supported");
    }
    if (m != "OFF") {
      sc_.fail_line("bad magic: expected 'OFF' (or COFF/NOFF/STOFF), found " +
                    io_detail::quoted(magic));
    }
    // ---- counts ----
    std::string_view t = next();
    if (t == "BINARY") sc_.fail_line("binary OFF is not supported");
    const std::size_t nv = parse_count(t, "vertex count", 6);
    const std::size_t nf = parse_count(next(), "face count", 8);
    const std::int64_t counts_line = sc_.line();
    // The edge count is optional in practice; ignore the rest of the counts line.
    sc_.skip_line();
    std::uint64_t need = 0;
    if (__builtin_mul_overflow(static_cast<std::uint64_t>(nv), 6u, &need) ||
        __builtin_add_overflow(need, static_cast<std::uint64_t>(nf) * 8u, &need) ||
        need > sc_.remaining() + 2) {
      fail_at_line(counts_line, "vertex count " + std::to_string(nv) + " and face count " +
                                    std::to_string(nf) + " exceed what the remaining " +
                                    std::to_string(sc_.remaining()) +
                                    " bytes of the file can hold");
    }

    // ---- vertices ----
    // Summarising, the values go into ranges a block at a time: vertex v at i = v % block.
    const std::size_t block = summary_ ? std::min(nv, kSummaryBlock) : nv;
    std::vector<double> xyz(3 * block);
    std::vector<float> normals(normals_ ? 3 * block : 0);
    std::vector<float> tcoords(texture_ ? 2 * block : 0);
    std::vector<std::uint8_t> colors;
    int color_comps = 3;
    bool wide = false;  // a coordinate has more digits than float32 needs
    for (std::size_t v = 0, i = 0; v < nv; ++v) {
      for (int a = 0; a < 3; ++a) {
        const auto tok = require("vertex coordinate");
        wide = wide || significant_digits(tok) > 9;
        xyz[3 * i + static_cast<std::size_t>(a)] = sc_.parse<double>(tok, "vertex coordinate");
      }
      const double* p = &xyz[3 * i];
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
        sc_.fail_line("vertex " + std::to_string(v) + " has a non-finite coordinate");
      }
      if (normals_) {
        for (int a = 0; a < 3; ++a) {
          normals[3 * i + static_cast<std::size_t>(a)] =
              sc_.parse<float>(require("vertex normal"), "vertex normal");
        }
      }
      if (color_) read_color(v, colors, color_comps);
      if (texture_) {
        for (int a = 0; a < 2; ++a) {
          tcoords[2 * i + static_cast<std::size_t>(a)] =
              sc_.parse<float>(require("texture coordinate"), "texture coordinate");
        }
      }
      if (summary_ && (i + 1 == block || v + 1 == nv)) {
        summary_->xyz.add(ScalarType::Float64, xyz.data(), i + 1);
        if (normals_) summary_->normals.add(ScalarType::Float32, normals.data(), i + 1);
        if (texture_) summary_->tcoords.add(ScalarType::Float32, tcoords.data(), i + 1);
        i = 0;  // the next vertex starts the block again
      } else {
        ++i;
      }
    }

    // ---- faces ----
    PolyData mesh;
    auto& offsets = mesh.polys.offsets();
    auto& conn = mesh.polys.connectivity();
    offsets.reserve(nf + 1);
    for (std::size_t f = 0; f < nf; ++f) {
      const auto n = sc_.parse<std::int64_t>(require("face vertex count"), "face vertex count");
      if (n < 3) {
        sc_.fail_line("face " + std::to_string(f) + " has " + std::to_string(n) +
                      " vertices, a polygon needs at least 3");
      }
      sc_.check_count(static_cast<std::uint64_t>(n), 2, "face vertex count");
      for (std::int64_t j = 0; j < n; ++j) {
        const auto id = sc_.parse<std::int64_t>(require("face vertex index"), "face vertex index");
        if (id < 0 || static_cast<std::uint64_t>(id) >= nv) {
          sc_.fail_line("face " + std::to_string(f) + ": vertex index " + std::to_string(id) +
                        " is out of range (" + std::to_string(nv) + " vertices)");
        }
        if (!summary_) conn.push_back(id);
      }
      if (summary_) {
        ++summary_->cell_types[poly_cell_type(2, static_cast<std::size_t>(n))];
      } else {
        offsets.push_back(static_cast<Index>(conn.size()));
      }
      sc_.skip_line();  // optional face colour
    }
    // Anything but comments and whitespace after the faces is an error.
    if (const auto extra = next(); !extra.empty()) {
      sc_.fail_line("unexpected data after the last face: " + io_detail::quoted(extra));
    }

    if (summary_) {
      summary_->points = nv;
      summary_->cells = nf;  // counted, not stored
      normals.clear();
      tcoords.clear();
    } else {
      mesh.points = Points(nv, wide ? ScalarType::Float64 : ScalarType::Float32);
      for (std::size_t i = 0; i < nv; ++i)
        mesh.points.set(i, {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]});
    }
    if (normals_) {
      mesh.point_data.add(DataArray::from_vector(kNormals, 3, std::move(normals)),
                          AttributeRole::Normals);
    }
    if (color_) {
      mesh.point_data.add(DataArray::from_vector("Colors", color_comps, std::move(colors)),
                          AttributeRole::Scalars);
    }
    if (texture_) {
      mesh.point_data.add(DataArray::from_vector(kTCoords, 2, std::move(tcoords)),
                          AttributeRole::TCoords);
    }
    return mesh;
  }

 private:
  [[noreturn]] void fail_at_line(std::int64_t line, const std::string& what) const {
    throw Error(at_line(sc_.name(), line, what));
  }

  /// Next token, skipping '#' comments.
  std::string_view next() {
    for (;;) {
      sc_.skip_space();
      if (sc_.peek_char() != '#') break;
      sc_.skip_line();
    }
    std::string_view t = sc_.token();
    if (auto h = t.find('#'); h != std::string_view::npos && h > 0) {
      sc_.seek(sc_.offset() - (t.size() - h));  // same line: the line count stays right
      t = t.substr(0, h);
    }
    return t;
  }
  std::string_view require(std::string_view what) {
    auto t = next();
    if (t.empty()) sc_.fail_line("unexpected end of file, expected " + std::string(what));
    return t;
  }
  std::size_t parse_count(std::string_view t, std::string_view what, std::size_t min_bytes) {
    if (t.empty()) sc_.fail_line("unexpected end of file, expected " + std::string(what));
    const auto v = sc_.parse<std::int64_t>(t, what);
    if (v < 0) sc_.fail_line(std::string(what) + " " + std::to_string(v) + " is negative");
    sc_.check_count(static_cast<std::uint64_t>(v), min_bytes, what);
    return static_cast<std::size_t>(v);
  }

  // COFF colour: the rest of the vertex line, 3 or 4 values, integers 0..255 or floats 0..1.
  void read_color(std::size_t i, std::vector<std::uint8_t>& colors, int& comps) {
    std::string_view rest;
    sc_.read_line(rest);
    const auto w = split_rest(rest);
    if (w.size() < 3 || w.size() > 4) {
      throw Error(at_line(sc_.name(), sc_.line() - 1,
                          "vertex " + std::to_string(i) +
                              ": expected 3 or 4 colour values, found " +
                              std::to_string(w.size())));
    }
    if (w.size() == 4 && comps == 3) {
      // Switch to RGBA; earlier vertices get alpha 255.
      std::vector<std::uint8_t> rgba;
      rgba.reserve(colors.size() / 3 * 4 + 4);
      for (std::size_t k = 0; k < colors.size(); k += 3) {
        rgba.insert(rgba.end(), {colors[k], colors[k + 1], colors[k + 2], 255});
      }
      colors = std::move(rgba);
      comps = 4;
    }
    for (std::size_t c = 0; c < static_cast<std::size_t>(comps); ++c) {
      if (c >= w.size()) {
        colors.push_back(255);
        continue;
      }
      const bool fl = w[c].find_first_of(".eE") != std::string_view::npos;
      double v = sc_.parse<double>(w[c], "colour value");
      if (fl) v = std::round(v * 255.0);
      if (!(v >= 0)) v = 0;
      if (v > 255) v = 255;
      colors.push_back(static_cast<std::uint8_t>(v));
    }
  }

  static constexpr std::size_t kSummaryBlock = 65536;  // vertices summarised at a time
  // The names of the point arrays read() makes (summarize() puts the streamed ranges in them).
  static constexpr const char* kNormals = "Normals";
  static constexpr const char* kTCoords = "TCoords";

  // What summarize() collects while read() parses.
  struct Streamed {
    Streamed() : xyz(3), normals(3), tcoords(2) {}
    std::uint64_t points = 0, cells = 0;
    std::map<CellType, std::uint64_t> cell_types;
    ValueRanges xyz, normals, tcoords;
  };

  Scanner sc_;
  bool texture_ = false;
  bool color_ = false;
  bool normals_ = false;
  std::optional<Streamed> summary_;
};

/// Polys followed by the triangles of the strips (alternating orientation).
/// The faces a writer emits: the polygons, then each strip's triangles (every other one flipped,
/// so that all keep the strip's orientation), each given to `f` as its ids.
template <class F>
void for_each_face(const PolyData& mesh, F&& f) {
  for (std::size_t c = 0; c < mesh.polys.size(); ++c) f(mesh.polys.cell(c));
  for (std::size_t s = 0; s < mesh.strips.size(); ++s) {
    const auto ids = mesh.strips.cell(s);
    for (std::size_t k = 0; k + 2 < ids.size(); ++k) {
      const auto tri = strip_triangle(ids, k);
      f(std::span<const Index>(tri));
    }
  }
}

/// The number of faces for_each_face gives.
std::size_t count_faces(const PolyData& mesh) {
  std::size_t n = mesh.polys.size();
  for (std::size_t s = 0; s < mesh.strips.size(); ++s) {
    const std::size_t k = mesh.strips.cell_size(s);
    if (k >= 3) n += k - 2;
  }
  return n;
}

/// The ids for_each_face gives, in all.
std::size_t count_face_ids(const PolyData& mesh) {
  return mesh.polys.connectivity().size() + 3 * (count_faces(mesh) - mesh.polys.size());
}

/// Text into an AtomicFile through a buffer written out every 4 MiB, so that writing costs a
/// few MiB of memory whatever the mesh's size (the file's text was built whole before), with
/// progress by values written (`values` in all).
class TextFile {
 public:
  TextFile(const std::filesystem::path& path, std::uint64_t estimate,
           const ProgressCallback& progress, std::uint64_t values)
      : file_(path), progress_(progress, values, "writing") {
    file_.reserve(estimate);
  }
  std::string& text() { return buf_; }
  /// After each record of `values` values.
  void record(std::uint64_t values) {
    progress_.add(values);
    if (buf_.size() >= kFlush) flush();
  }
  void commit() {
    flush();
    progress_.finish();  // before the commit: a cancel leaves the target unchanged
    file_.commit();
  }

 private:
  static constexpr std::size_t kFlush = std::size_t{4} << 20;
  void flush() {
    file_.stream().write(buf_.data(), static_cast<std::streamsize>(buf_.size()));
    buf_.clear();
  }
  AtomicFile file_;
  io_detail::Progress progress_;
  std::string buf_;
};

void validate_for_write(const PolyData& mesh, const std::string& file) {
  try {
    mesh.validate();
  } catch (const Error& e) {
    throw Error(file + ": cannot write an invalid mesh: " + e.what());
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// OFF

PolyData read_off(std::span<const std::byte> data, std::string_view name) {
  OffReader reader(data, name);
  return reader.read();
}

PolyData read_off(const std::filesystem::path& path, const ProgressCallback& progress) {
  return io_detail::read_with_progress(
      path, progress, [&](const io_detail::FileSource& src, io_detail::Progress* p,
                          std::uint64_t base) { return OffReader(src.bytes, path.string(), p, base).read(); });
}

namespace io_detail {

DatasetSummary summarize_off(const std::filesystem::path& path, const ProgressCallback& progress) {
  return read_with_progress(path, progress,
                            [&](const FileSource& src, Progress* p, std::uint64_t base) {
                              return OffReader(src.bytes, path.string(), p, base).summarize();
                            });
}

DatasetSummary summarize_off(std::span<const std::byte> data, std::string_view name) {
  return OffReader(data, name).summarize();
}

}  // namespace io_detail

void write_off(const PolyData& mesh, const std::filesystem::path& path,
               const ProgressCallback& progress) {
  const std::string file = path.string();
  if (!mesh.verts.empty() || !mesh.lines.empty()) {
    throw Error(file + ": OFF holds polygons only; the mesh has " +
                std::to_string(mesh.verts.size()) + " verts and " +
                std::to_string(mesh.lines.size()) + " lines");
  }
  validate_for_write(mesh, file);
  const bool single = mesh.points.type() == ScalarType::Float32;
  const std::size_t np = mesh.num_points();
  const std::size_t num_faces = count_faces(mesh);
  TextFile file_out(path, 24 * np + 12 * mesh.polys.connectivity().size(), progress,
                    3 * np + num_faces + count_face_ids(mesh));
  std::string& out = file_out.text();
  out = "OFF\n# written by isoforge\n";
  out += std::to_string(np) + " " + std::to_string(num_faces) + " 0\n";
  for (std::size_t i = 0; i < np; ++i) {
    const Vec3 p = mesh.points[i];
    for (int a = 0; a < 3; ++a) {
      if (a) out += ' ';
      append_coord(out, p[a], single);
    }
    out += '\n';
    file_out.record(3);
  }
  for_each_face(mesh, [&](std::span<const Index> ids) {
    append_number(out, ids.size());
    for (Index id : ids) {
      out += ' ';
      append_number(out, id);
    }
    out += '\n';
    file_out.record(1 + ids.size());
  });
  file_out.commit();
}

// ---------------------------------------------------------------------------------------------
// OBJ

void write_obj(const PolyData& mesh, const std::filesystem::path& path,
               const ProgressCallback& progress) {
  const std::string file = path.string();
  validate_for_write(mesh, file);
  const std::size_t np = mesh.num_points();
  const DataArray* normals = mesh.point_data.normals();
  if (normals && normals->components() != 3) normals = nullptr;
  const DataArray* tcoords = mesh.point_data.tcoords();
  if (tcoords && (tcoords->components() < 1 || tcoords->components() > 3)) tcoords = nullptr;
  const bool single = mesh.points.type() == ScalarType::Float32;

  const std::size_t per_point =
      3 + (normals ? 3 : 0) + (tcoords ? static_cast<std::size_t>(tcoords->components()) : 0);
  const std::size_t values = np * per_point + mesh.verts.connectivity().size() +
                             mesh.lines.connectivity().size() + count_face_ids(mesh);
  TextFile file_out(path, 40 * np + 16 * mesh.polys.connectivity().size(), progress, values);
  std::string& out = file_out.text();
  out = "# written by isoforge\n";
  out += "# " + std::to_string(np) + " vertices\n";
  for (std::size_t i = 0; i < np; ++i) {
    const Vec3 p = mesh.points[i];
    out += 'v';
    for (int a = 0; a < 3; ++a) {
      out += ' ';
      append_coord(out, p[a], single);
    }
    out += '\n';
    file_out.record(3);
  }
  if (normals) {
    const bool nsingle = normals->type() != ScalarType::Float64;
    for (std::size_t i = 0; i < np; ++i) {
      out += "vn";
      for (int a = 0; a < 3; ++a) {
        out += ' ';
        append_coord(out, normals->get(i, a), nsingle);
      }
      out += '\n';
      file_out.record(3);
    }
  }
  if (tcoords) {
    const bool tsingle = tcoords->type() != ScalarType::Float64;
    for (std::size_t i = 0; i < np; ++i) {
      out += "vt";
      for (int a = 0; a < tcoords->components(); ++a) {
        out += ' ';
        append_coord(out, tcoords->get(i, a), tsingle);
      }
      out += '\n';
      file_out.record(static_cast<std::uint64_t>(tcoords->components()));
    }
  }
  // A face's vertex: "i", "i/i", "i//i" or "i/i/i" (1-based, with its texture coordinate and
  // normal of the same index).
  const auto vertex_ref = [&](Index id) {
    const std::size_t at = out.size();
    append_number(out, id + 1);
    if (!normals && !tcoords) return;
    const std::string n = out.substr(at);
    if (tcoords) out += '/' + n;
    if (normals) out += (tcoords ? "/" : "//") + n;
  };
  for (std::size_t c = 0; c < mesh.verts.size(); ++c) {
    out += 'p';
    for (Index id : mesh.verts.cell(c)) {
      out += ' ';
      append_number(out, id + 1);
    }
    out += '\n';
    file_out.record(mesh.verts.cell_size(c));
  }
  for (std::size_t c = 0; c < mesh.lines.size(); ++c) {
    out += 'l';
    for (Index id : mesh.lines.cell(c)) {
      out += ' ';
      append_number(out, id + 1);
    }
    out += '\n';
    file_out.record(mesh.lines.cell_size(c));
  }
  for_each_face(mesh, [&](std::span<const Index> ids) {
    out += 'f';
    for (Index id : ids) {
      out += ' ';
      vertex_ref(id);
    }
    out += '\n';
    file_out.record(ids.size());
  });
  file_out.commit();
}

}  // namespace isoforge
