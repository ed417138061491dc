// VTK legacy `.vtk` files: reader and writer for the "Simple Legacy Formats" section of the
// "VTK File Formats" document (Kitware, VTK User's Guide), header versions 1.0 to 5.1, ASCII and
// BINARY (big-endian), datasets STRUCTURED_POINTS, STRUCTURED_GRID, RECTILINEAR_GRID, POLYDATA
// and UNSTRUCTURED_GRID with POINT_DATA / CELL_DATA attributes and FIELD data.
//
// Where the document is silent, this follows what VTK's own vtkDataReader/vtkDataWriter do:
//  * Binary blocks start after the newline that ends their keyword line; the writer puts one
//    newline after each block. Cell lists of versions < 5 and CELL_TYPES are 4-byte ints.
//  * Versions >= 5.0 write cell sections as `KEY nOffsets nConnectivity` + `OFFSETS type` +
//    `CONNECTIVITY type`. The reader takes either layout in any version (it looks for OFFSETS).
//  * `vtkIdType` arrays are 4-byte ints in binary files (VTK writes ids as int); they are read
//    into Int64 arrays.
//  * `long` / `unsigned_long` are read as 8-byte integers (Int64/UInt64): VTK reads them with
//    sizeof(long) of the reading machine, 8 on every LP64 system, and its writer no longer emits
//    them. This writer never does either: Int64/UInt64 are written as vtktypeint64/vtktypeuint64.
//  * `char` and `signed_char` are Int8 (Int8 is written as `char`); `bit` arrays become UInt8
//    arrays of 0/1 (binary bits are packed, most significant bit first).
//  * `string` / `utf8_string` arrays (FIELD data, PEDIGREE_IDS) are skipped: DataArray is numeric.
//  * Only the first SCALARS/COLOR_SCALARS, VECTORS, NORMALS, TEXTURE_COORDINATES and TENSORS of a
//    POINT_DATA/CELL_DATA section becomes the active attribute; later ones are plain arrays.
//  * `LOOKUP_TABLE default` is stored as the empty lookup-table name (DataArray's "default"), and
//    the empty name is written as `default`. Lookup-table names survive only on active scalars.
//  * A `LOOKUP_TABLE name size` data section becomes the field-data array "LookupTable:<name>"
//    (4 float components, rgba in [0, 1]); the writer writes it back as an ordinary FIELD array.
//  * METADATA blocks (VTK 9: COMPONENT_NAMES, INFORMATION) are skipped up to the blank line
//    that ends them.
//  * Array and lookup-table names are %XX-decoded on read and %XX-encoded on write (spaces,
//    control and non-ASCII bytes, '"' and '%'), as VTK does.
//  * RECTILINEAR_GRID becomes a StructuredGrid with explicit points (float32 when all three
//    coordinate arrays are float, else float64). Those points are not in the file, so their
//    number is capped (kMaxSynthesizedPoints, or the file size if larger) to keep a tiny lying
//    file from allocating gigabytes.
//  * The writer keeps array order: active arrays are written with their keyword where they stand
//    and runs of other arrays as FIELD blocks between them, so a read gives back the same
//    Attributes. Arrays active in several roles are written once per role.

#include "isoforge/io/vtk_legacy.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <new>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "detail/file_source.hpp"
#include "detail/scanner.hpp"
#include "detail/summaries.hpp"
#include "isoforge/core/buffer.hpp"
#include "isoforge/core/parallel.hpp"
#include "isoforge/core/summary.hpp"
#include "isoforge/io/atomic_file.hpp"
#include "isoforge/io/io.hpp"

namespace isoforge {

namespace {

using io_detail::Endian;
using io_detail::iequals;
using io_detail::Scanner;

/// Largest number of points a RECTILINEAR_GRID may expand to (unless the file is larger).
constexpr std::size_t kMaxSynthesizedPoints = std::size_t{1} << 24;


std::string str(std::uint64_t v) { return std::to_string(v); }
std::string str(std::int64_t v) { return std::to_string(v); }
std::string str(int v) { return std::to_string(v); }

/// A token or line for an error message: quoted, at most 40 bytes, unprintable bytes as \xNN.
std::string quote_token(std::string_view t) { return io_detail::quoted(t); }

std::string format_double(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return {buf, r.ptr};
}

// ---------------------------------------------------------------------------------------------
// Names

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

/// Decodes VTK's %XX escapes ("my%20array" -> "my array"). A '%' that is not followed by two
/// hex digits is kept as it is.
std::string decode_name(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size()) {
      const int hi = hex_digit(s[i + 1]);
      const int lo = hex_digit(s[i + 2]);
      if (hi >= 0 && lo >= 0) {
        out += static_cast<char>(hi * 16 + lo);
        i += 2;
        continue;
      }
    }
    out += s[i];
  }
  return out;
}

/// Encodes what cannot stand in a whitespace-separated token (and what VTK encodes): bytes up to
/// ' ', from 0x7F up, '"' and '%'.
std::string encode_name(std::string_view s) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (u <= 0x20 || u >= 0x7F || c == '"' || c == '%') {
      out += '%';
      out += kHex[u >> 4];
      out += kHex[u & 0xF];
    } else {
      out += c;
    }
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Data types

/// A legacy data type name: how its values are stored in the file and in memory.
struct LegacyType {
  enum class Kind { Number, Bit, String };
  Kind kind = Kind::Number;
  ScalarType file = ScalarType::Float32;    ///< element type in the file (binary size, parsing)
  ScalarType memory = ScalarType::Float32;  ///< element type of the resulting DataArray
};

std::optional<LegacyType> legacy_type(std::string_view name) {
  using K = LegacyType::Kind;
  using S = ScalarType;
  struct Entry {
    std::string_view name;
    LegacyType type;
  };
  static const Entry kTypes[] = {
      {"bit", {K::Bit, S::UInt8, S::UInt8}},
      {"char", {K::Number, S::Int8, S::Int8}},
      {"signed_char", {K::Number, S::Int8, S::Int8}},
      {"unsigned_char", {K::Number, S::UInt8, S::UInt8}},
      {"short", {K::Number, S::Int16, S::Int16}},
      {"unsigned_short", {K::Number, S::UInt16, S::UInt16}},
      {"int", {K::Number, S::Int32, S::Int32}},
      {"unsigned_int", {K::Number, S::UInt32, S::UInt32}},
      {"long", {K::Number, S::Int64, S::Int64}},
      {"unsigned_long", {K::Number, S::UInt64, S::UInt64}},
      {"vtktypeint64", {K::Number, S::Int64, S::Int64}},
      {"vtktypeuint64", {K::Number, S::UInt64, S::UInt64}},
      {"vtkidtype", {K::Number, S::Int32, S::Int64}},
      {"float", {K::Number, S::Float32, S::Float32}},
      {"double", {K::Number, S::Float64, S::Float64}},
      {"string", {K::String, S::UInt8, S::UInt8}},
      {"utf8_string", {K::String, S::UInt8, S::UInt8}},
  };
  for (const Entry& e : kTypes) {
    if (iequals(name, e.name)) return e.type;
  }
  return std::nullopt;
}

/// The legacy name the writer uses for each element type.
std::string_view legacy_type_name(ScalarType t) {
  switch (t) {
    case ScalarType::Int8: return "char";
    case ScalarType::UInt8: return "unsigned_char";
    case ScalarType::Int16: return "short";
    case ScalarType::UInt16: return "unsigned_short";
    case ScalarType::Int32: return "int";
    case ScalarType::UInt32: return "unsigned_int";
    case ScalarType::Int64: return "vtktypeint64";
    case ScalarType::UInt64: return "vtktypeuint64";
    case ScalarType::Float32: return "float";
    case ScalarType::Float64: return "double";
  }
  return "double";
}


bool same_values(const DataArray& a, const DataArray& b) {
  return a.type() == b.type() && a.components() == b.components() && a.size() == b.size() &&
         (a.size_bytes() == 0 || std::memcmp(a.bytes(), b.bytes(), a.size_bytes()) == 0);
}

bool is_blank(std::string_view line) {
  return std::all_of(line.begin(), line.end(), [](char c) { return Scanner::is_space(c); });
}

// ---------------------------------------------------------------------------------------------
// Reader

/// A place in the file, for error messages: the line (ASCII files) or byte offset (BINARY).
struct Where {
  std::int64_t line = 0;
  std::size_t offset = 0;
};

/// A cell section of polydata, checked against the points once the geometry is complete.
struct CellSection {
  std::string keyword;
  Where where;
  const CellArray* cells = nullptr;
  int min_size = 1;
};

/// A cell section counted as it streamed by (summary mode), not stored: what the summary needs,
/// and where to read it again when a check fails, so that the reader's own code gives the error.
struct StreamedCells {
  std::pair<std::size_t, std::int64_t> mark;  // the scanner before the section's counts
  std::uint64_t cells = 0;
  std::map<std::int64_t, std::uint64_t> by_size;  // cells of each size (polygonal data)
  std::vector<std::uint8_t> sizes;  // each cell's size, 255 for 255 or more (unstructured grids)
  std::int64_t min_id = 0, max_id = -1;  // of its point ids (checked when the points are known)
  bool short_cell = false;               // a cell below the section's minimum size
  /// Whether the reader's checks would fail on it, with `points` points.
  [[nodiscard]] bool suspect(std::size_t points) const {
    return short_cell || min_id < 0 || max_id >= static_cast<std::int64_t>(points);
  }
};

class LegacyReader {
 public:
  LegacyReader(io_detail::FileSource data, std::string_view name,
               io_detail::Progress* progress = nullptr, std::uint64_t progress_base = 0)
      : s_(data, std::string(name)) {
    s_.track(progress, progress_base);
  }

