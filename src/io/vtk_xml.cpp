// VTK XML file formats (.vti .vts .vtp .vtu): reader and writer for the serial XML formats of
// the "VTK File Formats" document ("XML File Formats" section): ImageData, StructuredGrid,
// PolyData and UnstructuredGrid files with ascii, inline base64 ("binary") and appended (raw or
// base64) DataArrays, optional vtkZLibDataCompressor blocks, UInt32/UInt64 headers and either
// byte order.
//
// Reader layout:
//   - the file is split at "<AppendedData": the XML part goes to pugixml (the open root is
//     closed with a synthesized "</VTKFile>"), the binary section after '_' is read here with
//     bounds checks;
//   - every DataArray payload is read through a ByteSource (raw bytes or a base64 stream that
//     tolerates both VTK encodings: header and data as one stream, or each padded on its own);
//   - sizes from headers are checked against what the array needs and what the file can hold
//     before anything is allocated, and a file-wide budget caps the decoded total.
// Writer: builds the XML and the appended block in memory, then writes them to a stream (through
// AtomicFile for paths).

#include "isoforge/io/vtk_xml.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <mutex>
#include <new>
#include <optional>
#include <pugixml.hpp>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

#include "detail/scanner.hpp"
#include "detail/summaries.hpp"
#include "detail/tuple_stream.hpp"
#include "detail/vtk_xml_codecs.hpp"
#include "isoforge/core/parallel.hpp"
#include "isoforge/io/atomic_file.hpp"
#include "isoforge/io/io.hpp"

// This file implements it (relative to the module, as the layering check wants).
#include "detail/vtk_xml_block.hpp"

namespace isoforge {

namespace {

using io_detail::Endian;
using io_detail::kHostEndian;
using io_detail::printable;


using io_detail::BlockCodec;

/// The decoded-size budget of a file: zlib cannot expand data by more than about 1032:1.
constexpr std::uint64_t kZlibMaxRatio = 1032;
/// Uncompressed bytes per compressed block: 256 KiB, 8 times VTK's default, chosen from the
/// measured size curve (docs/algorithms/vtk_xml_io.md, "The block size"); readers take any.
constexpr std::size_t kWriteBlockSize = std::size_t{1} << 18;
/// Decompressed bytes between two progress reports (when progress is asked for): whole blocks,
/// at least two per thread of a 2-core machine.
constexpr std::size_t kProgressBytes = std::size_t{4} << 20;

const char* codec_label(BlockCodec c) {
  return c == BlockCodec::Zlib ? "zlib" : c == BlockCodec::Lz4 ? "LZ4" : "LZMA";
}
/// Structured pieces are checked pairwise for overlap; more pieces than this are refused.
constexpr std::size_t kMaxStructuredPieces = 4096;

std::string num(std::uint64_t v) {
  return std::to_string(v);
}

// ================================================================================================
// Error context
// ================================================================================================

/// A place in the file: the element path ("Piece 0/PointData/DataArray 'Normals'") and a byte
/// offset. Every reader error goes through here, so it names the file, the place and the problem.
struct XmlWhere {
  std::string_view file;
  std::string path;
  std::uint64_t byte = 0;

  [[noreturn]] void fail(std::string_view what) const { fail_at(byte, what); }
  [[noreturn]] void fail_at(std::uint64_t at, std::string_view what) const {
    std::string msg = path.empty() ? std::string(what) : path + ": " + std::string(what);
    throw Error(at_byte(file, at, msg));
  }
  [[nodiscard]] XmlWhere child(pugi::xml_node node, std::string_view label) const {
    XmlWhere w{file, path.empty() ? std::string(label) : path + "/" + std::string(label), byte};
    const std::ptrdiff_t off = node.offset_debug();
    if (off >= 0) w.byte = static_cast<std::uint64_t>(off);
    return w;
  }
};

// ================================================================================================
// Numbers
// ================================================================================================

using io_detail::append_number;
using io_detail::ascii_lower;
using io_detail::trim_space;
constexpr auto is_space = io_detail::is_ascii_space;

using io_detail::parse_number;

std::optional<std::string_view> attr(pugi::xml_node n, const char* name) {
  const pugi::xml_attribute a = n.attribute(name);
  if (!a) return std::nullopt;
  return std::string_view(a.value());
}

/// A required (or defaulted) non-negative integer attribute.
std::uint64_t count_attr(pugi::xml_node n, const char* name, const XmlWhere& w,
                         std::optional<std::uint64_t> fallback = std::nullopt) {
  const auto v = attr(n, name);
  if (!v) {
    if (fallback) return *fallback;
    w.fail(std::string("missing attribute '") + name + "'");
  }
  std::int64_t x = 0;
  if (!parse_number(trim_space(*v), x)) {
    w.fail(std::string("attribute ") + name + "='" + printable(*v) + "' is not an integer");
  }
  if (x < 0) w.fail(std::string("attribute ") + name + "=" + std::to_string(x) + " is negative");
  return static_cast<std::uint64_t>(x);
}

/// Exactly `count` whitespace-separated values of T.
template <class T>
std::vector<T> list_attr(pugi::xml_node n, const char* name, std::size_t count, const XmlWhere& w) {
  const auto v = attr(n, name);
  if (!v) w.fail(std::string("missing attribute '") + name + "'");
  std::vector<T> out;
  std::string_view s = *v;
  while (true) {
    while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
    if (s.empty()) break;
    std::size_t len = 0;
    while (len < s.size() && !is_space(s[len])) ++len;
    T x{};
    if (out.size() == count || !parse_number(s.substr(0, len), x)) {
      w.fail(std::string("attribute ") + name + "='" + printable(*v) + "' is not " +
             std::to_string(count) + " numbers");
    }
    out.push_back(x);
    s.remove_prefix(len);
  }
  if (out.size() != count) {
    w.fail(std::string("attribute ") + name + "='" + printable(*v) + "' is not " +
           std::to_string(count) + " numbers");
  }
  return out;
}

std::optional<ScalarType> scalar_type_named(std::string_view name) {
  static constexpr ScalarType kAll[] = {ScalarType::Int8,   ScalarType::UInt8,  ScalarType::Int16,
                                        ScalarType::UInt16, ScalarType::Int32,  ScalarType::UInt32,
                                        ScalarType::Int64,  ScalarType::UInt64, ScalarType::Float32,
                                        ScalarType::Float64};
  for (ScalarType t : kAll) {
    if (scalar_type_name(t) == name) return t;
  }
  // Names some old writers use.
  if (name == "Char") return ScalarType::Int8;
  if (name == "UnsignedChar") return ScalarType::UInt8;
  return std::nullopt;
}

// ================================================================================================
// Base64
// ================================================================================================

constexpr char kB64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
constexpr std::int8_t kB64Invalid = -1, kB64Space = -2, kB64Pad = -3;

constexpr std::array<std::int8_t, 256> make_b64_table() {
  std::array<std::int8_t, 256> t{};
  for (auto& v : t) v = kB64Invalid;
  for (int i = 0; i < 64; ++i) t[static_cast<unsigned char>(kB64[i])] = static_cast<std::int8_t>(i);
  for (char c : {' ', '\t', '\n', '\r', '\f', '\v'}) t[static_cast<unsigned char>(c)] = kB64Space;
  t[static_cast<unsigned char>('=')] = kB64Pad;
  return t;
}
constexpr std::array<std::int8_t, 256> kB64Table = make_b64_table();

/// Streaming base64 encoder (one padded stream per `finish`).
class Base64Encoder {
 public:
  explicit Base64Encoder(std::string& out) : out_(out) {}
  void put(const std::byte* data, std::size_t n) {
    std::size_t i = 0;
    while (pending_ > 0 && pending_ < 3 && i < n)
      pend_[pending_++] = static_cast<std::uint8_t>(data[i++]);
    if (pending_ == 3) {
      emit(pend_[0], pend_[1], pend_[2], 3);
      pending_ = 0;
    }
    out_.reserve(out_.size() + (n - i) / 3 * 4 + 4);
    for (; i + 3 <= n; i += 3) {
      emit(static_cast<std::uint8_t>(data[i]), static_cast<std::uint8_t>(data[i + 1]),
           static_cast<std::uint8_t>(data[i + 2]), 3);
    }
    for (; i < n; ++i) pend_[pending_++] = static_cast<std::uint8_t>(data[i]);
  }
  void finish() {
    if (pending_ == 1) emit(pend_[0], 0, 0, 1);
    if (pending_ == 2) emit(pend_[0], pend_[1], 0, 2);
    pending_ = 0;
  }

 private:
  void emit(std::uint8_t a, std::uint8_t b, std::uint8_t c, int n) {
    const std::uint32_t v = (std::uint32_t{a} << 16) | (std::uint32_t{b} << 8) | c;
    out_ += kB64[(v >> 18) & 63];
    out_ += kB64[(v >> 12) & 63];
    out_ += n > 1 ? kB64[(v >> 6) & 63] : '=';
    out_ += n > 2 ? kB64[v & 63] : '=';
  }
  std::string& out_;
  std::uint8_t pend_[3] = {0, 0, 0};
  int pending_ = 0;
};

// ================================================================================================
// Byte sources: raw bytes, or base64 text decoded on the fly
// ================================================================================================

/// Sequential, bounds-checked reads from a raw byte span or from base64 text. Base64 groups are
/// decoded independently, so padding in the middle (VTK encodes a compression header and the
/// blocks as separate streams) is handled like one continuous stream.
class ByteSource {
 public:
  /// `file`: the input `data` lies in (copies come from its file, if it has one).
  static ByteSource raw(std::span<const std::byte> data, std::uint64_t file_offset,
                        const io_detail::FileSource& file) {
    ByteSource s;
    s.raw_ = data;
    s.file_ = &file;
    s.base_ = file_offset;
    return s;
  }
  static ByteSource base64(std::string_view text, std::uint64_t file_offset) {
    ByteSource s;
    s.b64_ = true;
    s.text_ = text;
    s.base_ = file_offset;
    return s;
  }

  /// An upper bound of the bytes left.
  [[nodiscard]] std::uint64_t available() const {
    if (!b64_) return raw_.size() - pos_;
    return static_cast<std::uint64_t>(buf_len_ - buf_pos_) + ((text_.size() - pos_) / 4 + 1) * 3;
  }
  [[nodiscard]] std::uint64_t file_pos() const { return base_ + pos_; }
  /// Whether the bytes come straight from the input (not decoded from base64).
  [[nodiscard]] bool is_raw() const { return !b64_; }

  void read(std::byte* dst, std::size_t n, const XmlWhere& w, std::string_view what) {
    if (!b64_) {
      if (n > raw_.size() - pos_) truncated(w, n, what);
      file_->copy(raw_.data() + pos_, dst, n);
      pos_ += n;
      return;
    }
    const std::size_t want = n;
    while (n > 0) {
      if (buf_pos_ < buf_len_) {
        *dst++ = buf_[buf_pos_++];
        --n;
        continue;
      }
      // Fast path: whole groups of four alphabet characters straight into dst.
      while (n >= 3 && pos_ + 4 <= text_.size()) {
        const auto* t = reinterpret_cast<const unsigned char*>(text_.data() + pos_);
        const int a = kB64Table[t[0]], b = kB64Table[t[1]], c = kB64Table[t[2]],
                  d = kB64Table[t[3]];
        if ((a | b | c | d) < 0) break;
        const std::uint32_t v =
            (static_cast<std::uint32_t>(a) << 18) | (static_cast<std::uint32_t>(b) << 12) |
            (static_cast<std::uint32_t>(c) << 6) | static_cast<std::uint32_t>(d);
        dst[0] = static_cast<std::byte>(v >> 16);
        dst[1] = static_cast<std::byte>(v >> 8);
        dst[2] = static_cast<std::byte>(v);
        dst += 3;
        n -= 3;
        pos_ += 4;
      }
      if (n == 0) break;
      if (!next_group(w)) truncated(w, want, what);
    }
  }

  /// `n` bytes as a view (raw: no copy; base64: decoded into a scratch buffer).
  std::span<const std::byte> view(std::size_t n, const XmlWhere& w, std::string_view what) {
    if (n > available()) truncated(w, n, what);
    if (!b64_) {
      auto s = raw_.subspan(pos_, n);
      pos_ += n;
      return s;
    }
    scratch_.resize(n);
    read(scratch_.data(), n, w, what);
    return scratch_;
  }

 private:
  ByteSource() = default;

  [[noreturn]] void truncated(const XmlWhere& w, std::size_t n, std::string_view what) const {
    w.fail_at(file_pos(), "truncated data: " + std::string(what) + " needs " + num(n) +
                              " bytes but the " + (b64_ ? "base64 text" : "appended section") +
                              " ends first");
  }

  /// Decodes the next group of up to four characters into buf_; false at the end of the text.
  bool next_group(const XmlWhere& w) {
    int vals[4] = {0, 0, 0, 0};
    int n = 0, pads = 0;
    while (n < 4 && pos_ < text_.size()) {
      const auto c = static_cast<unsigned char>(text_[pos_]);
      const int v = kB64Table[c];
      if (v == kB64Space) {
        ++pos_;
        continue;
      }
      if (v == kB64Invalid) {
        w.fail_at(file_pos(), "invalid character '" +
                                  printable(std::string(1, static_cast<char>(c))) +
                                  "' in base64 data");
      }
      if (v == kB64Pad) {
        if (n < 2) w.fail_at(file_pos(), "misplaced '=' padding in base64 data");
        ++pads;
      } else if (pads > 0) {
        w.fail_at(file_pos(), "base64 data continues after '=' padding inside a group");
      } else {
        vals[n] = v;
      }
      ++n;
      ++pos_;
    }
    if (n == 0) return false;
    const int significant = n - pads;
    if (significant < 2) w.fail_at(file_pos(), "base64 data ends with a dangling character");
    const std::uint32_t v =
        (static_cast<std::uint32_t>(vals[0]) << 18) | (static_cast<std::uint32_t>(vals[1]) << 12) |
        (static_cast<std::uint32_t>(vals[2]) << 6) | static_cast<std::uint32_t>(vals[3]);
    buf_[0] = static_cast<std::byte>(v >> 16);
    buf_[1] = static_cast<std::byte>(v >> 8);
    buf_[2] = static_cast<std::byte>(v);
    buf_len_ = significant - 1;
    buf_pos_ = 0;
    return true;
  }

