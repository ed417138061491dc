// OpenVDB .vdb io: validated reading and atomic writing.
//
// References implemented:
// - The OpenVDB file format as written by OpenVDB 10 (io/Archive, io/GridDescriptor,
//   io/Compression, tree/RootNode, InternalNode, LeafNode): header, metadata maps, grid
//   descriptors and offsets, transforms (math/Maps), 5-4-3 tree topology and buffers with
//   active-mask, zip and Blosc compression (format versions 222-224).
// - The Blosc 1.x chunk header (version, flags, typesize, nbytes, blocksize, cbytes).
// - K. Museth, "VDB: High-resolution sparse volumes with dynamic topology", ACM TOG 32(3), 2013.
//
// Reading never hands OpenVDB bytes that isoforge has not walked first (see vdb.hpp): every
// count and size is checked against the bytes that remain, the grid is copied into a bounded
// in-memory stream that throws at its end, and metadata whose OpenVDB reader trusts internal
// counts is dropped.

#include "isoforge/io/vdb.hpp"

#include <openvdb/io/GridDescriptor.h>
#include <openvdb/io/io.h>
#include <openvdb/math/Transform.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <istream>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <streambuf>

#include "isoforge/core/error.hpp"
#include "isoforge/io/atomic_file.hpp"
#include "isoforge/sparse/grid.hpp"

namespace isoforge {

namespace {

namespace vio = openvdb::io;

constexpr std::uint32_t kMinFormat = 222;  // OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION
constexpr std::uint32_t kMaxFormat = 224;  // OPENVDB_FILE_VERSION_MULTIPASS_IO (OpenVDB 10)
static_assert(openvdb::OPENVDB_FILE_VERSION == kMaxFormat, "walker written for format 224");
constexpr const char* kHalfSuffix = "_HalfFloat";
constexpr char kNameSep = '\x1e';  // OpenVDB's unique-name separator ("name" SEP "N")
constexpr const char* kFloatTree = "Tree_float_5_4_3";

// ---------------------------------------------------------------------------------------------
// Byte sources and a bounds-checked cursor
// ---------------------------------------------------------------------------------------------

class VdbSource {
 public:
  virtual ~VdbSource() = default;
  [[nodiscard]] virtual std::uint64_t size() const = 0;
  // Copies [offset, offset + n), which the caller has checked lies within size().
  virtual void read(std::uint64_t offset, void* dst, std::size_t n) const = 0;
};

class SpanSource final : public VdbSource {
 public:
  explicit SpanSource(std::span<const std::byte> data) : data_(data) {}
  [[nodiscard]] std::uint64_t size() const override { return data_.size(); }
  void read(std::uint64_t offset, void* dst, std::size_t n) const override {
    if (n) std::memcpy(dst, data_.data() + offset, n);
  }
  [[nodiscard]] std::span<const std::byte> bytes() const { return data_; }

 private:
  std::span<const std::byte> data_;
};

class FileSource final : public VdbSource {
 public:
  FileSource(const std::filesystem::path& path, const std::string& name) : name_(name) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw Error(name + ": file does not exist");
    if (std::filesystem::is_directory(path, ec)) throw Error(name + ": is a directory");
    in_.open(path, std::ios::binary);
    if (!in_) throw Error(name + ": cannot open for reading");
    in_.seekg(0, std::ios::end);
    const auto end = in_.tellg();
    if (end < 0) throw Error(name + ": cannot determine the file size");
    size_ = static_cast<std::uint64_t>(end);
  }
  [[nodiscard]] std::uint64_t size() const override { return size_; }
  void read(std::uint64_t offset, void* dst, std::size_t n) const override {
    if (n == 0) return;
    in_.clear();
    in_.seekg(static_cast<std::streamoff>(offset));
    in_.read(static_cast<char*>(dst), static_cast<std::streamsize>(n));
    if (!in_) throw Error(at_byte(name_, offset, "read error"));
  }

 private:
  std::string name_;
  mutable std::ifstream in_;
  std::uint64_t size_ = 0;
};

// Reads a VdbSource front to back within [pos, end), throwing an Error naming the file, the
// absolute byte offset (pos + base) and what was being read when the bytes run out.
class Cursor {
 public:
  Cursor(const VdbSource& src, const std::string& name, std::uint64_t pos, std::uint64_t end,
         std::uint64_t base = 0)
      : src_(&src), name_(&name), pos_(pos), end_(end), base_(base) {}

  [[nodiscard]] std::uint64_t pos() const { return pos_; }
  [[nodiscard]] std::uint64_t remaining() const { return end_ - pos_; }
  [[nodiscard]] std::uint64_t abs(std::uint64_t p) const { return p + base_; }
  [[nodiscard]] const std::string& name() const { return *name_; }

  [[noreturn]] void fail(const std::string& what) const {
    throw Error(at_byte(*name_, abs(pos_), what));
  }
  [[noreturn]] void fail_at(std::uint64_t p, const std::string& what) const {
    throw Error(at_byte(*name_, abs(p), what));
  }