  Dataset read() {
    Dataset ds = read_dataset();
    try {
      validate(ds);
    } catch (const Error& e) {
      fail(e.what());
    }
    return ds;
  }

  /// The summary of the file (`info`): read as by read(), except that the points and the
  /// point, cell and field arrays are streamed through ValueRanges instead of loaded (cells,
  /// coordinates of rectilinear grids, colours and lookup tables are still read).
  DatasetSummary summarize() {
    summary_ = true;
    const Dataset ds = read_dataset();
    DatasetSummary s = isoforge::summarize(ds);
    s.streamed = true;
    if (std::holds_alternative<PolyData>(ds)) {  // (an unstructured grid's types are read)
      s.cells = cells_of(ds);
      for (const auto& [kw, sec] : streamed_cells_) {
        const int k = iequals(kw, "VERTICES")   ? 0
                      : iequals(kw, "LINES")    ? 1
                      : iequals(kw, "POLYGONS") ? 2
                                                : 3;
        for (const auto& [size, count] : sec.by_size) {
          s.cell_types[poly_cell_type(k, static_cast<std::size_t>(size))] += count;
        }
      }
    }
    if (points_) {
      s.points = points_->tuples;
      if (s.points > 0) {
        Bounds b;
        for (int a = 0; a < 3; ++a) {
          b.min[a] = points_->ranges.component(a).first;
          b.max[a] = points_->ranges.component(a).second;
        }
        s.bounds = b;
      }
    }
    // The streamed arrays replace the empty ones the dataset holds in their place (the last
    // of a name wins, as in Attributes).
    auto fill = [&](AttributesSummary& into, Section section) {
      for (ArraySummary& a : streamed_[static_cast<std::size_t>(section)]) {
        if (ArraySummary* old = into.find(a.name)) *old = std::move(a);
      }
    };
    fill(s.point_data, Section::PointData);
    fill(s.cell_data, Section::CellData);
    fill(s.field_data, Section::Field);
    return s;
  }

 private:
  /// Where a streamed array goes (summary mode).
  enum class Section : std::uint8_t { PointData, CellData, Field };

  /// The dataset, unchecked by validate (in summary mode its streamed arrays are empty).
  Dataset read_dataset() {
    read_header();
    const Where w = skip_to_token();
    const std::string_view kw = s_.token();
    if (!iequals(kw, "DATASET")) {
      fail_at(w, kw.empty() ? "unexpected end of file, expected DATASET"
                            : "expected DATASET, found " + quote_token(kw));
    }
    const std::string_view type = s_.require_token("a dataset type after DATASET");
    Dataset ds;
    if (iequals(type, "STRUCTURED_POINTS")) {
      ds = read_structured_points();
    } else if (iequals(type, "STRUCTURED_GRID")) {
      ds = read_structured_grid();
    } else if (iequals(type, "RECTILINEAR_GRID")) {
      ds = read_rectilinear_grid();
    } else if (iequals(type, "POLYDATA")) {
      ds = read_polydata();
    } else if (iequals(type, "UNSTRUCTURED_GRID")) {
      ds = read_unstructured_grid();
    } else {
      fail_at(w, "unknown DATASET type " + quote_token(type) +
                     " (expected STRUCTURED_POINTS, STRUCTURED_GRID, RECTILINEAR_GRID, POLYDATA "
                     "or UNSTRUCTURED_GRID)");
    }
    field_data(ds) = std::move(field_);
    read_attributes(ds);
    return ds;
  }

  /// Where arrays of `section` are streamed to: null unless in summary mode.
  std::vector<ArraySummary>* streamed(Section section) {
    return summary_ ? &streamed_[static_cast<std::size_t>(section)] : nullptr;
  }
  /// The point count of `ds` (in summary mode, of its streamed points).
  std::size_t points_of(DatasetRef ds) const { return points_ ? points_->tuples : num_points(ds); }
  std::size_t points_of(const Points& p) const { return points_ ? points_->tuples : p.size(); }
  /// The cell count of `ds` (in summary mode, with its streamed cell sections).
  std::size_t cells_of(DatasetRef ds) const {
    if (ds.get_if<PolyData>() == nullptr) return num_cells(ds);
    std::size_t n = num_cells(ds);
    for (const auto& [kw, sec] : streamed_cells_) n += static_cast<std::size_t>(sec.cells);
    return n;
  }
  // ---- errors and tokens ----

  [[nodiscard]] Where here() const { return {s_.line(), s_.offset()}; }
  Where skip_to_token() {
    s_.skip_space();
    return here();
  }
  [[noreturn]] void fail_at(const Where& w, const std::string& what) const {
    if (binary_) throw Error(at_byte(s_.name(), w.offset, what));
    throw Error(at_line(s_.name(), w.line, what));
  }
  [[noreturn]] void fail(const std::string& what) const { fail_at(here(), what); }
  [[noreturn]] void unknown_keyword(const Where& w, std::string_view kw, std::string_view where,
                                    std::string_view expected) const {
    fail_at(w, "unknown keyword " + quote_token(kw) + " in " + std::string(where) + " (expected " +
                   std::string(expected) + ")");
  }

  /// A component count token: an integer >= 1.
  int parse_components(std::string_view token, const std::string& what) {
    const auto v = s_.parse<std::int64_t>(token, what);
    if (v < 1 || v > std::numeric_limits<int>::max()) {
      fail(what + " " + str(v) + " is out of range (must be at least 1)");
    }
    return static_cast<int>(v);
  }

  std::size_t values_count(std::size_t tuples, int components, const std::string& what) {
    std::uint64_t n = 0;
    if (io_detail::mul_overflow(tuples, static_cast<std::uint64_t>(components), n) ||
        n > std::numeric_limits<std::size_t>::max() / 8) {
      fail(what + ": " + str(static_cast<std::uint64_t>(tuples)) + " tuples of " +
           str(components) + " components are too many values");
    }
    return static_cast<std::size_t>(n);
  }

  // ---- header ----

  void read_header() {
    constexpr std::string_view kMagic = "# vtk DataFile Version";
    std::string_view line;
    if (!s_.read_line(line)) s_.fail_line("empty file, expected '# vtk DataFile Version x.y'");
    if (!line.starts_with(kMagic)) {
      throw Error(at_line(s_.name(), 1,
                          "not a VTK legacy file: the first line must start with '# vtk "
                          "DataFile Version', found " + quote_token(line)));
    }
    std::string_view version = line.substr(kMagic.size());
    while (!version.empty() && Scanner::is_space(version.front())) version.remove_prefix(1);
    version = version.substr(0, std::min(version.find_first_of(" \t"), version.size()));
    const auto dot = version.find('.');
    int major = 0;
    int minor = 0;
    bool ok = dot != std::string_view::npos;
    if (ok) {
      const char* b = version.data();
      const char* e = version.data() + version.size();
      auto r1 = std::from_chars(b, b + dot, major);
      auto r2 = std::from_chars(b + dot + 1, e, minor);
      ok = r1.ec == std::errc() && r1.ptr == b + dot && r2.ec == std::errc() && r2.ptr == e;
    }
    if (!ok) {
      throw Error(at_line(s_.name(), 1, "cannot read the file version in " + quote_token(line)));
    }
    if (major < 1 || major > 5 || (major == 5 && minor > 1)) {
      throw Error(at_line(s_.name(), 1,
                          "unsupported file version " + std::string(version) +
                              " (this reader handles 1.0 to 5.1)"));
    }
    if (!s_.read_line(line)) s_.fail_line("unexpected end of file, expected the title line");
    // The format keyword may follow blank lines (ironProt.vtk has one).
    const Where w = skip_to_token();
    const std::string_view format = s_.token();
    if (iequals(format, "ASCII")) {
      binary_ = false;
    } else if (iequals(format, "BINARY")) {
      binary_ = true;
      s_.report_byte_offsets(true);
    } else {
      fail_at(w, format.empty() ? "unexpected end of file, expected ASCII or BINARY"
                                : "expected ASCII or BINARY, found " + quote_token(format));
    }
  }

  // ---- values ----

  /// Reads `count` values stored as T: in BINARY files after the rest of the keyword line,
  /// big-endian; in ASCII files as whitespace-separated numbers. Checks the count against the
  /// bytes left before allocating.
  /// `Vec`: std::vector<T>, or Buffer<T> for an array's values (not zero-filled first: the
  /// binary copy lands in memory no one has touched).
  template <class T, class Vec = std::vector<T>>
  Vec read_numbers(std::size_t count, const std::string& what) {
    Vec v;
    if (binary_) {
      s_.skip_line();
      data_offset_ = s_.offset();
      s_.read_array(count, Endian::Big, v, what);
    } else {
      s_.check_count(count, 2, what + " value count");
      v.resize(count);
      s_.parse_tokens<T>(count, v.data(), what + " value");
    }
    return v;
  }

  std::vector<std::uint8_t> read_bits(std::size_t count, const std::string& what) {
    std::vector<std::uint8_t> v;
    if (binary_) {
      s_.skip_line();
      const auto bytes = s_.read_bytes(count / 8 + (count % 8 != 0 ? 1 : 0), what);
      v.resize(count);
      for (std::size_t i = 0; i < count; ++i) {
        const unsigned byte = std::to_integer<unsigned>(bytes[i / 8]);
        v[i] = static_cast<std::uint8_t>((byte >> (7 - i % 8)) & 1u);
      }
    } else {
      s_.check_count(count, 2, what + " value count");
      v.resize(count);
      const std::string item = what + " value";
      for (auto& x : v) x = s_.parse_token<std::int64_t>(item) != 0 ? 1 : 0;
    }
    return v;
  }

