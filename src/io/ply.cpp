// Stanford PLY polygon file format, version 1.0 (Greg Turk, "The PLY Polygon File Format",
// 1994, as documented by Paul Bourke): reader and writer for `format ascii`,
// `binary_little_endian` and `binary_big_endian`.
//
// Reader: every element of the header is parsed (unknown elements are skipped value by value,
// list counts included); "vertex" and "face" elements become points, point arrays, polys and
// cell arrays as described in isoforge/io/ply.hpp. Writer: points, point arrays as
// properties, polys and triangulated strips, cell arrays as face properties.

#include <algorithm>
#include <atomic>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "detail/file_source.hpp"
#include "detail/scanner.hpp"
#include "detail/summaries.hpp"
#include "detail/tuple_stream.hpp"
#include "isoforge/core/buffer.hpp"
#include "isoforge/core/cell.hpp"
#include "isoforge/core/parallel.hpp"
#include "isoforge/core/subset.hpp"
#include "isoforge/io/atomic_file.hpp"
#include "isoforge/io/io.hpp"
#include "isoforge/io/ply.hpp"

namespace isoforge {

namespace {

using io_detail::Endian;
using io_detail::Scanner;
using io_detail::split_words;

// ---------------------------------------------------------------------------------------------
// Types

std::optional<ScalarType> ply_scalar_type(std::string_view name) {
  if (name == "char" || name == "int8") return ScalarType::Int8;
  if (name == "uchar" || name == "uint8") return ScalarType::UInt8;
  if (name == "short" || name == "int16") return ScalarType::Int16;
  if (name == "ushort" || name == "uint16") return ScalarType::UInt16;
  if (name == "int" || name == "int32") return ScalarType::Int32;
  if (name == "uint" || name == "uint32") return ScalarType::UInt32;
  if (name == "float" || name == "float32") return ScalarType::Float32;
  if (name == "double" || name == "float64") return ScalarType::Float64;
  return std::nullopt;
}


// ---------------------------------------------------------------------------------------------
// Header

struct PlyProperty {
  std::string name;
  bool is_list = false;
  ScalarType count_type = ScalarType::UInt8;  // lists only
  ScalarType type = ScalarType::Float32;      // value type, or item type for lists
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::int64_t line = 0;
  std::vector<PlyProperty> props;

  [[nodiscard]] int find(std::string_view prop, bool list) const {
    for (std::size_t i = 0; i < props.size(); ++i) {
      if (props[i].name == prop && props[i].is_list == list) return static_cast<int>(i);
    }
    return -1;
  }
};

enum class PlyFormat { Ascii, Little, Big };

// ---------------------------------------------------------------------------------------------
// Reader

class PlyReader {
 public:
  PlyReader(io_detail::FileSource data, std::string_view name,
            io_detail::Progress* progress = nullptr, std::uint64_t progress_base = 0)
      : sc_(data, std::string(name)) {
    sc_.track(progress, progress_base);
  }

  /// The summary in one streaming pass, a window of records at a time: binary records of a fixed
  /// size (every face the same vertex count) decoded in parallel, the others (ascii, list
  /// properties, mixed faces) value by value as `read` does. False, with nothing decided, for a
  /// face element without an integer index list, which `read` rejects.
  bool summarize(DatasetSummary& s) {
    parse_header();
    for (const PlyElement& e : elements_) {
      if (e.name == "vertex") check_coordinates(e);
    }
    check_body_size();
    s = DatasetSummary{};
    s.kind = 2;
    s.streamed = true;
    for (const PlyElement& e : elements_) {
      if (e.name == "vertex") {
        summarize_vertices(e, s);
      } else if (e.name == "face") {
        if (!summarize_faces(e, s)) return false;
      } else {
        skip_element(e);
      }
    }
    if (have_vertex_) return true;
    if (s.cells > 0) return false;      // faces without vertices: the reader says so
    s.cell_data = AttributesSummary{};  // no vertex element: the reader's mesh is empty
    return true;
  }

  PolyData read() {
    parse_header();
    for (const PlyElement& e : elements_) {
      if (e.name == "vertex") check_coordinates(e);
    }
    check_body_size();
    for (const PlyElement& e : elements_) {
      if (e.name == "vertex") {
        read_vertices(e);
      } else if (e.name == "face") {
        read_faces(e);
      } else {
        skip_element(e);
      }
    }
    return build();
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    if (format_ == PlyFormat::Ascii) sc_.fail_line(what);
    sc_.fail_byte(what);
  }
  [[noreturn]] void fail_header(std::int64_t line, const std::string& what) const {
    throw Error(at_line(sc_.name(), line, what));
  }

  void parse_header() {
    std::string_view line;
    if (!sc_.read_line(line)) sc_.fail_line("empty file, expected the PLY magic 'ply'");
    if (line != "ply") {
      fail_header(1, "bad magic: expected 'ply', found " + io_detail::quoted(line));
    }
    bool have_format = false;
    bool ended = false;
    while (!ended) {
      const std::int64_t line_no = sc_.line();
      if (!sc_.read_line(line))
        fail_header(line_no, "unexpected end of file in the header (no end_header)");
      const auto w = split_words(line);
      if (w.empty()) continue;
      const std::string_view key = w[0];
      if (key == "comment" || key == "obj_info") continue;
      if (key == "end_header") {
        if (w.size() != 1) fail_header(line_no, "unexpected text after end_header");
        ended = true;
      } else if (key == "format") {
        if (have_format) fail_header(line_no, "duplicate format line");
        if (w.size() != 3) fail_header(line_no, "format line needs an encoding and a version");
        if (w[1] == "ascii") {
          format_ = PlyFormat::Ascii;
        } else if (w[1] == "binary_little_endian") {
          format_ = PlyFormat::Little;
        } else if (w[1] == "binary_big_endian") {
          format_ = PlyFormat::Big;
        } else {
          fail_header(line_no, "unknown format " + io_detail::quoted(w[1]) +
                                   " (expected ascii, binary_little_endian or binary_big_endian)");
        }
        if (w[2] != "1.0" && w[2] != "1") {
          fail_header(line_no, "unsupported PLY version " + io_detail::quoted(w[2]));
        }
        have_format = true;
      } else if (key == "element") {
        if (w.size() != 3) fail_header(line_no, "element line needs a name and a count");
        PlyElement e;
        e.name = std::string(w[1]);
        e.line = line_no;
        std::int64_t count = 0;
        const auto [ptr, ec] = std::from_chars(w[2].data(), w[2].data() + w[2].size(), count);
        if (ec != std::errc() || ptr != w[2].data() + w[2].size()) {
          fail_header(line_no, "element " + io_detail::quoted(e.name) + " count " +
                                   io_detail::quoted(w[2]) + " is not an integer");
        }
        if (count < 0) {
          fail_header(line_no,
                      "element '" + e.name + "' count " + std::to_string(count) + " is negative");
        }
        e.count = static_cast<std::uint64_t>(count);
        for (const auto& other : elements_) {
          if (other.name == e.name && (e.name == "vertex" || e.name == "face")) {
            fail_header(line_no, "duplicate element '" + e.name + "'");
          }
        }
        elements_.push_back(std::move(e));
      } else if (key == "property") {
        if (elements_.empty()) fail_header(line_no, "property before any element");
        PlyProperty p;
        if (w.size() >= 2 && w[1] == "list") {
          if (w.size() != 5)
            fail_header(line_no, "property list needs a count type, an item type and a name");
          auto ct = ply_scalar_type(w[2]);
          auto it = ply_scalar_type(w[3]);
          if (!ct)
            fail_header(line_no, "unknown property type " + io_detail::quoted(w[2]));
          if (!it)
            fail_header(line_no, "unknown property type " + io_detail::quoted(w[3]));
          if (is_floating(*ct)) {
            fail_header(line_no,
                        "list count type " + io_detail::quoted(w[2]) + " is not an integer type");
          }
          p.is_list = true;
          p.count_type = *ct;
          p.type = *it;
          p.name = std::string(w[4]);
        } else {
          if (w.size() != 3) fail_header(line_no, "property line needs a type and a name");
          auto t = ply_scalar_type(w[1]);
          if (!t)
            fail_header(line_no, "unknown property type " + io_detail::quoted(w[1]));
          p.type = *t;
          p.name = std::string(w[2]);
        }
        for (const auto& q : elements_.back().props) {
          if (q.name == p.name) {
            fail_header(line_no, "duplicate property '" + p.name + "' in element '" +
                                     elements_.back().name + "'");
          }
        }
        elements_.back().props.push_back(std::move(p));
      } else {
        fail_header(line_no, "unknown header keyword " + io_detail::quoted(key));
      }
    }
    if (!have_format) fail_header(sc_.line(), "header has no format line");
    endian_ = format_ == PlyFormat::Big ? Endian::Big : Endian::Little;
  }