  void need(std::uint64_t n, const char* what) const {
    if (n > remaining()) {
      fail("truncated: " + std::string(what) + " needs " + std::to_string(n) + " bytes but only " +
           std::to_string(remaining()) + " remain");
    }
  }
  void skip(std::uint64_t n, const char* what) {
    need(n, what);
    pos_ += n;
  }
  void seek(std::uint64_t p) { pos_ = p; }
  void bytes(void* dst, std::size_t n, const char* what) {
    need(n, what);
    src_->read(pos_, dst, n);
    pos_ += n;
  }
  template <class T>
  T get(const char* what) {
    T v{};
    bytes(&v, sizeof(T), what);
    return v;  // little-endian hosts only (as OpenVDB itself)
  }
  // OpenVDB's readString: uint32 length + bytes.
  std::string string(const char* what) {
    const auto n = get<std::uint32_t>(what);
    need(n, what);
    std::string s(n, '\0');
    bytes(s.data(), n, what);
    return s;
  }

 private:
  const VdbSource* src_;
  const std::string* name_;
  std::uint64_t pos_, end_, base_;
};

static_assert(std::endian::native == std::endian::little, "VDB files are little-endian");

// ---------------------------------------------------------------------------------------------
// VdbHeader, metadata, transform
// ---------------------------------------------------------------------------------------------

struct VdbHeader {
  std::uint32_t format = 0;
  std::uint32_t lib_major = 0, lib_minor = 0;
  bool has_offsets = false;
};

VdbHeader read_header(Cursor& c) {
  if (c.remaining() < 8) {
    c.fail("not a VDB file (" + std::to_string(c.remaining()) +
           " bytes, too short for the OpenVDB magic number)");
  }
  const auto magic = c.get<std::int64_t>("magic number");
  if (magic != static_cast<std::int64_t>(openvdb::OPENVDB_MAGIC)) {
    c.fail_at(0, "not a VDB file (no OpenVDB magic number)");
  }
  VdbHeader h;
  h.format = c.get<std::uint32_t>("file format version");
  if (h.format < kMinFormat) {
    c.fail("VDB file format version " + std::to_string(h.format) +
           " is too old (versions 222 to 224, OpenVDB 2.1 and later, are supported)");
  }
  if (h.format > kMaxFormat) {
    c.fail("VDB file format version " + std::to_string(h.format) +
           " is newer than this OpenVDB (10, format 224) can read");
  }
  h.lib_major = c.get<std::uint32_t>("library version");
  h.lib_minor = c.get<std::uint32_t>("library version");
  h.has_offsets = c.get<std::uint8_t>("grid offsets flag") != 0;
  c.skip(36, "file UUID");
  return h;
}

// Sizes that OpenVDB's TypedMetadata<T>::readValue reads regardless of the stored size.
std::optional<std::uint32_t> fixed_metadata_size(const std::string& type) {
  static const std::map<std::string, std::uint32_t> sizes = {
      {"bool", 1},   {"int32", 4},  {"int64", 8},  {"float", 4},  {"double", 8}, {"vec2i", 8},
      {"vec2s", 8},  {"vec2d", 16}, {"vec3i", 12}, {"vec3s", 12}, {"vec3d", 24}, {"vec4i", 16},
      {"vec4s", 16}, {"vec4d", 32}, {"mat4s", 64}, {"mat4d", 128}};
  const auto it = sizes.find(type);
  if (it == sizes.end()) return std::nullopt;
  return it->second;
}

struct MetaEntry {
  std::string name, type;
  std::uint64_t begin = 0, end = 0;  // whole entry (name .. payload)
  std::uint64_t value = 0;           // payload offset
  std::uint32_t size = 0;            // payload size
  bool keep = true;                  // safe to hand to OpenVDB
};

// Walks a MetaMap (count, then name, type name, size, payload per entry).
std::vector<MetaEntry> walk_metadata(Cursor& c, const char* what) {
  const auto count = c.get<std::uint32_t>(what);
  if (count > c.remaining() / 12) {
    c.fail("truncated or corrupt: " + std::string(what) + ": " + std::to_string(count) +
           " entries cannot fit in the " + std::to_string(c.remaining()) + " bytes that remain");
  }
  std::vector<MetaEntry> out;
  out.reserve(count);
  for (std::uint32_t i = 0; i < count; ++i) {
    MetaEntry e;
    e.begin = c.pos();
    e.name = c.string("metadata name");
    e.type = c.string("metadata type name");
    e.size = c.get<std::uint32_t>("metadata size");
    e.value = c.pos();
    c.skip(e.size, "metadata value");
    e.end = c.pos();
    if (const auto fixed = fixed_metadata_size(e.type)) {
      if (*fixed != e.size) {
        c.fail_at(e.value, "metadata '" + e.name + "' of type " + e.type + " has " +
                               std::to_string(e.size) + " bytes, expected " +
                               std::to_string(*fixed));
      }
    } else if (e.type != "string") {
      // Registered types other than the plain ones (delayed-load metadata, point attribute
      // metadata) have readers that trust counts inside the payload: drop them. Unregistered
      // types are read by OpenVDB as opaque bytes, which is safe.
      e.keep = !openvdb::Metadata::isRegisteredType(e.type);
    }
    out.push_back(std::move(e));
  }
  return out;
}

std::uint64_t map_size(const std::string& type) {
  if (type == "AffineMap" || type == "UnitaryMap") return 128;         // Mat4d
  if (type == "ScaleMap" || type == "UniformScaleMap") return 5 * 24;  // 5 Vec3d
  if (type == "TranslationMap") return 24;
  if (type == "ScaleTranslateMap" || type == "UniformScaleTranslateMap") return 6 * 24;
  return 0;
}

void walk_transform(Cursor& c) {
  const std::string type = c.string("transform type");
  if (type == "NonlinearFrustumMap") {
    c.skip(48 + 16, "frustum map");  // bbox, taper, depth
    const std::string second = c.string("frustum map's linear map type");
    const std::uint64_t n = map_size(second);
    if (n == 0) c.fail("unknown linear map type '" + second + "' in a frustum transform");
    c.skip(n, "frustum map's linear map");
    return;
  }
  const std::uint64_t n = map_size(type);
  if (n == 0) c.fail("unknown transform map type '" + type + "'");
  c.skip(n, "transform");
}

// A read-only streambuf over memory, with seeking (OpenVDB calls tellg).
class MemoryBuf final : public std::streambuf {
 public:
  MemoryBuf(const char* data, std::size_t n) {
    char* p = const_cast<char*>(data);
    setg(p, p, p + n);
  }