  /// Skips a string array: one (encoded) line per value in ASCII files, length-prefixed
  /// values in BINARY files.
  void skip_strings(std::size_t count, const std::string& what) {
    s_.check_count(count, 1, what + " value count");
    s_.skip_line();
    for (std::size_t i = 0; i < count; ++i) {
      if (!binary_) {
        if (s_.at_end()) fail("unexpected end of file in the values of " + what);
        s_.skip_line();
        continue;
      }
      const auto first = std::to_integer<unsigned>(s_.read_bytes(1, what)[0]);
      const std::size_t header = std::size_t{1} << (3 - (first >> 6));  // 1, 2, 4 or 8 bytes
      std::uint64_t len = first;
      for (auto b : s_.read_bytes(header - 1, what)) {
        len = (len << 8) | std::to_integer<unsigned>(b);
      }
      if (header < 8) len &= (std::uint64_t{1} << (8 * header - 2)) - 1;
      if (len > s_.remaining()) {
        s_.fail_byte("truncated: string " + str(static_cast<std::uint64_t>(i)) + " of " + what +
                     " needs " + str(len) + " bytes but only " +
                     str(static_cast<std::uint64_t>(s_.remaining())) + " remain");
      }
      s_.skip(static_cast<std::size_t>(len), what);
    }
  }

  /// Skips a METADATA block (its keyword already read) up to the blank line that ends it.
  void skip_metadata_body() {
    s_.skip_line();
    std::string_view line;
    while (s_.read_line(line)) {
      if (is_blank(line)) break;
    }
  }
  void skip_metadata() {
    if (!iequals(s_.peek_token(), "METADATA")) return;
    (void)s_.token();
    skip_metadata_body();
  }

  /// Hands `tuples` tuples of `components` values stored as `type` to `consume(values, n)` in
  /// pieces of host-order values, as read_numbers would read them, never holding the array.
  template <class Consume>
  void stream_numbers(ScalarType type, std::size_t tuples, int components,
                      const std::string& what, Consume&& consume) {
    const std::size_t elem = scalar_size(type);
    const std::size_t count = values_count(tuples, components, what);
    if (binary_) {
      s_.skip_line();
      data_offset_ = s_.offset();
      io_detail::TupleStream stream(type, components, io_detail::kHostEndian != Endian::Big,
                                    [&](const std::byte* v, std::size_t n) { consume(v, n); });
      s_.stream_values(count, elem, stream, what);
      return;
    }
    s_.check_count(count, 2, what + " value count");
    const auto comps = static_cast<std::size_t>(components);
    const std::size_t piece = std::max<std::size_t>(1, (std::size_t{1} << 16) / comps) * comps;
    visit_scalar_type(type, [&](auto tag) {
      using T = decltype(tag);
      std::vector<T> buffer(std::min(piece, count));
      for (std::size_t done = 0; done < count;) {
        const std::size_t m = std::min(piece, count - done);
        s_.parse_tokens<T>(m, buffer.data(), what + " value");
        consume(buffer.data(), m / comps);
        done += m;
      }
    });
  }

  /// Reads `tuples` x `components` values of the legacy type named `type` (then any METADATA
  /// block after them) into a DataArray called `name`. `what` names the data in errors. With
  /// `stream`, numbers are streamed into a summary appended there and the array is empty.
  DataArray read_array(std::string_view type, std::size_t tuples, int components,
                       std::string name, const std::string& what,
                       std::vector<ArraySummary>* stream = nullptr) {
    const auto lt = legacy_type(type);
    if (!lt) fail("unknown data type " + quote_token(type) + " for " + what);
    if (lt->kind == LegacyType::Kind::String) {
      fail(what + ": string arrays are only supported in FIELD data");
    }
    const std::size_t count = values_count(tuples, components, what);
    DataArray a;
    if (stream != nullptr && lt->kind == LegacyType::Kind::Number) {
      ArraySummary sum{name, lt->memory, components, tuples, ValueRanges(components)};
      stream_numbers(lt->file, tuples, components, what, [&](const void* v, std::size_t n) {
        sum.ranges.add(lt->file, v, n);
      });
      stream->push_back(std::move(sum));
      a = DataArray::uninitialized(std::move(name), lt->memory, components, 0);
    } else if (lt->kind == LegacyType::Kind::Bit) {
      a = DataArray::from_vector(std::move(name), components, read_bits(count, what));
    } else {
      a = visit_scalar_type(lt->file, [&](auto tag) {
        using T = decltype(tag);
        Buffer<T> v = read_numbers<T, Buffer<T>>(count, what);
        if constexpr (std::is_same_v<T, std::int32_t>) {
          if (lt->memory == ScalarType::Int64) {  // vtkIdType: int in the file
            return DataArray::from_buffer(std::move(name), components,
                                          Buffer<std::int64_t>(v.begin(), v.end()));
          }
        }
        return DataArray::from_buffer(std::move(name), components, std::move(v));
      });
    }
    skip_metadata();
    return a;
  }

  /// `count` integers of an integer data type read from the next token, as point ids.
  std::vector<Index> read_index_array(std::size_t count, const std::string& what) {
    const std::string_view type = s_.require_token(what + " data type");
    const auto lt = legacy_type(type);
    if (!lt || lt->kind != LegacyType::Kind::Number || is_floating(lt->memory)) {
      fail(what + " needs an integer data type, found " + quote_token(type));
    }
    const DataArray a = read_array(type, count, 1, "ids", what);
    std::vector<Index> out(count);
    a.visit([&](const auto& v) {
      for (std::size_t i = 0; i < count; ++i) out[i] = static_cast<Index>(v[i]);
    });
    return out;
  }

  // ---- geometry ----

  /// Next geometry keyword, or "" when the geometry ends (end of file, POINT_DATA, CELL_DATA).
  /// Dataset-level FIELD data and stray METADATA blocks are consumed here.
  std::string_view next_geometry_keyword(Where& w) {
    for (;;) {
      w = skip_to_token();
      const std::string_view t = s_.peek_token();
      if (t.empty() || iequals(t, "POINT_DATA") || iequals(t, "CELL_DATA")) return {};
      (void)s_.token();
      if (iequals(t, "FIELD")) {
        read_field(field_, std::nullopt, "dataset FIELD data", Section::Field);
      } else if (iequals(t, "METADATA")) {
        skip_metadata_body();
      } else {
        return t;
      }
    }
  }

  Dims read_dims(const Where& w, std::string_view what) {
    Dims d{};
    for (auto& v : d) v = s_.parse_token<std::int64_t>("DIMENSIONS value");
    try {
      (void)checked_point_count(d, what);
    } catch (const Error& e) {
      fail_at(w, "DIMENSIONS: " + std::string(e.what()));
    }
    return d;
  }

  Vec3 read_vec3(std::string_view kw) {
    const std::string what = std::string(kw) + " value";
    Vec3 v;
    for (int a = 0; a < 3; ++a) v[a] = s_.parse_token<double>(what);
    if (!is_finite(v)) fail(std::string(kw) + " has a non-finite value");
    return v;
  }

  Points read_points(const Where& w) {
    const std::size_t n = s_.parse_count("POINTS count", binary_ ? 3 : 6);
    const std::string_view type = s_.require_token("POINTS data type");
    if (const auto lt = legacy_type(type);
        summary_ && lt && lt->kind == LegacyType::Kind::Number) {
      // Streamed: the count and the bounds, each point checked as below.
      ArraySummary sum{"Points", lt->memory, 3, n, ValueRanges(3)};
      std::uint64_t index = 0;
      stream_numbers(lt->file, n, 3, "POINTS", [&](const void* v, std::size_t count) {
        if (lt->file == ScalarType::Float32 || lt->file == ScalarType::Float64) {
          visit_scalar_type(lt->file, [&](auto tag) {
            using T = decltype(tag);
            const T* x = static_cast<const T*>(v);
            for (std::size_t i = 0; i < count; ++i, x += 3) {
              const Vec3 q{double(x[0]), double(x[1]), double(x[2])};
              if (!is_finite(q)) non_finite_point(w, index + i, q);
            }
          });
        }
        sum.ranges.add(lt->file, v, count);
        index += count;
      });
      skip_metadata();
      points_ = std::move(sum);
      return Points();
    }
    Points p(read_array(type, n, 3, "Points", "POINTS"));  // non-float types become Float64
    const std::size_t bad = p.first_non_finite();
    if (bad < p.size()) non_finite_point(w, bad, p[bad]);
    return p;
  }

  [[noreturn]] void non_finite_point(const Where& w, std::uint64_t i, const Vec3& q) const {
    fail_at(w, "POINTS: point " + str(i) + " has a non-finite coordinate (" + format_double(q.x) +
                   ", " + format_double(q.y) + ", " + format_double(q.z) + ")");
  }