  bool b64_ = false;
  std::span<const std::byte> raw_;
  const io_detail::FileSource* file_ = nullptr;
  std::string_view text_;
  std::size_t pos_ = 0;
  std::uint64_t base_ = 0;
  std::byte buf_[3] = {};
  int buf_len_ = 0, buf_pos_ = 0;
  std::vector<std::byte> scratch_;
};

// ================================================================================================
// Reader
// ================================================================================================

enum class Kind { Image, Structured, Poly, Unstructured };

using Extent = std::array<std::int64_t, 6>;

bool extent_empty(const Extent& e) {
  return e[1] < e[0] || e[3] < e[2] || e[5] < e[4];
}
Dims extent_dims(const Extent& e) {
  return {e[1] - e[0] + 1, e[3] - e[2] + 1, e[5] - e[4] + 1};
}

std::string extent_string(const Extent& e) {
  std::string s;
  for (int i = 0; i < 6; ++i) s += (i ? " " : "") + std::to_string(e[i]);
  return s;
}

/// What a DataArray must look like where it is read.
// The attributes of <PointData>/<CellData> naming the active array of each role.
constexpr std::pair<const char*, AttributeRole> kRoles[] = {{"Scalars", AttributeRole::Scalars},
                                                            {"Vectors", AttributeRole::Vectors},
                                                            {"Normals", AttributeRole::Normals},
                                                            {"Tensors", AttributeRole::Tensors},
                                                            {"TCoords", AttributeRole::TCoords}};
// The cell sections of a PolyData piece and the attributes counting their cells.
constexpr const char* kCat[4] = {"Verts", "Lines", "Polys", "Strips"};
constexpr const char* kCount[4] = {"NumberOfVerts", "NumberOfLines", "NumberOfPolys",
                                   "NumberOfStrips"};

/// The points of a piece's extent (dimensions `d`); an Error through `w` if they overflow.
std::size_t extent_points(const Dims& d, const XmlWhere& w) {
  try {
    return checked_point_count(d, "Extent");
  } catch (const Error& e) {
    w.fail(e.what());
  }
}

/// Where the `index`th DataArray `a` of an attributes element is, for messages.
XmlWhere array_where(const XmlWhere& w, pugi::xml_node a, std::size_t index) {
  const auto name = attr(a, "Name");
  return w.child(a, name ? "DataArray '" + printable(*name, 80) + "'" : "DataArray " + num(index));
}

/// The roles an attributes element names (a role naming a skipped String/Bit array or an absent
/// one is then ignored, as VTK does).
std::vector<std::pair<AttributeRole, std::string_view>> named_roles(pugi::xml_node el) {
  std::vector<std::pair<AttributeRole, std::string_view>> out;
  for (const auto& [key, role] : kRoles) {
    const auto v = attr(el, key);
    if (v && !v->empty()) out.emplace_back(role, *v);
  }
  return out;
}

struct ArrayHeader {
  ScalarType type;
  std::string_view type_name;
  std::string name;
  int components;
  std::optional<std::uint64_t> values, bytes;  // when the tuple count is known
  std::size_t unit;                            // bytes per tuple
  std::string_view format;                     // ascii, binary or appended
};

struct ArrayRequest {
  std::optional<std::uint64_t> tuples;  ///< required tuple count (nullopt: any)
  int components = 0;                   ///< required components (0: any)
  bool skippable = true;                ///< String/Bit arrays are skipped (else an error)
};

struct StructuredPiece {
  Extent ext{};
  Attributes pd, cd;
  std::optional<DataArray> points;
  XmlWhere where;
};

struct PolyPiece {
  Points points;
  std::array<CellArray, 4> cells;  // verts, lines, polys, strips
  Attributes pd, cd;
  XmlWhere where;
};

struct UnstructuredPiece {
  Points points;
  CellArray cells;
  std::vector<CellType> types;
  Attributes pd, cd;
  XmlWhere where;
};

/// Drops the pieces that hold no point and no cell (parallel writers emit them, often without the
/// arrays of the others), as VTK's readers do; the first piece stays when all are empty.
template <class Piece, class Empty>
void drop_empty_pieces(std::vector<Piece>& pieces, Empty empty) {
  if (pieces.size() < 2) return;
  std::vector<Piece> kept;
  for (Piece& p : pieces) {
    if (!empty(p)) kept.push_back(std::move(p));
  }
  if (kept.empty()) kept.push_back(std::move(pieces.front()));
  pieces = std::move(kept);
}

/// Appends tuples [first, first + count) of src to dst (same type and components).
void append_tuples(DataArray& dst, const DataArray& src, std::size_t first, std::size_t count) {
  dst.visit([&](auto& v) {
    using T = typename std::decay_t<decltype(v)>::value_type;
    const auto s = src.values<T>();
    const auto c = static_cast<std::size_t>(src.components());
    v.insert(v.end(), s.begin() + static_cast<std::ptrdiff_t>(first * c),
             s.begin() + static_cast<std::ptrdiff_t>((first + count) * c));
  });
}

/// Copies a box of tuples `sub` (sizes along i, j, k) from src into the box starting at `at`
/// of dst, whose full sizes are `full`.
void copy_box(const DataArray& src, const std::array<std::size_t, 3>& sub, DataArray& dst,
              const std::array<std::size_t, 3>& full, const std::array<std::size_t, 3>& at) {
  const std::size_t tb = static_cast<std::size_t>(src.components()) * scalar_size(src.type());
  const std::byte* s = src.bytes();
  std::byte* d = dst.bytes();
  for (std::size_t k = 0; k < sub[2]; ++k) {
    for (std::size_t j = 0; j < sub[1]; ++j) {
      const std::size_t so = (j + sub[1] * k) * sub[0] * tb;
      const std::size_t dof = (at[0] + full[0] * ((at[1] + j) + full[1] * (at[2] + k))) * tb;
      std::memcpy(d + dof, s + so, sub[0] * tb);
    }
  }
}

/// As copy_box, for one-byte tuples, ANDing src into dst.
void and_box(const DataArray& src, const std::array<std::size_t, 3>& sub, DataArray& dst,
             const std::array<std::size_t, 3>& full, const std::array<std::size_t, 3>& at) {
  const std::byte* s = src.bytes();
  std::byte* d = dst.bytes();
  for (std::size_t k = 0; k < sub[2]; ++k) {
    for (std::size_t j = 0; j < sub[1]; ++j) {
      const std::byte* row = s + (j + sub[1] * k) * sub[0];
      std::byte* out = d + at[0] + full[0] * ((at[1] + j) + full[1] * (at[2] + k));
      for (std::size_t i = 0; i < sub[0]; ++i) out[i] &= row[i];
    }
  }
}

/// Where Reader::read_payload puts the bytes it decodes: the whole payload in one buffer
/// (`alloc(n)` gives it) ...
template <class Alloc>
struct WholeTarget {
  static constexpr std::uint64_t kMaxPiece = std::numeric_limits<std::uint64_t>::max();
  explicit WholeTarget(Alloc a) : alloc(std::move(a)) {}
  void start(std::uint64_t n) { base = alloc(n); }
  std::byte* piece(std::uint64_t offset, std::size_t /*n*/) { return base + offset; }
  void done(std::size_t /*n*/) {}
  Alloc alloc;
  std::byte* base = nullptr;
};

/// ... or a piece at a time through a TupleStream (summaries: memory for one piece).
struct StreamTarget {
  static constexpr std::uint64_t kMaxPiece = io_detail::TupleStream::kPiece;
  void start(std::uint64_t /*n*/) {}
  std::byte* piece(std::uint64_t /*offset*/, std::size_t n) { return stream.window(n); }
  void done(std::size_t n) { stream.filled(n); }
  io_detail::TupleStream& stream;
};

class Reader {
 public:
  Reader(io_detail::FileSource source, std::string_view name,
         io_detail::Progress* progress = nullptr, std::uint64_t progress_base = 0)
      : source_(source), data_(source.bytes), name_(name), progress_(progress), progress_base_(progress_base) {
    // Every decoded byte must come from somewhere: a legitimate file never decodes to more
    // than zlib's maximum expansion of the whole file.
    budget_ = static_cast<std::uint64_t>(data_.size()) * (kZlibMaxRatio + 8) + (1u << 20);
  }

  Dataset read();
  /// What the file holds, in one streaming pass (no array is loaded whole except ascii ones,
  /// no connectivity is read).
  DatasetSummary summarize();
  struct Opened {
    Kind kind;
    pugi::xml_node ds;
    XmlWhere where;
  };
  /// Parses the XML and the root's attributes: the dataset element and its kind.
  Opened open();
  /// One payload on its own (io/detail/vtk_xml_block.hpp): the whole input is the payload.
  std::vector<std::byte> decode_block(const io_detail::VtkXmlBlockFormat& format,
                                      std::optional<std::uint64_t> expected, std::size_t unit);

 private:
  [[nodiscard]] XmlWhere root_where(std::string path = "VTKFile") const {
    return XmlWhere{name_, std::move(path), 0};
  }

  void split_appended();
  /// Progress: the data up to byte `file_pos` of the file is decoded (one comparison when no
  /// report is due).
  void tick(std::uint64_t file_pos) {
    if (progress_) progress_->set(progress_base_ + file_pos);
  }
  /// LZMA reaches far higher ratios than zlib: the budget grows with its bound.
  [[nodiscard]] std::uint64_t lzma_budget() const {
    return static_cast<std::uint64_t>(data_.size()) *
               (io_detail::block_codec_max_ratio(BlockCodec::Lzma) + 8) +
           (1u << 20);
  }
  void charge(std::uint64_t bytes, const XmlWhere& w) {
    if (bytes > budget_) {
      w.fail("arrays decode to more data than the file can hold (" + num(bytes) +
             " more bytes); overlapping offsets or lying sizes");
    }
    budget_ -= bytes;
  }

  std::uint64_t read_word(ByteSource& s, const XmlWhere& w, std::string_view what) {
    std::byte b[8];
    const std::size_t n = header64_ ? 8 : 4;
    s.read(b, n, w, what);
    if (endian_ != kHostEndian) std::reverse(b, b + n);
    if (n == 8) {
      std::uint64_t v;
      std::memcpy(&v, b, 8);
      return v;
    }
    std::uint32_t v;
    std::memcpy(&v, b, 4);
    return v;
  }

  template <class Target>
  void read_payload(ByteSource& src, const XmlWhere& w, std::optional<std::uint64_t> expected,
                    std::size_t unit, Target& target);
  std::optional<ArrayHeader> array_header(pugi::xml_node el, const XmlWhere& w,
                                          const ArrayRequest& req);
  /// The binary payload of an array (none for ascii); `dw` says where it starts.
  std::optional<ByteSource> payload_source(pugi::xml_node el, const XmlWhere& w,
                                           const ArrayHeader& h, XmlWhere& dw,
                                           std::string& storage);
  std::optional<DataArray> read_array(pugi::xml_node el, const XmlWhere& w, const ArrayRequest& req);
  /// Summary mode: the array's values go through `consume` (whole tuples, host order, in pieces)
  /// instead of into memory; returns its header (none for a skipped array).
  std::optional<ArrayHeader> stream_array(pugi::xml_node el, const XmlWhere& w,
                                          const ArrayRequest& req,
                                          const io_detail::TupleStream::Consumer& consume,
                                          const std::function<void(const ArrayHeader&)>& ready);
  std::optional<ArraySummary> summarize_array(pugi::xml_node el, const XmlWhere& w,
                                              const ArrayRequest& req);
  void summarize_attributes(pugi::xml_node el, const XmlWhere& w,
                            std::optional<std::uint64_t> tuples, AttributesSummary& out);
  Bounds summarize_points(pugi::xml_node piece, const XmlWhere& w, std::uint64_t np);
  /// Counts the cells of a cell section by type: of polygonal data section `section` (0-3) from
  /// their offsets, of an unstructured grid (`section` -1) from its types array; the
  /// connectivity is not read.
  void count_cells(pugi::xml_node el, const XmlWhere& w, std::uint64_t ncells, int section,
                   std::map<CellType, std::uint64_t>& out);
  /// An image's origin, spacing and dimensions (no arrays) from its attributes.
  ImageData image_geometry(pugi::xml_node ds, const XmlWhere& w, const Extent& whole);
  void read_attributes(pugi::xml_node el, const XmlWhere& w, std::optional<std::uint64_t> tuples,
                       Attributes& out);
  Points read_points(pugi::xml_node piece, const XmlWhere& w, std::uint64_t np);
  /// An integer array of `count` values as Index, after `lead` zeros.
  Buffer<Index> read_index_array(pugi::xml_node el, const XmlWhere& w, std::uint64_t count,
                                 std::size_t lead = 0);
  CellArray read_cells(pugi::xml_node el, const XmlWhere& w, std::uint64_t ncells, std::uint64_t np);

  Extent read_extent(pugi::xml_node el, const char* name, const XmlWhere& w, bool allow_empty);
  std::vector<StructuredPiece> read_structured_pieces(pugi::xml_node ds, const XmlWhere& w,
                                                      const Extent& whole, bool with_points);
  void assemble_structured(const Extent& whole, std::vector<StructuredPiece>& pieces,
                           const XmlWhere& w, Attributes& pd, Attributes& cd, DataArray* points);

  ImageData read_image(pugi::xml_node ds, const XmlWhere& w);
  StructuredGrid read_structured(pugi::xml_node ds, const XmlWhere& w);
  PolyData read_poly(pugi::xml_node ds, const XmlWhere& w);
  UnstructuredGrid read_unstructured(pugi::xml_node ds, const XmlWhere& w);

  io_detail::FileSource source_;  // data_ and the file it is mapped from (if any)
  std::span<const std::byte> data_;
  std::string name_;
  io_detail::Progress* progress_ = nullptr;
  std::uint64_t progress_base_ = 0;
  std::uint64_t budget_ = 0;

  Endian endian_ = Endian::Little;
  bool header64_ = false;
  std::optional<BlockCodec> codec_;  // compressor= (none: plain byte-count headers)

  bool has_appended_ = false;
  bool appended_b64_ = false;
  std::span<const std::byte> appended_;
  std::uint64_t appended_start_ = 0;
  std::size_t xml_size_ = 0;  // bytes of the file that are XML