  // Minimum bytes one instance of `e` occupies (ASCII: a character and a separator per value).
  [[nodiscard]] std::uint64_t min_instance_bytes(const PlyElement& e) const {
    std::uint64_t n = 0;
    for (const auto& p : e.props) {
      if (format_ == PlyFormat::Ascii) {
        n += 2;
      } else {
        n += scalar_size(p.is_list ? p.count_type : p.type);
      }
    }
    return n;
  }

  // Rejects headers whose element counts cannot fit in the bytes that follow, before anything
  // is allocated.
  // x, y and z are required of the vertex element. Checked in the header: a body read with one
  // of them missing would be read with the wrong layout and fail later with a misleading message
  // ("face 0 has 0 vertices").
  void check_coordinates(const PlyElement& e) const {
    std::string have;
    for (const PlyProperty& p : e.props) have += (have.empty() ? "" : ", ") + p.name;
    for (const char* c : {"x", "y", "z"}) {
      if (e.find(c, false) < 0) {
        fail_header(e.line, std::string("the vertex element lacks the '") + c + "' property (it has " +
                                (have.empty() ? std::string("none") : have) +
                                "); x, y and z are required");
      }
    }
  }

  void check_body_size() const {
    std::uint64_t total = 0;
    const std::uint64_t remaining = sc_.remaining() + (format_ == PlyFormat::Ascii ? 1 : 0);
    for (const auto& e : elements_) {
      std::uint64_t need = 0;
      if (io_detail::mul_overflow(e.count, min_instance_bytes(e), need) ||
          __builtin_add_overflow(total, need, &total) || total > remaining) {
        fail_header(e.line, "element '" + e.name + "' count " + std::to_string(e.count) +
                                " exceeds what the remaining " + std::to_string(sc_.remaining()) +
                                " bytes of the file can hold");
      }
    }
  }

  template <class T>
  T read_value(const char* what) {
    if (format_ == PlyFormat::Ascii) return sc_.parse_token<T>(what);
    return sc_.read<T>(endian_, what);
  }

  double read_as_double(ScalarType t, const char* what) {
    return visit_scalar_type(t,
                    [&](auto tag) { return static_cast<double>(read_value<decltype(tag)>(what)); });
  }

  // Reads an integer-typed value (list count or index) as int64.
  std::int64_t read_integer(ScalarType t, const char* what) {
    return visit_scalar_type(t, [&](auto tag) -> std::int64_t {
      using T = decltype(tag);
      const T v = read_value<T>(what);
      if constexpr (std::is_floating_point_v<T>) {
        if (!(v >= -9.0e18 && v <= 9.0e18) || v != std::floor(v)) {
          fail(std::string(what) + " " + std::to_string(v) + " is not an integer");
        }
        return static_cast<std::int64_t>(v);
      } else {
        return static_cast<std::int64_t>(v);
      }
    });
  }

  // Reads a list count and checks it against the bytes left.
  std::uint64_t read_list_count(const PlyProperty& p) {
    const std::int64_t n = read_integer(p.count_type, "list count");
    if (n < 0) fail("list '" + p.name + "' count " + std::to_string(n) + " is negative");
    const std::uint64_t per = format_ == PlyFormat::Ascii ? 2 : scalar_size(p.type);
    if (static_cast<std::uint64_t>(n) > (sc_.remaining() + 1) / per) {
      fail("list '" + p.name + "' count " + std::to_string(n) + " exceeds what the remaining " +
           std::to_string(sc_.remaining()) + " bytes of the file can hold");
    }
    return static_cast<std::uint64_t>(n);
  }

  void skip_value(ScalarType t) {
    if (format_ == PlyFormat::Ascii) {
      (void)read_as_double(t, "property value");
    } else {
      sc_.skip(scalar_size(t), "property value");
    }
  }

  void skip_property(const PlyProperty& p) {
    if (!p.is_list) {
      skip_value(p.type);
      return;
    }
    const std::uint64_t n = read_list_count(p);
    if (format_ == PlyFormat::Ascii) {
      for (std::uint64_t i = 0; i < n; ++i) skip_value(p.type);
    } else {
      sc_.skip(static_cast<std::size_t>(n) * scalar_size(p.type), "list items");
    }
  }

  void skip_element(const PlyElement& e) {
    if (e.props.empty()) return;  // instances occupy no bytes
    for (std::uint64_t i = 0; i < e.count; ++i) {
      for (const auto& p : e.props) skip_property(p);
    }
  }

  void read_scalar_into(DataArray& a, std::size_t i, const char* what) {
    a.visit([&](auto& vec) {
      using T = typename std::decay_t<decltype(vec)>::value_type;
      vec[i] = read_value<T>(what);
    });
  }

  void read_vertices(const PlyElement& e) {
    have_vertex_ = true;
    const auto n = static_cast<std::size_t>(e.count);
    vertex_props_ = e.props;
    vertex_arrays_.clear();
    for (const auto& p : e.props) {
      vertex_arrays_.emplace_back(p.name, p.is_list ? ScalarType::UInt8 : p.type, 1,
                                  p.is_list ? 0 : n);
    }
    num_vertices_ = n;
    if (read_fixed_records(e, vertex_arrays_)) return;
    read_vertex_records(e, n);
  }