  /// A cell section after its keyword: classic `n size` + `count id id ...` lists, or
  /// `nOffsets nConnectivity` + OFFSETS + CONNECTIVITY arrays (versions >= 5.0).
  CellArray read_cells(const std::string& kw, const Where& w) {
    const std::size_t a = s_.parse_count(kw + " count", binary_ ? 1 : 2);
    const std::size_t b = s_.parse_count(kw + " size", binary_ ? 1 : 2);
    if (iequals(s_.peek_token(), "OFFSETS")) {
      (void)s_.token();
      std::vector<Index> offsets = read_index_array(a, kw + " OFFSETS");
      const Where cw = skip_to_token();
      const std::string_view t = s_.token();
      if (!iequals(t, "CONNECTIVITY")) {
        fail_at(cw, kw + ": expected CONNECTIVITY after the offsets, found " + quote_token(t));
      }
      std::vector<Index> conn = read_index_array(b, kw + " CONNECTIVITY");
      if (offsets.empty()) {
        if (!conn.empty()) fail_at(w, kw + ": connectivity without offsets");
        return {};
      }
      try {
        return CellArray(std::move(offsets), std::move(conn));
      } catch (const Error& e) {
        fail_at(w, kw + ": " + e.what());
      }
    }
    // Classic layout: `a` cells in `b` integers, each cell its point count then its ids.
    if (a > b) {
      fail_at(w, kw + ": " + str(static_cast<std::uint64_t>(a)) + " cells cannot fit in " +
                     str(static_cast<std::uint64_t>(b)) + " values");
    }
    // The values: read at once (binary, or ASCII parsed in parallel), or, after an ASCII
    // problem, token by token again so that the error names the line of the cell at fault.
    std::vector<std::int32_t> raw;
    std::vector<std::int32_t> raw_text;  // (a value beyond int32 goes the token-by-token way)
    const auto start = s_.mark();
    if (binary_) {
      raw = read_numbers<std::int32_t>(b, kw);
    } else {
      s_.check_count(b, 2, kw + " value count");
      raw_text.resize(b);
      try {
        s_.parse_tokens<std::int32_t>(b, raw_text.data(), kw + " value");
      } catch (const Error&) {
        raw_text.clear();  // parsed again below, failing at the bad token
        s_.restore(start);
      }
    }
    const bool buffered = binary_ || raw_text.size() == b;
    try {
      return classic_cells(kw, w, a, b, raw, raw_text, buffered);
    } catch (const Error&) {
      if (binary_ || !buffered) throw;
      s_.restore(start);  // again token by token: the same error, at its line
      return classic_cells(kw, w, a, b, raw, {}, false);
    }
  }

  /// A cell section after its keyword, as read_cells reads it. In summary mode it is streamed
  /// instead (stream_cells) and an empty array returned; a section the stream finds malformed
  /// is read again by read_cells, which gives the reader's error. Its ids are checked when the
  /// reader checks them, against the final point count (check_cells).
  CellArray read_cell_section(const std::string& kw, const Where& w, int min_size,
                              bool keep_sizes) {
    if (!summary_) return read_cells(kw, w);
    StreamedCells sec;
    sec.mark = s_.mark();
    try {
      stream_cells(kw, sec, min_size, keep_sizes);
    } catch (const Cancelled&) {
      throw;
    } catch (const Error&) {
      s_.restore(sec.mark);
      streamed_cells_.erase(kw);
      return read_cells(kw, w);
    }
    streamed_cells_.insert_or_assign(kw, std::move(sec));
    return {};
  }

  /// Streams a cell section (the layouts of read_cells) without storing it: counts its cells
  /// by size, keeps the range of its point ids and whether a cell is below `min_size`. Throws a
  /// bare Error on anything read_cells rejects (read_cell_section then lets read_cells say why).
  void stream_cells(const std::string& kw, StreamedCells& sec, int min_size, bool keep_sizes) {
    const std::size_t a = s_.parse_count(kw + " count", binary_ ? 1 : 2);
    const std::size_t b = s_.parse_count(kw + " size", binary_ ? 1 : 2);
    std::int64_t last_size = -1;
    std::uint64_t* last_count = nullptr;
    auto add_cell = [&](std::int64_t size) {
      ++sec.cells;
      if (size < min_size) sec.short_cell = true;
      if (keep_sizes) {
        sec.sizes.push_back(static_cast<std::uint8_t>(std::min<std::int64_t>(size, 255)));
      } else {
        if (size != last_size) {
          last_size = size;
          last_count = &sec.by_size[size];
        }
        ++*last_count;
      }
    };
    auto check_ids = [&](const auto* v, std::size_t m) {
      std::int64_t lo = sec.min_id, hi = sec.max_id;
      for (std::size_t i = 0; i < m; ++i) {
        const auto id = static_cast<std::int64_t>(v[i]);
        lo = std::min(lo, id);
        hi = std::max(hi, id);
      }
      sec.min_id = lo;
      sec.max_id = hi;
    };
    const Error malformed("");
    if (iequals(s_.peek_token(), "OFFSETS")) {
      (void)s_.token();
      // Offsets: 0 first, never decreasing, b last; the cells' sizes are their differences.
      std::int64_t prev = -1;
      std::size_t seen = 0;
      stream_index_array(a, kw + " OFFSETS", [&](const auto* v, std::size_t m) {
        for (std::size_t i = 0; i < m; ++i, ++seen) {
          const auto o = static_cast<std::int64_t>(v[i]);
          if (seen == 0 ? o != 0 : o < prev) throw malformed;
          if (seen > 0) add_cell(o - prev);
          prev = o;
        }
      });
      (void)skip_to_token();
      if (!iequals(s_.token(), "CONNECTIVITY")) throw malformed;
      stream_index_array(b, kw + " CONNECTIVITY", check_ids);
      if (a == 0 ? b != 0 : prev != static_cast<std::int64_t>(b)) throw malformed;
      return;
    }
    // Classic layout: a count, then that many ids, `a` times in `b` values.
    if (a > b) throw malformed;
    std::size_t pos = 0, cells = 0;
    std::int64_t left = 0;  // ids left in the current cell; 0: a count comes next
    stream_numbers(ScalarType::Int32, b, 1, kw, [&](const void* values, std::size_t m) {
      const auto* v = static_cast<const std::int32_t*>(values);
      for (std::size_t i = 0; i < m;) {
        if (left == 0) {
          const std::int64_t k = v[i++];
          ++pos;
          if (cells == a || k < 0 || static_cast<std::uint64_t>(k) > b - pos) throw malformed;
          ++cells;
          add_cell(k);
          left = k;
          continue;
        }
        const std::size_t take = std::min<std::size_t>(m - i, static_cast<std::size_t>(left));
        check_ids(v + i, take);
        i += take;
        pos += take;
        left -= static_cast<std::int64_t>(take);
      }
    });
    if (cells != a) throw malformed;
  }

  /// Streams `count` values of an integer legacy type (the type token next) to
  /// `consume(const T* values, std::size_t n)`, as read_index_array reads them.
  template <class Consume>
  void stream_index_array(std::size_t count, const std::string& what, Consume&& consume) {
    const std::string_view type = s_.require_token(what + " data type");
    const auto lt = legacy_type(type);
    if (!lt || lt->kind != LegacyType::Kind::Number || is_floating(lt->memory)) {
      throw Error("");
    }
    visit_scalar_type(lt->file, [&](auto tag) {
      using T = decltype(tag);
      stream_numbers(lt->file, count, 1, what,
                     [&](const void* v, std::size_t n) { consume(static_cast<const T*>(v), n); });
    });
    skip_metadata();
  }

  /// The cells of a section streamed by read_cell_section, read again (for the checks' errors);
  /// the scanner is left where it was.
  CellArray reread_cells(const std::string& kw, const Where& w, const StreamedCells& sec) {
    const auto back = s_.mark();
    s_.restore(sec.mark);
    CellArray cells = read_cells(kw, w);
    s_.restore(back);
    return cells;
  }

  /// The classic cell lists (see read_cells) from `raw` (binary), `raw_text` (ASCII, parsed)
  /// or, when not `buffered`, token by token from the scanner.
  CellArray classic_cells(const std::string& kw, const Where& w, std::size_t a, std::size_t b,
                          const std::vector<std::int32_t>& raw,
                          const std::vector<std::int32_t>& raw_text, bool buffered) {
    std::size_t pos = 0;
    const std::string item = kw + " value";
    auto next = [&]() -> std::int64_t {
      if (binary_) return raw[pos++];
      if (buffered) return raw_text[pos++];
      ++pos;
      return s_.parse_token<std::int64_t>(item);
    };
    auto fail_cell = [&](const std::string& what) {
      if (binary_) fail_at({0, data_offset_ + 4 * (pos - 1)}, what);
      fail(what);
    };
    // Offsets and ids go straight into the cell list's arrays: `b` values hold `a` counts and
    // b - a ids when they add up (a <= b is checked by the caller).
    Buffer<Index> offsets(a + 1), conn(b - a);
    offsets[0] = 0;
    std::size_t at = 0;  // ids so far
    for (std::size_t c = 0; c < a; ++c) {
      auto cell = [&] { return kw + ": cell " + str(static_cast<std::uint64_t>(c)); };
      if (pos == b) {
        fail_at(w, cell() + " starts after the declared size " +
                       str(static_cast<std::uint64_t>(b)) + " is used up (" +
                       str(static_cast<std::uint64_t>(a)) + " cells declared)");
      }
      const std::int64_t k = next();
      if (k < 0) fail_cell(cell() + " has a negative point count " + str(k));
      if (static_cast<std::uint64_t>(k) > b - pos) {
        fail_cell(cell() + " has " + str(k) + " points, more than the " +
                  str(static_cast<std::uint64_t>(b - pos)) + " values left of the declared size " +
                  str(static_cast<std::uint64_t>(b)));
      }
      const auto n = static_cast<std::size_t>(k);
      // More ids than b - a: the cells after this one will find no values left for their
      // counts, and fail below; until then the ids still have a place.
      if (at + n > conn.size()) conn.resize(at + n);
      if (binary_ || buffered) {
        const std::int32_t* v = (binary_ ? raw : raw_text).data() + pos;
        std::copy(v, v + n, conn.data() + at);
        pos += n;
      } else {
        for (std::size_t i = 0; i < n; ++i) conn[at + i] = next();
      }
      at += n;
      offsets[c + 1] = static_cast<Index>(at);
    }
    if (pos != b) {
      fail_at(w, kw + " declares " + str(static_cast<std::uint64_t>(b)) + " values but its " +
                     str(static_cast<std::uint64_t>(a)) + " cells hold " +
                     str(static_cast<std::uint64_t>(pos)));
    }
    // Adopted as built (offsets from 0, non-decreasing, ending at b - a = the ids' count; ids
    // are checked against the points later, in check_cells).
    CellArray cells;
    cells.offsets() = std::move(offsets);
    cells.connectivity() = std::move(conn);
    return cells;
  }