  std::vector<char> xml_;
  pugi::xml_document doc_;
};

void Reader::split_appended() {
  const std::string_view all(reinterpret_cast<const char*>(data_.data()), data_.size());
  const std::size_t pos = all.find("<AppendedData");
  if (pos == std::string_view::npos) {
    xml_size_ = all.size();
    xml_.assign(all.begin(), all.end());
    return;
  }
  const XmlWhere w{name_, "AppendedData", pos};
  const std::size_t gt = all.find('>', pos);
  if (gt == std::string_view::npos) w.fail("truncated <AppendedData> tag");
  // Parse the start tag on its own to read its attributes.
  std::string tag(all.substr(pos, gt - pos));
  if (!tag.empty() && tag.back() == '/') w.fail("empty <AppendedData/> element has no data");
  tag += "/>";
  pugi::xml_document tdoc;
  const pugi::xml_parse_result r =
      tdoc.load_buffer(tag.data(), tag.size(), pugi::parse_default, pugi::encoding_utf8);
  if (!r) w.fail(std::string("malformed <AppendedData> tag: ") + r.description());
  const pugi::xml_node tnode = tdoc.child("AppendedData");
  if (!tnode) w.fail("malformed <AppendedData> tag");
  const std::string_view enc = attr(tnode, "encoding").value_or("");
  if (enc == "raw") {
    appended_b64_ = false;
  } else if (enc == "base64") {
    appended_b64_ = true;
  } else {
    w.fail("encoding='" + printable(enc) + "' is not 'raw' or 'base64'");
  }
  std::size_t i = gt + 1;
  while (i < all.size() && is_space(all[i])) ++i;
  if (i >= all.size() || all[i] != '_') {
    w.fail_at(i, "expected '_' at the start of the appended data");
  }
  ++i;
  std::size_t end = all.size();
  const std::size_t close = all.rfind("</AppendedData>");
  if (close != std::string_view::npos && close >= i) end = close;
  has_appended_ = true;
  appended_ = data_.subspan(i, end - i);
  appended_start_ = i;
  xml_size_ = pos;
  static constexpr std::string_view kClose = "</VTKFile>";
  xml_.reserve(pos + kClose.size());
  xml_.assign(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(pos));
  xml_.insert(xml_.end(), kClose.begin(), kClose.end());
}

template <class Target>
void Reader::read_payload(ByteSource& src, const XmlWhere& w, std::optional<std::uint64_t> expected,
                          std::size_t unit, Target& target) {
  const std::uint64_t start = src.file_pos();
  if (!codec_) {
    const std::uint64_t n = read_word(src, w, "the data header");
    if (expected && n != *expected) {
      w.fail_at(start,
                "data header declares " + num(n) + " bytes but the array needs " + num(*expected));
    }
    if (!expected && n % unit != 0) {
      w.fail_at(start, "data header declares " + num(n) +
                           " bytes, not a whole number of tuples of " + num(unit) + " bytes");
    }
    if (n > src.available()) {
      w.fail_at(src.file_pos(), "truncated data: the header declares " + num(n) +
                                    " bytes but at most " + num(src.available()) + " remain");
    }
    charge(n, w);
    target.start(n);
    // Sixteen pieces with progress between them (each big one read on all threads).
    const std::uint64_t step = std::min<std::uint64_t>(
        std::max<std::uint64_t>(io_detail::Progress::kStep, n / 16), Target::kMaxPiece);
    for (std::uint64_t at = 0; at < n; at += step) {
      const auto m = static_cast<std::size_t>(std::min(step, n - at));
      src.read(target.piece(at, m), m, w, "the array data");
      target.done(m);
      tick(src.file_pos());
    }
    return;
  }

  const std::size_t word = header64_ ? 8 : 4;
  const std::uint64_t nblocks = read_word(src, w, "the compression header");
  const std::uint64_t block = read_word(src, w, "the compression header");
  const std::uint64_t last = read_word(src, w, "the compression header");
  if (nblocks > src.available() / word) {
    w.fail_at(start, "compression header declares " + num(nblocks) +
                         " blocks, more than the remaining data can describe");
  }
  if (nblocks > 0 && block == 0) w.fail_at(start, "compression header declares block size 0");
  if (last > block) {
    w.fail_at(start, "compression header: last block size " + num(last) +
                         " exceeds the block size " + num(block));
  }
  std::uint64_t total = 0;
  if (nblocks > 0) {
    if (io_detail::mul_overflow(nblocks - 1, block, total) ||
        __builtin_add_overflow(total, last ? last : block, &total)) {
      w.fail_at(start, "compression header sizes overflow");
    }
  }
  if (expected && total != *expected) {
    w.fail_at(start, "compression header declares " + num(total) +
                         " uncompressed bytes but the array needs " + num(*expected));
  }
  if (!expected && total % unit != 0) {
    w.fail_at(start, "compression header declares " + num(total) +
                         " bytes, not a whole number of tuples of " + num(unit) + " bytes");
  }
  std::vector<std::uint64_t> csize(static_cast<std::size_t>(nblocks));
  std::uint64_t csum = 0;
  for (auto& c : csize) {
    c = read_word(src, w, "the compression header");
    if (__builtin_add_overflow(csum, c, &csum)) w.fail_at(start, "compressed sizes overflow");
  }
  if (csum > src.available()) {
    w.fail_at(src.file_pos(), "truncated data: the compression header declares " + num(csum) +
                                  " compressed bytes but at most " + num(src.available()) +
                                  " remain");
  }
  const BlockCodec codec = *codec_;
  const std::uint64_t max_ratio = io_detail::block_codec_max_ratio(codec);
  for (std::size_t b = 0; b < csize.size(); ++b) {
    const std::uint64_t u = (b + 1 == csize.size() && last) ? last : block;
    if (u > csize[b] * max_ratio + 64) {
      w.fail_at(start, "compression header claims block " + num(b) + " inflates to " + num(u) +
                           " bytes from " + num(csize[b]) + " compressed bytes, more than " +
                           codec_label(codec) + " can produce");
    }
  }
  charge(total, w);
  target.start(total);
  // The compressed blocks: a view of the file (raw), or decoded once from base64. Every block is
  // an independent stream, decompressed in parallel straight into the target.
  const std::uint64_t data_pos = src.file_pos();
  const auto in = src.view(static_cast<std::size_t>(csum), w, "the compressed blocks");
  std::vector<io_detail::BlockJob> jobs(csize.size());
  std::vector<std::uint64_t> at(csize.size()), out_at(csize.size() + 1, 0);
  std::uint64_t cin = 0;
  for (std::size_t b = 0; b < csize.size(); ++b) {
    const std::uint64_t u = (b + 1 == csize.size() && last) ? last : block;
    jobs[b] = {in.data() + cin, static_cast<std::size_t>(csize[b]), nullptr,
               static_cast<std::size_t>(u)};
    at[b] = data_pos + cin;
    cin += csize[b];
    out_at[b + 1] = out_at[b] + u;
  }
  // Without progress one parallel loop; with it, slices with a report after each; never more
  // than the target takes at once.
  std::size_t slice =
      progress_ ? std::max<std::size_t>(kProgressBytes / std::max<std::uint64_t>(block, 1), 4)
                : std::max<std::size_t>(jobs.size(), 1);
  slice = std::min<std::uint64_t>(slice,
                                  std::max<std::uint64_t>(Target::kMaxPiece / std::max<std::uint64_t>(block, 1), 1));
  for (std::size_t b0 = 0; b0 < jobs.size(); b0 += slice) {
    const std::size_t b1 = std::min(jobs.size(), b0 + slice);
    const auto bytes = static_cast<std::size_t>(out_at[b1] - out_at[b0]);
    std::byte* dst = target.piece(out_at[b0], bytes);
    for (std::size_t b = b0; b < b1; ++b) {
      jobs[b].out = dst + (out_at[b] - out_at[b0]);
    }
    const io_detail::BlockFailure f =
        io_detail::decompress_blocks(codec, std::span(jobs).subspan(b0, b1 - b0),
                                     src.is_raw() ? &source_ : nullptr);
    if (f.index < b1 - b0) {
      const std::size_t b = b0 + f.index;
      w.fail_at(at[b], std::string(codec_label(codec)) + " error in compressed block " + num(b) +
                           " of " + num(nblocks) + ": " + f.why);
    }
    target.done(bytes);
    tick(b1 < jobs.size() ? at[b1] : data_pos + cin);
  }
}

std::vector<std::byte> Reader::decode_block(const io_detail::VtkXmlBlockFormat& format,
                                            std::optional<std::uint64_t> expected,
                                            std::size_t unit) {
  endian_ = format.big_endian ? Endian::Big : Endian::Little;
  header64_ = format.header64;
  if (format.compressed) codec_ = format.codec;
  if (codec_ == BlockCodec::Lzma) budget_ = lzma_budget();
  ByteSource src =
      format.base64
          ? ByteSource::base64(
                std::string_view(reinterpret_cast<const char*>(data_.data()), data_.size()), 0)
          : ByteSource::raw(data_, 0, source_);
  std::vector<std::byte> out;
  WholeTarget target([&](std::uint64_t n) {
    out.resize(static_cast<std::size_t>(n));
    return out.data();
  });
  read_payload(src, root_where("DataArray"), expected, unit, target);
  return out;
}

std::string_view element_text(pugi::xml_node el, std::string& storage, std::uint64_t& offset) {
  std::string_view first;
  int count = 0;
  for (pugi::xml_node c = el.first_child(); c; c = c.next_sibling()) {
    if (c.type() != pugi::node_pcdata && c.type() != pugi::node_cdata) continue;
    const std::string_view v = c.value();
    if (count == 0) {
      first = v;
      if (c.offset_debug() >= 0) offset = static_cast<std::uint64_t>(c.offset_debug());
    } else {
      if (count == 1) storage.assign(first);
      storage += ' ';
      storage += v;
    }
    ++count;
  }
  return count <= 1 ? first : std::string_view(storage);
}

/// Parses whitespace-separated values; `tick(i)` is told the offset reached in `text`.
template <class T, class Tick>
std::vector<T> parse_ascii(std::string_view text, std::optional<std::uint64_t> count,
                           const XmlWhere& w, std::string_view type_name, Tick&& tick) {
  std::vector<T> out;
  // Big arrays in parallel (io_detail::parse_numbers); any problem: parsed again below, one
  // value at a time, which names it.
  if (count && *count >= (std::uint64_t{1} << 16) && *count <= text.size() / 2 + 1) {
    out.resize(static_cast<std::size_t>(*count));
    const io_detail::ParsedNumbers r = io_detail::parse_numbers(
        text, out.size(), out.data());
    std::size_t rest = r.end;
    while (rest < text.size() && is_space(text[rest])) ++rest;
    if (r.found == out.size() && !r.bad && rest == text.size()) {
      tick(text.size());
      return out;
    }
    out.clear();
  }
  // Each value takes at least two characters (digit and separator), which bounds the reservation
  // whatever count the file claims.
  if (count)
    out.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(*count, text.size() / 2 + 1)));
  std::size_t i = 0;
  while (true) {
    while (i < text.size() && is_space(text[i])) ++i;
    if (i >= text.size()) break;
    std::size_t j = i;
    while (j < text.size() && !is_space(text[j])) ++j;
    const std::string_view tok = text.substr(i, j - i);
    if (count && out.size() == *count) {
      w.fail("ascii data holds more than the " + num(*count) + " values the array needs");
    }
    T v{};
    if (!parse_number(tok, v)) {
      w.fail("ascii value " + num(out.size()) + " '" + printable(tok) + "' is not a valid " +
             std::string(type_name));
    }
    out.push_back(v);
    i = j;
    tick(i);
  }
  if (count && out.size() != *count) {
    w.fail("ascii data holds " + num(out.size()) + " values but the array needs " + num(*count));
  }
  return out;
}

std::optional<ArrayHeader> Reader::array_header(pugi::xml_node el, const XmlWhere& w,
                                                const ArrayRequest& req) {
  const auto type_name = attr(el, "type");
  if (!type_name) w.fail("missing attribute 'type'");
  if (*type_name == "String" || *type_name == "Bit") {
    if (req.skippable) return std::nullopt;
    w.fail("type " + std::string(*type_name) + " is not allowed here (needs a numeric array)");
  }
  const auto type = scalar_type_named(*type_name);
  if (!type) w.fail("unknown type '" + printable(*type_name) + "'");
  const std::string name(attr(el, "Name").value_or(""));

  const std::uint64_t comps = count_attr(el, "NumberOfComponents", w, 1);
  if (comps < 1 || comps > static_cast<std::uint64_t>(std::numeric_limits<int>::max())) {
    w.fail("NumberOfComponents=" + num(comps) + " is out of range");
  }
  if (req.components != 0 && comps != static_cast<std::uint64_t>(req.components)) {
    w.fail("has " + num(comps) + " components, expected " + std::to_string(req.components));
  }
  std::optional<std::uint64_t> tuples = req.tuples;
  if (attr(el, "NumberOfTuples")) {
    const std::uint64_t nt = count_attr(el, "NumberOfTuples", w);
    if (tuples && nt != *tuples) {
      w.fail("NumberOfTuples=" + num(nt) + " but " + num(*tuples) + " tuples are needed here");
    }
    tuples = nt;
  }
  const std::size_t esize = scalar_size(*type);
  const std::size_t unit = esize * static_cast<std::size_t>(comps);
  std::optional<std::uint64_t> values, bytes;
  if (tuples) {
    std::uint64_t v = 0, b = 0;
    if (io_detail::mul_overflow(*tuples, comps, v) || io_detail::mul_overflow(v, esize, b) ||
        b > static_cast<std::uint64_t>(std::numeric_limits<std::ptrdiff_t>::max())) {
      w.fail(num(*tuples) + " tuples of " + num(comps) + " components overflow the array size");
    }
    values = v;
    bytes = b;
  }

  const auto format = attr(el, "format");
  if (!format) w.fail("missing attribute 'format'");
  return ArrayHeader{*type, *type_name, name, static_cast<int>(comps), values, bytes, unit,
                     *format};
}

std::optional<ByteSource> Reader::payload_source(pugi::xml_node el, const XmlWhere& w,
                                                 const ArrayHeader& h, XmlWhere& dw,
                                                 std::string& storage) {
  std::optional<ByteSource> src;
  dw = w;
  if (h.format == "binary") {
    const std::string_view text = element_text(el, storage, dw.byte);
    src = ByteSource::base64(text, dw.byte);
  } else if (h.format == "appended") {
    if (!has_appended_) w.fail("format is appended but the file has no <AppendedData> section");
    const std::uint64_t off = count_attr(el, "offset", w);
    if (off > appended_.size()) {
      w.fail("offset " + num(off) + " is beyond the end of the appended data section (" +
             num(appended_.size()) + " bytes): the file is truncated or the offset is wrong");
    }
    dw.byte = appended_start_ + off;
    if (appended_b64_) {
      const std::string_view text(reinterpret_cast<const char*>(appended_.data()) + off,
                                  appended_.size() - static_cast<std::size_t>(off));
      src = ByteSource::base64(text, dw.byte);
    } else {
      src = ByteSource::raw(appended_.subspan(static_cast<std::size_t>(off)), dw.byte, source_);
    }
  } else if (h.format != "ascii") {
    w.fail("format='" + printable(h.format) + "' is not ascii, binary or appended");
  }
  return src;
}

std::optional<DataArray> Reader::read_array(pugi::xml_node el, const XmlWhere& w,
                                            const ArrayRequest& req) {
  const std::optional<ArrayHeader> h = array_header(el, w, req);
  if (!h) return std::nullopt;
  // (Named references, not a structured binding: clang 14 cannot capture those in lambdas.)
  const ScalarType type = h->type;
  const std::string_view type_name = h->type_name;
  const std::string& name = h->name;
  const int ncomp = h->components;
  const std::optional<std::uint64_t> values = h->values, bytes = h->bytes;
  const std::size_t unit = h->unit;
  const std::string_view format = h->format;
  const auto comps = static_cast<std::uint64_t>(ncomp);
  const std::size_t esize = scalar_size(type);

  if (format == "ascii") {
    std::string storage;
    XmlWhere tw = w;
    const std::string_view text = element_text(el, storage, tw.byte);
    auto make = [&](auto tag) {
      using T = decltype(tag);
      auto vec = parse_ascii<T>(text, values, tw, type_name,
                                [&, at = tw.byte](std::size_t i) { tick(at + i); });
      if (!values && vec.size() % comps != 0) {
        tw.fail("ascii data holds " + num(vec.size()) + " values, not a multiple of " + num(comps) +
                " components");
      }
      charge(vec.size() * sizeof(T), tw);
      return DataArray::from_vector<T>(name, ncomp, std::move(vec));
    };
    return std::optional<DataArray>(visit_scalar_type(type, make));
  }

  XmlWhere dw;
  std::string storage;
  std::optional<ByteSource> src = payload_source(el, w, *h, dw, storage);

  // Not zero-filled: read_payload writes every byte (a raw payload is read whole, and every
  // block must decode to exactly its size), and zeroing first doubled the pages' first touch.
  std::optional<DataArray> out;
  WholeTarget target([&](std::uint64_t n) -> std::byte* {
    out.emplace(DataArray::uninitialized(name, type, ncomp, static_cast<std::size_t>(n / unit)));
    return out->bytes();
  });
  read_payload(*src, dw, bytes, unit, target);
  if (endian_ != kHostEndian) io_detail::swap_elements(out->bytes(), out->size(), esize);
  return out;
}

void Reader::read_attributes(pugi::xml_node el, const XmlWhere& w, std::optional<std::uint64_t> tuples,
                             Attributes& out) {
  if (!el) return;
  std::size_t index = 0;
  for (pugi::xml_node a = el.child("DataArray"); a; a = a.next_sibling("DataArray"), ++index) {
    const XmlWhere aw = array_where(w, a, index);
    auto arr = read_array(a, aw, ArrayRequest{tuples, 0, true});
    if (!arr) continue;
    if (arr->name().empty()) arr->set_name("Array " + num(index));
    if (out.has(arr->name())) aw.fail("duplicate array name '" + printable(arr->name(), 80) + "'");
    out.add(std::move(*arr));
  }
  for (const auto& [role, name] : named_roles(el)) {
    if (out.has(name)) out.set_active(role, name);
  }
}

Points Reader::read_points(pugi::xml_node piece, const XmlWhere& w, std::uint64_t np) {
  const pugi::xml_node pel = piece.child("Points");
  if (!pel) {
    if (np == 0) return Points();
    w.fail("missing <Points> element for NumberOfPoints=" + num(np));
  }
  const XmlWhere pw = w.child(pel, "Points");
  const pugi::xml_node da = pel.child("DataArray");
  if (!da) {
    if (np == 0) return Points();
    pw.fail("missing <DataArray> with the point coordinates");
  }
  const XmlWhere aw = pw.child(da, "DataArray");
  auto arr = read_array(da, aw, ArrayRequest{np, 3, false});
  if (arr->name().empty()) arr->set_name("Points");
  Points pts(std::move(*arr));
  const std::size_t bad = pts.first_non_finite();
  if (bad < pts.size()) {
    const Vec3 p = pts[bad];
    aw.fail("point " + num(bad) + " has a non-finite coordinate (" + std::to_string(p.x) + ", " +
            std::to_string(p.y) + ", " + std::to_string(p.z) + ")");
  }
  return pts;
}