 protected:
  pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode) override {
    off_type base = 0;
    if (dir == std::ios_base::cur) base = gptr() - eback();
    if (dir == std::ios_base::end) base = egptr() - eback();
    const off_type target = base + off;
    if (target < 0 || target > egptr() - eback()) return pos_type(off_type(-1));
    setg(eback(), eback() + target, egptr());
    return pos_type(target);
  }
  pos_type seekpos(pos_type pos, std::ios_base::openmode mode) override {
    return seekoff(off_type(pos), std::ios_base::beg, mode);
  }
};

// ---------------------------------------------------------------------------------------------
// Tree walker (standard 5-4-3 trees of fixed-size values)
// ---------------------------------------------------------------------------------------------

struct ValueInfo {
  std::uint32_t bytes = 0;       // sizeof(ValueType)
  std::uint32_t half_bytes = 0;  // bytes per value when saved as half (0: not a real type)
};

std::optional<ValueInfo> tree_value_info(const std::string& tree_type) {
  static const std::map<std::string, ValueInfo> types = {
      {"float", {4, 2}},  {"double", {8, 2}}, {"int32", {4, 0}}, {"int64", {8, 0}},
      {"vec2s", {8, 4}},  {"vec2d", {16, 4}}, {"vec2i", {8, 0}}, {"vec3s", {12, 6}},
      {"vec3d", {24, 6}}, {"vec3i", {12, 0}}};
  const std::string prefix = "Tree_", suffix = "_5_4_3";
  if (tree_type.size() <= prefix.size() + suffix.size() || tree_type.rfind(prefix, 0) != 0 ||
      tree_type.compare(tree_type.size() - suffix.size(), suffix.size(), suffix) != 0) {
    return std::nullopt;
  }
  const auto it =
      types.find(tree_type.substr(prefix.size(), tree_type.size() - prefix.size() - suffix.size()));
  if (it == types.end()) return std::nullopt;
  return it->second;
}

// A node mask of 2^(3*log2dim) bits, as loaded by NodeMask::load.
struct Mask {
  std::vector<std::uint64_t> words;
  void load(Cursor& c, std::uint32_t log2dim, const char* what) {
    const std::size_t bits = std::size_t{1} << (3 * log2dim);
    words.assign(bits / 64, 0);
    c.bytes(words.data(), bits / 8, what);
  }
  [[nodiscard]] std::uint64_t count() const {
    std::uint64_t n = 0;
    for (std::uint64_t w : words) n += static_cast<std::uint64_t>(std::popcount(w));
    return n;
  }
};

class TreeWalker {
 public:
  // With `verify_blocks`, every compressed block is also decompressed (with OpenVDB's own
  // routines, into scratch memory), so that OpenVDB cannot fail half-way through building the
  // tree, which would leak the nodes it had allocated.
  TreeWalker(Cursor& c, ValueInfo v, bool half, std::uint32_t compression, bool verify_blocks)
      : c_(c),
        v_(v),
        half_(half && v.half_bytes > 0),
        compression_(compression),
        verify_(verify_blocks) {}

