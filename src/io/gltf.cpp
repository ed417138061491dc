// glTF 2.0 binary (.glb) writer and reader.
//
// Khronos Group, "glTF 2.0 Specification" (2021), sections 4.4 (buffers, accessors), 4.7
// (meshes) and 4.4.4 (GLB); the extensions EXT_meshopt_compression (A. Kapoulkine, 2021) and
// KHR_draco_mesh_compression (2019). The meshopt codecs are meshoptimizer's
// (meshopt_encodeVertexBuffer, meshopt_encodeIndexBuffer/-Sequence). Layout and choices:
// docs/algorithms/gltf.md.

#include "isoforge/io/gltf.hpp"
#include "isoforge/core/cell.hpp"

#include <fmt/format.h>
#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <utility>

#include "detail/draco_codec.hpp"
#include "detail/file_source.hpp"
#include "detail/json.hpp"
#include "detail/summaries.hpp"
#include "isoforge/core/append.hpp"
#include "isoforge/core/normals.hpp"
#include "isoforge/core/parallel.hpp"
#include "isoforge/core/srgb.hpp"
#include "isoforge/io/atomic_file.hpp"
#include "isoforge/io/io.hpp"

namespace isoforge {

using io_detail::Json;

namespace {

constexpr std::uint32_t kGlbMagic = 0x46546C67;   // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kChunkBin = 0x004E4942;   // "BIN\0"
constexpr int kArrayBuffer = 34962;               // bufferView targets
constexpr int kElementArrayBuffer = 34963;
constexpr int kUnsignedByte = 5121;  // accessor component types
constexpr int kUnsignedShort = 5123;
constexpr int kUnsignedInt = 5125;
constexpr int kFloat = 5126;
constexpr int kModePoints = 0, kModeLines = 1, kModeLineLoop = 2, kModeLineStrip = 3,
              kModeTriangles = 4, kModeTriangleStrip = 5, kModeTriangleFan = 6;
constexpr const char* kMeshopt = "EXT_meshopt_compression";
constexpr const char* kDraco = "KHR_draco_mesh_compression";

std::size_t align4(std::size_t n) {
  return (n + 3) & ~std::size_t{3};
}

// ---------------------------------------------------------------------------------------------
// Writing
//
// The JSON chunk comes before the BIN chunk and names every view's offset and length, so the
// layout is settled first: sizes, bounds and the checks that decide what is written (finite
// values, float32 range) are read from the dataset in one pass each. Plain views are then made
// a slice at a time while the BIN chunk is written, straight from the dataset's arrays; only
// encoded views (meshopt, Draco) are held, and they are a fraction of the plain data.

// Writes the next `count` elements of a plain view: called in order over consecutive slices
// that cover the view once.
using Producer = std::function<void(std::byte* dst, std::size_t count)>;

// Elements of a plain view made and written at a time: about 4 MiB, a multiple of 6 so that
// index views (1, 2 or 3 indices per primitive) are cut between whole primitives.
std::size_t slice_elements(std::size_t stride) {
  constexpr std::size_t kSliceBytes = std::size_t{4} << 20;
  return std::max<std::size_t>(6, kSliceBytes / stride / 6 * 6);
}

// Points handled by one task of the parallel passes over a mesh's points.
constexpr std::size_t kPointGrain = std::size_t{1} << 14;

// The binary chunk and the glTF objects that describe it.
class GlbBuilder {
 public:
  explicit GlbBuilder(GltfCodec codec) : codec_(codec) {}

  // A bufferView of `count` elements of `stride` bytes that `produce` makes: vertex data
  // (`vertex`), or indices (triangles when `triangles`). Returns the bufferView index.
  std::size_t add_view(std::size_t count, std::size_t stride, bool vertex, bool triangles,
                       Producer produce) {
    const std::size_t size = count * stride;
    Json view;
    raw_bytes_ = align4(raw_bytes_);
    if (codec_ == GltfCodec::Meshopt) {
      // The plain data lives in the fallback buffer 1, which holds no bytes; the compressed
      // data in buffer 0 (the BIN chunk). Readers must support the extension (required).
      view["buffer"] = 1;
      view["byteOffset"] = raw_bytes_;
      view["byteLength"] = size;
      std::vector<unsigned char> encoded;
      std::string mode;
      if (vertex) {
        Buffer<unsigned char> plain(size);
        produce(reinterpret_cast<std::byte*>(plain.data()), count);
        encoded.resize(meshopt_encodeVertexBufferBound(count, stride));
        encoded.resize(meshopt_encodeVertexBuffer(encoded.data(), encoded.size(), plain.data(),
                                                  count, stride));
        mode = "ATTRIBUTES";
      } else {
        // meshopt takes 32-bit indices: 16-bit ones are made aside and widened.
        Buffer<unsigned> indices(count);
        if (stride == 4) {
          produce(reinterpret_cast<std::byte*>(indices.data()), count);
        } else {
          Buffer<std::uint16_t> shorts(count);
          produce(reinterpret_cast<std::byte*>(shorts.data()), count);
          std::copy(shorts.begin(), shorts.end(), indices.begin());
        }
        const std::size_t max_vertex =
            count ? *std::max_element(indices.begin(), indices.end()) + 1 : 0;
        if (triangles) {
          encoded.resize(meshopt_encodeIndexBufferBound(count, max_vertex));
          encoded.resize(
              meshopt_encodeIndexBuffer(encoded.data(), encoded.size(), indices.data(), count));
          mode = "TRIANGLES";
        } else {
          encoded.resize(meshopt_encodeIndexSequenceBound(count, max_vertex));
          encoded.resize(
              meshopt_encodeIndexSequence(encoded.data(), encoded.size(), indices.data(), count));
          mode = "INDICES";
        }
      }
      check_invariant(!encoded.empty(), "meshopt encoding fits its bound");
      const std::size_t bytes = encoded.size();
      const std::size_t at = add_encoded(std::move(encoded));
      Json& ext = view["extensions"][kMeshopt];
      ext["buffer"] = 0;
      ext["byteOffset"] = at;
      ext["byteLength"] = bytes;
      ext["byteStride"] = stride;
      ext["mode"] = mode;
      ext["count"] = count;
    } else {
      Piece p;
      p.count = count;
      p.stride = stride;
      p.produce = std::move(produce);
      view["buffer"] = 0;
      view["byteOffset"] = add_piece(std::move(p), size);
      view["byteLength"] = size;
    }
    raw_bytes_ += size;
    if (vertex) view["byteStride"] = stride;
    view["target"] = vertex ? kArrayBuffer : kElementArrayBuffer;
    return buffer_views_.push(std::move(view));
  }

  // A bufferView of opaque bytes (a Draco stream) in the BIN chunk.
  std::size_t add_blob(std::vector<unsigned char> bytes) {
    const std::size_t size = bytes.size();
    Json view;
    view["buffer"] = 0;
    view["byteOffset"] = add_encoded(std::move(bytes));
    view["byteLength"] = size;
    raw_bytes_ = align4(raw_bytes_) + size;
    return buffer_views_.push(std::move(view));
  }

  std::size_t add_accessor(Json accessor) { return accessors_.push(std::move(accessor)); }

  Json& buffer_views() { return buffer_views_; }
  Json& accessors() { return accessors_; }
  // The BIN chunk's data bytes (without the chunk's final padding).
  [[nodiscard]] std::size_t bin_size() const { return bin_size_; }
  [[nodiscard]] std::size_t raw_bytes() const { return raw_bytes_; }

  // Writes the BIN chunk's data and its padding to 4 bytes, plain views a slice at a time;
  // `wrote(bytes)` after each piece or slice (it may throw to stop).
  void write_bin(std::ostream& s, const std::function<void(std::size_t)>& wrote) {
    static constexpr char kZeros[4] = {};
    std::size_t largest = 0;  // the largest slice of a plain view
    for (const Piece& p : pieces_) {
      if (p.produce)
        largest = std::max(largest, std::min(p.count, slice_elements(p.stride)) * p.stride);
    }
    Buffer<std::byte> slice(largest);
    std::size_t at = 0;
    for (Piece& p : pieces_) {
      s.write(kZeros, static_cast<std::streamsize>(p.offset - at));
      if (p.produce) {
        const std::size_t step = slice_elements(p.stride);
        for (std::size_t first = 0; first < p.count; first += step) {
          const std::size_t m = std::min(step, p.count - first);
          p.produce(slice.data(), m);
          s.write(reinterpret_cast<const char*>(slice.data()),
                  static_cast<std::streamsize>(m * p.stride));
          wrote(p.offset + (first + m) * p.stride);
        }
        at = p.offset + p.count * p.stride;
        p.produce = {};  // what it holds (computed normals) is freed as soon as it is written
      } else {
        s.write(reinterpret_cast<const char*>(p.encoded.data()),
                static_cast<std::streamsize>(p.encoded.size()));
        at = p.offset + p.encoded.size();
        p.encoded = {};
        wrote(at);
      }
    }
    s.write(kZeros, static_cast<std::streamsize>(align4(at) - at));
  }