  /// Checks ids against the point count and the minimum cell size, naming the section. A
  /// streamed section was checked as it went by; when it is suspect, its cells are read again
  /// and checked here, so that the error is the reader's.
  void check_cells(const CellSection& sec, std::size_t num_points) {
    if (const auto it = streamed_cells_.find(sec.keyword);
        it != streamed_cells_.end() && sec.cells->size() == 0) {
      if (!it->second.suspect(num_points)) return;
      const CellArray cells = reread_cells(sec.keyword, sec.where, it->second);
      check_cells({sec.keyword, sec.where, &cells, sec.min_size}, num_points);
      return;
    }
    try {
      sec.cells->validate(num_points, sec.keyword.c_str());
    } catch (const Error& e) {
      fail_at(sec.where, e.what());
    }
    for (std::size_t c = 0; c < sec.cells->size(); ++c) {
      if (sec.cells->cell_size(c) < static_cast<std::size_t>(sec.min_size)) {
        fail_at(sec.where, sec.keyword + ": cell " + str(static_cast<std::uint64_t>(c)) +
                               " has " + str(static_cast<std::uint64_t>(sec.cells->cell_size(c))) +
                               " points, needs at least " + str(sec.min_size));
      }
    }
  }

  ImageData read_structured_points() {
    ImageData img;
    bool have_dims = false;
    Where w;
    for (std::string_view kw; !(kw = next_geometry_keyword(w)).empty();) {
      if (iequals(kw, "DIMENSIONS")) {
        img.dims = read_dims(w, "image data");
        have_dims = true;
      } else if (iequals(kw, "SPACING") || iequals(kw, "ASPECT_RATIO")) {
        img.spacing = read_vec3(kw);
      } else if (iequals(kw, "ORIGIN")) {
        img.origin = read_vec3(kw);
      } else {
        unknown_keyword(w, kw, "STRUCTURED_POINTS",
                        "DIMENSIONS, SPACING, ASPECT_RATIO, ORIGIN, FIELD or POINT_DATA");
      }
    }
    if (!have_dims) fail("STRUCTURED_POINTS has no DIMENSIONS");
    return img;
  }

  StructuredGrid read_structured_grid() {
    StructuredGrid sg;
    bool have_dims = false;
    std::optional<Where> points_at;
    Where w;
    for (std::string_view kw; !(kw = next_geometry_keyword(w)).empty();) {
      if (iequals(kw, "DIMENSIONS")) {
        sg.dims = read_dims(w, "structured grid");
        have_dims = true;
      } else if (iequals(kw, "POINTS")) {
        sg.points = read_points(w);
        points_at = w;
      } else {
        unknown_keyword(w, kw, "STRUCTURED_GRID", "DIMENSIONS, POINTS, FIELD or POINT_DATA");
      }
    }
    if (!have_dims) fail("STRUCTURED_GRID has no DIMENSIONS");
    if (!points_at) fail("STRUCTURED_GRID has no POINTS");
    const std::size_t np = checked_point_count(sg.dims, "structured grid");
    if (points_of(sg.points) != np) {
      fail_at(*points_at, "POINTS has " + str(static_cast<std::uint64_t>(points_of(sg.points))) +
                              " points but DIMENSIONS " + str(sg.dims[0]) + " " +
                              str(sg.dims[1]) + " " + str(sg.dims[2]) + " needs " +
                              str(static_cast<std::uint64_t>(np)));
    }
    return sg;
  }

  StructuredGrid read_rectilinear_grid() {
    static constexpr std::string_view kAxes[3] = {"X_COORDINATES", "Y_COORDINATES",
                                                  "Z_COORDINATES"};
    Dims dims{};
    bool have_dims = false;
    std::array<std::optional<DataArray>, 3> coords;
    std::array<Where, 3> coords_at{};
    Where w;
    for (std::string_view kw; !(kw = next_geometry_keyword(w)).empty();) {
      if (iequals(kw, "DIMENSIONS")) {
        dims = read_dims(w, "rectilinear grid");
        have_dims = true;
        continue;
      }
      int axis = -1;
      for (int a = 0; a < 3; ++a) {
        if (iequals(kw, kAxes[a])) axis = a;
      }
      if (axis < 0) {
        unknown_keyword(w, kw, "RECTILINEAR_GRID",
                        "DIMENSIONS, X_COORDINATES, Y_COORDINATES, Z_COORDINATES, FIELD or "
                        "POINT_DATA");
      }
      const std::string name(kAxes[axis]);
      const std::size_t n = s_.parse_count(name + " count", binary_ ? 1 : 2);
      const std::string_view type = s_.require_token(name + " data type");
      DataArray a = read_array(type, n, 1, name, name);
      for (std::size_t i = 0; i < n; ++i) {
        if (!std::isfinite(a.get(i))) {
          fail_at(w, name + ": value " + str(static_cast<std::uint64_t>(i)) + " is not finite");
        }
      }
      coords[static_cast<std::size_t>(axis)] = std::move(a);
      coords_at[static_cast<std::size_t>(axis)] = w;
    }
    if (!have_dims) fail("RECTILINEAR_GRID has no DIMENSIONS");
    bool all_float = true;
    for (std::size_t a = 0; a < 3; ++a) {
      if (!coords[a]) fail("RECTILINEAR_GRID has no " + std::string(kAxes[a]));
      if (coords[a]->tuples() != static_cast<std::size_t>(dims[a])) {
        fail_at(coords_at[a], std::string(kAxes[a]) + " has " +
                                  str(static_cast<std::uint64_t>(coords[a]->tuples())) +
                                  " values but DIMENSIONS says " + str(dims[a]));
      }
      all_float = all_float && coords[a]->type() == ScalarType::Float32;
    }
    const std::size_t np = checked_point_count(dims, "rectilinear grid");
    const std::size_t limit = std::max(kMaxSynthesizedPoints, s_.size());
    if (np > limit) {
      fail("RECTILINEAR_GRID with " + str(static_cast<std::uint64_t>(np)) +
           " points is too large to expand into explicit points (limit " +
           str(static_cast<std::uint64_t>(limit)) + ")");
    }
    StructuredGrid sg;
    sg.dims = dims;
    sg.points = Points(np, all_float ? ScalarType::Float32 : ScalarType::Float64);
    std::size_t id = 0;
    for (Index k = 0; k < dims[2]; ++k) {
      for (Index j = 0; j < dims[1]; ++j) {
        for (Index i = 0; i < dims[0]; ++i) {
          sg.points.set(id++, {coords[0]->get(static_cast<std::size_t>(i)),
                               coords[1]->get(static_cast<std::size_t>(j)),
                               coords[2]->get(static_cast<std::size_t>(k))});
        }
      }
    }
    return sg;
  }

  PolyData read_polydata() {
    PolyData pd;
    std::vector<CellSection> sections;
    Where w;
    for (std::string_view kw; !(kw = next_geometry_keyword(w)).empty();) {
      CellArray* cells = nullptr;
      int min_size = 1;
      if (iequals(kw, "POINTS")) {
        pd.points = read_points(w);
        continue;
      }
      if (iequals(kw, "VERTICES")) {
        cells = &pd.verts;
      } else if (iequals(kw, "LINES")) {
        cells = &pd.lines;
        min_size = 2;
      } else if (iequals(kw, "POLYGONS")) {
        cells = &pd.polys;
        min_size = 3;
      } else if (iequals(kw, "TRIANGLE_STRIPS")) {
        cells = &pd.strips;
        min_size = 3;
      } else {
        unknown_keyword(w, kw, "POLYDATA",
                        "POINTS, VERTICES, LINES, POLYGONS, TRIANGLE_STRIPS, FIELD, POINT_DATA or "
                        "CELL_DATA");
      }
      std::string name(kw);
      *cells = read_cell_section(name, w, min_size, false);
      sections.push_back({std::move(name), w, cells, min_size});
    }
    for (const CellSection& sec : sections) check_cells(sec, points_of(pd.points));
    return pd;
  }

  std::vector<CellType> read_cell_types(const Where& w) {
    const std::size_t n = s_.parse_count("CELL_TYPES count", binary_ ? 4 : 2);
    const std::vector<std::int32_t> ids = read_numbers<std::int32_t>(n, "CELL_TYPES");
    std::vector<CellType> types(n);
    for (std::size_t i = 0; i < n; ++i) {
      if (!is_valid_cell_type(ids[i])) {
        const std::string what = "CELL_TYPES: cell " + str(static_cast<std::uint64_t>(i)) +
                                 " has cell type " + str(ids[i]) +
                                 ", which is not a supported linear cell type (1 to 14)";
        if (binary_) fail_at({0, data_offset_ + 4 * i}, what);
        fail_at(w, what);
      }
      types[i] = static_cast<CellType>(ids[i]);
    }
    return types;
  }