  void walk() {
    const std::uint64_t at = c_.pos();
    const auto buffers = c_.get<std::int32_t>("tree buffer count");
    if (buffers != 1) {
      c_.fail_at(at, "tree buffer count is " + std::to_string(buffers) + ", expected 1");
    }
    // Root node topology.
    c_.skip(v_.bytes, "root background value");
    const auto tiles = c_.get<std::uint32_t>("root tile count");
    const auto children = c_.get<std::uint32_t>("root child count");
    if (tiles == 0 && children == 0) return;  // empty tree: no buffers either
    const std::uint64_t tile_bytes = 12 + v_.bytes + 1;
    if (tiles > c_.remaining() / tile_bytes) {
      c_.fail("truncated or corrupt: root node claims " + std::to_string(tiles) +
              " tiles, more than the " + std::to_string(c_.remaining()) +
              " remaining bytes can hold");
    }
    std::map<std::array<std::int32_t, 3>, std::vector<std::uint32_t>> table;  // child -> leaves
    for (std::uint32_t i = 0; i < tiles; ++i) {
      std::array<std::int32_t, 3> key{};
      c_.bytes(key.data(), 12, "root tile origin");
      c_.skip(v_.bytes + 1, "root tile value");
    }
    const std::uint64_t min_child = 12 + 2 * 4096 + 1;
    if (children > c_.remaining() / min_child) {
      c_.fail("truncated or corrupt: root node claims " + std::to_string(children) +
              " children, more than the " + std::to_string(c_.remaining()) +
              " remaining bytes can hold");
    }
    for (std::uint32_t i = 0; i < children; ++i) {
      const std::uint64_t at = c_.pos();
      std::array<std::int32_t, 3> key{};
      c_.bytes(key.data(), 12, "root child origin");
      // OpenVDB would let a duplicate replace (and leak) the earlier child.
      if (table.count(key)) c_.fail_at(at, "corrupt tree: duplicate root child");
      table[key] = internal_topology();
    }
    // Buffers: leaves in the root table's (sorted) order, then mask order.
    for (const auto& [key, leaves] : table) {
      for (std::uint32_t n : leaves) {
        for (std::uint32_t l = 0; l < n; ++l) leaf_buffer();
      }
    }
  }

 private:
  // Upper internal node (log2dim 5) whose children are lower internal nodes (4) whose children
  // are leaves (3). Returns the leaf count of each lower node, in mask order.
  std::vector<std::uint32_t> internal_topology() {
    Mask child, value;
    child.load(c_, 5, "internal node child mask");
    value.load(c_, 5, "internal node value mask");
    compressed_values(std::uint64_t{1} << 15, value, 5, "internal node values");
    std::vector<std::uint32_t> leaves;
    const std::uint64_t n = child.count();
    if (n > c_.remaining() / (2 * 512 + 1)) {
      c_.fail("truncated or corrupt: internal node has " + std::to_string(n) +
              " children, more than the remaining " + std::to_string(c_.remaining()) +
              " bytes can hold");
    }
    leaves.reserve(n);
    for (std::uint64_t i = 0; i < n; ++i) {
      Mask cm, vm;
      cm.load(c_, 4, "internal node child mask");
      vm.load(c_, 4, "internal node value mask");
      compressed_values(std::uint64_t{1} << 12, vm, 4, "internal node values");
      const std::uint64_t nl = cm.count();
      c_.skip(nl * 64, "leaf value masks");
      leaves.push_back(static_cast<std::uint32_t>(nl));
    }
    return leaves;
  }

  void leaf_buffer() {
    Mask value;
    value.load(c_, 3, "leaf value mask");
    compressed_values(512, value, 3, "leaf values");
  }

  // io::readCompressedValues for format >= 222.
  void compressed_values(std::uint64_t count, const Mask& value_mask, std::uint32_t log2dim,
                         const char* what) {
    const auto meta = c_.get<std::int8_t>("compression metadata");
    if (meta == 2 || meta == 4 || meta == 5) c_.skip(v_.bytes, "inactive value");
    if (meta == 5) c_.skip(v_.bytes, "second inactive value");
    if (meta == 3 || meta == 4 || meta == 5) {
      c_.skip((std::uint64_t{1} << (3 * log2dim)) / 8, "selection mask");
    }
    std::uint64_t n = count;
    if ((compression_ & vio::COMPRESS_ACTIVE_MASK) && meta != 6) n = value_mask.count();
    if (half_ && n < 1) return;  // HalfReader reads nothing for an empty buffer
    const std::uint64_t expected = n * (half_ ? v_.half_bytes : v_.bytes);
    if (compression_ & (vio::COMPRESS_BLOSC | vio::COMPRESS_ZIP)) {
      const bool blosc = compression_ & vio::COMPRESS_BLOSC;
      const std::uint64_t at = c_.pos();
      const auto size = c_.get<std::int64_t>(blosc ? "Blosc block size" : "zip block size");
      if (size <= 0) {
        // Stored uncompressed: OpenVDB reads -size bytes into a buffer of `expected` bytes.
        if (static_cast<std::uint64_t>(-(size + 1)) + 1 != expected || size == INT64_MIN) {
          c_.fail_at(at, std::string(what) + ": uncompressed block of " +
                             std::to_string(-static_cast<double>(size)) + " bytes, expected " +
                             std::to_string(expected));
        }
        c_.skip(expected, what);
        return;
      }
      c_.need(static_cast<std::uint64_t>(size), what);
      if (blosc) check_blosc(static_cast<std::uint64_t>(size), expected, what);
      if (verify_) verify_block(at, static_cast<std::uint64_t>(size), expected, blosc, what);
      c_.skip(static_cast<std::uint64_t>(size), what);
      return;
    }
    c_.skip(expected, what);
  }