 private:
  // One view's bytes in the BIN chunk: encoded ones held, plain ones made when written.
  struct Piece {
    std::size_t offset = 0;
    std::size_t count = 0, stride = 1;  // plain: elements of `stride` bytes
    Producer produce;
    std::vector<unsigned char> encoded;
  };

  std::size_t add_piece(Piece p, std::size_t size) {
    p.offset = align4(bin_size_);
    bin_size_ = p.offset + size;
    pieces_.push_back(std::move(p));
    return pieces_.back().offset;
  }
  std::size_t add_encoded(std::vector<unsigned char> bytes) {
    Piece p;
    const std::size_t size = bytes.size();
    bytes.shrink_to_fit();  // encoders size their output to a bound first
    p.encoded = std::move(bytes);
    return add_piece(std::move(p), size);
  }

  GltfCodec codec_;
  std::vector<Piece> pieces_;
  std::size_t bin_size_ = 0;
  std::size_t raw_bytes_ = 0;  // the plain layout's size (meshopt: the fallback buffer)
  Json buffer_views_ = Json::array();
  Json accessors_ = Json::array();
};

// "_NAME" for an array name: letters, digits and '_' upper-cased, anything else '_', unique
// among `used`.
std::string custom_semantic(std::string_view name, std::set<std::string>& used) {
  std::string s = "_";
  for (const char c : name) {
    const auto u = static_cast<unsigned char>(c);
    s += std::isalnum(u) ? static_cast<char>(std::toupper(u)) : '_';
  }
  if (s == "_") s = "_ARRAY";
  std::string unique = s;
  for (int i = 2; used.count(unique); ++i) unique = s + "_" + std::to_string(i);
  used.insert(unique);
  return unique;
}

// How many primitives of each kind a mesh's cells make: triangles (polygons fan-triangulated,
// strips), segments (polylines), points (vertex cells).
struct PrimitiveCounts {
  std::size_t triangles = 0, segments = 0, points = 0;
};

PrimitiveCounts count_primitives(const PolyData& pd) {
  PrimitiveCounts p;
  auto beyond = [](const CellArray& cells, std::size_t skip) {
    std::size_t total = 0;
    for (std::size_t c = 0; c < cells.size(); ++c) {
      const std::size_t size = cells.cell_size(c);
      total += size > skip ? size - skip : 0;
    }
    return total;
  };
  p.triangles = beyond(pd.polys, 2) + beyond(pd.strips, 2);
  p.segments = beyond(pd.lines, 1);
  p.points = beyond(pd.verts, 0);
  return p;
}

// The indices of one primitive mode (triangles, lines or points) of a mesh's cells, in the
// order of the cells, made on demand a whole number of primitives at a time.
class IndexCursor {
 public:
  IndexCursor(const PolyData& pd, int mode) : mode_(mode) {
    if (mode == kModeTriangles) {
      sets_ = {&pd.polys, &pd.strips};
    } else {
      sets_ = {mode == kModeLines ? &pd.lines : &pd.verts, nullptr};
    }
  }

  // Writes the next `count` indices (a multiple of the primitive's size; no more than remain).
  template <class T>
  void next(T* out, std::size_t count) {
    const auto id = [](Index i) { return static_cast<T>(i); };
    std::size_t made = 0;
    while (made < count) {
      check_invariant(set_ < 2 && sets_[set_], "index cursor stays within the cells");
      const CellArray& cells = *sets_[set_];
      if (cell_ == cells.size()) {
        ++set_, cell_ = 0, k_ = 0;
        continue;
      }
      const auto c = cells.cell(cell_);
      if (mode_ == kModeTriangles && k_ + 2 < c.size()) {
        const auto t =
            set_ == 0 ? std::array<Index, 3>{c[0], c[k_ + 1], c[k_ + 2]} : strip_triangle(c, k_);
        for (const Index i : t) out[made++] = id(i);
        ++k_;
      } else if (mode_ == kModeLines && k_ + 1 < c.size()) {
        out[made++] = id(c[k_]);
        out[made++] = id(c[k_ + 1]);
        ++k_;
      } else if (mode_ == kModePoints && k_ < c.size()) {
        out[made++] = id(c[k_++]);
      } else {
        ++cell_, k_ = 0;
      }
    }
  }

 private:
  int mode_;
  std::array<const CellArray*, 2> sets_{};
  std::size_t set_ = 0, cell_ = 0, k_ = 0;
};

// A producer of the indices of one primitive mode, as uint16 (`shorts`) or uint32.
Producer index_producer(const PolyData& pd, int mode, bool shorts) {
  return [cursor = IndexCursor(pd, mode), shorts](std::byte* dst, std::size_t count) mutable {
    if (shorts) {
      cursor.next(reinterpret_cast<std::uint16_t*>(dst), count);
    } else {
      cursor.next(reinterpret_cast<std::uint32_t*>(dst), count);
    }
  };
}

Json legend_json(const GltfLegend& legend, const std::string& where) {
  if (legend.colors.size() < 2) throw Error(where + ": a colour legend needs at least 2 colours");
  if (!std::isfinite(legend.min) || !std::isfinite(legend.max) || legend.min > legend.max) {
    throw Error(where + ": colour legend range must be finite with min <= max");
  }
  if (legend.log_scale && legend.min <= 0) {
    throw Error(where + ": a logarithmic colour legend needs min > 0");
  }
  Json j;
  j["array"] = legend.array;
  j["colormap"] = legend.colormap;
  j["range"] = Json(Json::Array{Json(legend.min), Json(legend.max)});
  j["log"] = legend.log_scale;
  Json colors = Json::array();
  for (const auto& c : legend.colors) {
    colors.push(
        Json(Json::Array{Json(int{c[0]}), Json(int{c[1]}), Json(int{c[2]}), Json(int{c[3]})}));
  }
  j["colors"] = std::move(colors);
  return j;
}

// The uint8 array written as COLOR_0, or nullptr.
const DataArray* color_array(const GltfMesh& m, const std::string& where) {
  auto suitable = [](const DataArray* a) {
    return a && a->type() == ScalarType::UInt8 && (a->components() == 3 || a->components() == 4);
  };
  if (!m.colors.empty()) {
    const DataArray* a = m.mesh.point_data.find(m.colors);
    if (!a) throw Error(where + ": no point array '" + m.colors + "' for the colours");
    if (!suitable(a)) {
      throw Error(where + ": colour array '" + m.colors +
                  "' must be UInt8 with 3 or 4 components (RGB/RGBA)");
    }
    return a;
  }
  const DataArray* s = m.mesh.point_data.scalars();
  return suitable(s) ? s : nullptr;
}

constexpr const char* kTypes[] = {"SCALAR", "VEC2", "VEC3", "VEC4"};

// One vertex attribute as written (plain) or handed to Draco: its layout, and how to make its
// elements from the dataset.
struct Stream {
  std::string semantic;
  std::size_t elem_bytes = 0;
  int component_type = kFloat;
  int components = 1;
  bool normalized = false;
  std::string array;  // the array's name ("" for positions and computed normals)
  // Writes elements [first, first + count) to `dst` (in parallel).
  std::function<void(std::size_t first, std::size_t count, std::byte* dst)> fill;
};

// A producer of a stream's elements from the first on.
Producer stream_producer(const Stream& st) {
  return [fill = st.fill, at = std::size_t{0}](std::byte* dst, std::size_t count) mutable {
    fill(at, count, dst);
    at += count;
  };
}

// Runs body(i, j) for the elements i = first + j of [first, first + count), in parallel.
template <class Body>
void for_elements(std::size_t first, std::size_t count, Body&& body) {
  parallel_for_range(count, kPointGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t j = b; j < e; ++j) body(first + j, j);
  });
}

// The unit vector of tuple i of a 3-component array as floats, or (0, 0, 1) and false where it
// has no direction (zero or non-finite).
bool unit_normal(const DataArray& a, std::size_t i, float* out) {
  double v[3] = {a.get(i, 0), a.get(i, 1), a.get(i, 2)};
  const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (!(len > 0) || !std::isfinite(len)) {
    out[0] = 0, out[1] = 0, out[2] = 1;
    return false;
  }
  for (int k = 0; k < 3; ++k) out[k] = static_cast<float>(v[k] / len);
  return true;
}