/// Values per task of the index arrays' passes.
constexpr std::size_t kIndexGrain = std::size_t{1} << 16;

namespace {

/// Widens the `n` values of type T at the start of `base` to Index values over the same bytes
/// (the buffer holds n Index values), in place. From the top down, in rounds: Index value i
/// covers the T values k*i .. k*i + k - 1 (k = sizeof(Index) / sizeof(T)), so once every value
/// from `hi` up is done, those of [ceil(hi / k), hi) only cover values already read, and each
/// round is a flat parallel pass. Element access by memcpy (the bytes change type).
template <class T>
void widen_in_place(std::byte* base, std::size_t n) {
  static_assert(sizeof(T) < sizeof(Index));
  constexpr std::size_t k = sizeof(Index) / sizeof(T);
  const auto widen = [base](std::size_t i) {
    T v;
    std::memcpy(&v, base + i * sizeof(T), sizeof(T));
    const auto x = static_cast<Index>(v);
    std::memcpy(base + i * sizeof(Index), &x, sizeof(Index));
  };
  std::size_t hi = n;
  while (hi > kIndexGrain) {
    const std::size_t lo = (hi + k - 1) / k;
    parallel_for_range(hi - lo, kIndexGrain, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = lo + b; i < lo + e; ++i) widen(i);
    });
    hi = lo;
  }
  for (std::size_t i = hi; i-- > 0;) widen(i);  // from the top: each covers values read before
}

}  // namespace

Buffer<Index> Reader::read_index_array(pugi::xml_node el, const XmlWhere& w, std::uint64_t count,
                                       std::size_t lead) {
  const ArrayRequest req{count, 1, false};
  const std::optional<ArrayHeader> h = array_header(el, w, req);
  if (is_floating(h->type)) {
    w.fail("must have an integer type, not " + std::string(scalar_type_name(h->type)));
  }
  Buffer<Index> out;
  if (h->format == "ascii") {
    auto arr = read_array(el, w, req);
    arr->visit([&](const auto& v) {
      using T = typename std::decay_t<decltype(v)>::value_type;
      if constexpr (std::is_integral_v<T>) {
        out.resize(v.size() + lead, 0);
        for (std::size_t i = 0; i < v.size(); ++i) {
          if constexpr (std::is_same_v<T, std::uint64_t>) {
            if (v[i] > static_cast<std::uint64_t>(std::numeric_limits<Index>::max())) {
              w.fail("value " + num(i) + " (" + num(v[i]) + ") is out of range");
            }
          }
          out[lead + i] = static_cast<Index>(v[i]);
        }
      }
    });
    return out;
  }
  // Binary: the file's values land at the start of the Index array (after `lead`) and are
  // widened there: no second array (a file of Int32 ids read at the memory of the result).
  XmlWhere dw;
  std::string storage;
  std::optional<ByteSource> src = payload_source(el, w, *h, dw, storage);
  const std::size_t es = scalar_size(h->type);
  WholeTarget target([&](std::uint64_t n) -> std::byte* {
    out.resize(static_cast<std::size_t>(n / h->unit) + lead);  // every element written below
    return reinterpret_cast<std::byte*>(out.data() + lead);
  });
  read_payload(*src, dw, h->bytes, h->unit, target);
  std::byte* base = reinterpret_cast<std::byte*>(out.data() + lead);
  const std::size_t n = out.size() - lead;
  if (endian_ != kHostEndian) io_detail::swap_elements(base, n, es);
  visit_scalar_type(h->type, [&](auto tag) {
    using T = decltype(tag);
    if constexpr (std::is_integral_v<T> && sizeof(T) < sizeof(Index)) {
      widen_in_place<T>(base, n);
    } else if constexpr (std::is_same_v<T, std::uint64_t>) {  // Index's bits where in range
      const std::size_t bad =
          parallel_find_first(n, kIndexGrain, [&](std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) {
              if (out[lead + i] < 0) return i;
            }
            return e;
          });
      if (bad < n) {
        std::uint64_t v;
        std::memcpy(&v, base + bad * sizeof(v), sizeof(v));
        w.fail("value " + num(bad) + " (" + num(v) + ") is out of range");
      }
    }  // Int64: read as it is
  });
  std::fill(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(lead), Index{0});
  return out;
}

pugi::xml_node named_array(pugi::xml_node el, std::string_view name) {
  for (pugi::xml_node a = el.child("DataArray"); a; a = a.next_sibling("DataArray")) {
    if (attr(a, "Name") == name) return a;
  }
  return {};
}

CellArray Reader::read_cells(pugi::xml_node el, const XmlWhere& w, std::uint64_t ncells,
                             std::uint64_t np) {
  const pugi::xml_node off_el = named_array(el, "offsets");
  const pugi::xml_node conn_el = named_array(el, "connectivity");
  if (ncells == 0 && !off_el && !conn_el) return CellArray();
  if (!off_el) w.fail("missing DataArray 'offsets' for " + num(ncells) + " cells");
  const XmlWhere ow = w.child(off_el, "DataArray 'offsets'");
  // The file's offsets are the cells' ends: read after a leading 0, they are the CellArray's.
  Buffer<Index> offsets = read_index_array(off_el, ow, ncells, 1);
  const std::span<const Index> ends = std::span<const Index>(offsets).subspan(1);
  // The checks are flat passes on all threads (a 1.5M-cell surface spent a tenth of its LZ4
  // conversion in them when serial).
  const std::size_t down = first_decrease(ends);
  if (down < ends.size()) {
    ow.fail("offsets are not monotonic: cell " + num(down) + " ends at " +
            std::to_string(ends[down]) + " before it starts at " +
            std::to_string(down > 0 ? ends[down - 1] : 0));
  }
  const auto nconn = static_cast<std::uint64_t>(ends.empty() ? 0 : ends.back());
  Buffer<Index> conn;
  if (!conn_el) {
    if (nconn != 0) w.fail("missing DataArray 'connectivity'");
  } else {
    const XmlWhere cw = w.child(conn_el, "DataArray 'connectivity'");
    conn = read_index_array(conn_el, cw, nconn);
    const std::size_t bad = first_out_of_range(conn, np);
    if (bad < conn.size()) {
      // The cell holding position `bad`: the first whose end is past it.
      const auto cell = static_cast<std::size_t>(
          std::upper_bound(ends.begin(), ends.end(), static_cast<Index>(bad)) - ends.begin());
      cw.fail("cell " + num(cell) + " refers to point " + std::to_string(conn[bad]) +
              ", outside [0, " + num(np) + ")");
    }
  }
  // Adopted as checked here (offsets from 0, sorted, ending at the connectivity's size; ids in
  // range): the constructor would pass over the offsets once more.
  CellArray cells;
  cells.offsets() = std::move(offsets);
  cells.connectivity() = std::move(conn);
  return cells;
}

Extent Reader::read_extent(pugi::xml_node el, const char* name, const XmlWhere& w, bool allow_empty) {
  const auto v = list_attr<std::int64_t>(el, name, 6, w);
  Extent e{};
  constexpr std::int64_t kLimit = std::int64_t{1} << 62;
  for (int i = 0; i < 6; ++i) {
    if (v[i] > kLimit || v[i] < -kLimit) {
      w.fail(std::string(name) + " value " + std::to_string(v[i]) + " is out of range");
    }
    e[i] = v[i];
  }
  if (extent_empty(e)) {
    if (allow_empty) return e;
    w.fail(std::string(name) + "='" + extent_string(e) +
           "' is empty or negative (each max must be >= min)");
  }
  for (int a = 0; a < 3; ++a) {
    std::int64_t d = 0;
    if (__builtin_sub_overflow(e[2 * a + 1], e[2 * a], &d) || d >= kLimit) {
      w.fail(std::string(name) + "='" + extent_string(e) + "' spans too many points (overflow)");
    }
  }
  return e;
}

std::vector<StructuredPiece> Reader::read_structured_pieces(pugi::xml_node ds, const XmlWhere& w,
                                                            const Extent& whole, bool with_points) {
  std::vector<StructuredPiece> pieces;
  std::size_t index = 0;
  for (pugi::xml_node p = ds.child("Piece"); p; p = p.next_sibling("Piece"), ++index) {
    const XmlWhere pw = w.child(p, "Piece " + num(index));
    if (pieces.size() >= kMaxStructuredPieces) {
      pw.fail("more than " + num(kMaxStructuredPieces) + " pieces are not supported");
    }
    Extent ext = whole;
    if (attr(p, "Extent")) ext = read_extent(p, "Extent", pw, true);
    if (extent_empty(ext)) continue;  // empty pieces (written by parallel writers) hold nothing
    StructuredPiece sp;
    sp.ext = ext;
    sp.where = pw;
    const Dims d = extent_dims(ext);
    const std::size_t np = extent_points(d, pw);
    const std::size_t nc = structured_cell_count(d);
    read_attributes(p.child("PointData"), pw.child(p.child("PointData"), "PointData"), np, sp.pd);
    read_attributes(p.child("CellData"), pw.child(p.child("CellData"), "CellData"), nc, sp.cd);
    if (with_points) sp.points = std::move(read_points(p, pw, np).array());
    pieces.push_back(std::move(sp));
  }
  if (pieces.empty()) w.fail("no <Piece> with a non-empty Extent");
  return pieces;
}

void check_same_arrays(const Attributes& a0, const Attributes& ap, const XmlWhere& w,
                       std::string_view what) {
  if (a0.size() != ap.size()) {
    w.fail(std::string(what) + " has " + num(ap.size()) + " arrays but piece 0 has " +
           num(a0.size()) + "; pieces must carry the same arrays");
  }
  for (const DataArray& a : a0) {
    const DataArray* b = ap.find(a.name());
    if (!b) {
      w.fail(std::string(what) + " lacks array '" + printable(a.name(), 80) + "' that piece 0 has");
    }
    if (b->type() != a.type() || b->components() != a.components()) {
      w.fail(std::string(what) + " array '" + printable(a.name(), 80) +
             "' differs in type or components from piece 0");
    }
  }
}

/// The cell boxes of pieces (in cell indices of the whole extent), and whether some overlap.
struct PieceBoxes {
  std::vector<std::array<std::int64_t, 6>> boxes;
  bool overlapping = false;
};

/// Whether the union of `boxes` covers [0, cells[a]) along every axis, on the grid of the boxes'
/// own boundaries (at most `kMaxCoverageCells` cells of it). \throw Error through `w` when that
/// grid is larger.
bool boxes_cover(const std::vector<std::array<std::int64_t, 6>>& boxes,
                 const std::array<std::int64_t, 3>& cells, const XmlWhere& w) {
  constexpr std::uint64_t kMaxCoverageCells = std::uint64_t{1} << 24;
  std::array<std::vector<std::int64_t>, 3> cuts;
  std::uint64_t grid = 1;
  for (int a = 0; a < 3; ++a) {
    cuts[a] = {0, cells[a]};
    for (const auto& b : boxes) {
      cuts[a].push_back(b[2 * a]);
      cuts[a].push_back(b[2 * a + 1]);
    }
    std::sort(cuts[a].begin(), cuts[a].end());
    cuts[a].erase(std::unique(cuts[a].begin(), cuts[a].end()), cuts[a].end());
    grid *= cuts[a].size() - 1;
  }
  if (grid > kMaxCoverageCells) {
    w.fail("the " + num(boxes.size()) + " overlapping pieces cut the WholeExtent into more than " +
           num(kMaxCoverageCells) + " blocks; such files are not supported");
  }
  const std::size_t gx = cuts[0].size() - 1, gy = cuts[1].size() - 1;
  std::vector<std::uint8_t> covered(static_cast<std::size_t>(grid), 0);
  auto slot = [&](int a, std::int64_t v) {
    return static_cast<std::size_t>(std::lower_bound(cuts[a].begin(), cuts[a].end(), v) -
                                    cuts[a].begin());
  };
  for (const auto& b : boxes) {
    const std::size_t x0 = slot(0, b[0]), x1 = slot(0, b[1]), y0 = slot(1, b[2]),
                      y1 = slot(1, b[3]), z0 = slot(2, b[4]), z1 = slot(2, b[5]);
    for (std::size_t z = z0; z < z1; ++z) {
      for (std::size_t y = y0; y < y1; ++y) {
        std::fill_n(covered.begin() + static_cast<std::ptrdiff_t>(x0 + gx * (y + gy * z)), x1 - x0,
                    std::uint8_t{1});
      }
    }
  }
  return std::find(covered.begin(), covered.end(), 0) == covered.end();
}

/// The cell boxes of pieces with extents `exts`. Pieces may overlap (VTK's writers repeat ghost
/// layers when asked for ghost levels). \throw Error (through the piece's `wheres` or `w`) unless
/// they lie inside the whole extent and together cover it.
PieceBoxes piece_boxes(const Extent& whole, const std::vector<Extent>& exts,
                       const std::vector<XmlWhere>& wheres, const XmlWhere& w) {
  const Dims wd = extent_dims(whole);
  std::array<std::int64_t, 3> cells{};
  std::uint64_t whole_cells = 1;
  for (int a = 0; a < 3; ++a) {
    cells[a] = wd[a] > 1 ? wd[a] - 1 : 1;
    whole_cells *= static_cast<std::uint64_t>(cells[a]);
  }
  PieceBoxes out;
  std::uint64_t covered = 0;
  for (std::size_t i = 0; i < exts.size(); ++i) {
    const Extent& ext = exts[i];
    std::array<std::int64_t, 6> box{};
    std::uint64_t vol = 1;
    for (int a = 0; a < 3; ++a) {
      const std::int64_t lo = ext[2 * a], hi = ext[2 * a + 1];
      if (lo < whole[2 * a] || hi > whole[2 * a + 1]) {
        wheres[i].fail("Extent '" + extent_string(ext) + "' lies outside WholeExtent '" +
                       extent_string(whole) + "'");
      }
      if (wd[a] > 1) {
        if (hi == lo) {
          wheres[i].fail("Extent '" + extent_string(ext) + "' is flat along axis " +
                         std::to_string(a) + "; pieces must tile the WholeExtent");
        }
        box[2 * a] = lo - whole[2 * a];
        box[2 * a + 1] = hi - whole[2 * a];
      } else {
        box[2 * a] = 0;
        box[2 * a + 1] = 1;
      }
      vol *= static_cast<std::uint64_t>(box[2 * a + 1] - box[2 * a]);
    }
    if (__builtin_add_overflow(covered, vol, &covered)) covered = UINT64_MAX;
    out.boxes.push_back(box);
  }
  const auto& boxes = out.boxes;
  for (std::size_t i = 0; i < boxes.size() && !out.overlapping; ++i) {
    for (std::size_t j = i + 1; j < boxes.size() && !out.overlapping; ++j) {
      bool overlap = true;
      for (int a = 0; a < 3 && overlap; ++a) {
        overlap = boxes[i][2 * a] < boxes[j][2 * a + 1] && boxes[j][2 * a] < boxes[i][2 * a + 1];
      }
      out.overlapping = overlap;
    }
  }
  // Without overlap the volumes add up to the whole exactly when the pieces cover it.
  if (out.overlapping ? !boxes_cover(boxes, cells, w) : covered != whole_cells) {
    w.fail(out.overlapping
               ? "the pieces leave cells of WholeExtent '" + extent_string(whole) +
                     "' uncovered; they must cover it"
               : "the pieces cover " + num(covered) + " of the " + num(whole_cells) +
                     " cells of WholeExtent '" + extent_string(whole) + "'; they must tile it");
  }
  return out;
}