  // Decompresses the block that starts (with its 8-byte size) at `at`.
  void verify_block(std::uint64_t at, std::uint64_t size, std::uint64_t expected, bool blosc,
                    const char* what) {
    Cursor b = c_;
    b.seek(at);
    std::vector<char> block(8 + size);
    b.bytes(block.data(), block.size(), what);
    scratch_.resize(std::max<std::size_t>(expected, 1));
    try {
      MemoryBuf buf(block.data(), block.size());
      std::istream is(&buf);
      is.exceptions(std::ios::failbit | std::ios::badbit);
      if (blosc) {
        vio::bloscFromStream(is, scratch_.data(), expected);
      } else {
        vio::unzipFromStream(is, scratch_.data(), expected);
      }
    } catch (const std::exception& e) {
      c_.fail_at(at, std::string(what) + ": corrupt " + (blosc ? "Blosc" : "zip") + " block (" +
                         e.what() + ")");
    }
  }

  // Blosc 1.x header: version, versionlz, flags, typesize, nbytes, blocksize, cbytes (LE).
  void check_blosc(std::uint64_t size, std::uint64_t expected, const char* what) {
    const std::uint64_t at = c_.pos();
    if (size < 16) c_.fail_at(at, std::string(what) + ": Blosc block shorter than its header");
    Cursor h = c_;
    const auto version = h.get<std::uint8_t>("Blosc header");
    (void)h.get<std::uint8_t>("Blosc header");
    const auto flags = h.get<std::uint8_t>("Blosc header");
    (void)h.get<std::uint8_t>("Blosc header");
    const auto nbytes = h.get<std::uint32_t>("Blosc header");
    const auto blocksize = h.get<std::uint32_t>("Blosc header");
    const auto cbytes = h.get<std::uint32_t>("Blosc header");
    if (version == 0 || version > 4 || nbytes != expected || cbytes != size ||
        (nbytes > 0 && blocksize == 0) || ((flags & 0x2) && cbytes != nbytes + 16)) {
      c_.fail_at(at, std::string(what) + ": corrupt Blosc block header (" + std::to_string(nbytes) +
                         " bytes in " + std::to_string(cbytes) + ", block stored as " +
                         std::to_string(size) + ", expected " + std::to_string(expected) +
                         " bytes)");
    }
  }

  Cursor& c_;
  ValueInfo v_;
  bool half_;
  std::uint32_t compression_;
  bool verify_;
  std::vector<char> scratch_;
};

// ---------------------------------------------------------------------------------------------
// Directory: grid descriptors
// ---------------------------------------------------------------------------------------------

struct GridEntry {
  std::string unique_name;  // may contain kNameSep + N
  std::string name;         // unique_name without the suffix
  std::string tree_type;    // without the half-float suffix
  bool half = false;
  std::string instance_parent;
  std::uint64_t data_begin = 0, data_end = 0;  // the grid's bytes (compression flags .. end)
};

std::string display_name(const std::string& unique_name) {
  return vio::GridDescriptor::nameAsString(unique_name);
}

std::string value_type_name(const std::string& tree_type) {
  ensure_openvdb_initialized();
  try {
    if (openvdb::GridBase::isRegistered(tree_type)) {
      return openvdb::GridBase::createGrid(tree_type)->valueType();
    }
  } catch (const std::exception&) {
  }
  return tree_type;
}

// Walks one grid's bytes from its compression flags; returns the offset of the metadata map
// and its entries. With `whole_tree`, walks topology and buffers too (standard trees only) and
// leaves the cursor at the grid's end.
struct GridLayout {
  std::uint32_t compression = 0;
  std::uint64_t meta_begin = 0, meta_end = 0;
  std::vector<MetaEntry> meta;
  std::uint64_t transform_begin = 0, transform_end = 0;
};