// A KHR_draco_mesh_compression TRIANGLES primitive of the mesh's triangles over the vertex
// `streams`: positions, normals (unit), colours (linear, as uint8: Draco's colour attribute) and
// the float arrays, encoded (and verified) by the Draco codec of io/draco.cpp. Its accessors
// declare what a decoder gets (the decoded point and triangle counts, the decoded bounds).
Json draco_primitive(GlbBuilder& glb, const std::vector<Stream>& streams, const PolyData& pd,
                     std::size_t triangles, const std::string& where,
                     const GltfWriteOptions& options, GltfWriteStats& stats) {
  const std::size_t n = pd.num_points();
  PolyData tri;
  io_detail::DracoRoles roles;
  std::map<std::string, std::string> semantic_of;  // array name in `tri` -> glTF semantic
  for (const Stream& st : streams) {
    if (st.semantic == "POSITION") {
      tri.points = Points(n);
      st.fill(0, n, reinterpret_cast<std::byte*>(tri.points.floats().data()));
      continue;
    }
    std::string name = st.array.empty() ? "Normals" : st.array;
    while (tri.point_data.has(name)) name += "_";
    DataArray a;
    if (st.semantic == "COLOR_0") {
      Buffer<std::uint16_t> linear(4 * n);
      st.fill(0, n, reinterpret_cast<std::byte*>(linear.data()));
      a = DataArray(name, ScalarType::UInt8, 4, n);
      auto out = a.values<std::uint8_t>();
      for (std::size_t i = 0; i < 4 * n; ++i) {
        out[i] = static_cast<std::uint8_t>((linear[i] + 128) / 257);
      }
      roles.colors = name;
    } else {
      a = DataArray(name, ScalarType::Float32, st.components, n);
      st.fill(0, n, static_cast<std::byte*>(a.bytes()));
      if (st.semantic == "NORMAL") roles.normals = name;
    }
    semantic_of[name] = st.semantic;
    tri.point_data.add(std::move(a));
  }
  {
    Buffer<std::uint32_t> ids(3 * triangles);
    IndexCursor(pd, kModeTriangles).next(ids.data(), ids.size());
    tri.polys.reserve(triangles, 3 * triangles);
    for (std::size_t k = 0; k < ids.size(); k += 3) {
      tri.polys.add({Index{ids[k]}, Index{ids[k + 1]}, Index{ids[k + 2]}});
    }
  }
  io_detail::DracoEncodedMesh enc = io_detail::encode_draco_mesh(tri, options.draco, roles, where);
  tri = {};
  const PolyData& dec = enc.decoded;
  const std::size_t m = dec.num_points();
  Json prim, attributes, ext, ids;  // (built apart: a reference into an object moves as it grows)
  ext["bufferView"] = glb.add_blob(std::move(enc.bytes));
  for (const io_detail::DracoAttributeId& id : enc.attributes) {
    Json acc;
    acc["count"] = m;
    std::string semantic;
    if (id.kind == io_detail::DracoKind::Position) {
      semantic = "POSITION";
      acc["componentType"] = kFloat;
      acc["type"] = "VEC3";
      Json lo = Json::array(), hi = Json::array();
      const Bounds b = dec.bounds();
      for (const double v : {b.min.x, b.min.y, b.min.z})
        lo.push(Json(double{static_cast<float>(v)}));
      for (const double v : {b.max.x, b.max.y, b.max.z})
        hi.push(Json(double{static_cast<float>(v)}));
      acc["min"] = std::move(lo);
      acc["max"] = std::move(hi);
    } else {
      const auto it = semantic_of.find(id.name);
      check_invariant(it != semantic_of.end(), "every Draco attribute is one of the streams");
      semantic = it->second;
      const DataArray& a = dec.point_data.get(id.name);
      acc["componentType"] = a.type() == ScalarType::UInt8 ? kUnsignedByte : kFloat;
      if (a.type() == ScalarType::UInt8) acc["normalized"] = true;
      acc["type"] = kTypes[a.components() - 1];
    }
    attributes[semantic] = glb.add_accessor(std::move(acc));
    ids[semantic] = id.unique_id;
  }
  ext["attributes"] = std::move(ids);
  prim["attributes"] = std::move(attributes);
  prim["extensions"][kDraco] = std::move(ext);
  Json indices;
  indices["count"] = 3 * dec.polys.size();
  indices["componentType"] = m <= 0xFFFF ? kUnsignedShort : kUnsignedInt;
  indices["type"] = "SCALAR";
  prim["indices"] = glb.add_accessor(std::move(indices));
  prim["mode"] = kModeTriangles;
  stats.draco.push_back(std::move(enc.stats));
  return prim;
}
// Lays out one mesh's vertex data and primitives in `glb`; returns the glTF mesh object.
Json write_mesh(GlbBuilder& glb, const GltfMesh& m, const std::string& where,
                const GltfWriteOptions& options, GltfWriteStats& stats) {
  const PolyData& pd = m.mesh;
  const std::size_t n = pd.num_points();
  if (n == 0) throw Error(where + ": a glTF mesh needs at least one point");
  if (n > std::size_t{0xFFFFFFFE}) throw Error(where + ": more than 2^32 - 2 points");
  if (const std::size_t bad = pd.points.first_non_finite(); bad < n) {
    throw Error(where + ": point " + std::to_string(bad) + " has a non-finite coordinate");
  }
  const auto as_floats = [&pd](std::size_t i) {
    const Vec3 p = pd.points[i];
    return std::array<float, 3>{static_cast<float>(p.x), static_cast<float>(p.y),
                                static_cast<float>(p.z)};
  };
  // In one parallel pass: the bounds of the float positions (POSITION's min and max) and the
  // first point beyond the float32 range, merged from the ranges (neither depends on the order).
  std::array<float, 3> lo, hi;
  lo.fill(std::numeric_limits<float>::max());
  hi.fill(std::numeric_limits<float>::lowest());
  std::size_t beyond = n;
  std::mutex merge;
  parallel_for_range(n, kPointGrain, [&](std::size_t b, std::size_t e) {
    std::array<float, 3> l, h;
    l.fill(std::numeric_limits<float>::max());
    h.fill(std::numeric_limits<float>::lowest());
    std::size_t bad = n;
    for (std::size_t i = b; i < e; ++i) {
      const auto f = as_floats(i);
      for (std::size_t k = 0; k < 3; ++k) l[k] = std::min(l[k], f[k]), h[k] = std::max(h[k], f[k]);
      if (bad == n && !(std::isfinite(f[0]) && std::isfinite(f[1]) && std::isfinite(f[2]))) bad = i;
    }
    const std::lock_guard<std::mutex> lock(merge);
    for (std::size_t k = 0; k < 3; ++k)
      lo[k] = std::min(lo[k], l[k]), hi[k] = std::max(hi[k], h[k]);
    beyond = std::min(beyond, bad);
  });
  if (beyond < n) {
    throw Error(where + ": point " + std::to_string(beyond) + " is beyond the float32 range");
  }
  // The vertex streams: positions, normals, colours, arrays; each made from the dataset when
  // its view is written (or handed to Draco).
  std::vector<Stream> streams;
  streams.push_back(Stream{"POSITION", 12, kFloat, 3, false, "",
                           [as_floats](std::size_t first, std::size_t count, std::byte* dst) {
                             auto* out = reinterpret_cast<float*>(dst);
                             for_elements(first, count, [&](std::size_t i, std::size_t j) {
                               const auto f = as_floats(i);
                               std::copy(f.begin(), f.end(), out + 3 * j);
                             });
                           }});
  const PrimitiveCounts counts = count_primitives(pd);
  stats.vertices += n;
  stats.triangles += counts.triangles;
  stats.segments += counts.segments;

  Json names = Json::array();  // extras: which attribute holds which array
  auto name_entry = [&](const std::string& semantic, const DataArray& a) {
    Json e;
    e["attribute"] = semantic;
    e["name"] = a.name();
    e["components"] = a.components();
    e["type"] = scalar_type_name(a.type());
    names.push(std::move(e));
  };
  const DataArray* normals_array = nullptr;
  if (options.normals) {
    const DataArray* given = pd.point_data.normals();
    if (given && (given->components() != 3 || given->tuples() != n)) given = nullptr;
    std::shared_ptr<const DataArray> computed;  // kept by the stream until it is written
    if (!given && counts.triangles > 0) {
      computed = std::make_shared<const DataArray>(point_normals(pd));
      given = computed.get();
    }
    if (given) {
      std::atomic<std::size_t> replaced{0};
      parallel_for_range(n, kPointGrain, [&](std::size_t b, std::size_t e) {
        std::size_t r = 0;
        float v[3];
        for (std::size_t i = b; i < e; ++i) r += unit_normal(*given, i, v) ? 0 : 1;
        replaced += r;
      });
      stats.normals_replaced += replaced;
      streams.push_back(
          Stream{"NORMAL", 12, kFloat, 3, false, computed ? "" : given->name(),
                 [given, computed](std::size_t first, std::size_t count, std::byte* dst) {
                   auto* out = reinterpret_cast<float*>(dst);
                   for_elements(first, count, [&](std::size_t i, std::size_t j) {
                     (void)unit_normal(*given, i, out + 3 * j);
                   });
                 }});
      if (!computed) {
        normals_array = given;
        name_entry("NORMAL", *given);
      }
    }
  }
  const DataArray* colors = color_array(m, where);
  std::string scalars_written;  // the active scalars' name, when they are in the file
  if (colors && colors == pd.point_data.scalars()) scalars_written = colors->name();
  if (colors) {
    // glTF's COLOR_0 is linear; uint8 colours (colour maps, PLY) are sRGB. Linear values in
    // normalized uint16 map back to the same uint8 sRGB codes (the smallest step, at 0, is 20
    // units). Always RGBA: glTF aligns every vertex element to 4 bytes.
    std::array<std::uint16_t, 256> linear{};
    for (int v = 0; v < 256; ++v) {
      linear[static_cast<std::size_t>(v)] =
          static_cast<std::uint16_t>(std::lround(srgb_to_linear(v / 255.0) * 65535.0));
    }
    streams.push_back(
        Stream{"COLOR_0", 8, kUnsignedShort, 4, true, colors->name(),
               [colors, linear](std::size_t first, std::size_t count, std::byte* dst) {
                 const auto c = static_cast<std::size_t>(colors->components());
                 const auto src = colors->values<std::uint8_t>();
                 auto* rgba = reinterpret_cast<std::uint16_t*>(dst);
                 for_elements(first, count, [&](std::size_t i, std::size_t j) {
                   for (std::size_t k = 0; k < 4; ++k) {
                     rgba[4 * j + k] = 65535;  // opaque where the array has no alpha
                     if (k >= c) continue;
                     const std::uint8_t v = src[c * i + k];
                     rgba[4 * j + k] = k < 3 ? linear[v] : static_cast<std::uint16_t>(v * 257);
                   }
                 });
               }});
    name_entry("COLOR_0", *colors);
  }
  if (options.arrays) {
    std::set<std::string> used;
    for (const DataArray& a : pd.point_data) {
      if (&a == normals_array || &a == colors) continue;
      const int c = a.components();
      if (c > 4) {
        stats.arrays_skipped.push_back(where + ": " + a.name() + " (" + std::to_string(c) +
                                       " components; glTF attributes have at most 4)");
        continue;
      }
      const std::size_t values = a.size();
      const auto value = [&a, c](std::size_t i) {
        return static_cast<float>(a.get(i / static_cast<std::size_t>(c), static_cast<int>(i % c)));
      };
      const std::size_t bad =
          parallel_find_first(values, kPointGrain, [&](std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) {
              if (!std::isfinite(value(i))) return i;
            }
            return e;
          });
      if (bad < values) {
        stats.arrays_skipped.push_back(where + ": " + a.name() +
                                       " (non-finite values; glTF accessors hold finite floats)");
        continue;
      }
      const std::string semantic = custom_semantic(a.name(), used);
      streams.push_back(
          Stream{semantic, 4 * static_cast<std::size_t>(c), kFloat, c, false, a.name(),
                 [value, c](std::size_t first, std::size_t count, std::byte* dst) {
                   auto* out = reinterpret_cast<float*>(dst);
                   const auto k = static_cast<std::size_t>(c);
                   for_elements(k * first, k * count,
                                [&](std::size_t i, std::size_t j) { out[j] = value(i); });
                 }});
      name_entry(semantic, a);
      if (&a == pd.point_data.scalars()) scalars_written = a.name();
    }
  }
  for (const DataArray& a : pd.cell_data) {
    stats.arrays_skipped.push_back(where + ": " + a.name() +
                                   " (cell data; glTF has point attributes only)");
  }

  // What the plain layout takes (the ratio's denominator, whatever the codec).
  const bool short_indices = n <= 0xFFFF;  // 65535 itself is the restart value: not allowed
  const std::size_t index_bytes = short_indices ? 2 : 4;
  std::size_t raw_bytes = 0;
  for (const Stream& st : streams) raw_bytes += align4(n * st.elem_bytes);
  for (const std::size_t indices : {3 * counts.triangles, 2 * counts.segments, counts.points}) {
    raw_bytes += align4(index_bytes * indices);
  }
  stats.raw_bytes += raw_bytes;
  // The plain accessors of the streams, made once when a primitive first needs them.
  Json attributes;
  auto plain_attributes = [&]() -> const Json& {
    if (attributes.is_object()) return attributes;
    for (const Stream& st : streams) {
      const std::size_t view = glb.add_view(n, st.elem_bytes, true, false, stream_producer(st));
      Json acc;
      acc["bufferView"] = view;
      acc["componentType"] = st.component_type;
      if (st.normalized) acc["normalized"] = true;
      acc["count"] = n;
      acc["type"] = kTypes[st.components - 1];
      if (st.semantic == "POSITION") {
        acc["min"] =
            Json(Json::Array{Json(double{lo[0]}), Json(double{lo[1]}), Json(double{lo[2]})});
        acc["max"] =
            Json(Json::Array{Json(double{hi[0]}), Json(double{hi[1]}), Json(double{hi[2]})});
      }
      attributes[st.semantic] = glb.add_accessor(std::move(acc));
    }
    return attributes;
  };

  // Primitives sharing the vertex accessors; `indices` of the mode's cells (none: every point).
  Json primitives = Json::array();
  auto add_primitive = [&](int mode, std::size_t indices) {
    Json prim;
    prim["attributes"] = plain_attributes();
    if (indices > 0) {
      const std::size_t view = glb.add_view(indices, index_bytes, false, mode == kModeTriangles,
                                            index_producer(pd, mode, short_indices));
      Json acc;
      acc["bufferView"] = view;
      acc["componentType"] = short_indices ? kUnsignedShort : kUnsignedInt;
      acc["count"] = indices;
      acc["type"] = "SCALAR";
      prim["indices"] = glb.add_accessor(std::move(acc));
    }
    prim["mode"] = mode;
    primitives.push(std::move(prim));
  };
  if (counts.triangles > 0) {
    if (options.codec == GltfCodec::Draco) {
      primitives.push(draco_primitive(glb, streams, pd, counts.triangles, where, options, stats));
    } else {
      add_primitive(kModeTriangles, 3 * counts.triangles);
    }
  }
  if (counts.segments > 0) add_primitive(kModeLines, 2 * counts.segments);
  if (counts.points > 0) {
    stats.points += counts.points;
    add_primitive(kModePoints, counts.points);
  }
  if (primitives.size() == 0) {  // points and no cells: every point is drawn
    stats.points += n;
    add_primitive(kModePoints, 0);
  }

  Json mesh;
  if (!m.name.empty()) mesh["name"] = m.name;
  mesh["primitives"] = std::move(primitives);
  Json& extras = mesh["extras"];
  extras["isoforge_arrays"] = std::move(names);
  if (!scalars_written.empty()) extras["isoforge_scalars"] = scalars_written;
  if (m.legend) extras["legend"] = legend_json(*m.legend, where);
  return mesh;
}