void Reader::assemble_structured(const Extent& whole, std::vector<StructuredPiece>& pieces,
                                 const XmlWhere& w, Attributes& pd, Attributes& cd,
                                 DataArray* points) {
  if (pieces.size() == 1 && pieces[0].ext == whole) {
    pd = std::move(pieces[0].pd);
    cd = std::move(pieces[0].cd);
    if (points) *points = std::move(*pieces[0].points);
    return;
  }
  const Dims wd = extent_dims(whole);
  std::array<std::size_t, 3> wpts{}, wcells{};
  for (int a = 0; a < 3; ++a) {
    wpts[a] = static_cast<std::size_t>(wd[a]);
    wcells[a] = wd[a] > 1 ? static_cast<std::size_t>(wd[a] - 1) : 1;
  }
  const std::uint64_t whole_cells = wcells[0] * wcells[1] * wcells[2];
  std::vector<Extent> extents;
  std::vector<XmlWhere> wheres;
  for (const auto& p : pieces) {
    extents.push_back(p.ext);
    wheres.push_back(p.where);
  }
  const PieceBoxes tiling = piece_boxes(whole, extents, wheres, w);
  const auto& boxes = tiling.boxes;
  const bool overlapping = tiling.overlapping;
  for (std::size_t i = 1; i < pieces.size(); ++i) {
    check_same_arrays(pieces[0].pd, pieces[i].pd, pieces[i].where, "PointData");
    check_same_arrays(pieces[0].cd, pieces[i].cd, pieces[i].where, "CellData");
  }
  const std::size_t np = wpts[0] * wpts[1] * wpts[2];
  auto assemble = [&](auto get_src, const DataArray& proto, bool cells) {
    const auto& full = cells ? wcells : wpts;
    DataArray out(proto.name(), proto.type(), proto.components(), cells ? whole_cells : np);
    // Overlapping pieces repeat the same values; only their ghost flags differ, where a piece
    // marks the layer it repeats as duplicate. A flag stays where every piece holding the point
    // or cell sets it, so the assembled whole, which repeats nothing, keeps no duplicate mark.
    const bool ghost_and = overlapping && proto.name() == "vtkGhostType" &&
                           proto.type() == ScalarType::UInt8 && proto.components() == 1;
    if (ghost_and) std::fill_n(out.bytes(), out.size(), std::byte{0xff});
    for (std::size_t i = 0; i < pieces.size(); ++i) {
      const Dims d = extent_dims(pieces[i].ext);
      std::array<std::size_t, 3> sub{}, at{};
      for (int a = 0; a < 3; ++a) {
        if (cells) {
          sub[a] = static_cast<std::size_t>(boxes[i][2 * a + 1] - boxes[i][2 * a]);
          at[a] = static_cast<std::size_t>(boxes[i][2 * a]);
        } else {
          sub[a] = static_cast<std::size_t>(d[a]);
          at[a] = static_cast<std::size_t>(pieces[i].ext[2 * a] - whole[2 * a]);
        }
      }
      if (ghost_and) {
        and_box(get_src(pieces[i]), sub, out, full, at);
      } else {
        copy_box(get_src(pieces[i]), sub, out, full, at);
      }
    }
    return out;
  };
  Attributes npd, ncd;
  for (const DataArray& a : pieces[0].pd) {
    npd.add(
        assemble([&](const StructuredPiece& p) -> const DataArray& { return p.pd.get(a.name()); },
                 a, false));
  }
  for (const DataArray& a : pieces[0].cd) {
    ncd.add(assemble(
        [&](const StructuredPiece& p) -> const DataArray& { return p.cd.get(a.name()); }, a, true));
  }
  for (std::size_t r = 0; r < kAttributeRoleCount; ++r) {
    const auto role = static_cast<AttributeRole>(r);
    npd.set_active(role, pieces[0].pd.active_name(role));
    ncd.set_active(role, pieces[0].cd.active_name(role));
  }
  if (points) {
    for (std::size_t i = 1; i < pieces.size(); ++i) {
      if (pieces[i].points->type() != pieces[0].points->type()) {
        for (auto& p : pieces) *p.points = p.points->converted(ScalarType::Float64);
        break;
      }
    }
    *points = assemble([](const StructuredPiece& p) -> const DataArray& { return *p.points; },
                       *pieces[0].points, false);
  }
  pd = std::move(npd);
  cd = std::move(ncd);
}

ImageData Reader::read_image(pugi::xml_node ds, const XmlWhere& w) {
  const Extent whole = read_extent(ds, "WholeExtent", w, false);
  ImageData img = image_geometry(ds, w, whole);
  read_attributes(ds.child("FieldData"), w.child(ds.child("FieldData"), "FieldData"), std::nullopt,
                  img.field_data);
  auto pieces = read_structured_pieces(ds, w, whole, false);
  assemble_structured(whole, pieces, w, img.point_data, img.cell_data, nullptr);
  return img;
}

ImageData Reader::image_geometry(pugi::xml_node ds, const XmlWhere& w, const Extent& whole) {
  ImageData img;
  std::array<double, 3> origin{0, 0, 0}, spacing{1, 1, 1};
  if (attr(ds, "Origin")) {
    const auto v = list_attr<double>(ds, "Origin", 3, w);
    std::copy(v.begin(), v.end(), origin.begin());
  }
  if (attr(ds, "Spacing")) {
    const auto v = list_attr<double>(ds, "Spacing", 3, w);
    std::copy(v.begin(), v.end(), spacing.begin());
  }
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(origin[a]) || !std::isfinite(spacing[a])) {
      w.fail("Origin/Spacing must be finite");
    }
  }
  if (attr(ds, "Direction")) {
    const auto d = list_attr<double>(ds, "Direction", 9, w);
    for (int i = 0; i < 9; ++i) {
      const double id = (i % 4 == 0) ? 1.0 : 0.0;
      if (!(std::abs(d[i] - id) <= 1e-12)) {
        w.fail(
            "Direction is not the identity; only axis-aligned images are supported "
            "(resample the image onto an axis-aligned grid first)");
      }
    }
  }
  img.dims = extent_dims(whole);
  try {
    (void)checked_point_count(img.dims, "WholeExtent");
  } catch (const Error& e) {
    w.fail(e.what());
  }
  for (int a = 0; a < 3; ++a) {
    img.origin[a] = origin[a] + static_cast<double>(whole[2 * a]) * spacing[a];
    img.spacing[a] = spacing[a];
  }
  return img;
}

StructuredGrid Reader::read_structured(pugi::xml_node ds, const XmlWhere& w) {
  StructuredGrid sg;
  const Extent whole = read_extent(ds, "WholeExtent", w, false);
  sg.dims = extent_dims(whole);
  try {
    (void)checked_point_count(sg.dims, "WholeExtent");
  } catch (const Error& e) {
    w.fail(e.what());
  }
  read_attributes(ds.child("FieldData"), w.child(ds.child("FieldData"), "FieldData"), std::nullopt,
                  sg.field_data);
  auto pieces = read_structured_pieces(ds, w, whole, true);
  DataArray pts;
  assemble_structured(whole, pieces, w, sg.point_data, sg.cell_data, &pts);
  sg.points = Points(std::move(pts));
  return sg;
}

PolyData Reader::read_poly(pugi::xml_node ds, const XmlWhere& w) {
  std::vector<PolyPiece> pieces;
  std::vector<std::array<std::size_t, 4>> counts;
  std::size_t index = 0;
  for (pugi::xml_node p = ds.child("Piece"); p; p = p.next_sibling("Piece"), ++index) {
    PolyPiece pp;
    pp.where = w.child(p, "Piece " + num(index));
    const XmlWhere& pw = pp.where;
    const std::uint64_t np = count_attr(p, "NumberOfPoints", pw);
    std::array<std::uint64_t, 4> n{};
    std::uint64_t nc = 0;
    for (int c = 0; c < 4; ++c) {
      n[c] = count_attr(p, kCount[c], pw, 0);
      if (__builtin_add_overflow(nc, n[c], &nc)) pw.fail("cell counts overflow");
    }
    pp.points = read_points(p, pw, np);
    read_attributes(p.child("PointData"), pw.child(p.child("PointData"), "PointData"), np, pp.pd);
    read_attributes(p.child("CellData"), pw.child(p.child("CellData"), "CellData"), nc, pp.cd);
    for (int c = 0; c < 4; ++c) {
      const pugi::xml_node el = p.child(kCat[c]);
      if (!el) {
        if (n[c] != 0)
          pw.fail(std::string("missing <") + kCat[c] + "> for " + kCount[c] + "=" + num(n[c]));
        continue;
      }
      pp.cells[c] = read_cells(el, pw.child(el, kCat[c]), n[c], np);
    }
    counts.push_back({static_cast<std::size_t>(n[0]), static_cast<std::size_t>(n[1]),
                      static_cast<std::size_t>(n[2]), static_cast<std::size_t>(n[3])});
    pieces.push_back(std::move(pp));
  }
  PolyData out;
  read_attributes(ds.child("FieldData"), w.child(ds.child("FieldData"), "FieldData"), std::nullopt,
                  out.field_data);
  if (pieces.empty()) return out;  // a PolyData without pieces is an empty dataset
  drop_empty_pieces(pieces, [](const PolyPiece& p) {
    return p.points.size() == 0 && std::all_of(p.cells.begin(), p.cells.end(),
                                               [](const CellArray& c) { return c.empty(); });
  });
  counts.resize(pieces.size());
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    for (int c = 0; c < 4; ++c)
      counts[i][static_cast<std::size_t>(c)] = pieces[i].cells[static_cast<std::size_t>(c)].size();
  }
  for (std::size_t i = 1; i < pieces.size(); ++i) {
    check_same_arrays(pieces[0].pd, pieces[i].pd, pieces[i].where, "PointData");
    check_same_arrays(pieces[0].cd, pieces[i].cd, pieces[i].where, "CellData");
  }
  out.points = std::move(pieces[0].points);
  for (int c = 0; c < 4; ++c) {
    CellArray& ca = c == 0 ? out.verts : c == 1 ? out.lines : c == 2 ? out.polys : out.strips;
    ca = std::move(pieces[0].cells[c]);
  }
  out.point_data = std::move(pieces[0].pd);
  if (pieces.size() == 1) {
    out.cell_data = std::move(pieces[0].cd);
    return out;
  }
  for (std::size_t i = 1; i < pieces.size(); ++i) {
    PolyPiece& pp = pieces[i];
    const auto base = static_cast<Index>(out.points.size());
    if (pp.points.type() != out.points.type()) {
      out.points = Points(out.points.array().converted(ScalarType::Float64));
      pp.points = Points(pp.points.array().converted(ScalarType::Float64));
    }
    append_tuples(out.points.array(), pp.points.array(), 0, pp.points.size());
    for (int c = 0; c < 4; ++c) {
      CellArray& ca = c == 0 ? out.verts : c == 1 ? out.lines : c == 2 ? out.polys : out.strips;
      const CellArray& src = pp.cells[c];
      const Index cbase = static_cast<Index>(ca.connectivity().size());
      for (Index id : src.connectivity()) ca.connectivity().push_back(id + base);
      for (std::size_t k = 1; k < src.offsets().size(); ++k) {
        ca.offsets().push_back(src.offsets()[k] + cbase);
      }
    }
    for (DataArray& a : out.point_data) append_tuples(a, pp.pd.get(a.name()), 0, pp.points.size());
  }
  // Cell data: VTK orders cells verts, lines, polys, strips over the whole dataset, so the
  // per-piece tuples are regrouped by category.
  Attributes cd;
  for (const DataArray& proto : pieces[0].cd) {
    DataArray merged(proto.name(), proto.type(), proto.components());
    for (int c = 0; c < 4; ++c) {
      for (std::size_t i = 0; i < pieces.size(); ++i) {
        std::size_t first = 0;
        for (int k = 0; k < c; ++k) first += counts[i][k];
        append_tuples(merged, pieces[i].cd.get(proto.name()), first, counts[i][c]);
      }
    }
    cd.add(std::move(merged));
  }
  for (std::size_t r = 0; r < kAttributeRoleCount; ++r) {
    const auto role = static_cast<AttributeRole>(r);
    cd.set_active(role, pieces[0].cd.active_name(role));
  }
  out.cell_data = std::move(cd);
  return out;
}

UnstructuredGrid Reader::read_unstructured(pugi::xml_node ds, const XmlWhere& w) {
  std::vector<UnstructuredPiece> pieces;
  std::size_t index = 0;
  for (pugi::xml_node p = ds.child("Piece"); p; p = p.next_sibling("Piece"), ++index) {
    UnstructuredPiece up;
    up.where = w.child(p, "Piece " + num(index));
    const XmlWhere& pw = up.where;
    const std::uint64_t np = count_attr(p, "NumberOfPoints", pw);
    const std::uint64_t nc = count_attr(p, "NumberOfCells", pw);
    up.points = read_points(p, pw, np);
    read_attributes(p.child("PointData"), pw.child(p.child("PointData"), "PointData"), np, up.pd);
    read_attributes(p.child("CellData"), pw.child(p.child("CellData"), "CellData"), nc, up.cd);
    const pugi::xml_node cel = p.child("Cells");
    if (!cel) {
      if (nc != 0) pw.fail("missing <Cells> for NumberOfCells=" + num(nc));
    } else {
      const XmlWhere cw = pw.child(cel, "Cells");
      up.cells = read_cells(cel, cw, nc, np);
      const pugi::xml_node tel = named_array(cel, "types");
      if (!tel) {
        if (nc != 0) cw.fail("missing DataArray 'types'");
      } else {
        const XmlWhere tw = cw.child(tel, "DataArray 'types'");
        const Buffer<Index> t = read_index_array(tel, tw, nc);
        up.types.resize(t.size());
        for (std::size_t c = 0; c < t.size(); ++c) {
          if (t[c] < 0 || t[c] > 255 || !is_valid_cell_type(static_cast<int>(t[c]))) {
            std::string extra;
            if (t[c] == 42) {
              extra = " (polyhedron)";
            } else if (t[c] > 14 && t[c] < 100) {
              extra = " (only linear cell types 0-14 are supported)";
            }
            tw.fail("cell " + num(c) + " has unsupported cell type " + std::to_string(t[c]) +
                    extra);
          }
          const auto type = static_cast<CellType>(t[c]);
          const int fixed = cell_fixed_size(type);
          const auto n = static_cast<int>(up.cells.cell_size(c));
          if ((fixed > 0 && n != fixed) || n < cell_min_size(type)) {
            tw.fail("cell " + num(c) + " (" + std::string(cell_type_name(type)) + ") has " +
                    std::to_string(n) + " points");
          }
          up.types[c] = type;
        }
      }
    }
    pieces.push_back(std::move(up));
  }
  UnstructuredGrid out;
  read_attributes(ds.child("FieldData"), w.child(ds.child("FieldData"), "FieldData"), std::nullopt,
                  out.field_data);
  if (pieces.empty()) return out;
  drop_empty_pieces(
      pieces, [](const UnstructuredPiece& p) { return p.points.size() == 0 && p.cells.empty(); });
  for (std::size_t i = 1; i < pieces.size(); ++i) {
    check_same_arrays(pieces[0].pd, pieces[i].pd, pieces[i].where, "PointData");
    check_same_arrays(pieces[0].cd, pieces[i].cd, pieces[i].where, "CellData");
  }
  out.points = std::move(pieces[0].points);
  out.cells = std::move(pieces[0].cells);
  out.types = std::move(pieces[0].types);
  out.point_data = std::move(pieces[0].pd);
  out.cell_data = std::move(pieces[0].cd);
  for (std::size_t i = 1; i < pieces.size(); ++i) {
    UnstructuredPiece& up = pieces[i];
    const auto base = static_cast<Index>(out.points.size());
    if (up.points.type() != out.points.type()) {
      out.points = Points(out.points.array().converted(ScalarType::Float64));
      up.points = Points(up.points.array().converted(ScalarType::Float64));
    }
    append_tuples(out.points.array(), up.points.array(), 0, up.points.size());
    const Index cbase = static_cast<Index>(out.cells.connectivity().size());
    for (Index id : up.cells.connectivity()) out.cells.connectivity().push_back(id + base);
    for (std::size_t k = 1; k < up.cells.offsets().size(); ++k) {
      out.cells.offsets().push_back(up.cells.offsets()[k] + cbase);
    }
    out.types.insert(out.types.end(), up.types.begin(), up.types.end());
    for (DataArray& a : out.point_data) append_tuples(a, up.pd.get(a.name()), 0, up.points.size());
    for (DataArray& a : out.cell_data) append_tuples(a, up.cd.get(a.name()), 0, up.types.size());
  }
  return out;
}