  UnstructuredGrid read_unstructured_grid() {
    UnstructuredGrid ug;
    std::optional<Where> cells_at;
    std::optional<Where> types_at;
    Where w;
    for (std::string_view kw; !(kw = next_geometry_keyword(w)).empty();) {
      if (iequals(kw, "POINTS")) {
        ug.points = read_points(w);
      } else if (iequals(kw, "CELLS")) {
        ug.cells = read_cell_section("CELLS", w, 0, true);
        cells_at = w;
      } else if (iequals(kw, "CELL_TYPES")) {
        ug.types = read_cell_types(w);
        types_at = w;
      } else {
        unknown_keyword(w, kw, "UNSTRUCTURED_GRID",
                        "POINTS, CELLS, CELL_TYPES, FIELD, POINT_DATA or CELL_DATA");
      }
    }
    if (cells_at) check_cells({"CELLS", *cells_at, &ug.cells, 0}, points_of(ug.points));
    const auto streamed = streamed_cells_.find("CELLS");
    const StreamedCells* sec = streamed != streamed_cells_.end() ? &streamed->second : nullptr;
    const std::size_t nc = sec ? static_cast<std::size_t>(sec->cells) : ug.cells.size();
    if (ug.types.size() != nc) {
      fail_at(types_at ? *types_at : (cells_at ? *cells_at : here()),
              "CELL_TYPES lists " + str(static_cast<std::uint64_t>(ug.types.size())) +
                  " types but CELLS has " + str(static_cast<std::uint64_t>(nc)) + " cells");
    }
    // Each cell's size fits its type (a streamed section's sizes saturate at 255, more than any
    // fixed size; on a mismatch its cells are read again for the message).
    auto check_types = [&](const auto& size_of) {
      for (std::size_t c = 0; c < ug.types.size(); ++c) {
        const CellType t = ug.types[c];
        const int fixed = cell_fixed_size(t);
        const auto n = static_cast<std::int64_t>(size_of(c));
        if ((fixed > 0 && n != fixed) || n < cell_min_size(t)) return c;
      }
      return ug.types.size();
    };
    auto fail_type = [&](std::size_t c, std::int64_t n) {
      const CellType t = ug.types[c];
      const int fixed = cell_fixed_size(t);
      fail_at(*types_at, "cell " + str(static_cast<std::uint64_t>(c)) + " is a " +
                             std::string(cell_type_name(t)) + " with " + str(n) +
                             " points (needs " +
                             (fixed > 0 ? str(fixed) : "at least " + str(cell_min_size(t))) + ")");
    };
    if (sec) {
      if (check_types([&](std::size_t c) { return sec->sizes[c]; }) != ug.types.size()) {
        const CellArray cells = reread_cells("CELLS", *cells_at, *sec);
        const std::size_t c = check_types([&](std::size_t i) { return cells.cell_size(i); });
        if (c != ug.types.size()) fail_type(c, static_cast<std::int64_t>(cells.cell_size(c)));
      }
    } else if (const std::size_t c =
                   check_types([&](std::size_t i) { return ug.cells.cell_size(i); });
               c != ug.types.size()) {
      fail_type(c, static_cast<std::int64_t>(ug.cells.cell_size(c)));
    }
    return ug;
  }

  // ---- attributes ----

  /// FIELD name n, then n arrays `name components tuples type` + values; "NULL_ARRAY" stands
  /// for a missing array. `tuples` is the required tuple count (none for dataset field data).
  void read_field(Attributes& dst, std::optional<std::size_t> tuples, const std::string& where,
                  Section into) {
    (void)s_.require_token("FIELD name");
    const std::size_t n = s_.parse_count("FIELD array count", 1);
    for (std::size_t i = 0; i < n; ++i) {
      const Where w = skip_to_token();
      const std::string_view raw = s_.require_token("FIELD array name");
      if (raw == "NULL_ARRAY") continue;
      std::string name = decode_name(raw);
      const std::string what = "FIELD array " + quote_token(name);
      const int comps = parse_components(s_.require_token(what + " component count"),
                                         what + " component count");
      const std::size_t nt = s_.parse_count(what + " tuple count", 0);
      const std::string_view type = s_.require_token(what + " data type");
      if (tuples && nt != *tuples) {
        fail_at(w, what + " has " + str(static_cast<std::uint64_t>(nt)) + " tuples but " +
                       where + " declares " + str(static_cast<std::uint64_t>(*tuples)));
      }
      const auto lt = legacy_type(type);
      if (lt && lt->kind == LegacyType::Kind::String) {
        skip_strings(values_count(nt, comps, what), what);
        skip_metadata();
        continue;
      }
      dst.add(read_array(type, nt, comps, std::move(name), what, streamed(into)));
    }
  }

  /// Adds an attribute array: active for `role` if that role is still free in this section
  /// (VTK's rule: the first one wins), else a plain array.
  static void add_attribute(Attributes& attrs, DataArray a, AttributeRole role) {
    if (!attrs.active_name(role).empty()) {
      attrs.add(std::move(a));
      return;
    }
    // The writer repeats an array active in several roles once per role.
    if (const DataArray* existing = attrs.find(a.name()); existing && same_values(*existing, a)) {
      attrs.set_active(role, a.name());
      return;
    }
    attrs.add(std::move(a), role);
  }

  void read_attributes(Dataset& ds) {
    const std::size_t np = points_of(ds);
    const std::size_t nc = cells_of(ds);
    Attributes* attrs = nullptr;
    std::size_t tuples = 0;
    std::string section;
    for (;;) {
      const Where w = skip_to_token();
      const std::string_view kw = s_.token();
      if (kw.empty()) return;
      if (iequals(kw, "POINT_DATA") || iequals(kw, "CELL_DATA")) {
        const bool points = iequals(kw, "POINT_DATA");
        section = points ? "POINT_DATA" : "CELL_DATA";
        const auto n = s_.parse_token<std::int64_t>(section + " count");
        if (n < 0) fail_at(w, section + " count " + str(n) + " is negative");
        const std::size_t want = points ? np : nc;
        if (static_cast<std::uint64_t>(n) != want) {
          fail_at(w, section + " " + str(n) + " does not match the " +
                         str(static_cast<std::uint64_t>(want)) +
                         (points ? " points" : " cells") + " of the dataset");
        }
        attrs = points ? &point_data(ds) : &cell_data(ds);
        tuples = want;
        continue;
      }
      if (attrs == nullptr) {
        fail_at(w, "unexpected keyword " + quote_token(kw) + " (expected POINT_DATA or CELL_DATA)");
      }
      read_attribute(kw, w, *attrs, tuples, section, field_data(ds),
                     section == "POINT_DATA" ? Section::PointData : Section::CellData);
    }
  }

  void read_attribute(std::string_view kw, const Where& w, Attributes& attrs, std::size_t n,
                      const std::string& section, Attributes& field, Section into) {
    const std::string key(kw);
    std::vector<ArraySummary>* const stream = streamed(into);
    auto read_name = [&]() { return decode_name(s_.require_token(key + " name")); };
    // `KEY name type` + values with a fixed component count.
    auto read_fixed = [&](int comps, std::optional<AttributeRole> role) {
      std::string name = read_name();
      const std::string_view type = s_.require_token(key + " data type");
      DataArray a = read_array(type, n, comps, name, key + " " + quote_token(name), stream);
      if (role) {
        add_attribute(attrs, std::move(a), *role);
      } else {
        attrs.add(std::move(a));
      }
    };
    if (iequals(kw, "SCALARS")) {
      std::string name = read_name();
      const std::string what = "SCALARS " + quote_token(name);
      const std::string_view type = s_.require_token(what + " data type");
      std::string_view next = s_.require_token("LOOKUP_TABLE after " + what);
      int comps = 1;
      if (!iequals(next, "LOOKUP_TABLE")) {
        comps = parse_components(next, what + " component count");
        next = s_.require_token("LOOKUP_TABLE after " + what);
      }
      if (!iequals(next, "LOOKUP_TABLE")) {
        fail(what + " must be followed by LOOKUP_TABLE, found " + quote_token(next));
      }
      std::string lut = decode_name(s_.require_token("lookup table name"));
      DataArray a = read_array(type, n, comps, name, what, stream);
      if (lut != "default") a.set_lookup_table(std::move(lut));
      add_attribute(attrs, std::move(a), AttributeRole::Scalars);
    } else if (iequals(kw, "COLOR_SCALARS")) {
      std::string name = read_name();
      const std::string what = "COLOR_SCALARS " + quote_token(name);
      const int comps =
          parse_components(s_.require_token(what + " component count"), what + " component count");
      const std::size_t count = values_count(n, comps, what);
      std::vector<std::uint8_t> v;
      if (binary_) {
        v = read_numbers<std::uint8_t>(count, what);
      } else {  // floats in [0, 1]
        const std::vector<float> f = read_numbers<float>(count, what);
        v.resize(count);
        for (std::size_t i = 0; i < count; ++i) {
          const double x = 255.0 * static_cast<double>(f[i]) + 0.5;
          v[i] = !(x > 0.0) ? 0 : (x >= 255.0 ? 255 : static_cast<std::uint8_t>(x));
        }
      }
      skip_metadata();
      add_attribute(attrs, DataArray::from_vector(std::move(name), comps, std::move(v)),
                    AttributeRole::Scalars);
    } else if (iequals(kw, "LOOKUP_TABLE")) {
      const std::string name = read_name();
      const std::string what = "LOOKUP_TABLE " + quote_token(name);
      const std::size_t size = s_.parse_count(what + " size", binary_ ? 4 : 8);
      std::vector<float> rgba;
      if (binary_) {
        const std::vector<std::uint8_t> bytes = read_numbers<std::uint8_t>(4 * size, what);
        rgba.resize(bytes.size());
        for (std::size_t i = 0; i < bytes.size(); ++i) {
          rgba[i] = static_cast<float>(bytes[i]) / 255.0f;
        }
      } else {
        rgba = read_numbers<float>(4 * size, what);
      }
      skip_metadata();
      field.add(DataArray::from_vector("LookupTable:" + name, 4, std::move(rgba)));
    } else if (iequals(kw, "VECTORS")) {
      read_fixed(3, AttributeRole::Vectors);
    } else if (iequals(kw, "NORMALS")) {
      read_fixed(3, AttributeRole::Normals);
    } else if (iequals(kw, "TENSORS")) {
      read_fixed(9, AttributeRole::Tensors);
    } else if (iequals(kw, "TENSORS6")) {
      read_fixed(6, AttributeRole::Tensors);
    } else if (iequals(kw, "TEXTURE_COORDINATES")) {
      std::string name = read_name();
      const std::string what = "TEXTURE_COORDINATES " + quote_token(name);
      const std::string_view dim_token = s_.require_token(what + " dimension");
      const int dim = parse_components(dim_token, what + " dimension");
      if (dim > 3) fail(what + " dimension " + str(dim) + " is not 1, 2 or 3");
      const std::string_view type = s_.require_token(what + " data type");
      add_attribute(attrs, read_array(type, n, dim, name, what, stream), AttributeRole::TCoords);
    } else if (iequals(kw, "GLOBAL_IDS") || iequals(kw, "EDGE_FLAGS")) {
      read_fixed(1, std::nullopt);
    } else if (iequals(kw, "PEDIGREE_IDS")) {
      std::string name = read_name();
      const std::string what = key + " " + quote_token(name);
      const std::string_view type = s_.require_token(what + " data type");
      const auto lt = legacy_type(type);
      if (lt && lt->kind == LegacyType::Kind::String) {
        skip_strings(n, what);
        skip_metadata();
      } else {
        attrs.add(read_array(type, n, 1, name, what, stream));
      }
    } else if (iequals(kw, "FIELD")) {
      read_field(attrs, n, section, into);
    } else if (iequals(kw, "METADATA")) {
      skip_metadata_body();
    } else {
      unknown_keyword(w, kw, section,
                      "SCALARS, COLOR_SCALARS, LOOKUP_TABLE, VECTORS, NORMALS, "
                      "TEXTURE_COORDINATES, TENSORS, TENSORS6, FIELD, POINT_DATA or CELL_DATA");
    }
  }