  /// The next `m` vertex records, value by value, into rows [0, m) of `vertex_arrays_`.
  void read_vertex_records(const PlyElement& e, std::size_t m) {
    for (std::size_t i = 0; i < m; ++i) {
      sc_.tick();  // progress, once a record
      for (std::size_t k = 0; k < e.props.size(); ++k) {
        if (e.props[k].is_list) {
          skip_property(e.props[k]);
        } else {
          read_scalar_into(vertex_arrays_[k], i, "vertex property value");
        }
      }
    }
  }

  /// Offsets of the scalar properties in a fixed-size binary record and the record's size (0:
  /// the records have lists).
  static std::size_t record_layout(const PlyElement& e, std::vector<std::size_t>& offset) {
    std::size_t rec = 0;
    for (const auto& p : e.props) {
      if (p.is_list) return 0;
      offset.push_back(rec);
      rec += scalar_size(p.type);
    }
    return rec;
  }

  /// Vertex records a window at a time: decoded and grouped as `build` does (normals, colours,
  /// texture coordinates), summarised, dropped.
  void summarize_vertices(const PlyElement& e, DatasetSummary& s) {
    std::vector<std::size_t> offset;
    std::size_t rec = format_ == PlyFormat::Ascii ? 0 : record_layout(e, offset);
    const auto n = static_cast<std::size_t>(e.count);
    if (rec != 0 && n > sc_.remaining() / rec) rec = 0;  // short: the value path says where
    have_vertex_ = true;
    vertex_props_ = e.props;
    const std::size_t window =
        rec != 0 ? std::max<std::size_t>(1, io_detail::TupleStream::kPiece / rec) : kValueWindow;
    std::size_t r0 = 0;
    do {  // once at least: an empty element still has its arrays
      const std::size_t m = std::min(window, n - r0);
      vertex_arrays_.clear();
      for (const auto& p : e.props) {
        vertex_arrays_.push_back(DataArray::uninitialized(
            p.name, p.is_list ? ScalarType::UInt8 : p.type, 1, p.is_list ? 0 : m));
      }
      if (rec != 0) {
        decode_columns(e.props, offset, rec, 0, m, vertex_arrays_, -1);
        sc_.skip(m * rec, "element records");
      } else {
        read_vertex_records(e, m);
      }
      num_vertices_ = m;
      polys_ = CellArray();  // build() takes it
      const PolyData piece = build();
      s.bounds.merge(piece.bounds());
      const DatasetSummary ps = isoforge::summarize(piece);
      for (const ArraySummary& a : ps.point_data.arrays) s.point_data.merge_array(a);
      s.point_data.active = ps.point_data.active;
      r0 += m;
    } while (r0 < n);
    s.points = n;
  }

  /// Faces counted by vertex count and their scalar properties summarised, a window at a time:
  /// windows of one vertex count decoded in parallel without reading their index lists, the
  /// others (ascii, mixed faces, other lists) read value by value, indices checked, then dropped.
  bool summarize_faces(const PlyElement& e, DatasetSummary& s) {
    int idx = e.find("vertex_indices", true);
    if (idx < 0) idx = e.find("vertex_index", true);
    if (idx < 0) return false;
    const PlyProperty& ip = e.props[static_cast<std::size_t>(idx)];
    if (is_floating(ip.type)) return false;
    // Corner texture coordinates duplicate points (build): the summary is that of the mesh read.
    if (corner_texcoord_prop(e) >= 0) return false;
    const auto n = static_cast<std::size_t>(e.count);
    auto window_arrays = [&](std::size_t m) {
      face_arrays_.clear();
      for (const auto& p : e.props) {
        face_arrays_.push_back(DataArray::uninitialized(
            p.name, p.is_list ? ScalarType::UInt8 : p.type, 1, p.is_list ? 0 : m));
      }
    };
    auto summarize_arrays = [&] {
      for (std::size_t k = 0; k < e.props.size(); ++k) {
        if (static_cast<int>(k) != idx && !e.props[k].is_list) {
          s.cell_data.merge_array(isoforge::summarize(face_arrays_[k]));
        }
      }
    };
    std::size_t r0 = 0;
    if (const std::optional<FaceLayout> layout = face_layout(e, idx)) {
      const std::size_t window =
          std::max<std::size_t>(1, io_detail::TupleStream::kPiece / layout->rec);
      while (r0 < n) {
        const std::size_t m = std::min(window, n - r0);
        if (!uniform_counts(*layout, ip, m)) break;  // the rest value by value
        window_arrays(m);
        decode_columns(e.props, layout->offset, layout->rec, 0, m, face_arrays_, idx);
        sc_.skip(m * layout->rec, "face records");
        summarize_arrays();
        s.cells += m;
        s.cell_types[poly_cell_type(2, layout->count)] += m;
        r0 += m;
      }
      if (r0 == n) return true;
    }
    std::uint64_t nverts = 0;
    for (const auto& el : elements_) {
      if (el.name == "vertex") nverts = el.count;
    }
    do {  // once at least: an empty element still has its arrays
      const std::size_t m = std::min(kValueWindow, n - r0);
      window_arrays(m);
      polys_ = CellArray();
      read_face_records(e, idx, nverts, r0, m);
      summarize_arrays();
      const auto& off = polys_.offsets();
      for (std::size_t f = 0; f < m; ++f) {
        s.cell_types[poly_cell_type(2, static_cast<std::size_t>(off[f + 1] - off[f]))] += 1;
      }
      s.cells += m;
      r0 += m;
    } while (r0 < n);
    polys_ = CellArray();
    return true;
  }

  /// Binary records of scalar properties only (fixed size): every property's column decoded in
  /// parallel straight from the file into `arrays` (sized). False (nothing read) for ASCII, lists
  /// or a body too short — the per-value path then reads or reports it.
  bool read_fixed_records(const PlyElement& e, std::vector<DataArray>& arrays) {
    if (format_ == PlyFormat::Ascii) return false;
    std::vector<std::size_t> offset;
    const std::size_t rec = record_layout(e, offset);
    const auto n = static_cast<std::size_t>(e.count);
    if (rec == 0 || n > sc_.remaining() / rec) return false;
    decode_columns(e.props, offset, rec, 0, n, arrays, -1);
    sc_.skip(n * rec, "element records");
    return true;
  }

  /// Decodes records [0, n) of `rec` bytes from the scanner's position into rows
  /// [row0, row0 + n) of `arrays[k]` for every scalar property k (at byte `offset[k]` of a
  /// record; list properties are skipped), in parallel.
  void decode_columns(const std::vector<PlyProperty>& props, const std::vector<std::size_t>& offset,
                      std::size_t rec, std::size_t row0, std::size_t n,
                      std::vector<DataArray>& arrays, int skip_prop) {
    const std::byte* base = sc_.data().data() + sc_.offset();
    const bool swap = endian_ != io_detail::kHostEndian;
    parallel_for_range(n, 1 << 14, [&](std::size_t b, std::size_t end) {
      for (std::size_t k = 0; k < props.size(); ++k) {
        if (props[k].is_list || static_cast<int>(k) == skip_prop) continue;
        arrays[k].visit([&](auto& vec) {
          using T = typename std::decay_t<decltype(vec)>::value_type;
          const std::byte* p = base + offset[k];
          for (std::size_t i = b; i < end; ++i) vec[row0 + i] = load<T>(p + i * rec, swap);
        });
      }
    });
  }