// ------------------------------------------------------------------------------------------------
// Summaries (io::summarize_file): the same checks of the structure, the values streamed.

std::optional<ArrayHeader> Reader::stream_array(pugi::xml_node el, const XmlWhere& w,
                                                const ArrayRequest& req,
                                                const io_detail::TupleStream::Consumer& consume,
                                                const std::function<void(const ArrayHeader&)>& ready) {
  std::optional<ArrayHeader> h = array_header(el, w, req);
  if (!h) return h;
  if (ready) ready(*h);
  if (h->format == "ascii") {
    // Text is parsed whole (ascii files are small next to the binary ones this pass is for).
    const std::optional<DataArray> a = read_array(el, w, req);
    if (a->tuples() > 0) consume(a->bytes(), a->tuples());
    h->values = a->size();
    return h;
  }
  XmlWhere dw;
  std::string storage;
  std::optional<ByteSource> src = payload_source(el, w, *h, dw, storage);
  io_detail::TupleStream stream(h->type, h->components, endian_ != kHostEndian, consume);
  StreamTarget target{stream};
  read_payload(*src, dw, h->bytes, h->unit, target);
  h->values = stream.tuples() * static_cast<std::uint64_t>(h->components);
  return h;
}

std::optional<ArraySummary> Reader::summarize_array(pugi::xml_node el, const XmlWhere& w,
                                                    const ArrayRequest& req) {
  // The type and components are known once the header is parsed, before the first piece.
  std::optional<ValueRanges> ranges;
  ScalarType type{};
  const auto h = stream_array(
      el, w, req, [&](const std::byte* v, std::size_t n) { ranges->add(type, v, n); },
      [&](const ArrayHeader& header) {
        type = header.type;
        ranges.emplace(header.components);
      });
  if (!h) return std::nullopt;
  const auto tuples = *h->values / static_cast<std::uint64_t>(h->components);
  return ArraySummary{h->name, h->type, h->components, tuples, std::move(*ranges)};
}

void Reader::summarize_attributes(pugi::xml_node el, const XmlWhere& w,
                                  std::optional<std::uint64_t> tuples, AttributesSummary& out) {
  if (!el) return;
  std::size_t index = 0;
  std::vector<std::string> names;
  for (pugi::xml_node a = el.child("DataArray"); a; a = a.next_sibling("DataArray"), ++index) {
    const XmlWhere aw = array_where(w, a, index);
    auto arr = summarize_array(a, aw, ArrayRequest{tuples, 0, true});
    if (!arr) continue;
    if (arr->name.empty()) arr->name = "Array " + num(index);
    if (std::find(names.begin(), names.end(), arr->name) != names.end()) {
      aw.fail("duplicate array name '" + printable(arr->name, 80) + "'");
    }
    names.push_back(arr->name);
    out.merge_array(std::move(*arr));
  }
  for (const auto& [role, name] : named_roles(el)) {
    if (out.find(std::string(name)) != nullptr) out.active[static_cast<std::size_t>(role)] = name;
  }
}

Bounds Reader::summarize_points(pugi::xml_node piece, const XmlWhere& w, std::uint64_t np) {
  const pugi::xml_node pel = piece.child("Points");
  if (!pel) {
    if (np == 0) return {};
    w.fail("missing <Points> element for NumberOfPoints=" + num(np));
  }
  const XmlWhere pw = w.child(pel, "Points");
  const pugi::xml_node da = pel.child("DataArray");
  if (!da) {
    if (np == 0) return {};
    pw.fail("missing <DataArray> with the point coordinates");
  }
  const XmlWhere aw = pw.child(da, "DataArray");
  ValueRanges ranges(3);
  ScalarType type{};
  bool finite = true;
  stream_array(
      da, aw, ArrayRequest{np, 3, false},
      [&](const std::byte* v, std::size_t n) {
        ranges.add(type, v, n);
        visit_scalar_type(type, [&](auto tag) {
          using T = decltype(tag);
          if constexpr (std::is_floating_point_v<T>) {
            const T* t = reinterpret_cast<const T*>(v);
            T sum = 0;  // NaN or infinite if any value is
            for (std::size_t i = 0; i < 3 * n; ++i) sum += t[i] * T(0);
            finite = finite && sum == 0;
          }
        });
      },
      [&](const ArrayHeader& h) { type = h.type; });
  if (!finite) {
    (void)read_points(piece, w, np);  // names the point
    aw.fail("non-finite coordinates");
  }
  Bounds b;
  if (np == 0) return b;
  for (int c = 0; c < 3; ++c) {
    b.min[c] = ranges.component(c).first;
    b.max[c] = ranges.component(c).second;
  }
  return b;
}

/// Calls f(value) for each of `n` integer values of `type` in host order (an Error through
/// `w` for floating types or values beyond Index).
template <class F>
void each_index(ScalarType type, const std::byte* v, std::size_t n, const XmlWhere& w, F&& f) {
  visit_scalar_type(type, [&](auto tag) {
    using T = decltype(tag);
    if constexpr (std::is_floating_point_v<T>) {
      w.fail("must have an integer type, not " + std::string(scalar_type_name(type)));
    } else {
      const T* t = reinterpret_cast<const T*>(v);
      for (std::size_t i = 0; i < n; ++i) {
        if constexpr (std::is_same_v<T, std::uint64_t>) {
          if (t[i] > static_cast<std::uint64_t>(std::numeric_limits<Index>::max())) {
            w.fail("value " + num(i) + " (" + num(t[i]) + ") is out of range");
          }
        }
        f(static_cast<Index>(t[i]));
      }
    }
  });
}

void Reader::count_cells(pugi::xml_node el, const XmlWhere& w, std::uint64_t ncells, int section,
                         std::map<CellType, std::uint64_t>& out) {
  ScalarType type{};
  const auto ready = [&](const ArrayHeader& h) { type = h.type; };
  const pugi::xml_node off_el = named_array(el, "offsets");
  if (section >= 0) {
    if (ncells == 0 && !off_el && !named_array(el, "connectivity")) return;
    if (!off_el) w.fail("missing DataArray 'offsets' for " + num(ncells) + " cells");
    const XmlWhere ow = w.child(off_el, "DataArray 'offsets'");
    Index prev = 0;
    std::uint64_t cell = 0;
    std::array<std::uint64_t, 5> by_size{};  // cells of 0-4 points, then of more
    std::uint64_t larger = 0;
    stream_array(
        off_el, ow, ArrayRequest{ncells, 1, false},
        [&](const std::byte* v, std::size_t n) {
          each_index(type, v, n, ow, [&](Index end) {
            if (end < prev) {
              ow.fail("offsets are not monotonic: cell " + num(cell) + " ends at " +
                      std::to_string(end) + " before it starts at " + std::to_string(prev));
            }
            const auto size = static_cast<std::uint64_t>(end - prev);
            ++(size < by_size.size() ? by_size[size] : larger);
            prev = end;
            ++cell;
          });
        },
        ready);
    for (std::size_t k = 0; k < by_size.size(); ++k) {
      if (by_size[k] > 0) out[poly_cell_type(section, k)] += by_size[k];
    }
    if (larger > 0) out[poly_cell_type(section, by_size.size())] += larger;
    if (prev > 0 && !named_array(el, "connectivity")) w.fail("missing DataArray 'connectivity'");
    return;
  }
  const pugi::xml_node tel = named_array(el, "types");
  if (!tel) {
    if (ncells != 0) w.fail("missing DataArray 'types'");
    return;
  }
  if (!off_el) w.fail("missing DataArray 'offsets' for " + num(ncells) + " cells");
  const XmlWhere tw = w.child(tel, "DataArray 'types'");
  std::array<std::uint64_t, 256> count{};
  std::uint64_t cell = 0;
  stream_array(
      tel, tw, ArrayRequest{ncells, 1, false},
      [&](const std::byte* v, std::size_t n) {
        each_index(type, v, n, tw, [&](Index t) {
          if (t < 0 || t > 255 || !is_valid_cell_type(static_cast<int>(t))) {
            tw.fail("cell " + num(cell) + " has unsupported cell type " + std::to_string(t));
          }
          ++count[static_cast<std::size_t>(t)];
          ++cell;
        });
      },
      ready);
  for (std::size_t t = 0; t < count.size(); ++t) {
    if (count[t] > 0) out[static_cast<CellType>(t)] += count[t];
  }
}

DatasetSummary Reader::summarize() {
  const auto [kind, ds, w] = open();
  DatasetSummary s;
  s.streamed = true;
  summarize_attributes(ds.child("FieldData"), w.child(ds.child("FieldData"), "FieldData"),
                       std::nullopt, s.field_data);
  std::size_t index = 0;
  if (kind == Kind::Image || kind == Kind::Structured) {
    s.kind = kind == Kind::Image ? 0 : 1;
    const Extent whole = read_extent(ds, "WholeExtent", w, false);
    if (kind == Kind::Image) {
      const ImageData img = image_geometry(ds, w, whole);
      s.dims = img.dims;
      s.origin = img.origin;
      s.spacing = img.spacing;
      s.bounds = img.bounds();
    } else {
      s.dims = extent_dims(whole);
    }
    try {
      s.points = checked_point_count(s.dims, "WholeExtent");
    } catch (const Error& e) {
      w.fail(e.what());
    }
    s.cells = structured_cell_count(s.dims);
    if (s.cells > 0) {
      ImageData shape;  // the cell type follows from the dimensions alone
      shape.dims = s.dims;
      CellType t = cell_type(shape, 0);
      if (kind == Kind::Structured) {
        StructuredGrid grid;
        grid.dims = s.dims;
        t = cell_type(grid, 0);
      }
      s.cell_types[t] = s.cells;
    }
    // The pieces' extents are checked to tile the whole one first, as the reader does.
    std::vector<pugi::xml_node> nodes;
    std::vector<Extent> extents;
    std::vector<XmlWhere> wheres;
    for (pugi::xml_node p = ds.child("Piece"); p; p = p.next_sibling("Piece"), ++index) {
      const XmlWhere pw = w.child(p, "Piece " + num(index));
      Extent ext = whole;
      if (attr(p, "Extent")) ext = read_extent(p, "Extent", pw, true);
      if (extent_empty(ext)) continue;
      if (extents.size() >= kMaxStructuredPieces) {
        pw.fail("more than " + num(kMaxStructuredPieces) + " pieces are not supported");
      }
      nodes.push_back(p);
      extents.push_back(ext);
      wheres.push_back(pw);
    }
    if (extents.empty()) w.fail("no <Piece> with a non-empty Extent");
    if ((extents.size() > 1 || extents[0] != whole) &&
        piece_boxes(whole, extents, wheres, w).overlapping) {
      // The ranges of overlapping pieces' ghost flags are not those of the assembled whole (see
      // assemble_structured): such files, which are small in practice, are summarised read.
      if (kind == Kind::Image) return isoforge::summarize(read_image(ds, w));
      return isoforge::summarize(read_structured(ds, w));
    }
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      const pugi::xml_node p = nodes[i];
      const XmlWhere& pw = wheres[i];
      const Dims d = extent_dims(extents[i]);
      const std::size_t np = extent_points(d, pw);
      summarize_attributes(p.child("PointData"), pw.child(p.child("PointData"), "PointData"), np,
                           s.point_data);
      summarize_attributes(p.child("CellData"), pw.child(p.child("CellData"), "CellData"),
                           structured_cell_count(d), s.cell_data);
      if (kind == Kind::Structured) s.bounds.merge(summarize_points(p, pw, np));
    }
    return s;
  }
  s.kind = kind == Kind::Poly ? 2 : 3;
  for (pugi::xml_node p = ds.child("Piece"); p; p = p.next_sibling("Piece"), ++index) {
    const XmlWhere pw = w.child(p, "Piece " + num(index));
    const std::uint64_t np = count_attr(p, "NumberOfPoints", pw);
    std::uint64_t nc = 0;
    std::array<std::uint64_t, 4> n{};
    if (kind == Kind::Poly) {
      for (int c = 0; c < 4; ++c) {
        n[c] = count_attr(p, kCount[c], pw, 0);
        if (__builtin_add_overflow(nc, n[c], &nc)) pw.fail("cell counts overflow");
      }
    } else {
      nc = count_attr(p, "NumberOfCells", pw);
    }
    s.points += np;
    s.cells += nc;
    s.bounds.merge(summarize_points(p, pw, np));
    summarize_attributes(p.child("PointData"), pw.child(p.child("PointData"), "PointData"), np,
                         s.point_data);
    summarize_attributes(p.child("CellData"), pw.child(p.child("CellData"), "CellData"), nc,
                         s.cell_data);
    if (kind == Kind::Poly) {
      for (int c = 0; c < 4; ++c) {
        const pugi::xml_node el = p.child(kCat[c]);
        if (!el) {
          if (n[c] != 0) {
            pw.fail(std::string("missing <") + kCat[c] + "> for " + kCount[c] + "=" + num(n[c]));
          }
          continue;
        }
        count_cells(el, pw.child(el, kCat[c]), n[c], c, s.cell_types);
      }
    } else {
      const pugi::xml_node cel = p.child("Cells");
      if (!cel) {
        if (nc != 0) pw.fail("missing <Cells> for NumberOfCells=" + num(nc));
        continue;
      }
      count_cells(cel, pw.child(cel, "Cells"), nc, -1, s.cell_types);
    }
  }
  return s;
}

Reader::Opened Reader::open() {
  split_appended();
  const pugi::xml_parse_result r =
      doc_.load_buffer_inplace(xml_.data(), xml_.size(), pugi::parse_default, pugi::encoding_utf8);
  if (!r) {
    const auto off = static_cast<std::uint64_t>(std::max<std::ptrdiff_t>(r.offset, 0));
    throw Error(at_byte(name_, std::min<std::uint64_t>(off, xml_size_),
                        std::string("malformed XML: ") + r.description()));
  }
  const pugi::xml_node root = doc_.document_element();
  if (!root) throw Error(at_byte(name_, 0, "not a VTK XML file: no root element"));
  if (std::string_view(root.name()) != "VTKFile") {
    throw Error(
        at_byte(name_, static_cast<std::uint64_t>(std::max<std::ptrdiff_t>(root.offset_debug(), 0)),
                "not a VTK XML file: the root element is <" + printable(root.name()) +
                    ">, expected <VTKFile>"));
  }
  const XmlWhere w = root_where("").child(root, "VTKFile");

  const auto type = attr(root, "type");
  if (!type) w.fail("missing attribute 'type'");
  Kind kind{};
  if (*type == "ImageData") {
    kind = Kind::Image;
  } else if (*type == "StructuredGrid") {
    kind = Kind::Structured;
  } else if (*type == "PolyData") {
    kind = Kind::Poly;
  } else if (*type == "UnstructuredGrid") {
    kind = Kind::Unstructured;
  } else if (!type->empty() && type->front() == 'P') {
    w.fail("type='" + printable(*type) +
           "' is a parallel (partitioned) file; read its piece files instead");
  } else {
    w.fail("type='" + printable(*type) +
           "' is not supported (supported: ImageData, StructuredGrid, PolyData, "
           "UnstructuredGrid)");
  }

  if (const auto v = attr(root, "version")) {
    const std::string_view s = trim_space(*v);
    const std::size_t dot = s.find('.');
    int major = -1, minor = 0;
    const bool ok = parse_number(s.substr(0, dot), major) &&
                    (dot == std::string_view::npos || parse_number(s.substr(dot + 1), minor));
    if (!ok || major < 0 || minor < 0)
      w.fail("version='" + printable(*v) + "' is not a version number");
    if (major > 2) {
      w.fail("version " + std::string(s) + " is newer than the supported versions 0.1-2.x");
    }
  }
  if (const auto v = attr(root, "byte_order")) {
    if (*v == "LittleEndian") {
      endian_ = Endian::Little;
    } else if (*v == "BigEndian") {
      endian_ = Endian::Big;
    } else {
      w.fail("byte_order='" + printable(*v) + "' is not LittleEndian or BigEndian");
    }
  }
  if (const auto v = attr(root, "header_type")) {
    if (*v == "UInt32") {
      header64_ = false;
    } else if (*v == "UInt64") {
      header64_ = true;
    } else {
      w.fail("header_type='" + printable(*v) + "' is not UInt32 or UInt64");
    }
  }
  if (const auto v = attr(root, "compressor"); v && !v->empty()) {
    for (const BlockCodec c : {BlockCodec::Zlib, BlockCodec::Lz4, BlockCodec::Lzma}) {
      if (*v == io_detail::block_codec_vtk_name(c)) codec_ = c;
    }
    if (!codec_) {
      w.fail("unknown compressor '" + printable(*v) +
             "' (supported: vtkZLibDataCompressor, vtkLZ4DataCompressor, "
             "vtkLZMADataCompressor)");
    }
    if (codec_ == BlockCodec::Lzma) budget_ = lzma_budget();
  }

  const pugi::xml_node ds = root.child(type->data());
  if (!ds) w.fail("missing <" + std::string(*type) + "> element");
  // Paths below name the dataset element, e.g. "PolyData/Piece 0/PointData/DataArray 'N'".
  const XmlWhere dw = root_where("").child(ds, std::string(*type));
  return {kind, ds, dw};
}