  Scanner s_;
  bool binary_ = false;
  std::size_t data_offset_ = 0;  ///< start of the last binary block read
  Attributes field_;             ///< dataset-level FIELD data, read with the geometry
  // Summary mode (summarize): the streamed points and arrays, by section.
  bool summary_ = false;
  std::optional<ArraySummary> points_;
  std::array<std::vector<ArraySummary>, 3> streamed_;
  std::map<std::string, StreamedCells, std::less<>> streamed_cells_;  // by section keyword
};

// ---------------------------------------------------------------------------------------------
// Writer

/// Active roles of the array called `name`, in keyword order.
std::vector<AttributeRole> roles_of(const Attributes& attrs, const std::string& name) {
  std::vector<AttributeRole> roles;
  for (std::size_t r = 0; r < kAttributeRoleCount; ++r) {
    const auto role = static_cast<AttributeRole>(r);
    if (attrs.active_name(role) == name) roles.push_back(role);
  }
  return roles;
}

/// Throws (naming `target`) for everything the legacy format cannot hold, before any byte is
/// written.
void check_writable(DatasetRef ds, const VtkLegacyWriteOptions& options,
                    const std::string& target) {
  auto fail = [&](const std::string& what) { throw Error(target + ": " + what); };
  if (options.version != "4.2" && options.version != "5.1") {
    fail("VTK legacy version must be \"4.2\" or \"5.1\", not " + quote_token(options.version));
  }
  try {
    validate(ds);
  } catch (const Error& e) {
    fail("cannot write invalid " + std::string(dataset_type_name(ds)) + ": " + e.what());
  }
  const Points* pts =
      ds.visit(Overloaded{[](const ImageData&) -> const Points* { return nullptr; },
                            [](const auto& d) -> const Points* { return &d.points; }});
  if (pts != nullptr) {
    const std::size_t bad = pts->first_non_finite();
    if (bad < pts->size()) {
      fail("point " + str(static_cast<std::uint64_t>(bad)) +
           " has a non-finite coordinate, which VTK legacy readers reject");
    }
    if (options.version == "4.2" &&
        pts->size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
      fail("version 4.2 cell lists store point ids as 32-bit ints; write version 5.1 for " +
           str(static_cast<std::uint64_t>(pts->size())) + " points");
    }
  }
  for (const Attributes* attrs : {&point_data(ds), &cell_data(ds)}) {
    for (std::size_t r = 0; r < kAttributeRoleCount; ++r) {
      const auto role = static_cast<AttributeRole>(r);
      const DataArray* a = attrs->active(role);
      if (a == nullptr) continue;
      const int c = a->components();
      const bool three = role == AttributeRole::Vectors || role == AttributeRole::Normals;
      const bool ok = role == AttributeRole::Scalars || (three && c == 3) ||
                      (role == AttributeRole::Tensors && (c == 9 || c == 6)) ||
                      (role == AttributeRole::TCoords && c >= 1 && c <= 3);
      if (!ok) {
        fail("active " + std::string(attribute_role_name(role)) + " " + quote_token(a->name()) +
             " has " + str(c) + " components, which VTK legacy " +
             std::string(attribute_role_name(role)) + " cannot hold (" +
             (role == AttributeRole::Tensors    ? "9 or 6"
              : role == AttributeRole::TCoords ? "1 to 3"
                                                : "3") +
             "); clear the role to write it as a FIELD array");
      }
    }
  }
}

class LegacyWriter {
 public:
  LegacyWriter(std::ostream& out, const VtkLegacyWriteOptions& options)
      : out_(out), binary_(options.binary), v5_(options.version == "5.1"),
        callback_(options.progress) {
    std::string title = options.title;
    std::replace(title.begin(), title.end(), '\n', ' ');
    std::replace(title.begin(), title.end(), '\r', ' ');
    buf_ = "# vtk DataFile Version " + options.version + "\n" + title + "\n" +
           (binary_ ? "BINARY\n" : "ASCII\n");
  }

  void write(DatasetRef ds) {
    // Progress by values written (the buffer is flushed to the stream every megabyte).
    progress_ = io_detail::Progress(callback_, io_detail::payload_values(ds), "writing");
    ds.visit([&](const auto& d) { write_geometry(d); });
    write_attributes(cell_data(ds), "CELL_DATA", num_cells(ds));
    write_attributes(point_data(ds), "POINT_DATA", num_points(ds));
    flush();
    progress_.finish();
  }

 private:
  void flush() {
    out_.write(buf_.data(), static_cast<std::streamsize>(buf_.size()));
    buf_.clear();
  }
  void maybe_flush() {
    if (buf_.size() >= (std::size_t{1} << 20)) flush();
  }
  void text(std::string_view s) { buf_ += s; }

  template <class T>
  void number(T v) {
    char tmp[64];
    const auto r = std::to_chars(tmp, tmp + sizeof tmp, v);  // shortest round-trip for floats
    buf_.append(tmp, r.ptr);
  }
  static constexpr std::size_t kSliceBytes = std::size_t{1} << 20;

  /// Values as ASCII (nine per line) or big-endian binary, then a newline.
  template <class T>
  void values(std::span<const T> v) {
    if (binary_) {
      binary_values(std::as_bytes(v), sizeof(T));
      buf_ += '\n';
      return;
    }
    for (std::size_t i = 0; i < v.size(); ++i) {
      number(v[i]);
      buf_ += (i % 9 == 8 || i + 1 == v.size()) ? '\n' : ' ';
      if (i % 4096 == 4095) {
        maybe_flush();
        progress_.add(4096);
      }
    }
    progress_.add(v.size() % 4096);
    if (v.empty()) buf_ += '\n';
  }

  /// Big-endian values: written straight from the array where no bytes are swapped, else a
  /// 1 MiB slice at a time (progress after each), copied and swapped on all threads into a
  /// buffer kept for the file.
  void binary_values(std::span<const std::byte> bytes, std::size_t elem) {
    flush();
    const bool swap = elem > 1 && io_detail::kHostEndian != Endian::Big;
    const std::size_t per = std::max<std::size_t>(1, kSliceBytes / elem) * elem;
    for (std::size_t at = 0; at < bytes.size(); at += per) {
      const std::size_t m = std::min(per, bytes.size() - at);
      const std::byte* out = bytes.data() + at;
      if (swap) {
        if (slice_.size() < m) slice_.resize(per);
        io_detail::copy_swapped(out, slice_.data(), m / elem, elem);
        out = slice_.data();
      }
      out_.write(reinterpret_cast<const char*>(out), static_cast<std::streamsize>(m));
      progress_.add(m / elem);
    }
  }
  void values(const DataArray& a) {
    a.visit([&](const auto& v) { values(std::span(v.data(), v.size())); });
  }

  void header_line(std::string_view key, const DataArray& a, std::string_view extra = {}) {
    text(key);
    text(" ");
    text(encode_name(a.name()));
    text(" ");
    text(extra);
    text(legacy_type_name(a.type()));
    text("\n");
  }

  void write_field(const std::vector<const DataArray*>& arrays) {
    if (arrays.empty()) return;
    text("FIELD FieldData " + str(static_cast<std::uint64_t>(arrays.size())) + "\n");
    for (const DataArray* a : arrays) {
      text(encode_name(a->name()) + " " + str(a->components()) + " " +
           str(static_cast<std::uint64_t>(a->tuples())) + " ");
      text(legacy_type_name(a->type()));
      text("\n");
      values(*a);
    }
  }
  void write_dataset_field(const Attributes& field) {
    std::vector<const DataArray*> arrays;
    for (const DataArray& a : field) arrays.push_back(&a);
    write_field(arrays);
  }