  template <class T>
  static T load(const std::byte* p, bool swap) {
    T v;
    std::memcpy(&v, p, sizeof(T));
    return swap ? io_detail::byteswap_value(v) : v;
  }

  /// Binary faces whose one list is the index list and whose every face has the first face's
  /// vertex count (a triangle or quad mesh): the counts are checked at the fixed record size,
  /// then all records decoded in parallel. False (nothing read) otherwise.
  /// The layout of binary face records whose one list is the index list, taken from the first
  /// record: its vertex count (3-64), the bytes before the list, the record size and every
  /// property's offset. None for ascii, other lists, floating counts or a short body.
  struct FaceLayout {
    std::size_t count = 0, before = 0, rec = 0;
    std::vector<std::size_t> offset;
  };
  std::optional<FaceLayout> face_layout(const PlyElement& e, int idx) const {
    if (format_ == PlyFormat::Ascii || e.count == 0) return std::nullopt;
    const PlyProperty& ip = e.props[static_cast<std::size_t>(idx)];
    if (is_floating(ip.count_type)) return std::nullopt;
    FaceLayout f;
    for (std::size_t k = 0; k < e.props.size(); ++k) {
      if (static_cast<int>(k) == idx) continue;
      if (e.props[k].is_list) return std::nullopt;
      if (static_cast<int>(k) < idx) f.before += scalar_size(e.props[k].type);
    }
    const std::size_t cs = scalar_size(ip.count_type), is = scalar_size(ip.type);
    if (f.before + cs > sc_.remaining()) return std::nullopt;
    const std::byte* base = sc_.data().data() + sc_.offset();
    const std::int64_t c0 = visit_scalar_type(ip.count_type, [&](auto tag) -> std::int64_t {
      using C = decltype(tag);
      if constexpr (std::is_integral_v<C>) {
        return static_cast<std::int64_t>(load<C>(base + f.before, endian_ != io_detail::kHostEndian));
      }
      return -1;
    });
    if (c0 < 3 || c0 > 64) return std::nullopt;
    f.count = static_cast<std::size_t>(c0);
    for (std::size_t k = 0; k < e.props.size(); ++k) {
      f.offset.push_back(f.rec);
      f.rec += static_cast<int>(k) == idx ? cs + f.count * is : scalar_size(e.props[k].type);
    }
    if (e.count > sc_.remaining() / f.rec) return std::nullopt;
    return f;
  }

  /// Whether the `n` face records at the scanner's position all have the layout's count.
  bool uniform_counts(const FaceLayout& f, const PlyProperty& ip, std::size_t n) const {
    const std::byte* base = sc_.data().data() + sc_.offset();
    const bool swap = endian_ != io_detail::kHostEndian;
    std::atomic<bool> uniform{true};
    visit_scalar_type(ip.count_type, [&](auto ctag) {
      using C = decltype(ctag);
      if constexpr (std::is_integral_v<C>) {
        const auto want = static_cast<C>(f.count);
        parallel_for_range(n, 1 << 16, [&](std::size_t b, std::size_t end) {
          bool ok = true;
          for (std::size_t i = b; i < end; ++i) ok &= load<C>(base + i * f.rec + f.before, swap) == want;
          if (!ok) uniform.store(false, std::memory_order_relaxed);
        });
      }
    });
    return uniform.load();
  }

  bool read_fixed_faces(const PlyElement& e, int idx, std::uint64_t nverts) {
    const std::optional<FaceLayout> layout = face_layout(e, idx);
    const PlyProperty& ip = e.props[static_cast<std::size_t>(idx)];
    const auto n = static_cast<std::size_t>(e.count);
    // Every count equal to the first: else the variable-size path.
    if (!layout || !uniform_counts(*layout, ip, n)) return false;
    const std::size_t c = layout->count, rec = layout->rec, is = scalar_size(ip.type);
    const std::byte* base = sc_.data().data() + sc_.offset();
    const bool swap = endian_ != io_detail::kHostEndian;
    auto& conn = polys_.connectivity();
    auto& offsets = polys_.offsets();
    conn.resize(n * c);
    offsets.resize(n + 1);
    std::atomic<std::size_t> bad{n};  // the first face with an index out of range
    const std::byte* list = base + layout->before + scalar_size(ip.count_type);
    bool integral = true;
    visit_scalar_type(ip.type, [&](auto itag) {
      using I = decltype(itag);
      if constexpr (!std::is_integral_v<I>) {
        integral = false;
      } else {
        parallel_for_range(n, 1 << 14, [&](std::size_t b, std::size_t end) {
          std::size_t first_bad = n;
          for (std::size_t f = b; f < end; ++f) {
            const std::byte* p = list + f * rec;
            bool ok = true;
            for (std::size_t j = 0; j < c; ++j) {
              const auto v = static_cast<std::int64_t>(load<I>(p + j * is, swap));
              ok &= v >= 0 && static_cast<std::uint64_t>(v) < nverts;
              conn[f * c + j] = static_cast<Index>(v);
            }
            offsets[f + 1] = static_cast<Index>((f + 1) * c);
            if (!ok && first_bad == n) first_bad = f;
          }
          std::size_t cur = bad.load();
          while (first_bad < cur && !bad.compare_exchange_weak(cur, first_bad)) {
          }
        });
      }
    });
    if (!integral) {
      conn.clear();
      offsets.assign(1, 0);
      return false;
    }
    offsets[0] = 0;
    if (bad.load() < n) {
      const std::size_t f = bad.load();
      for (std::size_t j = 0; j < c; ++j) {
        const Index v = conn[f * c + j];
        if (v < 0 || static_cast<std::uint64_t>(v) >= nverts) {
          sc_.seek(sc_.offset() + f * rec);
          fail("face " + std::to_string(f) + ": vertex index " + std::to_string(v) +
               " is out of range (" + std::to_string(nverts) + " vertices)");
        }
      }
    }
    decode_columns(e.props, layout->offset, rec, 0, n, face_arrays_, idx);
    sc_.skip(n * rec, "face records");
    return true;
  }

  void read_faces(const PlyElement& e) {
    int idx = e.find("vertex_indices", true);
    if (idx < 0) idx = e.find("vertex_index", true);
    if (idx < 0) {
      fail_header(e.line,
                  "element 'face' has no 'vertex_indices' (or 'vertex_index') list property");
    }
    if (is_floating(e.props[static_cast<std::size_t>(idx)].type)) {
      fail_header(e.line, "face vertex index type is not an integer type");
    }
    const auto n = static_cast<std::size_t>(e.count);
    // The vertex count comes from the header, so faces may precede the vertex element.
    std::uint64_t nverts = 0;
    for (const auto& el : elements_) {
      if (el.name == "vertex") nverts = el.count;
    }
    face_props_ = e.props;
    face_arrays_.clear();
    for (const auto& p : e.props) {
      face_arrays_.emplace_back(p.name, p.is_list ? ScalarType::UInt8 : p.type, 1,
                                p.is_list ? 0 : n);
    }
    face_index_prop_ = idx;
    face_texcoord_prop_ = corner_texcoord_prop(e);
    corner_uv_.clear();
    if (read_fixed_faces(e, idx, nverts)) return;
    read_face_records(e, idx, nverts, 0, n);
  }