Dataset Reader::read() {
  const auto [kind, ds, dw] = open();
  Dataset out;
  switch (kind) {
    case Kind::Image:
      out = read_image(ds, dw);
      break;
    case Kind::Structured:
      out = read_structured(ds, dw);
      break;
    case Kind::Poly:
      out = read_poly(ds, dw);
      break;
    case Kind::Unstructured:
      out = read_unstructured(ds, dw);
      break;
  }
  try {
    validate(out);
  } catch (const Error& e) {
    throw Error(name_ + ": invalid dataset: " + e.what());
  }
  return out;
}

// ================================================================================================
// Writer
// ================================================================================================

void append_escaped(std::string& out, std::string_view s) {
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          out += "&#" + std::to_string(static_cast<int>(c)) + ";";
        } else {
          out += c;
        }
    }
  }
}


/// What the writer stores of one array: its XML attributes and its values as bytes (a view of a
/// dataset's storage: cell offsets and connectivity are written without being copied first).
struct ArrayView {
  std::string_view name;
  ScalarType type = ScalarType::Float32;
  int components = 1;
  std::size_t values = 0;  ///< scalars in all
  const std::byte* bytes = nullptr;
  /// `bytes` holds Index values written as `type` Int32 (cell ids that all fit).
  bool narrow = false;

  static ArrayView of(const DataArray& a) {
    return {a.name(), a.type(), a.components(), a.size(), a.bytes()};
  }
  /// Bytes written (of `type`).
  [[nodiscard]] std::size_t size_bytes() const { return values * scalar_size(type); }

  /// Writes values [first, first + count) as `type` to `out`, in the host's byte order.
  void copy_values(std::size_t first, std::size_t count, std::byte* out) const {
    if (!narrow) {
      std::memcpy(out, bytes + first * scalar_size(type), count * scalar_size(type));
      return;
    }
    const auto* in = reinterpret_cast<const Index*>(bytes) + first;
    auto* to = reinterpret_cast<std::int32_t*>(out);
    parallel_for_range(count, std::size_t{1} << 16, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) to[i] = static_cast<std::int32_t>(in[i]);
    });
  }
};

/// One array's binary payload in the appended section: its header words and its data (a view of
/// the dataset, or compressed blocks, or byte-swapped values on a big-endian host).
struct Payload {
  std::string header;
  const std::byte* data = nullptr;
  std::size_t size = 0;
  io_detail::CompressedBlocks compressed;
  std::vector<std::byte> converted;  ///< narrowed and/or byte-swapped values
  /// Uncompressed narrowed ids: `data` is the array's view, narrowed piece by piece as written.
  std::optional<ArrayView> narrowed;
};

/// One thread writing buffers to a stream in turn, for the whole document (a thread started for
/// each slice cost more than some of the writes). The stream is the caller's again after wait().
class BackgroundWrites {
 public:
  explicit BackgroundWrites(std::ostream& os) : os_(os), thread_([this] { run(); }) {}
  BackgroundWrites(const BackgroundWrites&) = delete;
  BackgroundWrites& operator=(const BackgroundWrites&) = delete;
  ~BackgroundWrites() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    changed_.notify_all();
    thread_.join();
  }

  /// Waits until the buffer before is written, then starts writing [data, data + n) (which must
  /// stay until the next write() or wait()).
  void write(const std::byte* data, std::size_t n) {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [this] { return data_ == nullptr; });
    data_ = data;
    size_ = n;
    lock.unlock();
    changed_.notify_all();
  }
  /// Waits until the buffer handed over is written.
  void wait() {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [this] { return data_ == nullptr; });
  }

 private:
  void run() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      changed_.wait(lock, [this] { return data_ != nullptr || stop_; });
      if (data_ == nullptr) return;  // stopped
      const std::byte* data = data_;
      const std::size_t n = size_;
      lock.unlock();
      os_.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(n));
      lock.lock();
      data_ = nullptr;
      changed_.notify_all();
    }
  }

  std::ostream& os_;
  std::mutex mutex_;
  std::condition_variable changed_;
  const std::byte* data_ = nullptr;  // being written (nullptr: idle)
  std::size_t size_ = 0;
  bool stop_ = false;
  std::thread thread_;  // last: started once the members above exist
};

class Writer {
 public:
  explicit Writer(const VtkXmlWriteOptions& o)
      : enc_(o.encoding),
        compress_(o.encoding != VtkXmlEncoding::Ascii && o.compress),
        codec_(o.compressor == VtkXmlCompressor::Lz4 ? BlockCodec::Lz4 : BlockCodec::Zlib),
        level_(o.level),
        id_type_(o.id_type),
        callback_(o.progress) {
    if (compress_ && o.level != 0) {
      const auto [lo, hi] = vtk_xml_level_range(o.compressor);
      if (o.level < lo || o.level > hi) {
        throw Error("VTK XML writer: " + std::string(vtk_xml_compressor_name(o.compressor)) +
                    " level " + std::to_string(o.level) + " is out of range " +
                    std::to_string(lo) + "-" + std::to_string(hi));
      }
    }
  }

  // The XML is built in memory while the arrays are encoded (90% of the progress, by values
  // encoded); then the XML and the payloads are written out, the payloads straight from the
  // arrays or from their compressed blocks.
  void write(DatasetRef ds, std::ostream& os) {
    os_ = &os;
    // Compressed appended data goes to a seekable stream (a file) as it is compressed, slice by
    // slice: the XML holds a fixed-width place for each offset and each array a place for its
    // block sizes, both filled in afterwards. Else the blocks are kept until the XML is done.
    const std::streampos base = os.tellp();
    streaming_ = compress_ && enc_ == VtkXmlEncoding::Appended && base != std::streampos(-1) &&
                 kHostEndian == Endian::Little;
    progress_ = io_detail::Progress(callback_, io_detail::payload_values(ds), "writing", 0,
                                    streaming_ ? 1.0 : 0.9);
    x_ = "<?xml version=\"1.0\"?>\n<VTKFile type=\"";
    const char* type =
        ds.visit(Overloaded{[](const ImageData&) { return "ImageData"; },
                            [](const StructuredGrid&) { return "StructuredGrid"; },
                            [](const PolyData&) { return "PolyData"; },
                            [](const UnstructuredGrid&) { return "UnstructuredGrid"; }});
    x_ += type;
    x_ += "\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"";
    if (compress_) {
      x_ += " compressor=\"";
      x_ += io_detail::block_codec_vtk_name(codec_);
      x_ += '"';
    }
    x_ += ">\n";
    narrow_ids_ = narrow_ids(ds);
    ds.visit([&](const auto& d) { body(d); });
    constexpr std::string_view kAppended = "  <AppendedData encoding=\"raw\">\n   _";
    constexpr std::string_view kAppendedEnd = "\n  </AppendedData>\n";
    const bool appended = enc_ == VtkXmlEncoding::Appended;
    if (streaming_) {
      write_streaming(os, base, kAppended, kAppendedEnd);
      return;
    }
    const std::size_t size =
        x_.size() + (appended ? kAppended.size() + app_size_ + kAppendedEnd.size() : 0);
    io_detail::Progress out(callback_, size, "writing", progress_.to(), 1);
    if (appended) {
      x_ += kAppended;
      io_detail::write_blocks(os, x_.data(), x_.size(), out);
      std::unique_ptr<std::byte[]> piece;
      for (const Payload& p : app_) {
        io_detail::write_blocks(os, p.header.data(), p.header.size(), out);
        if (!p.narrowed) {
          io_detail::write_blocks(os, reinterpret_cast<const char*>(p.data), p.size, out);
          continue;
        }
        // Narrowed a piece at a time: memory stays the dataset's.
        constexpr std::size_t kPiece = std::size_t{1} << 20;  // values
        if (!piece) piece.reset(new std::byte[kPiece * sizeof(std::int32_t)]);
        for (std::size_t v = 0; v < p.narrowed->values; v += kPiece) {
          const std::size_t m = std::min(kPiece, p.narrowed->values - v);
          p.narrowed->copy_values(v, m, piece.get());
          io_detail::write_blocks(os, reinterpret_cast<const char*>(piece.get()),
                                  m * sizeof(std::int32_t), out);
        }
      }
      x_ = kAppendedEnd;
    }
    x_ += "</VTKFile>\n";
    io_detail::write_blocks(os, x_.data(), x_.size(), out);
    out.finish();
  }

 private:
  void indent(int n) { x_.append(static_cast<std::size_t>(n) * 2, ' '); }

  void extent_attr(const char* name, const Dims& d) {
    x_ += ' ';
    x_ += name;
    x_ += "=\"";
    for (int a = 0; a < 3; ++a) {
      x_ += a ? " 0 " : "0 ";
      append_number(x_, d[a] - 1);
    }
    x_ += '"';
  }
  void vec_attr(const char* name, const Vec3& v) {
    x_ += ' ';
    x_ += name;
    x_ += "=\"";
    for (int a = 0; a < 3; ++a) {
      if (a) x_ += ' ';
      append_number(x_, v[a]);
    }
    x_ += '"';
  }

  void body(const ImageData& d) {
    x_ += "  <ImageData";
    extent_attr("WholeExtent", d.dims);
    vec_attr("Origin", d.origin);
    vec_attr("Spacing", d.spacing);
    x_ += ">\n";
    field(d.field_data);
    x_ += "    <Piece";
    extent_attr("Extent", d.dims);
    x_ += ">\n";
    attributes("PointData", d.point_data);
    attributes("CellData", d.cell_data);
    x_ += "    </Piece>\n  </ImageData>\n";
  }
  void body(const StructuredGrid& d) {
    x_ += "  <StructuredGrid";
    extent_attr("WholeExtent", d.dims);
    x_ += ">\n";
    field(d.field_data);
    x_ += "    <Piece";
    extent_attr("Extent", d.dims);
    x_ += ">\n";
    attributes("PointData", d.point_data);
    attributes("CellData", d.cell_data);
    points(d.points);
    x_ += "    </Piece>\n  </StructuredGrid>\n";
  }
  void body(const PolyData& d) {
    x_ += "  <PolyData>\n";
    field(d.field_data);
    x_ += "    <Piece NumberOfPoints=\"" + num(d.points.size()) + "\" NumberOfVerts=\"" +
          num(d.verts.size()) + "\" NumberOfLines=\"" + num(d.lines.size()) +
          "\" NumberOfStrips=\"" + num(d.strips.size()) + "\" NumberOfPolys=\"" +
          num(d.polys.size()) + "\">\n";
    attributes("PointData", d.point_data);
    attributes("CellData", d.cell_data);
    points(d.points);
    cells("Verts", d.verts);
    cells("Lines", d.lines);
    cells("Strips", d.strips);
    cells("Polys", d.polys);
    x_ += "    </Piece>\n  </PolyData>\n";
  }
  void body(const UnstructuredGrid& d) {
    x_ += "  <UnstructuredGrid>\n";
    field(d.field_data);
    x_ += "    <Piece NumberOfPoints=\"" + num(d.points.size()) + "\" NumberOfCells=\"" +
          num(d.types.size()) + "\">\n";
    attributes("PointData", d.point_data);
    attributes("CellData", d.cell_data);
    points(d.points);
    x_ += "      <Cells>\n";
    cell_arrays(d.cells, 4);
    // CellType is one byte holding VTK's cell type number: the types are written as they are.
    static_assert(sizeof(CellType) == 1);
    array({"types", ScalarType::UInt8, 1, d.types.size(),
           reinterpret_cast<const std::byte*>(d.types.data())},
          4, false);
    x_ += "      </Cells>\n";
    x_ += "    </Piece>\n  </UnstructuredGrid>\n";
  }