  void write_points(const Points& p) {
    text("POINTS " + str(static_cast<std::uint64_t>(p.size())) + " ");
    text(legacy_type_name(p.type()));
    text("\n");
    values(p.array());
  }

  void write_dims(const Dims& d) {
    text("DIMENSIONS " + str(d[0]) + " " + str(d[1]) + " " + str(d[2]) + "\n");
  }
  void write_vec3(std::string_view key, const Vec3& v) {
    text(key);
    for (int a = 0; a < 3; ++a) {
      text(" ");
      number(v[a]);
    }
    text("\n");
  }

  void write_cells(std::string_view key, const CellArray& cells) {
    const auto& offsets = cells.offsets();
    const auto& conn = cells.connectivity();
    const std::size_t n = cells.size();
    if (v5_) {
      text(std::string(key) + " " + str(static_cast<std::uint64_t>(n + 1)) + " " +
           str(static_cast<std::uint64_t>(conn.size())) + "\nOFFSETS vtktypeint64\n");
      values(std::span(offsets.data(), offsets.size()));
      text("CONNECTIVITY vtktypeint64\n");
      values(std::span(conn.data(), conn.size()));
      return;
    }
    text(std::string(key) + " " + str(static_cast<std::uint64_t>(n)) + " " +
         str(static_cast<std::uint64_t>(n + conn.size())) + "\n");
    if (binary_) {
      binary_cells(cells);
      buf_ += '\n';
      return;
    }
    for (std::size_t c = 0; c < n; ++c) {
      const auto ids = cells.cell(c);
      number(ids.size());
      for (Index id : ids) {
        buf_ += ' ';
        number(id);
      }
      buf_ += '\n';
      progress_.add(ids.size() + 1);
      if (c % 1024 == 1023) maybe_flush();
    }
  }

  /// The 4.2 layout's cells, binary: each cell's size then its ids, big-endian Int32 (the
  /// writer checked that they fit), a slice of about 1 MiB of cells at a time (at least one
  /// cell), filled on all threads.
  void binary_cells(const CellArray& cells) {
    flush();
    const auto& offsets = cells.offsets();
    const auto& conn = cells.connectivity();
    const std::size_t n = cells.size();
    const auto word = [&](std::size_t c) { return static_cast<std::size_t>(offsets[c]) + c; };
    const std::size_t per = kSliceBytes / sizeof(std::int32_t);
    for (std::size_t c0 = 0; c0 < n;) {
      const std::size_t c1 = io_detail::slice_end(c0, n, per, word);
      const std::size_t words = word(c1) - word(c0);
      if (slice_.size() < words * sizeof(std::int32_t)) slice_.resize(words * sizeof(std::int32_t));
      std::byte* out = slice_.data();
      const auto put = [out](std::size_t at, Index v) {
        auto x = static_cast<std::uint32_t>(static_cast<std::int32_t>(v));
        if (io_detail::kHostEndian != Endian::Big) x = io_detail::byteswap_value(x);
        std::memcpy(out + at * sizeof x, &x, sizeof x);
      };
      parallel_for_range(c1 - c0, std::size_t{1} << 12, [&](std::size_t b, std::size_t e) {
        for (std::size_t c = c0 + b; c < c0 + e; ++c) {
          std::size_t at = word(c) - word(c0);
          put(at++, offsets[c + 1] - offsets[c]);
          for (auto k = offsets[c]; k < offsets[c + 1]; ++k)
            put(at++, conn[static_cast<std::size_t>(k)]);
        }
      });
      out_.write(reinterpret_cast<const char*>(out), static_cast<std::streamsize>(words * 4));
      progress_.add(words);
      c0 = c1;
    }
  }

  void write_geometry(const ImageData& img) {
    text("DATASET STRUCTURED_POINTS\n");
    write_dataset_field(img.field_data);
    write_dims(img.dims);
    write_vec3("SPACING", img.spacing);
    write_vec3("ORIGIN", img.origin);
  }
  void write_geometry(const StructuredGrid& sg) {
    text("DATASET STRUCTURED_GRID\n");
    write_dataset_field(sg.field_data);
    write_dims(sg.dims);
    write_points(sg.points);
  }
  void write_geometry(const PolyData& pd) {
    text("DATASET POLYDATA\n");
    write_dataset_field(pd.field_data);
    write_points(pd.points);
    if (!pd.verts.empty()) write_cells("VERTICES", pd.verts);
    if (!pd.lines.empty()) write_cells("LINES", pd.lines);
    if (!pd.polys.empty()) write_cells("POLYGONS", pd.polys);
    if (!pd.strips.empty()) write_cells("TRIANGLE_STRIPS", pd.strips);
  }
  void write_geometry(const UnstructuredGrid& ug) {
    text("DATASET UNSTRUCTURED_GRID\n");
    write_dataset_field(ug.field_data);
    write_points(ug.points);
    if (ug.cells.empty()) return;
    write_cells("CELLS", ug.cells);
    text("CELL_TYPES " + str(static_cast<std::uint64_t>(ug.types.size())) + "\n");
    std::vector<std::int32_t> types(ug.types.size());
    for (std::size_t i = 0; i < types.size(); ++i) {
      types[i] = static_cast<std::int32_t>(ug.types[i]);
    }
    values(std::span<const std::int32_t>(types));
  }

  void write_attribute(const DataArray& a, AttributeRole role) {
    switch (role) {
      case AttributeRole::Scalars: {
        text("SCALARS " + encode_name(a.name()) + " ");
        text(legacy_type_name(a.type()));
        if (a.components() != 1) text(" " + str(a.components()));
        text("\nLOOKUP_TABLE " +
             (a.lookup_table().empty() ? std::string("default") : encode_name(a.lookup_table())) +
             "\n");
        break;
      }
      case AttributeRole::Vectors: header_line("VECTORS", a); break;
      case AttributeRole::Normals: header_line("NORMALS", a); break;
      case AttributeRole::Tensors:
        header_line(a.components() == 6 ? "TENSORS6" : "TENSORS", a);
        break;
      case AttributeRole::TCoords:
        header_line("TEXTURE_COORDINATES", a, str(a.components()) + " ");
        break;
    }
    values(a);
  }

  /// Arrays in their order: active ones with their keywords, runs of the others as FIELD blocks.
  void write_attributes(const Attributes& attrs, std::string_view section, std::size_t n) {
    if (attrs.empty()) return;
    text(std::string(section) + " " + str(static_cast<std::uint64_t>(n)) + "\n");
    std::vector<const DataArray*> plain;
    for (const DataArray& a : attrs) {
      const std::vector<AttributeRole> roles = roles_of(attrs, a.name());
      if (roles.empty()) {
        plain.push_back(&a);
        continue;
      }
      write_field(plain);
      plain.clear();
      for (AttributeRole role : roles) write_attribute(a, role);
    }
    write_field(plain);
  }

  std::ostream& out_;
  bool binary_;
  bool v5_;
  const ProgressCallback& callback_;
  io_detail::Progress progress_;
  std::string buf_;
  Buffer<std::byte> slice_;  // binary values, swapped
};

}  // namespace

namespace {

// `work` on a reader of `data`; anything it throws but an Error becomes one naming the file.
template <class Work>
auto with_reader(const io_detail::FileSource& data, std::string_view name,
                 io_detail::Progress* progress, std::uint64_t progress_base, Work work) {
  try {
    LegacyReader reader(data, name, progress, progress_base);
    return work(reader);
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw Error(std::string(name) + ": out of memory while reading");
  } catch (const std::exception& e) {
    throw Error(std::string(name) + ": internal error while reading: " + e.what());
  }
}

Dataset read_legacy(const io_detail::FileSource& data, std::string_view name,
                    io_detail::Progress* progress, std::uint64_t progress_base) {
  return with_reader(data, name, progress, progress_base, [](LegacyReader& r) { return r.read(); });
}

DatasetSummary summarize_legacy(const io_detail::FileSource& data, std::string_view name,
                                io_detail::Progress* progress, std::uint64_t progress_base) {
  return with_reader(data, name, progress, progress_base,
                     [](LegacyReader& r) { return r.summarize(); });
}

}  // namespace

Dataset read_vtk_legacy(const std::filesystem::path& path, const ProgressCallback& progress) {
  return io_detail::read_with_progress(
      path, progress, [&](const io_detail::FileSource& src, io_detail::Progress* p,
                          std::uint64_t base) { return read_legacy(src, path.string(), p, base); });
}

Dataset read_vtk_legacy(std::span<const std::byte> data, std::string_view name) {
  return read_legacy(data, name, nullptr, 0);
}

namespace io_detail {

DatasetSummary summarize_vtk_legacy(const std::filesystem::path& path,
                                    const ProgressCallback& progress) {
  return read_with_progress(path, progress,
                            [&](const FileSource& src, Progress* p, std::uint64_t base) {
                              return summarize_legacy(src, path.string(), p, base);
                            });
}

DatasetSummary summarize_vtk_legacy(std::span<const std::byte> data, std::string_view name) {
  return summarize_legacy(data, name, nullptr, 0);
}

}  // namespace io_detail

void write_vtk_legacy(DatasetRef ds, const std::filesystem::path& path,
                      const VtkLegacyWriteOptions& options) {
  check_writable(ds, options, path.string());
  AtomicFile file(path);
  file.reserve(io_detail::payload_bytes(ds) + (std::uint64_t{1} << 16));
  LegacyWriter(file.stream(), options).write(ds);
  file.commit();
}

void write_vtk_legacy(DatasetRef ds, std::ostream& out, const VtkLegacyWriteOptions& options) {
  check_writable(ds, options, "VTK legacy writer");
  LegacyWriter(out, options).write(ds);
  if (!out) throw Error("VTK legacy writer: writing to the stream failed");
}

}  // namespace isoforge