  /// The next `m` face records (faces [first, first + m) of the element, for messages), value
  /// by value: index lists appended to `polys_` (each index checked against `nverts`), scalar
  /// properties into rows [0, m) of `face_arrays_`.
  void read_face_records(const PlyElement& e, int idx, std::uint64_t nverts, std::size_t first,
                         std::size_t m) {
    auto& offsets = polys_.offsets();
    auto& conn = polys_.connectivity();
    offsets.reserve(offsets.size() + m);
    // Most meshes are triangles: room for three indices a face, grown only past that.
    conn.reserve(conn.size() + std::min<std::size_t>(3 * m, sc_.remaining()));
    const int tc = corner_texcoord_prop(e);
    std::vector<double> uv;  // this face's corner texture coordinates
    for (std::size_t i = 0; i < m; ++i) {
      const std::size_t f = first + i;
      const std::size_t corners_before = conn.size();
      sc_.tick();  // progress, once a record
      for (std::size_t k = 0; k < e.props.size(); ++k) {
        const PlyProperty& p = e.props[k];
        if (static_cast<int>(k) == tc) {
          const std::uint64_t count = read_list_count(p);
          uv.resize(static_cast<std::size_t>(count));
          for (double& v : uv) v = read_as_double(p.type, "texcoord value");
        } else if (static_cast<int>(k) == idx) {
          const std::uint64_t count = read_list_count(p);
          if (count < 3) {
            fail("face " + std::to_string(f) + " has " + std::to_string(count) +
                 " vertices, a polygon needs at least 3");
          }
          for (std::uint64_t j = 0; j < count; ++j) {
            const std::int64_t v = read_integer(p.type, "face vertex index");
            if (v < 0 || static_cast<std::uint64_t>(v) >= nverts) {
              fail("face " + std::to_string(f) + ": vertex index " + std::to_string(v) +
                   " is out of range (" + std::to_string(nverts) + " vertices)");
            }
            conn.push_back(v);
          }
          offsets.push_back(static_cast<Index>(conn.size()));
        } else if (p.is_list) {
          skip_property(p);
        } else {
          read_scalar_into(face_arrays_[k], i, "face property value");
        }
      }
      if (tc >= 0) {
        const std::size_t corners = conn.size() - corners_before;
        if (uv.empty()) uv.assign(2 * corners, std::numeric_limits<double>::quiet_NaN());
        if (uv.size() != 2 * corners) {
          fail("face " + std::to_string(f) + ": 'texcoord' has " + std::to_string(uv.size()) +
               " values; a face of " + std::to_string(corners) + " vertices needs " +
               std::to_string(2 * corners) + " (u, v per vertex)");
        }
        corner_uv_.insert(corner_uv_.end(), uv.begin(), uv.end());
      }
    }
  }

  /// The face element's list "texcoord" (or "texcoords"): texture coordinates per face corner,
  /// u v for each vertex of the index list (MeshLab's wedge texture coordinates); -1 if none.
  [[nodiscard]] static int corner_texcoord_prop(const PlyElement& e) {
    int k = e.find("texcoord", true);
    if (k < 0) k = e.find("texcoords", true);
    return k;
  }

  /// Corner texture coordinates to "TCoords" per point: a vertex whose corners have different
  /// coordinates is duplicated, with its point arrays, once per distinct pair (as VTK's reader
  /// does); vertices in no face, or only in faces with an empty list, get (0, 0). Faces are
  /// renumbered to the copies.
  void split_corner_texcoords(PolyData& mesh) {
    const std::size_t n = mesh.points.size();
    auto& conn = mesh.polys.connectivity();
    std::vector<float> uv(2 * n, 0.f);      // per point, copies appended
    std::vector<Index> next(n, -1);         // per point: the next copy of its vertex, or -1
    std::vector<std::uint8_t> given(n, 0);  // per vertex: its coordinates set by a corner
    std::vector<Index> source;              // per copy: the vertex copied
    for (std::size_t c = 0; c < conn.size(); ++c) {
      const auto u = static_cast<float>(corner_uv_[2 * c]);
      const auto v = static_cast<float>(corner_uv_[2 * c + 1]);
      const auto v0 = static_cast<std::size_t>(conn[c]);
      if (std::isnan(u) && std::isnan(v)) continue;  // a face with an empty list: on its vertex
      if (!given[v0]) {
        given[v0] = 1;
        uv[2 * v0] = u;
        uv[2 * v0 + 1] = v;
        continue;
      }
      // The copy with the same bits (so a NaN component matches itself), else a new one.
      std::size_t p = v0, last = v0;
      bool found = false;
      for (Index q = conn[c]; q >= 0; q = next[static_cast<std::size_t>(q)]) {
        p = static_cast<std::size_t>(q);
        last = p;
        if (std::memcmp(&uv[2 * p], &u, sizeof u) == 0 &&
            std::memcmp(&uv[2 * p + 1], &v, sizeof v) == 0) {
          found = true;
          break;
        }
      }
      if (!found) {
        p = n + source.size();
        source.push_back(static_cast<Index>(v0));
        uv.push_back(u);
        uv.push_back(v);
        next.push_back(-1);
        next[last] = static_cast<Index>(p);
      }
      conn[c] = static_cast<Index>(p);
    }
    const std::size_t total = n + source.size();
    DataArray tcoords("TCoords", ScalarType::Float32, 2, total);
    std::copy(uv.begin(), uv.end(), tcoords.values<float>().begin());
    if (!source.empty()) {
      mesh.points.resize(total);
      for (DataArray& a : mesh.point_data) a.resize(total);
      for (std::size_t i = 0; i < source.size(); ++i) {
        const auto from = static_cast<std::size_t>(source[i]);
        mesh.points.set(n + i, mesh.points[from]);
        copy_tuple(mesh.point_data, from, mesh.point_data, n + i);
      }
    }
    mesh.point_data.add(std::move(tcoords), AttributeRole::TCoords);
  }

  // Index of the scalar vertex property `name`, or -1.
  [[nodiscard]] int vertex_prop(std::string_view name) const {
    for (std::size_t i = 0; i < vertex_props_.size(); ++i) {
      if (vertex_props_[i].name == name && !vertex_props_[i].is_list) return static_cast<int>(i);
    }
    return -1;
  }