  void field(const Attributes& a) {
    if (a.empty()) return;
    x_ += "    <FieldData>\n";
    for (const DataArray& arr : a) array(ArrayView::of(arr), 3, true);
    x_ += "    </FieldData>\n";
  }
  void attributes(const char* tag, const Attributes& a) {
    static constexpr std::pair<const char*, AttributeRole> kRoles[] = {
        {"Scalars", AttributeRole::Scalars},
        {"Vectors", AttributeRole::Vectors},
        {"Normals", AttributeRole::Normals},
        {"Tensors", AttributeRole::Tensors},
        {"TCoords", AttributeRole::TCoords}};
    x_ += "      <";
    x_ += tag;
    for (const auto& [key, role] : kRoles) {
      const std::string& n = a.active_name(role);
      if (n.empty()) continue;
      x_ += ' ';
      x_ += key;
      x_ += "=\"";
      append_escaped(x_, n);
      x_ += '"';
    }
    x_ += ">\n";
    for (const DataArray& arr : a) array(ArrayView::of(arr), 4, false);
    x_ += "      </";
    x_ += tag;
    x_ += ">\n";
  }
  void points(const Points& p) {
    x_ += "      <Points>\n";
    ArrayView v = ArrayView::of(p.array());
    if (v.name.empty()) v.name = "Points";
    array(v, 4, false);
    x_ += "      </Points>\n";
  }
  /// Whether the cell ids are written as Int32: every id and offset fits (ids lie in
  /// [0, points), offsets in [0, connectivity size]; the dataset is validated), unless Int64 is
  /// asked for. \throw Error if Int32 is asked for and they do not fit.
  bool narrow_ids(DatasetRef ds) const {
    if (id_type_ == VtkXmlIdType::Int64) return false;
    constexpr auto kMax = static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max());
    std::size_t largest = 0;  // the largest id or offset that can occur
    const auto add = [&](std::size_t points, const CellArray& c) {
      if (c.connectivity().empty()) return;
      largest = std::max({largest, points - 1, c.connectivity().size()});
    };
    ds.visit(Overloaded{[](const ImageData&) {}, [](const StructuredGrid&) {},
                        [&](const PolyData& d) {
                          for (const CellArray* c : {&d.verts, &d.lines, &d.strips, &d.polys}) {
                            add(d.points.size(), *c);
                          }
                        },
                        [&](const UnstructuredGrid& d) { add(d.points.size(), d.cells); }});
    if (largest <= kMax) return true;
    if (id_type_ == VtkXmlIdType::Int32) {
      throw Error("VTK XML writer: id type Int32 cannot hold the cell ids and offsets (up to " +
                  num(largest) + "); use Int64 or Auto");
    }
    return false;
  }

  void cell_arrays(const CellArray& c, int level) {
    static_assert(std::is_same_v<Index, std::int64_t>);
    const auto& conn = c.connectivity();
    const auto& offs = c.offsets();  // [0, end of cell 0, ...]: VTK stores the ends
    const ScalarType type = narrow_ids_ ? ScalarType::Int32 : ScalarType::Int64;
    array({"connectivity", type, 1, conn.size(), reinterpret_cast<const std::byte*>(conn.data()),
           narrow_ids_},
          level, false);
    array(
        {"offsets", type, 1, offs.empty() ? 0 : offs.size() - 1,
         offs.empty() ? nullptr : reinterpret_cast<const std::byte*>(offs.data() + 1), narrow_ids_},
        level, false);
  }
  void cells(const char* tag, const CellArray& c) {
    x_ += "      <";
    x_ += tag;
    x_ += ">\n";
    cell_arrays(c, 4);
    x_ += "      </";
    x_ += tag;
    x_ += ">\n";
  }

  /// Header + (compressed) data of one array, little-endian.
  Payload payload(const ArrayView& a) {
    Payload p;
    const std::size_t n = a.size_bytes();
    const std::size_t es = scalar_size(a.type);
    const std::byte* bytes = a.bytes;
    const bool swap = kHostEndian != Endian::Little && es > 1 && n > 0;
    if (a.narrow && !compress_ && enc_ == VtkXmlEncoding::Appended && !swap) {
      p.narrowed = a;  // narrowed as written, a piece at a time
    } else if (a.narrow || swap) {
      p.converted.resize(n);
      a.copy_values(0, a.values, p.converted.data());
      if (swap) io_detail::swap_elements(p.converted.data(), a.values, es);
      bytes = p.converted.data();
    }
    auto put_word = [&](std::uint64_t v) {
      unsigned char b[8];
      for (int i = 0; i < 8; ++i) b[i] = static_cast<unsigned char>(v >> (8 * i));
      p.header.append(reinterpret_cast<const char*>(b), 8);
    };
    if (!compress_) {
      put_word(n);
      p.data = bytes;
      p.size = n;
      progress_.add(a.values);
      return p;
    }
    std::size_t reported = 0;
    p.compressed = io_detail::compress_blocks(
        codec_, level_, bytes, n, kWriteBlockSize, [&](std::size_t done) {
          progress_.add((done - reported) / es);
          reported = done;
        });
    put_word(p.compressed.sizes.size());
    put_word(kWriteBlockSize);
    put_word(n % kWriteBlockSize);
    for (const std::uint64_t c : p.compressed.sizes) put_word(c);
    p.data = p.compressed.data.get();
    p.size = p.compressed.bytes;
    return p;
  }

  /// Inline data (ascii, base64) goes out as it is encoded: the XML so far is written whenever it
  /// passes 4 MiB, so that memory stays the dataset's whatever the file's size. (Appended data
  /// has offsets to fill in, and stays until write() ends.)
  void spill() {
    constexpr std::size_t kSpill = std::size_t{4} << 20;
    if (enc_ == VtkXmlEncoding::Appended || x_.size() < kSpill) return;
    os_->write(x_.data(), static_cast<std::streamsize>(x_.size()));
    x_.clear();
  }

  /// The values of `a` as text, six to a line, converted a piece at a time (narrowed ids too).
  void ascii_values(const ArrayView& a, int level) {
    constexpr std::size_t kPiece = std::size_t{1} << 16;  // values
    visit_scalar_type(a.type, [&](auto tag) {
      using T = decltype(tag);
      std::vector<T> piece(std::min(kPiece, a.values));
      for (std::size_t first = 0; first < a.values; first += kPiece) {
        const std::size_t m = std::min(kPiece, a.values - first);
        a.copy_values(first, m, reinterpret_cast<std::byte*>(piece.data()));
        for (std::size_t k = 0; k < m; ++k) {
          const std::size_t i = first + k;
          if (i % 6 == 0) {
            if (i) x_ += '\n';
            indent(level);
          } else {
            x_ += ' ';
          }
          if constexpr (std::is_same_v<T, std::int8_t> || std::is_same_v<T, std::uint8_t>) {
            append_number(x_, static_cast<int>(piece[k]));
          } else {
            append_number(x_, piece[k]);
          }
        }
        progress_.add(m);
        spill();
      }
    });
    if (a.values > 0) x_ += '\n';
  }

  void array(const ArrayView& a, int level, bool with_tuples) {
    indent(level);
    x_ += "<DataArray type=\"";
    x_ += scalar_type_name(a.type);
    x_ += "\" Name=\"";
    append_escaped(x_, a.name);
    x_ += "\" NumberOfComponents=\"" + std::to_string(a.components) + "\"";
    if (with_tuples) {
      x_ += " NumberOfTuples=\"" + num(a.values / static_cast<std::size_t>(a.components)) + "\"";
    }
    switch (enc_) {
      case VtkXmlEncoding::Ascii: {
        x_ += " format=\"ascii\">\n";
        ascii_values(a, level + 1);
        break;
      }
      case VtkXmlEncoding::Base64: {
        x_ += " format=\"binary\">\n";
        const Payload p = payload(a);
        indent(level + 1);
        Base64Encoder enc(x_);
        enc.put(reinterpret_cast<const std::byte*>(p.header.data()), p.header.size());
        if (compress_) enc.finish();  // VTK encodes the compression header on its own
        constexpr std::size_t kPiece = std::size_t{3} << 20;  // bytes: whole base64 groups
        for (std::size_t at = 0; at < p.size; at += kPiece) {
          enc.put(p.data + at, std::min(kPiece, p.size - at));
          spill();
        }
        enc.finish();
        x_ += '\n';
        break;
      }
      case VtkXmlEncoding::Appended: {
        if (streaming_) {
          x_ += " format=\"appended\" offset=\"";
          deferred_.push_back({a, x_.size()});
          x_.append(kOffsetField, ' ');  // the offset, its closing quote and padding, later
          x_ += "/>\n";
          return;
        }
        x_ += " format=\"appended\" offset=\"" + num(app_size_) + "\"/>\n";
        Payload p = payload(a);
        app_size_ += p.header.size() + p.size;
        app_.push_back(std::move(p));
        return;
      }
    }
    indent(level);
    x_ += "</DataArray>\n";
  }

  /// Characters kept for an offset in the XML: up to 20 digits, the quote, spaces (which XML
  /// allows before the tag's end).
  static constexpr std::size_t kOffsetField = 21;

  /// Writes the XML with the offsets left blank, then each deferred array: its header words (the
  /// block sizes as zeros), its blocks compressed slice by slice and written at once, then its
  /// header again with the sizes; then the offsets into the XML and the end of the document.
  /// Memory: two slices of compressed blocks (one compressed while the other is written), whatever
  /// the dataset's size.
  void write_streaming(std::ostream& os, std::streampos base, std::string_view appended,
                       std::string_view appended_end) {
    x_ += appended;
    os.write(x_.data(), static_cast<std::streamsize>(x_.size()));
    progress_.add(0);  // the start
    std::vector<std::uint64_t> offsets;
    std::uint64_t at = 0;  // bytes of the appended data so far
    std::string header;
    // Each slice is written by another thread while the next one is compressed, into the storage
    // of the slice before: two buffers in turn for the whole document, their pages touched once
    // (fresh pages cost the kernel's zeroing: 8% of a surface's CPU time when every array took
    // two new ones).
    std::size_t largest = 0;
    for (const Deferred& d : deferred_) largest = std::max(largest, d.array.size_bytes());
    const std::size_t slice_blocks =
        (std::min(largest, kStreamSlice) + kWriteBlockSize - 1) / kWriteBlockSize;
    io_detail::CompressedBlocks writing =
        io_detail::compress_storage(codec_, kWriteBlockSize, slice_blocks);
    io_detail::CompressedBlocks spare =
        io_detail::compress_storage(codec_, kWriteBlockSize, slice_blocks);
    std::unique_ptr<std::byte[]> narrowed;  // a slice of narrowed ids
    BackgroundWrites writes(os);
    for (const Deferred& d : deferred_) {
      offsets.push_back(at);
      const ArrayView& a = d.array;
      const std::size_t n = a.size_bytes();
      const std::size_t es = scalar_size(a.type);
      const std::size_t nblocks = (n + kWriteBlockSize - 1) / kWriteBlockSize;
      const auto put_word = [&header](std::uint64_t v) {
        unsigned char b[8];
        for (int i = 0; i < 8; ++i) b[i] = static_cast<unsigned char>(v >> (8 * i));
        header.append(reinterpret_cast<const char*>(b), 8);
      };
      std::vector<std::uint64_t> sizes;
      sizes.reserve(nblocks);
      const auto make_header = [&] {
        header.clear();
        put_word(nblocks);
        put_word(kWriteBlockSize);
        put_word(n % kWriteBlockSize);
        for (std::size_t b = 0; b < nblocks; ++b) put_word(b < sizes.size() ? sizes[b] : 0);
      };
      make_header();
      const std::streampos header_at = os.tellp();
      os.write(header.data(), static_cast<std::streamsize>(header.size()));
      std::uint64_t data_bytes = 0;
      std::size_t reported = 0;
      for (std::size_t s = 0; s < n; s += kStreamSlice) {
        const std::size_t m = std::min(kStreamSlice, n - s);
        const std::byte* in = a.bytes + s;
        if (a.narrow) {  // narrowed a slice at a time
          if (!narrowed) narrowed.reset(new std::byte[kStreamSlice]);
          a.copy_values(s / es, m / es, narrowed.get());
          in = narrowed.get();
        }
        io_detail::CompressedBlocks c = io_detail::compress_blocks(
            codec_, level_, in, m, kWriteBlockSize,
            [&](std::size_t done) {
              progress_.add((s + done - reported) / es);
              reported = s + done;
            },
            std::move(spare));
        sizes.insert(sizes.end(), c.sizes.begin(), c.sizes.end());
        data_bytes += c.bytes;
        writes.wait();
        spare = std::move(writing);
        writing = std::move(c);
        writes.write(writing.data.get(), writing.bytes);
      }
      writes.wait();
      if (!os) throw Error("VTK XML writer: writing the compressed data failed");
      const std::streampos end = os.tellp();
      make_header();
      os.seekp(header_at);
      os.write(header.data(), static_cast<std::streamsize>(header.size()));
      os.seekp(end);
      at += header.size() + data_bytes;
    }
    x_.assign(appended_end);
    x_ += "</VTKFile>\n";
    os.write(x_.data(), static_cast<std::streamsize>(x_.size()));
    const std::streampos end = os.tellp();
    for (std::size_t i = 0; i < deferred_.size(); ++i) {
      std::string field = num(offsets[i]) + '"';
      field.resize(kOffsetField, ' ');
      os.seekp(base + static_cast<std::streamoff>(deferred_[i].field));
      os.write(field.data(), static_cast<std::streamsize>(field.size()));
    }
    os.seekp(end);
    progress_.finish();
  }

  /// Input bytes compressed between two writes when streaming (whole blocks).
  static constexpr std::size_t kStreamSlice = 16 * kWriteBlockSize;  // 4 MiB

  struct Deferred {
    ArrayView array;
    std::size_t field;  // where its offset goes in the XML
  };

  VtkXmlEncoding enc_;
  bool streaming_ = false;
  std::vector<Deferred> deferred_;
  bool compress_;
  BlockCodec codec_;
  int level_;
  VtkXmlIdType id_type_;
  bool narrow_ids_ = false;  // cell ids written as Int32
  const ProgressCallback& callback_;
  io_detail::Progress progress_;  // of building the document
  std::string x_;                 // XML text
  std::ostream* os_ = nullptr;    // where write() writes
  std::vector<Payload> app_;      // the appended section, array by array
  std::size_t app_size_ = 0;      // its bytes so far
};


}  // namespace

namespace {

template <class Result = Dataset>
Result read_xml(const io_detail::FileSource& data, std::string_view name,
                io_detail::Progress* progress, std::uint64_t progress_base) {
  try {
    Reader r(data, name, progress, progress_base);
    if constexpr (std::is_same_v<Result, DatasetSummary>) {
      return r.summarize();
    } else {
      return r.read();
    }
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw Error(std::string(name) + ": out of memory while reading the file");
  } catch (const std::exception& e) {
    throw Error(std::string(name) + ": " + e.what());
  }
}

}  // namespace

Dataset read_vtk_xml(std::span<const std::byte> data, std::string_view name) {
  return read_xml(data, name, nullptr, 0);
}

Dataset read_vtk_xml(const std::filesystem::path& path, const ProgressCallback& progress) {
  return io_detail::read_with_progress(
      path, progress,
      [&](const io_detail::FileSource& src, io_detail::Progress* p, std::uint64_t base) {
        return read_xml(src, path.string(), p, base);
      });
}

namespace io_detail {

DatasetSummary summarize_vtk_xml(std::span<const std::byte> data, std::string_view name) {
  return read_xml<DatasetSummary>(data, name, nullptr, 0);
}

DatasetSummary summarize_vtk_xml(const std::filesystem::path& path,
                                 const ProgressCallback& progress) {
  return read_with_progress(
      path, progress, [&](const FileSource& src, Progress* p, std::uint64_t base) {
        return read_xml<DatasetSummary>(src, path.string(), p, base);
      });
}

std::vector<std::byte> decode_vtk_xml_block(std::span<const std::byte> data,
                                            const VtkXmlBlockFormat& format,
                                            std::optional<std::uint64_t> expected, std::size_t unit,
                                            std::string_view name) {
  if (unit == 0) throw Error(std::string(name) + ": decode_vtk_xml_block: unit is 0");
  try {
    Reader r(data, name);
    return r.decode_block(format, expected, unit);
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw Error(std::string(name) + ": out of memory while decoding a data array");
  }
}

}  // namespace io_detail

std::string_view vtk_xml_compressor_name(VtkXmlCompressor compressor) {
  return compressor == VtkXmlCompressor::Lz4 ? "lz4" : "zlib";
}

std::pair<int, int> vtk_xml_level_range(VtkXmlCompressor compressor) {
  (void)compressor;  // both take 1-12 (libdeflate's levels; LZ4 fast and HC 2-12)
  return {1, 12};
}

std::string_view vtk_xml_extension(DatasetRef ds) {
  return ds.visit(Overloaded{[](const ImageData&) { return std::string_view(".vti"); },
                             [](const StructuredGrid&) { return std::string_view(".vts"); },
                             [](const PolyData&) { return std::string_view(".vtp"); },
                             [](const UnstructuredGrid&) { return std::string_view(".vtu"); }});
}

void write_vtk_xml(DatasetRef ds, std::ostream& out, const VtkXmlWriteOptions& options) {
  try {
    validate(ds);
  } catch (const Error& e) {
    throw Error(std::string("VTK XML writer: invalid ") + std::string(dataset_type_name(ds)) +
                ": " + e.what());
  }
  Writer w(options);
  w.write(ds, out);
  if (!out) throw Error("VTK XML writer: writing to the stream failed");
}

void write_vtk_xml(DatasetRef ds, const std::filesystem::path& path,
                   const VtkXmlWriteOptions& options) {
  const std::string want(vtk_xml_extension(ds));
  const std::string ext = ascii_lower(path.extension().string());
  if (ext != want) {
    std::filesystem::path fixed = path;
    fixed.replace_extension(want);
    throw Error(path.string() + ": " + std::string(dataset_type_name(ds)) + " is written as " +
                want + ", not '" + path.extension().string() + "' (use " + fixed.string() + ")");
  }
  try {
    validate(ds);
  } catch (const Error& e) {
    throw Error(path.string() + ": cannot write invalid " + std::string(dataset_type_name(ds)) +
                ": " + e.what());
  }
  AtomicFile file(path);
  // Raw, base64, ascii and LZ4 files are about the arrays' size or more; zlib files are often a
  // fraction of it, and take long enough to compress that allocating as they go costs nothing.
  const bool zlib = options.compress && options.encoding != VtkXmlEncoding::Ascii &&
                    options.compressor == VtkXmlCompressor::Zlib;
  if (!zlib) file.reserve(io_detail::payload_bytes(ds) + (std::uint64_t{1} << 16));
  Writer w(options);
  w.write(ds, file.stream());
  file.commit();
}

}  // namespace isoforge