GridLayout walk_grid(Cursor& c, const GridEntry& g, bool whole_tree, bool verify_blocks) {
  GridLayout l;
  l.compression = c.get<std::uint32_t>("grid compression flags");
  l.meta_begin = c.pos();
  l.meta = walk_metadata(c, "grid metadata");
  l.meta_end = c.pos();
  l.transform_begin = c.pos();
  walk_transform(c);
  l.transform_end = c.pos();
  if (!whole_tree || !g.instance_parent.empty()) return l;
  const auto info = tree_value_info(g.tree_type);
  if (!info) {
    c.fail("grid '" + display_name(g.unique_name) + "' has tree type " + g.tree_type +
           ", which isoforge cannot validate");
  }
  TreeWalker(c, *info, g.half, l.compression, verify_blocks).walk();
  return l;
}

struct Directory {
  VdbHeader header;
  std::vector<GridEntry> grids;
};

Directory read_directory(const VdbSource& src, const std::string& name) {
  Cursor c(src, name, 0, src.size());
  Directory d;
  d.header = read_header(c);
  (void)walk_metadata(c, "file metadata");
  const auto count = c.get<std::int32_t>("grid count");
  if (count < 0) c.fail("negative grid count " + std::to_string(count));
  if (static_cast<std::uint64_t>(count) > c.remaining() / 24) {
    c.fail("truncated or corrupt: grid count " + std::to_string(count) + " cannot fit in the " +
           std::to_string(c.remaining()) + " bytes that remain");
  }
  for (std::int32_t i = 0; i < count; ++i) {
    GridEntry g;
    g.unique_name = c.string("grid name");
    g.name = g.unique_name.substr(0, g.unique_name.find(kNameSep));
    g.tree_type = c.string("grid type");
    const std::string suffix = kHalfSuffix;
    if (g.tree_type.size() >= suffix.size() &&
        g.tree_type.compare(g.tree_type.size() - suffix.size(), suffix.size(), suffix) == 0) {
      g.half = true;
      g.tree_type.resize(g.tree_type.size() - suffix.size());
    }
    g.instance_parent = c.string("grid instance parent");
    const std::uint64_t offsets_at = c.pos();
    const auto grid_pos = c.get<std::int64_t>("grid offsets");
    const auto block_pos = c.get<std::int64_t>("grid offsets");
    const auto end_pos = c.get<std::int64_t>("grid offsets");
    if (d.header.has_offsets) {
      const auto here = static_cast<std::int64_t>(c.pos());
      if (grid_pos < here || block_pos < grid_pos || end_pos < block_pos) {
        c.fail_at(offsets_at, "grid '" + display_name(g.unique_name) + "' has corrupt offsets (" +
                                  std::to_string(grid_pos) + ", " + std::to_string(block_pos) +
                                  ", " + std::to_string(end_pos) + ")");
      }
      if (static_cast<std::uint64_t>(end_pos) > src.size()) {
        c.fail_at(offsets_at, "truncated: grid '" + display_name(g.unique_name) +
                                  "' ends at byte " + std::to_string(end_pos) +
                                  " but the file has " + std::to_string(src.size()) + " bytes");
      }
      g.data_begin = static_cast<std::uint64_t>(grid_pos);
      g.data_end = static_cast<std::uint64_t>(end_pos);
      c.seek(g.data_end);
    } else {
      // A stream: the grid follows its descriptor; walk it to find the next descriptor.
      g.data_begin = c.pos();
      if (!g.instance_parent.empty() || tree_value_info(g.tree_type)) {
        (void)walk_grid(c, g, true, false);
      } else if (i + 1 < count) {
        c.fail("grid '" + display_name(g.unique_name) + "' of type " + g.tree_type +
               " in an OpenVDB stream (no grid offsets) cannot be skipped");
      } else {
        c.seek(src.size());  // last grid: it runs to the end
      }
      g.data_end = c.pos();
    }
    d.grids.push_back(std::move(g));
  }
  return d;
}

// ---------------------------------------------------------------------------------------------
// Reading one grid through OpenVDB, from validated bytes
// ---------------------------------------------------------------------------------------------

// Gives access to OpenVDB's protected grid reader (the one io::Stream and io::File use).
class GridReader final : public vio::Archive {
 public:
  static void read(openvdb::GridBase::Ptr grid, const vio::GridDescriptor& gd, std::istream& is) {
    Archive::readGrid(std::move(grid), gd, is);
  }
};