  PolyData build() {
    PolyData mesh;
    if (!have_vertex_) {
      if (!polys_.empty()) throw Error(sc_.name() + ": faces but no vertex element");
      return mesh;
    }
    const std::size_t n = num_vertices_;
    std::vector<bool> used(vertex_props_.size(), false);
    for (std::size_t k = 0; k < vertex_props_.size(); ++k) used[k] = vertex_props_[k].is_list;

    const int ix = vertex_prop("x"), iy = vertex_prop("y"), iz = vertex_prop("z");
    check_invariant(ix >= 0 && iy >= 0 && iz >= 0, "x, y, z checked by check_coordinates");
    const int xyz[3] = {ix, iy, iz};
    bool dbl = false;
    for (int a : xyz) {
      dbl = dbl || vertex_props_[static_cast<std::size_t>(a)].type == ScalarType::Float64;
      used[static_cast<std::size_t>(a)] = true;
    }
    mesh.points = Points(  // every point set below
        DataArray::uninitialized("Points", dbl ? ScalarType::Float64 : ScalarType::Float32, 3, n));
    for (std::size_t i = 0; i < n; ++i) {
      Vec3 p{vertex_arrays_[static_cast<std::size_t>(ix)].get(i),
             vertex_arrays_[static_cast<std::size_t>(iy)].get(i),
             vertex_arrays_[static_cast<std::size_t>(iz)].get(i)};
      mesh.points.set(i, p);
    }
    if (const std::size_t bad = mesh.points.first_non_finite(); bad < n) {
      const Vec3 p = mesh.points[bad];
      throw Error(sc_.name() + ": vertex " + std::to_string(bad) +
                  " has a non-finite coordinate (" + std::to_string(p.x) + ", " +
                  std::to_string(p.y) + ", " + std::to_string(p.z) + ")");
    }

    // Grouped attributes.
    auto group = [&](std::initializer_list<const char*> names, const char* array_name,
                     AttributeRole role) {
      std::vector<int> ids;
      for (const char* nm : names) {
        const int id = vertex_prop(nm);
        if (id < 0) return;
        ids.push_back(id);
      }
      bool any_double = false;
      for (int id : ids) {
        any_double =
            any_double || vertex_props_[static_cast<std::size_t>(id)].type == ScalarType::Float64;
      }
      DataArray a(array_name, any_double ? ScalarType::Float64 : ScalarType::Float32,
                  static_cast<int>(ids.size()), n);
      for (std::size_t c = 0; c < ids.size(); ++c) {
        const DataArray& src = vertex_arrays_[static_cast<std::size_t>(ids[c])];
        for (std::size_t i = 0; i < n; ++i) a.set(i, static_cast<int>(c), src.get(i));
        used[static_cast<std::size_t>(ids[c])] = true;
      }
      mesh.point_data.add(std::move(a), role);
    };
    group({"nx", "ny", "nz"}, "Normals", AttributeRole::Normals);

    // Colors: uint8; floating colours are taken as 0..1 and scaled, integers are clamped.
    {
      std::vector<int> ids;
      for (const char* nm : {"red", "green", "blue"}) ids.push_back(vertex_prop(nm));
      if (std::all_of(ids.begin(), ids.end(), [](int id) { return id >= 0; })) {
        if (const int ia = vertex_prop("alpha"); ia >= 0) ids.push_back(ia);
        DataArray c("Colors", ScalarType::UInt8, static_cast<int>(ids.size()), n);
        auto& cv = c.vector<std::uint8_t>();
        for (std::size_t k = 0; k < ids.size(); ++k) {
          const auto id = static_cast<std::size_t>(ids[k]);
          const DataArray& src = vertex_arrays_[id];
          const bool fl = is_floating(src.type());
          for (std::size_t i = 0; i < n; ++i) {
            double v = src.get(i);
            if (fl) v = std::round(v * 255.0);
            if (!(v >= 0)) v = 0;  // also NaN
            if (v > 255) v = 255;
            cv[i * ids.size() + k] = static_cast<std::uint8_t>(v);
          }
          used[id] = true;
        }
        mesh.point_data.add(std::move(c), AttributeRole::Scalars);
      }
    }
    if (vertex_prop("u") >= 0 && vertex_prop("v") >= 0) {
      group({"u", "v"}, "TCoords", AttributeRole::TCoords);
    } else if (vertex_prop("s") >= 0 && vertex_prop("t") >= 0) {
      group({"s", "t"}, "TCoords", AttributeRole::TCoords);
    } else {
      group({"texture_u", "texture_v"}, "TCoords", AttributeRole::TCoords);
    }
    for (std::size_t k = 0; k < vertex_props_.size(); ++k) {
      if (!used[k]) mesh.point_data.add(std::move(vertex_arrays_[k]));
    }

    mesh.polys = std::move(polys_);
    for (std::size_t k = 0; k < face_props_.size(); ++k) {
      if (static_cast<int>(k) != face_index_prop_ && !face_props_[k].is_list) {
        mesh.cell_data.add(std::move(face_arrays_[k]));
      }
    }
    if (face_texcoord_prop_ >= 0 && mesh.point_data.tcoords() == nullptr) {
      split_corner_texcoords(mesh);
    }
    return mesh;
  }

  static constexpr std::size_t kValueWindow = std::size_t{1} << 16;  // records a summary window

  Scanner sc_;
  PlyFormat format_ = PlyFormat::Ascii;
  Endian endian_ = Endian::Little;
  std::vector<PlyElement> elements_;

  bool have_vertex_ = false;
  std::size_t num_vertices_ = 0;
  std::vector<PlyProperty> vertex_props_;
  std::vector<DataArray> vertex_arrays_;
  std::vector<PlyProperty> face_props_;
  std::vector<DataArray> face_arrays_;
  int face_index_prop_ = -1;
  int face_texcoord_prop_ = -1;    // the face element's corner texture coordinates, or -1
  std::vector<double> corner_uv_;  // u, v per corner of polys_, in order
  CellArray polys_;
};

// ---------------------------------------------------------------------------------------------
// Writer

std::string_view ply_type_name(ScalarType t) {
  switch (t) {
    case ScalarType::Int8:
      return "char";
    case ScalarType::UInt8:
      return "uchar";
    case ScalarType::Int16:
      return "short";
    case ScalarType::UInt16:
      return "ushort";
    case ScalarType::Int32:
      return "int";
    case ScalarType::UInt32:
      return "uint";
    case ScalarType::Float32:
      return "float";
    default:
      return "double";  // Float64; 64-bit integers are written as double
  }
}

ScalarType ply_output_type(ScalarType t) {
  if (t == ScalarType::Int64 || t == ScalarType::UInt64) return ScalarType::Float64;
  return t;
}

/// One written property: component `comp` of `array`, named `name`, written as `type`.
struct OutProp {
  const DataArray* array = nullptr;
  int comp = 0;
  std::string name;
  ScalarType type = ScalarType::Float32;
};

class PlyOut {
 public:
  PlyOut(PlyEncoding enc) : enc_(enc) {}