void put_u32(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out += static_cast<char>((v >> (8 * i)) & 0xFF);
}

}  // namespace

std::string_view gltf_codec_name(GltfCodec codec) {
  switch (codec) {
    case GltfCodec::None:
      return "none";
    case GltfCodec::Meshopt:
      return "meshopt";
    case GltfCodec::Draco:
      return "draco";
  }
  return "?";
}

GltfCodec gltf_codec_from_name(std::string_view name) {
  if (name == "none") return GltfCodec::None;
  if (name == "meshopt") return GltfCodec::Meshopt;
  if (name == "draco") return GltfCodec::Draco;
  throw Error("glTF codec '" + std::string(name) + "' is not one of none, meshopt, draco");
}

bool gltf_codec_available(GltfCodec) {
  return true;
}

GltfWriteStats write_gltf(std::span<const GltfMesh> meshes, const std::filesystem::path& path,
                          const GltfWriteOptions& options) {
  const std::string file = path.string();
  if (!gltf_codec_available(options.codec)) {
    throw Error(file + ": the glTF codec '" + std::string(gltf_codec_name(options.codec)) +
                "' is not available in this build");
  }
  if (meshes.empty()) throw Error(file + ": a glTF file needs at least one mesh");
  GltfWriteStats stats;
  GlbBuilder glb(options.codec);
  Json gltf;
  gltf["asset"]["version"] = "2.0";
  gltf["asset"]["generator"] = "isoforge";
  Json json_meshes = Json::array();
  Json nodes = Json::array();
  Json scene_nodes = Json::array();
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    const std::string where = file + ": mesh " + std::to_string(i) +
                              (meshes[i].name.empty() ? "" : " '" + meshes[i].name + "'");
    meshes[i].mesh.validate();
    const std::size_t index = json_meshes.push(write_mesh(glb, meshes[i], where, options, stats));
    Json node;
    node["mesh"] = index;
    if (!meshes[i].name.empty()) node["name"] = meshes[i].name;
    scene_nodes.push(nodes.push(std::move(node)));
  }
  stats.meshes = meshes.size();
  Json scene;
  scene["nodes"] = std::move(scene_nodes);
  if (!options.units.empty()) scene["extras"]["units"] = options.units;
  gltf["scene"] = 0;
  gltf["scenes"] = Json(Json::Array{std::move(scene)});
  gltf["nodes"] = std::move(nodes);
  gltf["meshes"] = std::move(json_meshes);
  gltf["accessors"] = std::move(glb.accessors());
  gltf["bufferViews"] = std::move(glb.buffer_views());
  Json buffers = Json::array();
  Json bin_buffer;
  bin_buffer["byteLength"] = glb.bin_size();
  buffers.push(std::move(bin_buffer));
  if (options.codec == GltfCodec::Draco && !stats.draco.empty()) {
    gltf["extensionsUsed"] = Json(Json::Array{Json(kDraco)});
    gltf["extensionsRequired"] = Json(Json::Array{Json(kDraco)});
  }
  if (options.codec == GltfCodec::Meshopt) {
    Json fallback;
    fallback["byteLength"] = glb.raw_bytes();
    fallback["extensions"][kMeshopt]["fallback"] = true;
    buffers.push(std::move(fallback));
    gltf["extensionsUsed"] = Json(Json::Array{Json(kMeshopt)});
    gltf["extensionsRequired"] = Json(Json::Array{Json(kMeshopt)});
  }
  gltf["buffers"] = std::move(buffers);

  std::string json = gltf.dump();
  json.resize(align4(json.size()), ' ');  // the JSON chunk is padded with spaces
  const std::size_t bin_size = align4(glb.bin_size());
  const std::size_t total = 12 + 8 + json.size() + (bin_size ? 8 + bin_size : 0);
  if (total > std::size_t{0xFFFFFFFF}) throw Error(file + ": more than 4 GiB: too big for .glb");
  report_progress(options.progress, 0.5, "writing");
  std::string header;
  put_u32(header, kGlbMagic);
  put_u32(header, 2);
  put_u32(header, static_cast<std::uint32_t>(total));
  put_u32(header, static_cast<std::uint32_t>(json.size()));
  put_u32(header, kChunkJson);
  AtomicFile out(path);
  out.reserve(total);
  auto& s = out.stream();
  s.write(header.data(), static_cast<std::streamsize>(header.size()));
  s.write(json.data(), static_cast<std::streamsize>(json.size()));
  json = {};
  if (bin_size) {
    std::string chunk;
    put_u32(chunk, static_cast<std::uint32_t>(bin_size));
    put_u32(chunk, kChunkBin);
    s.write(chunk.data(), 8);
    glb.write_bin(s, [&](std::size_t written) {
      report_progress(options.progress, 0.5 + 0.5 * double(written) / double(bin_size), "writing");
    });
  }
  out.commit();
  stats.bytes = total;
  report_progress(options.progress, 1.0, "writing");
  return stats;
}