// The grid's bytes with dropped metadata entries removed, and the half-float flag that
// OpenVDB takes from the metadata (not from the descriptor) made to agree with the descriptor,
// which the walker followed.
std::vector<char> sanitized_grid_bytes(const VdbSource& src, const GridEntry& g, const GridLayout& l) {
  const std::string half_key = openvdb::GridBase::META_SAVE_HALF_FLOAT;
  std::vector<char> out;
  out.reserve(g.data_end - g.data_begin + 64);
  auto append = [&](std::uint64_t from, std::uint64_t to) {
    const std::size_t at = out.size();
    out.resize(at + (to - from));
    src.read(from, out.data() + at, to - from);
  };
  auto put_u32 = [&](std::uint32_t v) {
    const char* p = reinterpret_cast<const char*>(&v);
    out.insert(out.end(), p, p + 4);
  };
  auto put_string = [&](const std::string& str) {
    put_u32(static_cast<std::uint32_t>(str.size()));
    out.insert(out.end(), str.begin(), str.end());
  };
  append(g.data_begin, l.meta_begin);  // compression flags
  std::uint32_t kept = 0;
  for (const MetaEntry& e : l.meta) kept += e.keep && e.name != half_key ? 1 : 0;
  put_u32(kept + (g.half ? 1 : 0));
  for (const MetaEntry& e : l.meta) {
    if (e.keep && e.name != half_key) append(e.begin, e.end);
  }
  if (g.half) {
    put_string(half_key);
    put_string("bool");
    put_u32(1);
    out.push_back(1);
  }
  append(l.meta_end, g.data_end);
  return out;
}

struct StreamTags {
  vio::StreamMetadata::Ptr meta{new vio::StreamMetadata};
  void apply(std::istream& is, const VdbHeader& h) {
    vio::setStreamMetadataPtr(is, meta, /*transfer=*/false);
    vio::setVersion(is, openvdb::VersionId(h.lib_major, h.lib_minor), h.format);
    vio::setDataCompression(is, vio::COMPRESS_NONE);
    vio::setGridClass(is, openvdb::GRID_UNKNOWN);
  }
};

openvdb::GridBase::Ptr read_validated_grid(const VdbSource& src, const std::string& name,
                                           const VdbHeader& header, const GridEntry& g) {
  const std::string gname = display_name(g.unique_name);
  if (!g.instance_parent.empty()) {
    throw Error(name + ": grid '" + gname + "' is an instance of grid '" +
                display_name(g.instance_parent) + "' (instanced grids are not supported)");
  }
  // Copy the grid's bytes into memory and walk them completely.
  std::vector<std::byte> raw(g.data_end - g.data_begin);
  src.read(g.data_begin, raw.data(), raw.size());
  const SpanSource mem(raw);
  Cursor c(mem, name, 0, raw.size(), g.data_begin);
  const GridLayout layout = walk_grid(c, g, true, true);
  GridEntry local = g;
  local.data_begin = 0;
  local.data_end = c.pos();  // trailing bytes (if any) are not OpenVDB's business
  std::vector<char> bytes = sanitized_grid_bytes(mem, local, layout);
  raw.clear();
  raw.shrink_to_fit();

  ensure_openvdb_initialized();
  try {
    openvdb::GridBase::Ptr grid = openvdb::GridBase::createGrid(g.tree_type);
    grid->setSaveFloatAsHalf(g.half);
    MemoryBuf buf(bytes.data(), bytes.size());
    std::istream is(&buf);
    is.exceptions(std::ios::failbit | std::ios::badbit);
    StreamTags tags;
    tags.apply(is, header);
    const vio::GridDescriptor gd(g.unique_name, g.tree_type, g.half);
    GridReader::read(grid, gd, is);
    if (grid->getName().empty()) grid->setName(g.name);
    return grid;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(name + ": grid '" + gname + "': corrupt grid data (" + e.what() + ")");
  }
}

std::string grid_list(const Directory& d) {
  std::string s;
  for (const GridEntry& g : d.grids) {
    if (!s.empty()) s += ", ";
    s += "'" + display_name(g.unique_name) + "' (" + value_type_name(g.tree_type) + ")";
  }
  return s.empty() ? "none" : s;
}