  template <class T>
  void put(T v) {
    if (enc_ == PlyEncoding::Ascii) {
      if (!first_) buf_ += ' ';
      first_ = false;
      char tmp[64];
      auto r = std::to_chars(tmp, tmp + sizeof(tmp), v);
      buf_.append(tmp, r.ptr);
      return;
    }
    if ((enc_ == PlyEncoding::BinaryBigEndian) != (io_detail::kHostEndian == Endian::Big)) {
      v = io_detail::byteswap_value(v);
    }
    char tmp[sizeof(T)];
    std::memcpy(tmp, &v, sizeof(T));
    buf_.append(tmp, sizeof(T));
  }
  void put_as(ScalarType t, double v) {
    visit_scalar_type(t, [&](auto tag) {
      using T = decltype(tag);
      put(static_cast<T>(v));
    });
  }
  void end_record() {
    if (enc_ == PlyEncoding::Ascii) buf_ += '\n';
    first_ = true;
  }
  std::string& buffer() { return buf_; }

 private:
  PlyEncoding enc_;
  std::string buf_;
  bool first_ = true;
};

/// `v` as a binary value of type `t` at `at` (bytes swapped if `swap`); the byte after it.
std::byte* encode_binary(ScalarType t, double v, std::byte* at, bool swap) {
  visit_scalar_type(t, [&](auto tag) {
    using T = decltype(tag);
    T x = static_cast<T>(v);
    if (swap) x = io_detail::byteswap_value(x);
    std::memcpy(at, &x, sizeof x);
  });
  return at + scalar_size(t);
}

std::string sanitize(std::string name) {
  for (char& c : name) {
    if (Scanner::is_space(c)) c = '_';
  }
  return name;
}

}  // namespace

PolyData read_ply(std::span<const std::byte> data, std::string_view name) {
  PlyReader reader(data, name);
  return reader.read();
}

namespace io_detail {

namespace {

// The streamed summary, or, when the file is not one it streams (or is bad: the reader then
// says what is wrong, at the right record), the summary of the file read whole from the same
// source.
DatasetSummary summarize_source(const FileSource& src, std::string_view name, Progress* p,
                                std::uint64_t base) {
  DatasetSummary s;
  try {
    if (PlyReader(src, name, p, base).summarize(s)) return s;
  } catch (const Error&) {
  }
  return isoforge::summarize(PlyReader(src, name, p, base).read());
}

}  // namespace

DatasetSummary summarize_ply(std::span<const std::byte> data, std::string_view name) {
  return summarize_source(data, name, nullptr, 0);
}

DatasetSummary summarize_ply(const std::filesystem::path& path, const ProgressCallback& progress) {
  return read_with_progress(path, progress,
                            [&](const FileSource& src, Progress* p, std::uint64_t base) {
                              return summarize_source(src, path.string(), p, base);
                            });
}

}  // namespace io_detail

PolyData read_ply(const std::filesystem::path& path, const ProgressCallback& progress) {
  return io_detail::read_with_progress(
      path, progress, [&](const io_detail::FileSource& src, io_detail::Progress* p,
                          std::uint64_t base) { return PlyReader(src, path.string(), p, base).read(); });
}

void write_ply(const PolyData& mesh, const std::filesystem::path& path,
               const PlyWriteOptions& options) {
  const std::string file = path.string();
  if (!mesh.verts.empty() || !mesh.lines.empty()) {
    throw Error(file + ": PLY holds surfaces (polygons and strips) only; the mesh has " +
                std::to_string(mesh.verts.size()) + " verts and " +
                std::to_string(mesh.lines.size()) + " lines");
  }
  try {
    mesh.validate();
  } catch (const Error& e) {
    throw Error(file + ": cannot write an invalid mesh: " + e.what());
  }
  const std::size_t np = mesh.num_points();
  if (np > std::numeric_limits<std::uint32_t>::max()) {
    throw Error(file + ": " + std::to_string(np) + " points exceed what 32-bit PLY indices hold");
  }

  // ---- vertex properties ----
  std::vector<OutProp> vprops;
  std::set<std::string> used{"x", "y", "z"};
  auto add_prop = [&](std::vector<OutProp>& props, const DataArray* a, int comp, std::string name,
                      ScalarType type, const char* what) {
    if (!used.insert(name).second) {
      throw Error(file + ": " + what + " array '" + a->name() +
                  "' would be written as PLY property '" + name + "', which is already used");
    }
    props.push_back({a, comp, std::move(name), type});
  };
  const DataArray* normals = mesh.point_data.normals();
  if (!normals || normals->components() != 3) {
    normals = mesh.point_data.find("Normals");
    if (normals && normals->components() != 3) normals = nullptr;
  }
  const DataArray* colors = mesh.point_data.find("Colors");
  if (colors && (colors->type() != ScalarType::UInt8 ||
                 (colors->components() != 3 && colors->components() != 4))) {
    colors = nullptr;
  }
  const DataArray* tcoords = mesh.point_data.tcoords();
  if (!tcoords || tcoords->components() != 2) {
    tcoords = mesh.point_data.find("TCoords");
    if (tcoords && tcoords->components() != 2) tcoords = nullptr;
  }
  for (const DataArray& a : mesh.point_data) {
    const ScalarType t = ply_output_type(a.type());
    if (&a == normals) {
      const char* names[3] = {"nx", "ny", "nz"};
      for (int c = 0; c < 3; ++c) add_prop(vprops, &a, c, names[c], t, "point");
    } else if (&a == colors) {
      const char* names[4] = {"red", "green", "blue", "alpha"};
      for (int c = 0; c < a.components(); ++c) add_prop(vprops, &a, c, names[c], t, "point");
    } else if (&a == tcoords) {
      add_prop(vprops, &a, 0, "u", t, "point");
      add_prop(vprops, &a, 1, "v", t, "point");
    } else if (a.components() == 1) {
      add_prop(vprops, &a, 0, sanitize(a.name()), t, "point");
    } else {
      for (int c = 0; c < a.components(); ++c) {
        add_prop(vprops, &a, c, sanitize(a.name()) + "_" + std::to_string(c), t, "point");
      }
    }
  }

  // ---- faces: polys, then strips as triangles (cell data of a strip's triangles: the strip's)
  std::size_t num_faces = mesh.polys.size();
  std::size_t max_face = 0;
  for (std::size_t f = 0; f < mesh.polys.size(); ++f) {
    max_face = std::max(max_face, mesh.polys.cell_size(f));
  }
  for (std::size_t s = 0; s < mesh.strips.size(); ++s) {
    const std::size_t n = mesh.strips.cell_size(s);
    if (n >= 3) {
      num_faces += n - 2;
      max_face = std::max<std::size_t>(max_face, 3);
    }
  }
  const ScalarType count_type = max_face <= 255 ? ScalarType::UInt8 : ScalarType::Int32;
  const ScalarType index_type =
      np <= static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()) ? ScalarType::Int32
                                                                               : ScalarType::UInt32;
  std::vector<OutProp> fprops;
  used = {"vertex_indices"};
  for (const DataArray& a : mesh.cell_data) {
    const ScalarType t = ply_output_type(a.type());
    if (a.components() == 1) {
      add_prop(fprops, &a, 0, sanitize(a.name()), t, "cell");
    } else {
      for (int c = 0; c < a.components(); ++c) {
        add_prop(fprops, &a, c, sanitize(a.name()) + "_" + std::to_string(c), t, "cell");
      }
    }
  }