GltfWriteStats write_gltf(const PolyData& mesh, const std::filesystem::path& path,
                          const GltfWriteOptions& options) {
  const GltfMesh one{path.stem().string(), mesh};
  return write_gltf(std::span<const GltfMesh>(&one, 1), path, options);
}

// ---------------------------------------------------------------------------------------------
// Reading

namespace {

class GlbReader {
 public:
  /// `file`: the mapping `data` is (its pages are released behind the accessors read), or null.
  GlbReader(std::span<const std::byte> data, std::string_view name,
            const io_detail::MappedFile* file = nullptr)
      : data_(data), name_(name), file_(file) {}

  GltfContent read() {
    GltfContent content;
    const Json& meshes = open(&content.units);
    for (std::size_t i = 0; i < meshes.size(); ++i)
      content.meshes.push_back(read_mesh(meshes.as_array()[i], i, nullptr));
    return content;
  }

  /// The summary of what read() gives (all meshes appended), checked as read() checks, one
  /// vertex set at a time: its points and point arrays summarised and dropped, its cells
  /// counted from the index accessors (every index checked, none stored).
  DatasetSummary summarize() {
    const Json& meshes = open(nullptr);
    std::vector<DatasetSummary> parts;
    for (std::size_t i = 0; i < meshes.size(); ++i) {
      const std::size_t before = parts.size();
      (void)read_mesh(meshes.as_array()[i], i, &parts);
      // A mesh without primitives is an empty part of read()'s append (which drops every array).
      if (parts.size() == before) parts.push_back(isoforge::summarize(PolyData{}));
    }
    DatasetSummary s = append_summaries(parts);
    s.streamed = true;
    return s;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { throw Error(name_ + ": " + what); }

  // Drops the mapped pages of the file bytes [from, to) once read (MappedFile::release): the
  // resident set stays the arrays made, not the file. Nothing for bytes not in the mapping
  // (decoded meshopt views).
  void release(const std::byte* from, const std::byte* to) const {
    if (file_ && from >= data_.data() && to <= data_.data() + data_.size() && to > from) {
      file_->release(static_cast<std::uint64_t>(from - data_.data()),
                     static_cast<std::size_t>(to - from));
    }
  }

  // The container parsed, the required extensions checked and the units (when `units` is not
  // null) taken from the first scene that gives them: the 'meshes' array.
  const Json& open(std::string* units) {
    parse_container();
    if (const Json* required = gltf_.find("extensionsRequired"); required && required->is_array()) {
      for (const Json& e : required->as_array()) {
        if (!e.is_string() || (e.as_string() != kMeshopt && e.as_string() != kDraco)) {
          fail("requires the extension " + (e.is_string() ? e.as_string() : std::string("?")) +
               ", which this reader does not support");
        }
      }
    }
    if (const Json* scenes = gltf_.find("scenes"); units && scenes && scenes->is_array()) {
      for (const Json& scene : scenes->as_array()) {
        const Json* extras = scene.find("extras");
        const Json* u = extras ? extras->find("units") : nullptr;
        if (u && u->is_string()) {
          *units = u->as_string();
          break;
        }
      }
    }
    const Json& meshes = member(gltf_, "meshes", "the glTF");
    if (!meshes.is_array()) fail("'meshes' is not an array");
    return meshes;
  }

  std::uint32_t u32(std::size_t at) const {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(data_[at + i]) << (8 * i);
    return v;
  }

  void parse_container() {
    if (data_.size() < 4 || u32(0) != kGlbMagic)
      fail("byte 0: not a binary glTF file (no 'glTF' magic)");
    if (data_.size() < 20) fail("byte 4: truncated: a .glb starts with a 20-byte header");
    if (u32(4) != 2)
      fail("byte 4: glTF container version " + std::to_string(u32(4)) + ", expected 2");
    const std::uint32_t length = u32(8);
    if (length > data_.size()) {
      fail("byte 8: truncated: the header says " + std::to_string(length) +
           " bytes but the file has " + std::to_string(data_.size()));
    }
    std::size_t at = 12;
    bool first = true;
    while (at + 8 <= length) {
      const std::uint32_t size = u32(at), type = u32(at + 4);
      if (size > length - at - 8) {
        fail("byte " + std::to_string(at) + ": chunk of " + std::to_string(size) +
             " bytes runs past the end of the file");
      }
      const auto bytes = data_.subspan(at + 8, size);
      if (first && type != kChunkJson)
        fail("byte " + std::to_string(at) + ": the first chunk is not JSON");
      if (type == kChunkJson && first) {
        gltf_ = io_detail::parse_json(
            std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), name_);
        if (!gltf_.is_object()) fail("JSON chunk is not an object");
      } else if (type == kChunkBin && !has_bin_) {
        bin_ = bytes;
        has_bin_ = true;
      }
      first = false;
      at += 8 + size;
    }
    if (first) fail("byte 12: no JSON chunk");
  }