openvdb::FloatGrid::Ptr read_float_grid(const VdbSource& src, const std::string& name,
                                        std::string_view grid_name) {
  const Directory d = read_directory(src, name);
  const GridEntry* chosen = nullptr;
  if (grid_name.empty()) {
    for (const GridEntry& g : d.grids) {
      if (g.tree_type == kFloatTree) {
        chosen = &g;
        break;
      }
    }
    if (!chosen) throw Error(name + ": the file holds no float grid (grids: " + grid_list(d) + ")");
  } else {
    const std::string want(grid_name);
    for (const GridEntry& g : d.grids) {
      if (g.name == want || display_name(g.unique_name) == want) {
        chosen = &g;
        break;
      }
    }
    if (!chosen) {
      throw Error(name + ": no float grid named '" + want + "' (grids: " + grid_list(d) + ")");
    }
    if (chosen->tree_type != kFloatTree) {
      throw Error(name + ": grid '" + want + "' is a " + value_type_name(chosen->tree_type) +
                  " grid, not a float grid");
    }
  }
  openvdb::GridBase::Ptr base = read_validated_grid(src, name, d.header, *chosen);
  auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
  if (!grid)
    throw Error(name + ": grid '" + display_name(chosen->unique_name) + "' is not a float grid");
  return grid;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Public reading
// ---------------------------------------------------------------------------------------------

openvdb::FloatGrid::Ptr read_vdb_grid(const std::filesystem::path& path,
                                      std::string_view grid_name) {
  const std::string name = path.string();
  try {
    FileSource src(path, name);
    if (!src.size()) throw Error(name + ": not a VDB file (the file is empty)");
    return read_float_grid(src, name, grid_name);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(name + ": cannot read VDB file: " + e.what());
  }
}

openvdb::FloatGrid::Ptr read_vdb_grid(std::span<const std::byte> data, std::string_view name,
                                      std::string_view grid_name) {
  const std::string n(name);
  try {
    const SpanSource src(data);
    return read_float_grid(src, n, grid_name);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(n + ": cannot read VDB data: " + e.what());
  }
}

std::vector<VdbGridInfo> inspect_vdb(const std::filesystem::path& path) {
  const std::string name = path.string();
  try {
    FileSource src(path, name);
    const Directory d = read_directory(src, name);
    ensure_openvdb_initialized();
    std::vector<VdbGridInfo> out;
    for (const GridEntry& g : d.grids) {
      VdbGridInfo info;
      info.name = display_name(g.unique_name);
      info.type = value_type_name(g.tree_type);
      Cursor c(src, name, g.data_begin, g.data_end);
      const GridLayout l = walk_grid(c, g, false, false);
      // Let OpenVDB parse the (validated, sanitized) metadata and transform.
      GridEntry head = g;
      head.data_end = l.transform_end;
      std::vector<char> bytes = sanitized_grid_bytes(src, head, l);
      openvdb::GridBase::Ptr grid;
      try {
        grid = openvdb::GridBase::isRegistered(g.tree_type)
                   ? openvdb::GridBase::createGrid(g.tree_type)
                   : openvdb::GridBase::Ptr(openvdb::FloatGrid::create());
        MemoryBuf buf(bytes.data(), bytes.size());
        std::istream is(&buf);
        is.exceptions(std::ios::failbit | std::ios::badbit);
        StreamTags tags;
        tags.apply(is, d.header);
        is.seekg(4);
        grid->readMeta(is);
        grid->readTransform(is);
      } catch (const std::exception& e) {
        throw Error(name + ": grid '" + info.name + "': corrupt metadata or transform (" +
                    e.what() + ")");
      }
      info.grid_class = openvdb::GridBase::gridClassToString(grid->getGridClass());
      info.voxel_size = grid->voxelSize()[0];
      const auto bmin =
          grid->getMetadata<openvdb::Vec3IMetadata>(openvdb::GridBase::META_FILE_BBOX_MIN);
      const auto bmax =
          grid->getMetadata<openvdb::Vec3IMetadata>(openvdb::GridBase::META_FILE_BBOX_MAX);
      const auto count =
          grid->getMetadata<openvdb::Int64Metadata>(openvdb::GridBase::META_FILE_VOXEL_COUNT);
      if (bmin && bmax && count) {
        info.active_bbox =
            openvdb::CoordBBox(openvdb::Coord(bmin->value()), openvdb::Coord(bmax->value()));
        info.active_voxels = static_cast<std::size_t>(std::max<std::int64_t>(0, count->value()));
      } else if (g.instance_parent.empty() && tree_value_info(g.tree_type)) {
        // No statistics stored: read the grid and compute them.
        const openvdb::GridBase::Ptr full = read_validated_grid(src, name, d.header, g);
        info.active_bbox = full->evalActiveVoxelBoundingBox();
        info.active_voxels = static_cast<std::size_t>(full->activeVoxelCount());
      }
      out.push_back(std::move(info));
    }
    return out;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(name + ": cannot read VDB file: " + e.what());
  }
}

// ---------------------------------------------------------------------------------------------
// Writing
// ---------------------------------------------------------------------------------------------

namespace {

void write_grids(const openvdb::GridCPtrVec& grids, const std::filesystem::path& path) {
  const std::string name = path.string();
  if (grids.empty()) throw Error(name + ": write_vdb: no grids to write");
  for (std::size_t i = 0; i < grids.size(); ++i) {
    if (!grids[i]) throw Error(name + ": write_vdb: grid " + std::to_string(i) + " is null");
  }
  ensure_openvdb_initialized();
  AtomicFile out(path);
  try {
    openvdb::io::File file(out.temp_path().string());
    file.write(grids);
    file.close();
  } catch (const std::exception& e) {
    throw Error(name + ": cannot write VDB file: " + e.what());
  }
  out.commit();
}

}  // namespace

void write_vdb(const std::vector<openvdb::GridBase::Ptr>& grids,
               const std::filesystem::path& path) {
  write_grids(openvdb::GridCPtrVec(grids.begin(), grids.end()), path);
}

void write_vdb(const openvdb::FloatGrid& grid, const std::filesystem::path& path) {
  // OpenVDB writes through shared pointers; a shallow copy shares the tree (no voxel copy).
  write_grids(openvdb::GridCPtrVec{grid.copyGrid()}, path);
}

}  // namespace isoforge