  // ---- header ----
  const ScalarType pt =
      mesh.points.type() == ScalarType::Float64 ? ScalarType::Float64 : ScalarType::Float32;
  PlyOut out(options.encoding);
  std::string& buf = out.buffer();
  buf += "ply\nformat ";
  buf += options.encoding == PlyEncoding::Ascii             ? "ascii"
         : options.encoding == PlyEncoding::BinaryBigEndian ? "binary_big_endian"
                                                            : "binary_little_endian";
  buf += " 1.0\ncomment written by isoforge\n";
  buf += "element vertex " + std::to_string(np) + "\n";
  for (const char* c : {"x", "y", "z"}) {
    buf += "property " + std::string(ply_type_name(pt)) + " " + c + "\n";
  }
  for (const auto& p : vprops) {
    buf += "property " + std::string(ply_type_name(p.type)) + " " + p.name + "\n";
  }
  buf += "element face " + std::to_string(num_faces) + "\n";
  buf += "property list " + std::string(ply_type_name(count_type)) + " " +
         std::string(ply_type_name(index_type)) + " vertex_indices\n";
  for (const auto& p : fprops) {
    buf += "property " + std::string(ply_type_name(p.type)) + " " + p.name + "\n";
  }
  buf += "end_header\n";

  // ---- body: encoded into a buffer written out every 4 MiB (memory: the buffer, whatever the
  // mesh's size); progress by values ----
  const std::uint64_t vertex_values = 3 + vprops.size(), face_values = 1 + fprops.size();
  io_detail::Progress progress(options.progress,
                               np * vertex_values + mesh.polys.connectivity().size() +
                                   3 * (num_faces - mesh.polys.size()) + num_faces * face_values,
                               "writing");
  AtomicFile file_out(path);
  file_out.reserve(io_detail::payload_bytes(mesh) + buf.size());
  std::ostream& os = file_out.stream();
  constexpr std::size_t kFlush = std::size_t{4} << 20;
  const auto flush = [&](bool always) {
    if (always || buf.size() >= kFlush) {
      os.write(buf.data(), static_cast<std::streamsize>(buf.size()));
      buf.clear();
    }
  };
  const auto face = [&](std::span<const Index> ids, std::size_t row) {
    out.put_as(count_type, static_cast<double>(ids.size()));
    for (Index id : ids) out.put_as(index_type, static_cast<double>(id));
    for (const auto& q : fprops) out.put_as(q.type, q.array->get(row, q.comp));
    out.end_record();
    progress.add(ids.size() + face_values);
    flush(false);
  };
  if (options.encoding == PlyEncoding::Ascii) {
    for (std::size_t i = 0; i < np; ++i) {
      const Vec3 p = mesh.points[i];
      for (int a = 0; a < 3; ++a) out.put_as(pt, p[a]);
      for (const auto& q : vprops) out.put_as(q.type, q.array->get(i, q.comp));
      out.end_record();
      progress.add(vertex_values);
      flush(false);
    }
    for (std::size_t f = 0; f < mesh.polys.size(); ++f) face(mesh.polys.cell(f), f);
  } else {
    // Binary records have known sizes, so vertices and polygons are encoded a slice of about
    // 1 MiB at a time, each record on any thread at its place (a polygon's from the offsets).
    flush(true);
    const bool swap = (options.encoding == PlyEncoding::BinaryBigEndian) !=
                      (io_detail::kHostEndian == Endian::Big);
    constexpr std::size_t kSlice = std::size_t{1} << 20;
    constexpr std::size_t kGrain = std::size_t{1} << 12;
    Buffer<std::byte> slice;
    const auto emit = [&](std::size_t bytes, std::uint64_t values) {
      os.write(reinterpret_cast<const char*>(slice.data()), static_cast<std::streamsize>(bytes));
      progress.add(values);
    };
    std::size_t vrow = 3 * scalar_size(pt);
    for (const auto& q : vprops) vrow += scalar_size(q.type);
    const std::size_t vper = std::max<std::size_t>(1, kSlice / vrow);
    for (std::size_t v0 = 0; v0 < np; v0 += vper) {
      const std::size_t v1 = std::min(np, v0 + vper);
      if (slice.size() < (v1 - v0) * vrow) slice.resize((v1 - v0) * vrow);
      parallel_for_range(v1 - v0, kGrain, [&](std::size_t b, std::size_t e) {
        for (std::size_t i = v0 + b; i < v0 + e; ++i) {
          std::byte* at = slice.data() + (i - v0) * vrow;
          const Vec3 p = mesh.points[i];
          for (int a = 0; a < 3; ++a) at = encode_binary(pt, p[a], at, swap);
          for (const auto& q : vprops)
            at = encode_binary(q.type, q.array->get(i, q.comp), at, swap);
        }
      });
      emit((v1 - v0) * vrow, (v1 - v0) * vertex_values);
    }
    const auto& offsets = mesh.polys.offsets();
    const auto& conn = mesh.polys.connectivity();
    const std::size_t nf = mesh.polys.size(), index_size = scalar_size(index_type);
    std::size_t frow = scalar_size(count_type);
    for (const auto& q : fprops) frow += scalar_size(q.type);
    // Byte position of polygon f, counted from polygon 0 (increasing in f).
    const auto place = [&](std::size_t f) {
      return f * frow + static_cast<std::size_t>(offsets[f]) * index_size;
    };
    for (std::size_t f0 = 0; f0 < nf;) {
      const std::size_t f1 = io_detail::slice_end(f0, nf, kSlice, place);
      const std::size_t bytes = place(f1) - place(f0);
      if (slice.size() < bytes) slice.resize(bytes);
      parallel_for_range(f1 - f0, kGrain, [&](std::size_t b, std::size_t e) {
        for (std::size_t f = f0 + b; f < f0 + e; ++f) {
          std::byte* at = slice.data() + (place(f) - place(f0));
          at =
              encode_binary(count_type, static_cast<double>(offsets[f + 1] - offsets[f]), at, swap);
          for (auto k = offsets[f]; k < offsets[f + 1]; ++k) {
            at = encode_binary(index_type, static_cast<double>(conn[static_cast<std::size_t>(k)]),
                               at, swap);
          }
          for (const auto& q : fprops)
            at = encode_binary(q.type, q.array->get(f, q.comp), at, swap);
        }
      });
      emit(bytes, static_cast<std::uint64_t>(offsets[f1] - offsets[f0]) + (f1 - f0) * face_values);
      f0 = f1;
    }
  }
  for (std::size_t s = 0; s < mesh.strips.size(); ++s) {
    const auto ids = mesh.strips.cell(s);
    for (std::size_t k = 0; k + 2 < ids.size(); ++k) {
      const auto tri = strip_triangle(ids, k);
      face(tri, mesh.polys.size() + s);
    }
  }
  flush(true);
  if (!os) throw Error(file + ": writing failed");
  progress.finish();  // before the commit: a cancel leaves the target unchanged
  file_out.commit();
}

}  // namespace isoforge