  const Json& member(const Json& object, std::string_view key, const std::string& what) const {
    const Json* v = object.find(key);
    if (!v) fail(what + ": missing '" + std::string(key) + "'");
    return *v;
  }
  std::size_t index(const Json& object, std::string_view key, const std::string& what,
                    std::size_t limit) const {
    const Json& v = member(object, key, what);
    if (!v.is_number() || v.as_number() < 0 || v.as_number() != std::floor(v.as_number()) ||
        v.as_number() >= static_cast<double>(limit)) {
      fail(what + ": '" + std::string(key) + "' is not an integer below " + std::to_string(limit));
    }
    return static_cast<std::size_t>(v.as_number());
  }
  std::size_t optional_index(const Json& object, std::string_view key, const std::string& what,
                             std::size_t limit, std::size_t fallback) const {
    return object.find(key) ? index(object, key, what, limit) : fallback;
  }
  const Json& element(std::string_view array, std::size_t i) const {
    const Json* a = gltf_.find(array);
    if (!a || !a->is_array() || i >= a->size()) {
      fail(std::string(array) + " " + std::to_string(i) + " does not exist");
    }
    return a->as_array()[i];
  }

  // The bytes of buffer `b` (the BIN chunk; a meshopt fallback buffer has none).
  std::span<const std::byte> buffer(std::size_t b) const {
    const Json& buf = element("buffers", b);
    const std::string what = "buffers " + std::to_string(b);
    if (buf.find("uri")) fail(what + ": external buffers (uri) are not supported in a .glb");
    if (b != 0 || !has_bin_) fail(what + ": no binary chunk holds this buffer");
    const std::size_t length = index(buf, "byteLength", what, std::size_t{1} << 32);
    if (length > bin_.size())
      fail(what + ": byteLength " + std::to_string(length) + " exceeds the binary chunk");
    return bin_.first(length);
  }

  // The bytes of bufferView `v`, decoded when it is meshopt-compressed.
  std::span<const std::byte> view(std::size_t v) {
    if (auto it = decoded_.find(v); it != decoded_.end()) return it->second;
    const Json& bv = element("bufferViews", v);
    const std::string what = "bufferViews " + std::to_string(v);
    const std::size_t length = index(bv, "byteLength", what, std::size_t{1} << 32);
    const Json* ext = bv.find("extensions");
    const Json* mo = ext ? ext->find(kMeshopt) : nullptr;
    if (mo) {
      const std::string w = what + ": " + kMeshopt;
      const auto src = buffer(index(*mo, "buffer", w, 1 << 20));
      const std::size_t offset = optional_index(*mo, "byteOffset", w, std::size_t{1} << 32, 0);
      const std::size_t size = index(*mo, "byteLength", w, std::size_t{1} << 32);
      const std::size_t stride = index(*mo, "byteStride", w, 257);
      const std::size_t count = index(*mo, "count", w, std::size_t{1} << 32);
      const std::string mode =
          member(*mo, "mode", w).is_string() ? member(*mo, "mode", w).as_string() : "";
      if (const Json* f = mo->find("filter"); f && !(f->is_string() && f->as_string() == "NONE")) {
        fail(w + ": filters are not supported");
      }
      if (offset > src.size() || size > src.size() - offset)
        fail(w + ": data runs past the buffer");
      if (stride == 0 || count * stride != length) fail(w + ": count * byteStride != byteLength");
      // The codecs shrink data by at most about 64 times (2 header bits per 16 bytes), so a
      // larger claim is corrupt: checked before allocating.
      if (length > 256 * size + 65536)
        fail(w + ": " + std::to_string(length) + " bytes cannot come from " + std::to_string(size));
      std::vector<std::byte> out(length);
      const auto* in = reinterpret_cast<const unsigned char*>(src.data() + offset);
      int rc = -1;
      if (mode == "ATTRIBUTES") {
        if (stride % 4 != 0) fail(w + ": ATTRIBUTES byteStride must be a multiple of 4");
        rc = meshopt_decodeVertexBuffer(out.data(), count, stride, in, size);
      } else if (mode == "TRIANGLES" || mode == "INDICES") {
        if (stride != 2 && stride != 4) fail(w + ": index byteStride must be 2 or 4");
        if (mode == "TRIANGLES" && count % 3 != 0)
          fail(w + ": TRIANGLES count is not a multiple of 3");
        rc = mode == "TRIANGLES" ? meshopt_decodeIndexBuffer(out.data(), count, stride, in, size)
                                 : meshopt_decodeIndexSequence(out.data(), count, stride, in, size);
      } else {
        fail(w + ": unknown mode '" + mode + "'");
      }
      if (rc != 0) fail(w + ": corrupt compressed data (meshopt error " + std::to_string(rc) + ")");
      return decoded_[v] = std::move(out);
    }
    const auto src = buffer(index(bv, "buffer", what, 1 << 20));
    const std::size_t offset = optional_index(bv, "byteOffset", what, std::size_t{1} << 32, 0);
    if (offset > src.size() || length > src.size() - offset) fail(what + ": runs past its buffer");
    return src.subspan(offset, length);
  }

  struct Accessor {
    int component_type = 0;
    int components = 0;
    std::size_t count = 0;
    bool normalized = false;
  };

  // Calls `start(info)` once the accessor is checked, then put(k, value) for its `count *
  // components` values in order as doubles (normalized integers mapped to [0, 1]).
  template <class Start, class Put>
  void visit_accessor(std::size_t a, Accessor& info, Start&& start, Put&& put) {
    const Json& acc = element("accessors", a);
    const std::string what = "accessors " + std::to_string(a);
    info.component_type = static_cast<int>(index(acc, "componentType", what, 5127));
    info.count = index(acc, "count", what, std::size_t{1} << 32);
    const Json& type = member(acc, "type", what);
    static const std::map<std::string, int> kComponents = {{"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3},
                                                           {"VEC4", 4},   {"MAT2", 4}, {"MAT3", 9},
                                                           {"MAT4", 16}};
    const auto it = type.is_string() ? kComponents.find(type.as_string()) : kComponents.end();
    if (it == kComponents.end()) fail(what + ": unknown type");
    info.components = it->second;
    const Json* norm = acc.find("normalized");
    info.normalized = norm && norm->is_bool() && norm->as_bool();
    if (acc.find("sparse")) fail(what + ": sparse accessors are not supported");
    std::size_t size = 0;
    switch (info.component_type) {
      case 5120:
      case kUnsignedByte:
        size = 1;
        break;
      case 5122:
      case kUnsignedShort:
        size = 2;
        break;
      case kUnsignedInt:
      case kFloat:
        size = 4;
        break;
      default:
        fail(what + ": unknown componentType " + std::to_string(info.component_type));
    }
    if (!acc.find("bufferView")) fail(what + ": accessors without a bufferView are not supported");
    const std::size_t v = index(acc, "bufferView", what, std::size_t{1} << 32);
    const auto bytes = view(v);
    const std::size_t offset = optional_index(acc, "byteOffset", what, std::size_t{1} << 32, 0);
    const std::size_t elem = size * static_cast<std::size_t>(info.components);
    const Json& bv = element("bufferViews", v);
    std::size_t stride =
        optional_index(bv, "byteStride", "bufferViews " + std::to_string(v), 253, elem);
    if (stride < elem) fail(what + ": byteStride is smaller than an element");
    if (info.count > 0 &&
        (offset > bytes.size() || (info.count - 1) * stride + elem > bytes.size() - offset)) {
      fail(what + ": " + std::to_string(info.count) + " elements run past bufferView " +
           std::to_string(v));
    }
    start(info);
    constexpr std::size_t kReleaseEvery = std::size_t{8} << 20;  // bytes read between releases
    const std::byte* unreleased = bytes.data() + offset;
    for (std::size_t i = 0; i < info.count; ++i) {
      const std::byte* p = bytes.data() + offset + i * stride;
      if (static_cast<std::size_t>(p - unreleased) >= kReleaseEvery) {
        release(unreleased, p);
        unreleased = p;
      }
      for (int c = 0; c < info.components; ++c, p += size) {
        double value = 0;
        switch (info.component_type) {
          case 5120: {
            std::int8_t x;
            std::memcpy(&x, p, 1);
            value = info.normalized ? std::max(x / 127.0, -1.0) : x;
            break;
          }
          case kUnsignedByte: {
            std::uint8_t x;
            std::memcpy(&x, p, 1);
            value = info.normalized ? x / 255.0 : x;
            break;
          }
          case 5122: {
            std::int16_t x;
            std::memcpy(&x, p, 2);
            value = info.normalized ? std::max(x / 32767.0, -1.0) : x;
            break;
          }
          case kUnsignedShort: {
            std::uint16_t x;
            std::memcpy(&x, p, 2);
            value = info.normalized ? x / 65535.0 : x;
            break;
          }
          case kUnsignedInt: {
            std::uint32_t x;
            std::memcpy(&x, p, 4);
            value = x;
            break;
          }
          default: {
            float x;
            std::memcpy(&x, p, 4);
            value = x;
          }
        }
        put(i * static_cast<std::size_t>(info.components) + static_cast<std::size_t>(c), value);
      }
    }
    if (info.count > 0)
      release(unreleased, bytes.data() + offset + (info.count - 1) * stride + elem);
  }

  // Accessor `a` as doubles, `count * components` of them.
  std::vector<double> read_accessor(std::size_t a, Accessor& info) {
    std::vector<double> out;
    visit_accessor(
        a, info,
        [&](const Accessor& i) { out.resize(i.count * static_cast<std::size_t>(i.components)); },
        [&](std::size_t k, double v) { out[k] = v; });
    return out;
  }

  // Vertices of one POSITION accessor and the arrays that go with them.
  struct VertexSet {
    std::size_t position = 0;
    PolyData pd;
  };

  // Adds the array of attribute `semantic` (`values`: n tuples of `value_components` doubles,
  // colours linear in [0, 1]) to `pd` under the name, components and type isoforge's extras
  // give, with its role.
  void add_array(PolyData& pd, const std::string& semantic, const std::vector<double>& values,
                 int value_components, const std::string& what, const Json* names,
                 const std::string& scalars_name) const {
    const std::size_t n = pd.num_points();
    std::string name = semantic == "NORMAL"    ? "Normals"
                       : semantic == "COLOR_0" ? "Colors"
                                               : semantic;
    int components = value_components;
    ScalarType type = semantic == "COLOR_0" ? ScalarType::UInt8 : ScalarType::Float32;
    if (names && names->is_array()) {
      for (const Json& e : names->as_array()) {
        const Json* a = e.find("attribute");
        if (!a || !a->is_string() || a->as_string() != semantic) continue;
        if (const Json* nm = e.find("name"); nm && nm->is_string()) name = nm->as_string();
        if (const Json* c = e.find("components");
            c && c->is_number() && c->as_number() >= 1 && c->as_number() <= value_components) {
          components = static_cast<int>(c->as_number());
        }
        if (const Json* t = e.find("type"); t && t->is_string()) {
          try {
            type = scalar_type_from_name(t->as_string());
          } catch (const Error&) {
            fail(what + ": unknown array type '" + t->as_string() + "'");
          }
        }
      }
    }
    if (pd.point_data.has(name)) return;  // a duplicate name: the first wins
    DataArray array(name, type, components, n);
    const bool color = semantic == "COLOR_0";
    // An integer array's values must fit its type (a corrupt file may say Int32 over 1e19).
    const auto [lowest, highest] = visit_scalar_type(type, [](auto t) {
      using T = decltype(t);
      return std::pair<double, double>{static_cast<double>(std::numeric_limits<T>::lowest()),
                                       static_cast<double>(std::numeric_limits<T>::max())};
    });
    const bool integral = !is_floating(type);
    for (std::size_t i = 0; i < n; ++i) {
      for (int c = 0; c < components; ++c) {
        double v =
            values[i * static_cast<std::size_t>(value_components) + static_cast<std::size_t>(c)];
        if (color) {  // linear [0, 1] (float or normalized) to sRGB codes; alpha is linear
          v = std::clamp(v, 0.0, 1.0);
          v = std::round((c < 3 ? linear_to_srgb(v) : v) * 255.0);
        }
        if (integral && !(v >= lowest && v <= highest)) {
          fail(what + ": value " + fmt::format("{}", v) + " of array '" + name +
               "' does not fit its type " + std::string(scalar_type_name(type)));
        }
        array.set(i, c, v);
      }
    }
    if (semantic == "NORMAL") {
      pd.point_data.add(std::move(array), AttributeRole::Normals);
    } else if ((color && scalars_name.empty()) || (!scalars_name.empty() && name == scalars_name)) {
      pd.point_data.add(std::move(array), AttributeRole::Scalars);
    } else {
      pd.point_data.add(std::move(array));
    }
  }

  PolyData read_vertices(const Json& attributes, const std::string& what, const Json* names,
                         const std::string& scalars_name) {
    PolyData pd;
    Accessor info;
    float* floats = nullptr;
    visit_accessor(
        index(attributes, "POSITION", what, std::size_t{1} << 32), info,
        [&](const Accessor& i) {
          if (i.components != 3) fail(what + ": POSITION is not VEC3");
          pd.points = Points(DataArray::uninitialized("Points", ScalarType::Float32, 3, i.count));
          floats = pd.points.floats().data();
        },
        [&](std::size_t k, double v) { floats[k] = static_cast<float>(v); });
    const std::size_t n = info.count;
    for (const auto& [semantic, value] : attributes.as_object()) {
      if (semantic == "POSITION") continue;
      if (!value.is_number()) fail(what + ": attribute " + semantic + " is not an accessor index");
      const auto values =
          read_accessor(index(attributes, semantic, what, std::size_t{1} << 32), info);
      if (info.count != n)
        fail(what + ": attribute " + semantic + " has " + std::to_string(info.count) +
             " elements, POSITION " + std::to_string(n));
      add_array(pd, semantic, values, info.components, what, names, scalars_name);
    }
    return pd;
  }

  // A KHR_draco_mesh_compression primitive: decoded by the Draco codec, its attributes named
  // through the extension's semantic -> unique id map and isoforge's extras.
  PolyData read_draco_primitive(const Json& ext, const std::string& what, const Json* names,
                                const std::string& scalars_name) {
    const std::string w = what + ": " + kDraco;
    const auto bytes = view(index(ext, "bufferView", w, std::size_t{1} << 32));
    io_detail::DracoDecodedMesh decoded = io_detail::decode_draco_mesh(bytes, name_ + ": " + w);
    PolyData pd;
    pd.points = std::move(decoded.mesh.points);
    pd.polys = std::move(decoded.mesh.polys);
    const Json& ids = member(ext, "attributes", w);
    if (!ids.is_object()) fail(w + ": 'attributes' is not an object");
    for (const auto& [semantic, id] : ids.as_object()) {
      if (semantic == "POSITION") continue;
      const std::size_t uid = index(ids, semantic, w, std::size_t{1} << 31);
      const DataArray* a = nullptr;
      for (const auto& attribute : decoded.attributes) {
        if (attribute.unique_id == static_cast<int>(uid))
          a = decoded.mesh.point_data.find(attribute.name);
      }
      if (!a) fail(w + ": no attribute with unique id " + std::to_string(uid) + " for " + semantic);
      std::vector<double> values(a->size());
      const int c = a->components();
      const bool normalized = semantic == "COLOR_0" && a->type() == ScalarType::UInt8;
      for (std::size_t i = 0; i < values.size(); ++i) {
        values[i] = a->get(i / static_cast<std::size_t>(c),
                           static_cast<int>(i % static_cast<std::size_t>(c)));
        if (normalized) values[i] /= 255.0;
      }
      add_array(pd, semantic, values, c, w, names, scalars_name);
    }
    return pd;
  }

  // The cells primitive mode `mode` makes of `c` indices: their section (0 verts, 1 lines,
  // 2 polys) and how many.
  static std::pair<int, std::size_t> mode_cells(int mode, std::size_t c) {
    switch (mode) {
      case kModePoints:
        return {0, c};
      case kModeLines:
        return {1, c / 2};
      case kModeLineStrip:
        return {1, c > 0 ? c - 1 : 0};
      case kModeLineLoop:
        return {1, c > 2 ? c : (c > 0 ? c - 1 : 0)};
      case kModeTriangles:
        return {2, c / 3};
      default:
        return {2, c > 1 ? c - 2 : 0};  // strip or fan
    }
  }

  // Mesh `m`: its primitives, grouped by POSITION accessor into vertex sets, appended. With
  // `summaries` not null, nothing is returned: each vertex set's summary goes there instead,
  // made from its points and point arrays as soon as they are read (then dropped), and its
  // cells counted (indices checked, not stored).
  GltfContent::Mesh read_mesh(const Json& mesh, std::size_t m,
                              std::vector<DatasetSummary>* summaries) {
    const std::string what = "meshes " + std::to_string(m);
    GltfContent::Mesh out;
    if (const Json* nm = mesh.find("name"); nm && nm->is_string()) out.name = nm->as_string();
    const Json* extras = mesh.find("extras");
    const Json* names = extras ? extras->find("isoforge_arrays") : nullptr;
    std::string scalars_name;
    if (const Json* s = extras ? extras->find("isoforge_scalars") : nullptr; s && s->is_string()) {
      scalars_name = s->as_string();
    }
    if (const Json* legend = extras ? extras->find("legend") : nullptr;
        legend && legend->is_object()) {
      out.legend = read_legend(*legend, what);
    }
    const Json& prims = member(mesh, "primitives", what);
    if (!prims.is_array()) fail(what + ": 'primitives' is not an array");
    std::vector<VertexSet> sets;
    std::vector<CellArray> verts, lines, polys;
    // A summary's vertex sets, each summarised (and its points dropped) as soon as it is read;
    // its cells are added as the primitives are counted.
    std::vector<DatasetSummary> sums;
    const auto summarize_set = [&sums](PolyData& pd) {
      sums.push_back(isoforge::summarize(pd));
      pd = PolyData{};
    };
    for (std::size_t p = 0; p < prims.size(); ++p) {
      const Json& prim = prims.as_array()[p];
      const std::string pw = what + " primitive " + std::to_string(p);
      if (const Json* ext = prim.find("extensions"); ext && ext->find(kDraco)) {
        sets.push_back({std::numeric_limits<std::size_t>::max(),
                        read_draco_primitive(*ext->find(kDraco), pw, names, scalars_name)});
        if (summaries) {
          summarize_set(sets.back().pd);  // its triangles counted by summarize
        } else {
          polys.push_back(std::exchange(sets.back().pd.polys, CellArray{}));
          verts.emplace_back();
          lines.emplace_back();
        }
        continue;
      }
      const Json& attributes = member(prim, "attributes", pw);
      if (!attributes.is_object()) fail(pw + ": 'attributes' is not an object");
      const std::size_t position = index(attributes, "POSITION", pw, std::size_t{1} << 32);
      std::size_t set = sets.size();
      for (std::size_t s = 0; s < sets.size(); ++s) {
        if (sets[s].position == position) set = s;
      }
      if (set == sets.size()) {
        sets.push_back({position, read_vertices(attributes, pw, names, scalars_name)});
        if (summaries) {
          summarize_set(sets.back().pd);
        } else {
          verts.emplace_back();
          lines.emplace_back();
          polys.emplace_back();
        }
      }
      const std::size_t n = summaries ? sums[set].points : sets[set].pd.num_points();
      std::vector<std::uint32_t> idx;
      std::size_t c = n;  // indices
      if (prim.find("indices")) {
        Accessor info;
        visit_accessor(
            index(prim, "indices", pw, std::size_t{1} << 32), info,
            [&](const Accessor& i) {
              if (i.components != 1 || i.component_type == kFloat)
                fail(pw + ": indices are not integer scalars");
              c = i.count;
              if (!summaries) idx.resize(i.count);
            },
            [&](std::size_t k, double v) {
              if (v >= static_cast<double>(n)) {
                fail(pw + ": index " + std::to_string(static_cast<std::uint64_t>(v)) +
                     " >= " + std::to_string(n) + " vertices");
              }
              if (!summaries) idx[k] = static_cast<std::uint32_t>(v);
            });
      } else if (!summaries) {
        idx.resize(n);
        for (std::size_t i = 0; i < n; ++i) idx[i] = static_cast<std::uint32_t>(i);
      }
      const int mode = static_cast<int>(optional_index(prim, "mode", pw, 7, kModeTriangles));
      const std::pair<int, std::size_t> made = mode_cells(mode, c);
      if (summaries) {
        if (made.second > 0) {
          const auto section = static_cast<std::size_t>(made.first);
          sums[set].cells += made.second;
          sums[set].cell_types[poly_cell_type(made.first, section + 1)] += made.second;
        }
        decoded_.clear();  // the decoded meshopt views: decoded again if another primitive asks
        continue;
      }
      CellArray* sections[3] = {&verts[set], &lines[set], &polys[set]};
      CellArray& into = *sections[made.first];
      // The cells' room at once (not grown cell by cell: twice the memory while doubling).
      into.reserve(
          into.size() + made.second,
          into.connectivity().size() + static_cast<std::size_t>(made.first + 1) * made.second);
      auto cell = [&into](std::initializer_list<std::uint32_t> ids) {
        Index tmp[3];
        std::size_t k = 0;
        for (const auto i : ids) tmp[k++] = static_cast<Index>(i);
        into.add(std::span<const Index>(tmp, k));
      };
      switch (mode) {
        case kModePoints:
          for (const auto i : idx) cell({i});
          break;
        case kModeLines:
          for (std::size_t k = 0; k + 1 < c; k += 2) cell({idx[k], idx[k + 1]});
          break;
        case kModeLineStrip:
        case kModeLineLoop:
          for (std::size_t k = 0; k + 1 < c; ++k) cell({idx[k], idx[k + 1]});
          if (mode == kModeLineLoop && c > 2) cell({idx[c - 1], idx[0]});
          break;
        case kModeTriangles:
          for (std::size_t k = 0; k + 2 < c; k += 3) cell({idx[k], idx[k + 1], idx[k + 2]});
          break;
        case kModeTriangleStrip:
          for (std::size_t k = 0; k + 2 < c; ++k) {
            const auto t = strip_triangle(std::span<const std::uint32_t>(idx), k);
            cell({t[0], t[1], t[2]});
          }
          break;
        default:
          static_assert(kModeTriangleFan == 6);  // optional_index capped mode at 6
          for (std::size_t k = 1; k + 1 < c; ++k) cell({idx[0], idx[k], idx[k + 1]});
      }
    }
    if (summaries) {
      for (DatasetSummary& sum : sums) summaries->push_back(std::move(sum));
      return out;
    }
    std::vector<PolyData> parts;
    for (std::size_t s = 0; s < sets.size(); ++s) {
      sets[s].pd.verts = std::move(verts[s]);
      sets[s].pd.lines = std::move(lines[s]);
      sets[s].pd.polys = std::move(polys[s]);
      parts.push_back(std::move(sets[s].pd));
    }
    out.mesh = parts.empty() ? PolyData{} : append(std::move(parts));
    out.mesh.validate();
    return out;
  }

  GltfLegend read_legend(const Json& j, const std::string& what) const {
    GltfLegend legend;
    if (const Json* a = j.find("array"); a && a->is_string()) legend.array = a->as_string();
    if (const Json* c = j.find("colormap"); c && c->is_string()) legend.colormap = c->as_string();
    if (const Json* r = j.find("range"); r && r->is_array() && r->size() == 2 &&
                                         r->as_array()[0].is_number() &&
                                         r->as_array()[1].is_number()) {
      legend.min = r->as_array()[0].as_number();
      legend.max = r->as_array()[1].as_number();
    }
    if (const Json* l = j.find("log"); l && l->is_bool()) legend.log_scale = l->as_bool();
    if (const Json* cs = j.find("colors"); cs && cs->is_array()) {
      for (const Json& c : cs->as_array()) {
        if (!c.is_array() || c.size() != 4) fail(what + ": legend colours are not RGBA");
        std::array<std::uint8_t, 4> rgba{};
        for (int k = 0; k < 4; ++k) {
          const Json& v = c.as_array()[static_cast<std::size_t>(k)];
          if (!v.is_number() || v.as_number() < 0 || v.as_number() > 255)
            fail(what + ": legend colour out of 0..255");
          rgba[static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(v.as_number());
        }
        legend.colors.push_back(rgba);
      }
    }
    return legend;
  }

  std::span<const std::byte> data_;
  std::string name_;
  const io_detail::MappedFile* file_ = nullptr;
  Json gltf_;
  std::span<const std::byte> bin_;
  bool has_bin_ = false;
  std::map<std::size_t, std::vector<std::byte>> decoded_;
};

}  // namespace

GltfContent read_gltf(std::span<const std::byte> data, std::string_view name) {
  return GlbReader(data, name).read();
}

GltfContent read_gltf(const std::filesystem::path& path) {
  const io_detail::MappedFile file(path);  // (not copied: the reader takes views of it)
  return GlbReader(file.bytes(), path.string(), &file).read();
}

namespace io_detail {

DatasetSummary summarize_gltf(std::span<const std::byte> data, std::string_view name) {
  return GlbReader(data, name).summarize();
}

DatasetSummary summarize_gltf(const std::filesystem::path& path, const ProgressCallback& progress) {
  const MappedFile file(path);
  DatasetSummary s = GlbReader(file.bytes(), path.string(), &file).summarize();
  report_progress(progress, 1.0, "reading");
  return s;
}

}  // namespace io_detail

}  // namespace isoforge
