// Draco `.drc`: writing (encode, decode again, measure_errors) and reading. The one file of isoforge
// that includes Draco's headers (docs/architecture.md).
//
// Draco: Google's geometry compression library (Galligan, Hemmer, Brettle et al., 2017–2022).
// Connectivity: J. Rossignac, "Edgebreaker: Connectivity compression for triangle meshes", IEEE
// TVCG 5(1), 1999, and its valence variant (Szymczak, King, Rossignac 2001). Positions and
// arrays: uniform quantization + parallelogram prediction (Touma & Gotsman, "Triangle mesh
// compression", Graphics Interface 1998); normals: octahedral coding (Cigolle et al., "A survey
// of efficient representations for independent unit vectors", JCGT 3(2), 2014).
//
// The error budget: quantization puts each value on a grid origin + q·step; rounding to the
// nearest grid point moves a c-component tuple by at most step·√c/2. isoforge picks the step
// itself (Draco's explicit quantization: origin and range given, bits = the fewest that cover
// the range), so the step is not limited to range/(2^bits − 1) as draco_encoder's is: it starts
// from the guaranteed 2e/√c and grows while the exact rounding of the actual data, replayed
// here, stays within e; then the file is decoded and measured, and refined if a measurement
// exceeds the budget. Method and measurements: docs/algorithms/draco.md.

#include "isoforge/io/draco.hpp"
#include "isoforge/core/cell.hpp"

#include <draco/compression/config/compression_shared.h>
#include <draco/compression/decode.h>
#include <draco/compression/expert_encode.h>
#include <draco/core/decoder_buffer.h>
#include <draco/core/encoder_buffer.h>
#include <draco/mesh/mesh.h>
#include <draco/metadata/geometry_metadata.h>
#include <draco/point_cloud/point_cloud.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>
#include <numeric>
#include <string>
#include <unordered_map>
#include <utility>

#include "detail/draco_codec.hpp"
#include "detail/progress.hpp"
#include "isoforge/core/parallel.hpp"
#include "isoforge/io/atomic_file.hpp"

namespace isoforge {

namespace {

using io_detail::DracoKind;

// Metadata keys of each attribute (Draco attribute metadata, strings and ints).
constexpr const char* kMetaName = "name";
constexpr const char* kMetaType = "isoforge_type";    // ScalarType of the array
constexpr const char* kMetaRoles = "isoforge_roles";  // bit r set: active for AttributeRole r
constexpr const char* kPointsName = "Points";

// An integer array whose values span more than this is stored as Float64 without loss: Draco's
// integer coder builds a histogram as long as the largest residual (a 2^31 span aborts it).
constexpr double kMaxIntegerSpan = double(1 << 24);
// |values| up to 2^53 are exact in a double.
constexpr double kMaxExactInDouble = 9007199254740992.0;
// A normals array is coded as unit vectors (octahedral) only if every tuple has this length.
constexpr double kUnitTolerance = 1e-3;

draco::GeometryAttribute::Type draco_type_of(DracoKind k) {
  switch (k) {
    case DracoKind::Position: return draco::GeometryAttribute::POSITION;
    case DracoKind::Normal: return draco::GeometryAttribute::NORMAL;
    case DracoKind::Color: return draco::GeometryAttribute::COLOR;
    case DracoKind::TexCoord: return draco::GeometryAttribute::TEX_COORD;
    case DracoKind::Generic: break;
  }
  return draco::GeometryAttribute::GENERIC;
}

draco::DataType draco_data_type(ScalarType t) {
  switch (t) {
    case ScalarType::Int8: return draco::DT_INT8;
    case ScalarType::UInt8: return draco::DT_UINT8;
    case ScalarType::Int16: return draco::DT_INT16;
    case ScalarType::UInt16: return draco::DT_UINT16;
    case ScalarType::Int32: return draco::DT_INT32;
    case ScalarType::UInt32: return draco::DT_UINT32;
    case ScalarType::Int64: return draco::DT_INT64;
    case ScalarType::UInt64: return draco::DT_UINT64;
    case ScalarType::Float32: return draco::DT_FLOAT32;
    case ScalarType::Float64: return draco::DT_FLOAT64;
  }
  return draco::DT_FLOAT32;
}

bool scalar_type_of(draco::DataType t, ScalarType* out) {
  switch (t) {
    case draco::DT_INT8: *out = ScalarType::Int8; return true;
    case draco::DT_UINT8: *out = ScalarType::UInt8; return true;
    case draco::DT_BOOL: *out = ScalarType::UInt8; return true;
    case draco::DT_INT16: *out = ScalarType::Int16; return true;
    case draco::DT_UINT16: *out = ScalarType::UInt16; return true;
    case draco::DT_INT32: *out = ScalarType::Int32; return true;
    case draco::DT_UINT32: *out = ScalarType::UInt32; return true;
    case draco::DT_INT64: *out = ScalarType::Int64; return true;
    case draco::DT_UINT64: *out = ScalarType::UInt64; return true;
    case draco::DT_FLOAT32: *out = ScalarType::Float32; return true;
    case draco::DT_FLOAT64: *out = ScalarType::Float64; return true;
    default: return false;
  }
}


// One attribute to encode: the positions or a point array.
struct DracoSource {
  std::string name;
  DracoKind kind = DracoKind::Generic;
  ScalarType type = ScalarType::Float32;  // the array's element type (restored on reading)
  int components = 1;
  int roles = 0;
  bool quantized = false;        // a float attribute on a quantization grid (or octahedral)
  draco::DataType dtype = draco::DT_FLOAT32;  // as stored in the Draco attribute
  std::vector<float> f;          // float32 values to encode (quantized attributes)
  std::vector<double> exact;     // the original values when they are not float32
  std::vector<std::byte> raw;    // values of unquantized attributes, in `dtype`
  const DataArray* array = nullptr;
  double budget = 0;             // maximum error asked for (0 = none)
  std::vector<float> lo, hi;     // per-component range of f
  // Chosen quantization.
  int bits = 0;
  double step = 0;
  std::vector<float> origin;
  float range = 0;
  bool explicit_grid = false;  // origin and range given to Draco (else it computes its own)
  int unique_id = -1;
  int att_id = -1;

  [[nodiscard]] double original(std::size_t t, int c) const {
    const std::size_t i = t * static_cast<std::size_t>(components) + static_cast<std::size_t>(c);
    if (!exact.empty()) return exact[i];
    if (!f.empty()) return f[i];
    return array->get(t, c);
  }
  [[nodiscard]] double extent() const {
    double e = 0;
    for (int c = 0; c < components; ++c) e = std::max(e, double(hi[c]) - double(lo[c]));
    return e;
  }
};

struct Prepared {
  std::size_t points = 0;
  bool mesh = false;  // triangles (else a point cloud)
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::size_t degenerate_input = 0;
  std::vector<char> referenced;  // per point: in a triangle with three distinct ids
  std::vector<DracoSource> sources;   // positions first
  std::vector<std::string> dropped;
  std::uint64_t raw_bytes = 0;
};

bool is_float(ScalarType t) { return t == ScalarType::Float32 || t == ScalarType::Float64; }

void fill_float_source(DracoSource& s, const DataArray& a) {
  const std::size_t n = a.size();
  s.f.resize(n);
  if (a.type() == ScalarType::Float32) {
    std::copy(a.values<float>().begin(), a.values<float>().end(), s.f.begin());
  } else {
    const auto v = a.values<double>();
    s.exact.assign(v.begin(), v.end());
    for (std::size_t i = 0; i < n; ++i) s.f[i] = static_cast<float>(v[i]);
  }
  s.lo.assign(static_cast<std::size_t>(s.components), std::numeric_limits<float>::infinity());
  s.hi.assign(static_cast<std::size_t>(s.components), -std::numeric_limits<float>::infinity());
  for (std::size_t i = 0; i < n; ++i) {
    const auto c = i % static_cast<std::size_t>(s.components);
    s.lo[c] = std::min(s.lo[c], s.f[i]);
    s.hi[c] = std::max(s.hi[c], s.f[i]);
  }
  if (n == 0) {
    std::fill(s.lo.begin(), s.lo.end(), 0.f);
    std::fill(s.hi.begin(), s.hi.end(), 0.f);
  }
}

// Raw bytes of an integer array in the type Draco stores: its own type, or Float64 when its
// span is too wide for Draco's integer coder.
void fill_integer_source(DracoSource& s, const DataArray& a, std::string_view name) {
  const std::size_t n = a.size();
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t i = 0; i < n; ++i) {
    const double v = a.get(i / static_cast<std::size_t>(s.components),
                           static_cast<int>(i % static_cast<std::size_t>(s.components)));
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  if (n == 0 || hi - lo <= kMaxIntegerSpan) {
    s.dtype = draco_data_type(a.type());
    s.raw.resize(a.size_bytes());
    if (!s.raw.empty()) std::memcpy(s.raw.data(), a.bytes(), a.size_bytes());
    return;
  }
  if (std::max(std::abs(lo), std::abs(hi)) > kMaxExactInDouble) {
    throw Error(std::string(name) + ": point array '" + a.name() +
                "': 64-bit integers beyond 2^53 spread over more than 2^24 cannot be stored in "
                "Draco without loss");
  }
  s.dtype = draco::DT_FLOAT64;
  s.raw.resize(n * sizeof(double));
  for (std::size_t i = 0; i < n; ++i) {
    const double v = a.get(i / static_cast<std::size_t>(s.components),
                           static_cast<int>(i % static_cast<std::size_t>(s.components)));
    std::memcpy(s.raw.data() + i * sizeof(double), &v, sizeof v);
  }
}

bool all_finite(const std::vector<float>& v) {
  return std::all_of(v.begin(), v.end(), [](float x) { return std::isfinite(x); });
}

bool unit_length(const std::vector<float>& v) {
  for (std::size_t i = 0; i + 2 < v.size(); i += 3) {
    const double l = std::sqrt(double(v[i]) * v[i] + double(v[i + 1]) * v[i + 1] +
                               double(v[i + 2]) * v[i + 2]);
    if (std::abs(l - 1) > kUnitTolerance) return false;
  }
  return true;
}

void check_draco_options(const DracoWriteOptions& o, std::string_view name) {
  const auto bits = [&](int b, const char* what) {
    if (b < 1 || b > 30) {
      throw Error(std::string(name) + ": " + what + " quantization bits must be in [1, 30], not " +
                  std::to_string(b));
    }
  };
  bits(o.bits.position, "position");
  bits(o.bits.normal, "normal");
  bits(o.bits.color, "color");
  bits(o.bits.texcoord, "texcoord");
  bits(o.bits.generic, "generic");
  if (o.level < 0 || o.level > 10) {
    throw Error(std::string(name) + ": compression level must be in [0, 10], not " +
                std::to_string(o.level));
  }
  const auto budget = [&](double e, const std::string& what) {
    if (!std::isfinite(e) || e < 0) {
      throw Error(std::string(name) + ": " + what + " must be finite and >= 0, not " +
                  std::to_string(e));
    }
  };
  budget(o.max_position_error, "maximum position error");
  budget(o.max_position_error_relative, "relative maximum position error");
  if (o.max_position_error > 0 && o.max_position_error_relative > 0) {
    throw Error(std::string(name) +
                ": give the maximum position error either absolute or relative, not both");
  }
  for (std::size_t i = 0; i < o.max_array_errors.size(); ++i) {
    const auto& b = o.max_array_errors[i];
    if (b.name.empty()) throw Error(std::string(name) + ": an array budget has no array name");
    if (!std::isfinite(b.max_error) || b.max_error <= 0) {
      throw Error(std::string(name) + ": maximum error of array '" + b.name +
                  "' must be finite and > 0, not " + std::to_string(b.max_error));
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (o.max_array_errors[j].name == b.name) {
        throw Error(std::string(name) + ": array '" + b.name + "' has two error budgets");
      }
    }
  }
}

void triangulate(const PolyData& mesh, Prepared& p) {
  p.triangles.reserve(mesh.polys.connectivity().size() + mesh.strips.connectivity().size());
  const auto add = [&](Index a, Index b, Index c) {
    p.triangles.push_back({static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b),
                           static_cast<std::uint32_t>(c)});
  };
  for (std::size_t i = 0; i < mesh.polys.size(); ++i) {
    const auto cell = mesh.polys.cell(i);
    for (std::size_t k = 1; k + 1 < cell.size(); ++k) add(cell[0], cell[k], cell[k + 1]);
  }
  for (std::size_t i = 0; i < mesh.strips.size(); ++i) {
    const auto s = mesh.strips.cell(i);
    for (std::size_t k = 0; k + 2 < s.size(); ++k) {
      const auto t = strip_triangle(s, k);
      add(t[0], t[1], t[2]);
    }
  }
}

int draco_roles_of(const Attributes& at, const std::string& name) {
  int r = 0;
  for (std::size_t k = 0; k < kAttributeRoleCount; ++k) {
    if (at.active_name(static_cast<AttributeRole>(k)) == name) r |= 1 << k;
  }
  return r;
}

Prepared prepare(const PolyData& mesh, const DracoWriteOptions& options,
                 const io_detail::DracoRoles& roles, std::string_view name) {
  check_draco_options(options, name);
  try {
    mesh.validate();
  } catch (const Error& e) {
    throw Error(std::string(name) + ": cannot write an invalid mesh: " + e.what());
  }
  if (!mesh.lines.empty()) {
    throw Error(std::string(name) + ": Draco has no lines; the polydata has " +
                std::to_string(mesh.lines.size()) +
                " line cells (write .vtp, or .vtk, or remove the lines)");
  }
  const bool faces = !mesh.polys.empty() || !mesh.strips.empty();
  if (faces && !mesh.verts.empty()) {
    throw Error(std::string(name) + ": Draco holds a mesh or a point cloud, not both; the "
                "polydata has " + std::to_string(mesh.verts.size()) + " vertex cells besides its "
                "faces (remove the vertex cells)");
  }
  if (mesh.points.size() >= std::numeric_limits<std::uint32_t>::max()) {
    throw Error(std::string(name) + ": " + std::to_string(mesh.points.size()) +
                " points exceed Draco's 32-bit point ids");
  }
  Prepared p;
  p.points = mesh.points.size();
  p.mesh = faces;
  if (faces) triangulate(mesh, p);
  p.referenced.assign(p.points, p.mesh ? 0 : 1);
  for (const auto& t : p.triangles) {
    const bool repeated = t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
    const bool coincident = !repeated && (mesh.points[t[0]] == mesh.points[t[1]] ||
                                          mesh.points[t[1]] == mesh.points[t[2]] ||
                                          mesh.points[t[0]] == mesh.points[t[2]]);
    if (repeated || coincident) ++p.degenerate_input;
    if (!repeated) {
      for (auto v : t) p.referenced[v] = 1;
    }
  }
  for (const DataArray& a : mesh.cell_data) p.dropped.push_back("cell data '" + a.name() + "'");
  for (const DataArray& a : mesh.field_data) p.dropped.push_back("field data '" + a.name() + "'");

  const bool budget = options.max_position_error > 0 || options.max_position_error_relative > 0;
  // Positions.
  {
    DracoSource s;
    s.name = kPointsName;
    s.kind = DracoKind::Position;
    s.type = mesh.points.type();
    s.components = 3;
    s.quantized = true;
    s.array = &mesh.points.array();
    fill_float_source(s, mesh.points.array());
    const std::size_t bad = mesh.points.first_non_finite();
    if (bad < mesh.points.size() || !all_finite(s.f)) {
      throw Error(std::string(name) + ": point " + std::to_string(bad) +
                  " is not finite (or beyond float32); Draco quantizes positions");
    }
    if (budget) {
      if (options.max_position_error > 0) {
        s.budget = options.max_position_error;
      } else {
        const Bounds b = mesh.points.bounds();
        double d2 = 0;
        for (int c = 0; c < 3; ++c) {
          const double e = p.points ? b.max[c] - b.min[c] : 0;
          d2 += e * e;
        }
        s.budget = options.max_position_error_relative * std::sqrt(d2);
        if (!(s.budget > 0)) {
          throw Error(std::string(name) + ": a relative position error needs a bounding box "
                      "with a non-zero diagonal");
        }
      }
    }
    p.sources.push_back(std::move(s));
  }
  // Roles chosen for Draco's semantics.
  const auto named_or = [&](const std::string& given, const char* what) -> const DataArray* {
    if (given.empty()) return nullptr;
    const DataArray* a = mesh.point_data.find(given);
    if (!a) throw Error(std::string(name) + ": no point array '" + given + "' for " + what);
    return a;
  };
  const DataArray* normals = named_or(roles.normals, "the normals");
  if (!normals && roles.normals.empty()) normals = mesh.point_data.normals();
  const DataArray* colors = named_or(roles.colors, "the colours");
  if (!colors && roles.colors.empty()) {
    const auto fits = [](const DataArray* a) {
      return a && a->type() == ScalarType::UInt8 && (a->components() == 3 || a->components() == 4);
    };
    if (fits(mesh.point_data.scalars())) {
      colors = mesh.point_data.scalars();
    } else if (fits(mesh.point_data.find("Colors"))) {
      colors = mesh.point_data.find("Colors");
    }
  }
  const DataArray* tcoords = named_or(roles.tcoords, "the texture coordinates");
  if (!tcoords && roles.tcoords.empty()) tcoords = mesh.point_data.tcoords();
  if (tcoords && !(is_float(tcoords->type()) && tcoords->components() == 2)) {
    if (!roles.tcoords.empty()) {
      throw Error(std::string(name) + ": texture coordinates '" + tcoords->name() +
                  "' must be a 2-component float array");
    }
    tcoords = nullptr;
  }
  for (const auto& b : options.max_array_errors) {
    const DataArray* a = mesh.point_data.find(b.name);
    if (!a) {
      throw Error(std::string(name) + ": error budget for '" + b.name +
                  "', which is not a point array");
    }
    if (!is_float(a->type())) {
      throw Error(std::string(name) + ": error budget for '" + b.name + "', a " +
                  std::string(scalar_type_name(a->type())) +
                  " array: integer arrays are stored exactly");
    }
  }
  for (const DataArray& a : mesh.point_data) {
    if (std::find(roles.skip.begin(), roles.skip.end(), a.name()) != roles.skip.end()) continue;
    DracoSource s;
    s.name = a.name();
    s.type = a.type();
    s.components = a.components();
    s.array = &a;
    s.roles = draco_roles_of(mesh.point_data, a.name());
    if (s.components > 127) {
      throw Error(std::string(name) + ": point array '" + a.name() + "' has " +
                  std::to_string(s.components) + " components; Draco holds at most 127");
    }
    for (const auto& b : options.max_array_errors) {
      if (b.name == a.name()) s.budget = b.max_error;
    }
    if (is_float(a.type())) {
      fill_float_source(s, a);
      s.quantized = all_finite(s.f);
      if (!s.quantized) {
        if (s.budget > 0) {
          throw Error(std::string(name) + ": point array '" + a.name() +
                      "' has non-finite values and cannot be quantized to meet its budget");
        }
        // Stored without loss in its own type.
        s.dtype = draco_data_type(a.type());
        s.raw.resize(a.size_bytes());
        if (!s.raw.empty()) std::memcpy(s.raw.data(), a.bytes(), a.size_bytes());
        s.f.clear();
        s.exact.clear();
      }
      if (&a == normals && s.components == 3 && s.quantized && unit_length(s.f)) {
        s.kind = DracoKind::Normal;
      } else if (&a == colors && s.components >= 3) {
        s.kind = DracoKind::Color;
      } else if (&a == tcoords) {
        s.kind = DracoKind::TexCoord;
      }
    } else {
      fill_integer_source(s, a, name);
      if (&a == colors) s.kind = DracoKind::Color;
    }
    p.sources.push_back(std::move(s));
  }
  p.raw_bytes = 4 * (3 * std::uint64_t(p.points) + 3 * std::uint64_t(p.triangles.size()));
  for (const DataArray& a : mesh.point_data) p.raw_bytes += 4 * std::uint64_t(a.size());
  return p;
}

// ---- quantization grid --------------------------------------------------------------------

// Draco's rounding, replayed in float32 as its quantizer computes it: value -> grid index.
struct Grid {
  float inverse = 0;  // max_q / range
  float delta = 0;    // range / max_q
  [[nodiscard]] float decoded(float v, float origin) const {
    const float q = std::floor((v - origin) * inverse + 0.5f);
    return q * delta + origin;
  }
};

Grid grid_of(int bits, float range) {
  const float max_q = static_cast<float>((std::uint32_t{1} << bits) - 1);
  return {max_q / range, range / max_q};
}

// Draco's encoder takes an explicit grid through its options, which hold numbers as text
// written with std::to_string (six decimals) and read back with strtof/atof (libdraco 1.5.5,
// draco/core/options.cc): an origin of 1e-7 arrives as 0 and a range of 1e-7 as 0. The value
// Draco reads back for `v`:
float draco_option_value(float v) {
  return std::strtof(std::to_string(v).c_str(), nullptr);
}

// The value nearest `v` on the side `up` (>= v) or down (<= v) that Draco's options read back
// unchanged. \throw Error (internal) if none is found, which no finite float causes.
float draco_option_float(float v, bool up) {
  float f = draco_option_value(v);
  for (int i = 0; i < 16; ++i) {
    const bool side = up ? f >= v : f <= v;
    if (side && draco_option_value(f) == f) return f;
    if (side) {
      f = draco_option_value(f);  // not yet read back unchanged
      continue;
    }
    const float a = std::abs(f);
    const float step =
        std::max(std::nextafter(a, std::numeric_limits<float>::infinity()) - a, 1e-6f);
    f = draco_option_value(up ? f + step : f - step);
  }
  throw Error("draco: internal: no quantization parameter near " + std::to_string(v) +
              " survives Draco's options");
}

// Sets bits/origin/range so that the grid step is `step` (or as close above as float and
// Draco's options allow) and covers the source's range. Returns false if more than 30 bits
// would be needed.
bool set_step(DracoSource& s, double step) {
  s.origin.resize(s.lo.size());
  double extent = 0;
  for (std::size_t c = 0; c < s.lo.size(); ++c) {
    s.origin[c] = draco_option_float(s.lo[c], false);
    extent = std::max(extent, double(s.hi[c]) - double(s.origin[c]));
  }
  int bits = 1;
  while (bits < 30 && step * double((std::uint32_t{1} << bits) - 1) < extent) ++bits;
  if (step * double((std::uint32_t{1} << bits) - 1) < extent) return false;
  s.bits = bits;
  const double want = std::max(step * double((std::uint32_t{1} << bits) - 1), extent);
  if (!(want < double(std::numeric_limits<float>::max()))) return false;
  s.range = draco_option_float(std::nextafter(static_cast<float>(want), 3e38f), true);
  if (!(s.range > 0)) s.range = draco_option_float(1e-6f, true);
  s.step = double(s.range) / double((std::uint32_t{1} << bits) - 1);
  s.explicit_grid = true;
  return true;
}

// Draco's own grid for `bits`: origin = minimum, range = the largest extent (1 if zero).
void set_bits(DracoSource& s, int bits) {
  s.bits = bits;
  s.origin.assign(s.lo.begin(), s.lo.end());
  float r = 0;
  for (int c = 0; c < s.components; ++c) r = std::max(r, s.hi[c] - s.lo[c]);
  s.range = r > 0 ? r : 1.f;
  s.step = double(s.range) / double((std::uint32_t{1} << bits) - 1);
  s.explicit_grid = false;
}

// The largest error the grid of `s` gives on its tuples (replayed, before encoding).
double predicted_error(const DracoSource& s, const std::vector<char>* only) {
  const Grid g = grid_of(s.bits, s.range);
  const std::size_t tuples = s.f.size() / static_cast<std::size_t>(s.components);
  double worst = 0;
  for (std::size_t t = 0; t < tuples; ++t) {
    if (only && !(*only)[t]) continue;
    double e2 = 0;
    for (int c = 0; c < s.components; ++c) {
      const std::size_t i = t * static_cast<std::size_t>(s.components) + static_cast<std::size_t>(c);
      const double d = s.original(t, c) - double(g.decoded(s.f[i], s.origin[c]));
      e2 += d * d;
    }
    worst = std::max(worst, e2);
  }
  return std::sqrt(worst);
}

// The largest step whose replayed error stays within the budget (grid quantization only). The
// replay rounds as Draco does, in float32, but the decoder's float32 arithmetic may differ by an
// ulp or two: `slack` keeps that far from the budget (the decoded file is measured anyway).
void choose_step(DracoSource& s, const std::vector<char>* only, double shrink, std::string_view name) {
  const double e = s.budget * shrink;
  const double c = std::sqrt(double(s.components));
  double magnitude = 0;
  for (int k = 0; k < s.components; ++k) {
    magnitude = std::max({magnitude, std::abs(double(s.lo[k])), std::abs(double(s.hi[k]))});
  }
  const double slack = 2 * c * magnitude * std::numeric_limits<float>::epsilon();
  const auto meets = [&] { return predicted_error(s, only) + slack <= e; };
  // Draco's own grid (origin the minimum, range the extent) with the fewest bits that meet the
  // budget: the fallback where the explicit grid cannot (Draco's options hold its origin and
  // range to six decimals, so a range below 1e-6 cannot be given).
  int auto_bits = 0;
  const double guess = std::ceil(std::log2(s.extent() * c / (2 * e) + 1));
  for (int b = std::clamp(int(std::isfinite(guess) ? guess : 30) - 1, 1, 30); b <= 30; ++b) {
    set_bits(s, b);
    if (meets()) {
      auto_bits = b;
      break;
    }
  }
  // The explicit grid whose step is the largest that meets the budget.
  double lo = 2 * e / c;  // guaranteed: every tuple moves at most step·√c/2
  const auto ok = [&](double step) { return set_step(s, step) && meets(); };
  int tries = 0;
  bool found = true;
  while (!ok(lo)) {
    // Float32 rounding adds to the grid's error: shrink until it fits.
    lo *= 0.97;
    if (++tries > 300 || !set_step(s, lo)) {
      found = false;
      break;
    }
  }
  if (found && tries == 0) {
    double hi = 2 * e * 1.0001;  // no grid can do better than step/2 on one component
    for (int i = 0; i < 12; ++i) {
      const double mid = 0.5 * (lo + hi);
      if (ok(mid)) {
        lo = mid;
      } else {
        hi = mid;
      }
    }
  }
  if (found) set_step(s, lo);
  if (auto_bits > 0 && (!found || s.bits > auto_bits)) set_bits(s, auto_bits);
  if (!found && auto_bits == 0) {
    throw Error(
        fmt::format("{}: the error budget {:g} of '{}' is below what float32 values with "
                    "30-bit quantization can meet",
                    name, s.budget, s.name));
  }
}

// Octahedral coding error of unit normals with `bits` (replayed by encoding is costly; this
// is the starting estimate, refined by measuring): about π/2 over 2^bits cells per side.
int normal_bits_for(double budget) {
  int bits = 2;
  while (bits < 30 && 2.5 / double((std::uint32_t{1} << bits) - 1) > budget) ++bits;
  return bits;
}

// ---- building and coding ------------------------------------------------------------------

// Whether the reader, without metadata, gives back this attribute's name, type and roles
// (see decode_draco_mesh: the default names of Draco's kinds).
bool reads_back_as_is(const DracoSource& s) {
  const auto role = [](AttributeRole r) { return 1 << static_cast<int>(r); };
  switch (s.kind) {
    case DracoKind::Position: return s.name == kPointsName && s.type == ScalarType::Float32;
    case DracoKind::Normal:
      return s.name == "Normals" && s.type == ScalarType::Float32 &&
             s.roles == role(AttributeRole::Normals);
    case DracoKind::Color:
      return s.name == "Colors" && s.type == ScalarType::UInt8 &&
             s.roles == role(AttributeRole::Scalars);
    case DracoKind::TexCoord:
      return s.name == "TCoords" && s.type == ScalarType::Float32 &&
             s.roles == role(AttributeRole::TCoords);
    case DracoKind::Generic: break;
  }
  return false;
}

std::unique_ptr<draco::PointCloud> build(const Prepared& p, std::vector<DracoSource>& sources) {
  std::unique_ptr<draco::PointCloud> pc;
  if (p.mesh) {
    auto m = std::make_unique<draco::Mesh>();
    m->SetNumFaces(p.triangles.size());
    for (std::size_t i = 0; i < p.triangles.size(); ++i) {
      const auto& t = p.triangles[i];
      m->SetFace(draco::FaceIndex(static_cast<std::uint32_t>(i)),
                 {draco::PointIndex(t[0]), draco::PointIndex(t[1]), draco::PointIndex(t[2])});
    }
    pc = std::move(m);
  } else {
    pc = std::make_unique<draco::PointCloud>();
  }
  pc->set_num_points(static_cast<std::uint32_t>(p.points));
  if (!std::all_of(sources.begin(), sources.end(), reads_back_as_is)) {
    pc->AddMetadata(std::make_unique<draco::GeometryMetadata>());
  }
  for (DracoSource& s : sources) {
    const draco::DataType dt = s.quantized ? draco::DT_FLOAT32 : s.dtype;
    const auto size = static_cast<std::int64_t>(draco::DataTypeLength(dt)) * s.components;
    draco::GeometryAttribute ga;
    ga.Init(draco_type_of(s.kind), nullptr, static_cast<std::uint8_t>(s.components), dt,
            s.kind == DracoKind::Color && dt == draco::DT_UINT8, size, 0);
    s.att_id = pc->AddAttribute(ga, true, static_cast<std::uint32_t>(p.points));
    draco::PointAttribute* att = pc->attribute(s.att_id);
    const void* src = s.quantized ? static_cast<const void*>(s.f.data())
                                  : static_cast<const void*>(s.raw.data());
    if (p.points > 0) att->buffer()->Write(0, src, static_cast<std::size_t>(size) * p.points);
    s.unique_id = static_cast<int>(att->unique_id());
    if (reads_back_as_is(s)) continue;  // no metadata needed: saves its bytes
    auto md = std::make_unique<draco::AttributeMetadata>();
    md->AddEntryString(kMetaName, s.name);
    md->AddEntryInt(kMetaType, static_cast<int>(s.type));
    md->AddEntryInt(kMetaRoles, s.roles);
    pc->AddAttributeMetadata(s.att_id, std::move(md));
  }
  return pc;
}

std::vector<std::uint8_t> encode_once(const draco::PointCloud& pc, const Prepared& p,
                                      const std::vector<DracoSource>& sources,
                                      const DracoWriteOptions& o, std::string_view name) {
  std::unique_ptr<draco::ExpertEncoder> enc =
      p.mesh ? std::make_unique<draco::ExpertEncoder>(static_cast<const draco::Mesh&>(pc))
             : std::make_unique<draco::ExpertEncoder>(pc);
  const int speed = 10 - o.level;
  enc->SetSpeedOptions(speed, speed);
  if (p.mesh) {
    enc->SetEncodingMethod(o.method == DracoMethod::Sequential ? draco::MESH_SEQUENTIAL_ENCODING
                                                               : draco::MESH_EDGEBREAKER_ENCODING);
  } else if (o.method == DracoMethod::Sequential) {
    enc->SetEncodingMethod(draco::POINT_CLOUD_SEQUENTIAL_ENCODING);
  }
  for (const DracoSource& s : sources) {
    // At speeds 0 and 1 Draco predicts every quantized attribute of an Edgebreaker mesh with its
    // constrained multi-parallelogram scheme, whose encoder (libdraco 1.5.5) crashes on some
    // generic arrays (values of order 1e-7 and below); plain parallelogram prediction there.
    if (p.mesh && speed <= 1 && s.kind == DracoKind::Generic &&
        o.method != DracoMethod::Sequential) {
      const draco::Status st =
          enc->SetAttributePredictionScheme(s.att_id, draco::MESH_PREDICTION_PARALLELOGRAM);
      if (!st.ok()) throw Error(std::string(name) + ": Draco: " + st.error_msg());
    }
    if (!s.quantized || s.bits == 0) continue;
    if (s.kind == DracoKind::Normal || !s.explicit_grid) {
      enc->SetAttributeQuantization(s.att_id, s.bits);
    } else {
      enc->SetAttributeExplicitQuantization(s.att_id, s.bits, s.components, s.origin.data(),
                                            s.range);
    }
  }
  draco::EncoderBuffer buffer;
  draco::Status st;
  try {
    st = enc->EncodeToBuffer(&buffer);
  } catch (const std::exception& e) {
    throw Error(std::string(name) + ": Draco could not encode (" + e.what() + ")");
  }
  if (!st.ok()) throw Error(std::string(name) + ": Draco could not encode: " + st.error_msg());
  const auto* b = reinterpret_cast<const std::uint8_t*>(buffer.data());
  return {b, b + buffer.size()};
}

// ---- measuring ----------------------------------------------------------------------------

struct Measured {
  double position = 0;
  std::vector<double> arrays;  // per source (index 0 = positions)
  std::size_t unmatched = 0;
};

Measured measure_errors(const Prepared& p, const std::vector<DracoSource>& sources,
                 const io_detail::DracoDecodedMesh& dec, const DracoWriteOptions& o) {
  Measured m;
  m.arrays.assign(sources.size(), 0.0);
  const PolyData& d = dec.mesh;
  const DracoSource& pos = sources[0];
  std::vector<const DataArray*> decoded(sources.size(), nullptr);
  for (std::size_t k = 1; k < sources.size(); ++k) decoded[k] = d.point_data.find(sources[k].name);

  const auto error_at = [&](std::size_t i, std::size_t j) {
    double e2 = 0;
    const Vec3 q = d.points[j];
    for (int c = 0; c < 3; ++c) {
      const double dd = pos.original(i, c) - q[c];
      e2 += dd * dd;
    }
    return std::sqrt(e2);
  };
  // The error of source k's tuple at original point i against a decoded tuple b(c).
  const auto tuple_error = [&](std::size_t k, std::size_t i, const auto& b) {
    const DracoSource& s = sources[k];
    double e2 = 0;
    for (int c = 0; c < s.components; ++c) {
      const double a = s.quantized ? s.original(i, c) : s.array->get(i, c);
      const double bc = b(c);
      if (std::isnan(a) && std::isnan(bc)) continue;
      const double dd = a == bc ? 0.0 : a - bc;
      e2 += dd * dd;
    }
    return std::sqrt(e2);
  };
  const auto array_error = [&](std::size_t k, std::size_t i, std::size_t j) {
    if (!decoded[k]) return std::numeric_limits<double>::infinity();
    return tuple_error(k, i, [&](int c) { return decoded[k]->get(j, c); });
  };

  // Original points are matched independently: ranges of them in parallel, each range with its
  // own maxima, merged at the end (maxima and counts do not depend on the order).
  std::mutex merge_mutex;
  const auto merge = [&](const Measured& local) {
    const std::lock_guard<std::mutex> lock(merge_mutex);
    m.position = std::max(m.position, local.position);
    for (std::size_t k = 1; k < sources.size(); ++k) {
      m.arrays[k] = std::max(m.arrays[k], local.arrays[k]);
    }
    m.unmatched += local.unmatched;
  };
  constexpr std::size_t kGrain = 4096;
  const bool same_order = o.method == DracoMethod::Sequential && d.points.size() == p.points;
  if (same_order) {
    parallel_for_range(p.points, kGrain, [&](std::size_t b, std::size_t e) {
      Measured local;
      local.arrays.assign(sources.size(), 0.0);
      for (std::size_t i = b; i < e; ++i) {
        local.position = std::max(local.position, error_at(i, i));
        for (std::size_t k = 1; k < sources.size(); ++k) {
          local.arrays[k] = std::max(local.arrays[k], array_error(k, i, i));
        }
      }
      merge(local);
    });
    m.arrays[0] = m.position;
    return m;
  }
  // Points reordered (Edgebreaker, k-d tree): each original point is matched to the decoded
  // points on its nearest grid point — where rounding puts it — and, among several there (points
  // that share a quantized position), to the one whose values are closest.
  using Key = std::array<std::int64_t, 3>;
  const double step = pos.step;
  const auto key_of = [&](const Vec3& v) {
    Key k;
    for (int c = 0; c < 3; ++c) k[c] = std::llround((v[c] - double(pos.origin[c])) / step);
    return k;
  };
  std::vector<std::pair<Key, std::uint32_t>> keys(d.points.size());
  parallel_for_range(keys.size(), kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t j = b; j < e; ++j) {
      keys[j] = {key_of(d.points[j]), static_cast<std::uint32_t>(j)};
    }
  });
  std::sort(keys.begin(), keys.end());
  const auto run_end = [&](std::size_t b) {
    std::size_t e = b + 1;
    while (e < keys.size() && keys[e].first == keys[b].first) ++e;
    return e;
  };
  const auto same_point = [&](std::size_t b, std::size_t e) {
    const Vec3 q = d.points[keys[b].second];
    for (std::size_t t = b + 1; t < e; ++t) {
      if (d.points[keys[t].second] != q) return false;
    }
    return true;
  };
  // A coarse grid puts thousands of decoded points on one grid point, every one a candidate of
  // every original point rounded there. Such a long run of equal keys whose decoded points
  // coincide is matched at once: one position error, and per array the least error over the
  // run's distinct decoded tuples (quantized values repeat), found once per run, before the
  // matching. A short run is matched tuple by tuple (the least error over a run is the same
  // over its distinct tuples).
  constexpr std::size_t kLongRun = 32;
  struct Run {
    bool same_point = false;
    std::vector<std::vector<double>> tuples;  // per source: distinct decoded tuples, flattened
  };
  std::unordered_map<std::size_t, Run> long_runs;  // by the run's first index in `keys`
  for (std::size_t b = 0; b < keys.size();) {
    const std::size_t e = run_end(b);
    if (e - b >= kLongRun) long_runs.try_emplace(b);
    b = e;
  }
  std::vector<std::pair<const std::size_t, Run>*> to_fill;
  for (auto& entry : long_runs) to_fill.push_back(&entry);
  parallel_for_range(to_fill.size(), 1, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t u = lo; u < hi; ++u) {
      const std::size_t b = to_fill[u]->first;
      Run& r = to_fill[u]->second;
      const std::size_t end = run_end(b);
      r.same_point = same_point(b, end);
      if (!r.same_point) continue;
      r.tuples.resize(sources.size());
      for (std::size_t k = 1; k < sources.size(); ++k) {
        if (!decoded[k]) continue;
        const auto comps = static_cast<std::size_t>(sources[k].components);
        std::vector<std::vector<std::uint64_t>> bits;  // exact, NaN included
        for (std::size_t t = b; t < end; ++t) {
          std::vector<std::uint64_t> tuple(comps);
          for (std::size_t c = 0; c < comps; ++c) {
            tuple[c] = std::bit_cast<std::uint64_t>(decoded[k]->get(keys[t].second, int(c)));
          }
          bits.push_back(std::move(tuple));
        }
        std::sort(bits.begin(), bits.end());
        bits.erase(std::unique(bits.begin(), bits.end()), bits.end());
        for (const auto& tuple : bits) {
          for (std::uint64_t x : tuple) r.tuples[k].push_back(std::bit_cast<double>(x));
        }
      }
    }
  });
  parallel_for_range(p.points, kGrain, [&](std::size_t lo, std::size_t hi) {
    Measured local;
    local.arrays.assign(sources.size(), 0.0);
    std::vector<std::uint32_t> cands;
    for (std::size_t i = lo; i < hi; ++i) {
      if (!p.referenced[i]) continue;
      const Vec3 v{pos.original(i, 0), pos.original(i, 1), pos.original(i, 2)};
      const Key k0 = key_of(v);
      const auto first = std::lower_bound(keys.begin(), keys.end(), std::make_pair(k0, 0u));
      if (first != keys.end() && first->first == k0) {
        const auto b = static_cast<std::size_t>(first - keys.begin());
        const auto long_run = long_runs.find(b);
        if (long_run != long_runs.end() && long_run->second.same_point) {
          const Run& r = long_run->second;
          local.position = std::max(local.position, error_at(i, first->second));
          for (std::size_t k = 1; k < sources.size(); ++k) {
            double e = std::numeric_limits<double>::infinity();
            const auto comps = static_cast<std::size_t>(sources[k].components);
            for (std::size_t u = 0; u < r.tuples[k].size() && e > 0; u += comps) {
              e = std::min(
                  e, tuple_error(k, i, [&](int c) { return r.tuples[k][u + std::size_t(c)]; }));
            }
            local.arrays[k] = std::max(local.arrays[k], e);
          }
          continue;
        }
        if (long_run == long_runs.end()) {
          const std::size_t end = run_end(b);
          if (same_point(b, end)) {
            local.position = std::max(local.position, error_at(i, first->second));
            for (std::size_t k = 1; k < sources.size(); ++k) {
              double e = std::numeric_limits<double>::infinity();
              for (std::size_t t = b; t < end && e > 0; ++t) {
                e = std::min(e, array_error(k, i, keys[t].second));
              }
              local.arrays[k] = std::max(local.arrays[k], e);
            }
            continue;
          }
        }
      }
      double best = std::numeric_limits<double>::infinity();
      cands.clear();
      for (int pass = 0; pass < 2 && cands.empty(); ++pass) {
        for (int dx = -pass; dx <= pass; ++dx)
          for (int dy = -pass; dy <= pass; ++dy)
            for (int dz = -pass; dz <= pass; ++dz) {
              const Key k{k0[0] + dx, k0[1] + dy, k0[2] + dz};
              auto it = std::lower_bound(keys.begin(), keys.end(), std::make_pair(k, 0u));
              for (; it != keys.end() && it->first == k; ++it) {
                const double e = error_at(i, it->second);
                if (e < best) {
                  best = e;
                  cands.clear();
                }
                if (e == best) cands.push_back(it->second);
              }
            }
      }
      if (cands.empty()) {
        ++local.unmatched;
        continue;
      }
      local.position = std::max(local.position, best);
      for (std::size_t k = 1; k < sources.size(); ++k) {
        double e = std::numeric_limits<double>::infinity();
        for (auto j : cands) e = std::min(e, array_error(k, i, j));
        local.arrays[k] = std::max(local.arrays[k], e);
      }
    }
    merge(local);
  });
  m.arrays[0] = m.position;
  return m;
}

// ---- decoding -----------------------------------------------------------------------------

template <class T>
void read_values(const draco::PointAttribute& att, std::size_t n, int comps, DataArray& out,
                 std::string_view name) {
  auto v = out.values<T>();
  for (std::size_t i = 0; i < n; ++i) {
    const draco::AttributeValueIndex avi = att.mapped_index(draco::PointIndex(static_cast<std::uint32_t>(i)));
    if (avi.value() >= att.size() ||
        !att.ConvertValue<T>(avi, static_cast<std::int8_t>(comps), v.data() + i * comps)) {
      throw Error(std::string(name) + ": corrupt Draco data: attribute " +
                  std::to_string(att.unique_id()) + " has no value for point " + std::to_string(i));
    }
  }
}

}  // namespace

namespace io_detail {

namespace {
DracoDecodedMesh decode_unguarded(std::span<const std::byte> data, const std::string& file);

// Draco's decoders size their arrays by the counts in the stream before reading the data, so a
// few corrupt bytes can ask for gigabytes (or minutes). The counts are checked here first against the size
// of the data: a real file holds far fewer than kMaxCountPerByte points or faces per byte
// (Edgebreaker needs about 2 bits per triangle for connectivity alone; the bunny holds 1 point
// per byte at 8 bits).
constexpr std::uint64_t kMaxCountPerByte = 64;
constexpr std::uint64_t kCountSlack = 4096;

struct HeaderReader {
  std::span<const std::byte> data;
  std::size_t at = 0;
  bool ok = true;
  std::uint64_t byte() {
    if (at >= data.size()) {
      ok = false;
      return 0;
    }
    return std::to_integer<std::uint64_t>(data[at++]);
  }
  std::uint64_t varint() {
    std::uint64_t v = 0;
    for (int shift = 0; shift < 64 && ok; shift += 7) {
      const std::uint64_t b = byte();
      v |= (b & 0x7f) << shift;
      if (!(b & 0x80)) return v;
    }
    ok = false;
    return 0;
  }
  std::uint64_t u32() {
    std::uint64_t v = 0;
    for (int k = 0; k < 4; ++k) v |= byte() << (8 * k);
    return v;
  }
  void skip(std::uint64_t n) {
    if (n > data.size() - std::min(at, data.size())) {
      ok = false;
      return;
    }
    at += static_cast<std::size_t>(n);
  }
  void metadata(int depth) {  // one Metadata: entries, then named sub-metadata
    if (depth > 32) {
      ok = false;
      return;
    }
    const std::uint64_t entries = varint();
    for (std::uint64_t e = 0; e < entries && ok; ++e) {
      skip(byte());     // name
      skip(varint());   // value
    }
    const std::uint64_t subs = varint();
    for (std::uint64_t k = 0; k < subs && ok; ++k) {
      skip(byte());
      metadata(depth + 1);
    }
  }
};

void check_counts(std::span<const std::byte> data, const std::string& file) {
  HeaderReader r{data};
  if (data.size() < 11) return;  // Draco's own header check reports it
  r.skip(5);
  const std::uint64_t major = r.byte(), minor = r.byte();
  const std::uint64_t type = r.byte(), method = r.byte();
  const std::uint64_t flags = r.byte() | (r.byte() << 8);
  const bool v22 = major > 2 || (major == 2 && minor >= 2);
  if (flags & 0x8000) {  // metadata: attribute metadata, then the geometry's
    const std::uint64_t n = r.varint();
    for (std::uint64_t k = 0; k < n && r.ok; ++k) {
      (void)r.varint();
      r.metadata(0);
    }
    r.metadata(0);
  }
  const std::uint64_t limit = kMaxCountPerByte * data.size() + kCountSlack;
  const auto check = [&](std::uint64_t count, const char* what) {
    if (r.ok && count > limit) {
      throw Error(file + ": corrupt Draco data: " + std::to_string(count) + " " + what +
                  " in " + std::to_string(data.size()) + " bytes");
    }
  };
  if (type == 0) {  // point cloud: an int32 count first
    check(r.u32(), "points");
  } else if (type == 1 && method == 0) {  // sequential mesh
    const std::uint64_t faces = v22 ? r.varint() : r.u32();
    check(faces, "faces");
    check(v22 ? r.varint() : r.u32(), "points");
  } else if (type == 1 && method == 1) {  // Edgebreaker: traverser type, vertices, faces
    (void)r.byte();
    if (!v22) (void)r.u32();
    check(v22 ? r.varint() : r.u32(), "vertices");
    check(v22 ? r.varint() : r.u32(), "faces");
  }
}
}  // namespace

DracoDecodedMesh decode_draco_mesh(std::span<const std::byte> data, std::string_view name) {
  const std::string file(name);
  try {
    check_counts(data, file);
    return decode_unguarded(data, file);
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw Error(file + ": corrupt Draco data: its counts ask for more memory than there is");
  } catch (const std::exception& e) {
    // Draco's decoder signals some corrupt input by standard exceptions (length_error, ...).
    throw Error(file + ": corrupt Draco data (" + e.what() + ")");
  }
}

namespace {
DracoDecodedMesh decode_unguarded(std::span<const std::byte> data, const std::string& file) {
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(data.data()), data.size());
  auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
  if (!type.ok()) {
    throw Error(file + ": not a Draco file or a corrupt header: " + type.status().error_msg_string());
  }
  draco::Decoder decoder;
  std::unique_ptr<draco::PointCloud> pc;
  const draco::Mesh* mesh = nullptr;
  if (type.value() == draco::TRIANGULAR_MESH) {
    auto r = decoder.DecodeMeshFromBuffer(&buffer);
    if (!r.ok()) throw Error(file + ": corrupt or truncated Draco mesh: " + r.status().error_msg_string());
    mesh = r.value().get();
    pc = std::move(r).value();
  } else if (type.value() == draco::POINT_CLOUD) {
    auto r = decoder.DecodePointCloudFromBuffer(&buffer);
    if (!r.ok()) {
      throw Error(file + ": corrupt or truncated Draco point cloud: " +
                  r.status().error_msg_string());
    }
    pc = std::move(r).value();
  } else {
    throw Error(file + ": unsupported Draco geometry type " + std::to_string(int(type.value())));
  }
  const std::size_t n = pc->num_points();
  DracoDecodedMesh out;
  PolyData& pd = out.mesh;
  const draco::GeometryMetadata* gm = pc->GetMetadata();
  const auto meta = [&](const draco::PointAttribute& att) -> const draco::AttributeMetadata* {
    return gm ? gm->GetAttributeMetadataByUniqueId(static_cast<std::int32_t>(att.unique_id()))
              : nullptr;
  };
  const int pos_id = pc->GetNamedAttributeId(draco::GeometryAttribute::POSITION);
  if (pos_id < 0) throw Error(file + ": the Draco data has no POSITION attribute");
  const draco::PointAttribute& pos = *pc->attribute(pos_id);
  if (pos.num_components() < 2 || pos.num_components() > 3) {
    throw Error(file + ": POSITION has " + std::to_string(int(pos.num_components())) +
                " components; isoforge reads 2 or 3");
  }
  {
    int t = -1;
    const auto* md = meta(pos);
    const bool f64 = md && md->GetEntryInt(kMetaType, &t) && t == int(ScalarType::Float64);
    DataArray xyz(kPointsName, f64 ? ScalarType::Float64 : ScalarType::Float32, 3, n);
    const int comps = pos.num_components();
    std::vector<double> tmp(n * 3, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      const auto avi = pos.mapped_index(draco::PointIndex(static_cast<std::uint32_t>(i)));
      if (avi.value() >= pos.size() ||
          !pos.ConvertValue<double>(avi, static_cast<std::int8_t>(comps), tmp.data() + 3 * i)) {
        throw Error(file + ": corrupt Draco data: no position for point " + std::to_string(i));
      }
    }
    if (f64) {
      std::copy(tmp.begin(), tmp.end(), xyz.values<double>().begin());
    } else {
      std::transform(tmp.begin(), tmp.end(), xyz.values<float>().begin(),
                     [](double v) { return static_cast<float>(v); });
    }
    pd.points = Points(std::move(xyz));
    out.attributes.push_back({kPointsName, static_cast<int>(pos.unique_id()), DracoKind::Position});
  }
  if (mesh) {
    const std::size_t nf = mesh->num_faces();
    Buffer<Index> offsets(nf + 1), conn(3 * nf);
    for (std::size_t f = 0; f < nf; ++f) {
      const auto& face = mesh->face(draco::FaceIndex(static_cast<std::uint32_t>(f)));
      for (int c = 0; c < 3; ++c) {
        if (face[c].value() >= n) {
          throw Error(file + ": corrupt Draco data: face " + std::to_string(f) +
                      " names point " + std::to_string(face[c].value()) + " of " +
                      std::to_string(n));
        }
        conn[3 * f + c] = face[c].value();
      }
      offsets[f] = static_cast<Index>(3 * f);
    }
    offsets[nf] = static_cast<Index>(3 * nf);
    pd.polys = CellArray(std::move(offsets), std::move(conn));
  } else {
    Buffer<Index> offsets(n + 1), conn(n);
    for (std::size_t i = 0; i < n; ++i) {
      offsets[i] = static_cast<Index>(i);
      conn[i] = static_cast<Index>(i);
    }
    offsets[n] = static_cast<Index>(n);
    pd.verts = CellArray(std::move(offsets), std::move(conn));
  }
  for (int a = 0; a < pc->num_attributes(); ++a) {
    if (a == pos_id) continue;
    const draco::PointAttribute& att = *pc->attribute(a);
    const int comps = att.num_components();
    if (comps < 1) throw Error(file + ": corrupt Draco data: an attribute has no components");
    const auto* md = meta(att);
    std::string nm;
    int t = -1, roles = 0;
    bool has_roles = false;
    if (md) {
      md->GetEntryString(kMetaName, &nm);
      md->GetEntryInt(kMetaType, &t);
      has_roles = md->GetEntryInt(kMetaRoles, &roles);
    }
    DracoKind kind = DracoKind::Generic;
    switch (att.attribute_type()) {
      case draco::GeometryAttribute::POSITION: kind = DracoKind::Position; break;
      case draco::GeometryAttribute::NORMAL: kind = DracoKind::Normal; break;
      case draco::GeometryAttribute::COLOR: kind = DracoKind::Color; break;
      case draco::GeometryAttribute::TEX_COORD: kind = DracoKind::TexCoord; break;
      default: break;
    }
    if (nm.empty()) {
      switch (kind) {
        case DracoKind::Normal: nm = "Normals"; break;
        case DracoKind::Color: nm = "Colors"; break;
        case DracoKind::TexCoord: nm = "TCoords"; break;
        case DracoKind::Position: nm = "position"; break;
        case DracoKind::Generic: nm = "generic"; break;
      }
    }
    if (pd.point_data.has(nm) || nm == kPointsName) nm += "_" + std::to_string(att.unique_id());
    ScalarType st;
    if (t >= 0 && t <= int(ScalarType::Float64)) {
      st = static_cast<ScalarType>(t);
    } else if (!scalar_type_of(att.data_type(), &st)) {
      throw Error(file + ": attribute '" + nm + "' has an unsupported Draco data type");
    }
    DataArray arr(nm, st, comps, n);
    visit_scalar_type(st, [&](auto tag) {
      using T = decltype(tag);
      read_values<T>(att, n, comps, arr, file);
    });
    pd.point_data.add(std::move(arr));
    if (has_roles) {
      for (std::size_t r = 0; r < kAttributeRoleCount; ++r) {
        if (roles & (1 << r)) pd.point_data.set_active(static_cast<AttributeRole>(r), nm);
      }
    } else if (kind == DracoKind::Normal && comps == 3 && !pd.point_data.normals()) {
      pd.point_data.set_active(AttributeRole::Normals, nm);
    } else if (kind == DracoKind::Color && !pd.point_data.scalars()) {
      pd.point_data.set_active(AttributeRole::Scalars, nm);
    } else if (kind == DracoKind::TexCoord && !pd.point_data.tcoords()) {
      pd.point_data.set_active(AttributeRole::TCoords, nm);
    }
    out.attributes.push_back({nm, static_cast<int>(att.unique_id()), kind});
  }
  try {
    pd.validate();
  } catch (const Error& e) {
    throw Error(file + ": corrupt Draco data: " + e.what());
  }
  return out;
}
}  // namespace

DracoEncodedMesh encode_draco_mesh(const PolyData& mesh, const DracoWriteOptions& options,
                                   const DracoRoles& roles, std::string_view name) {
  using Clock = std::chrono::steady_clock;
  const auto seconds_since = [](Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
  };
  const Clock::time_point t_start = Clock::now();
  report_progress(options.progress, 0.0, "draco");
  Prepared p = prepare(mesh, options, roles, name);
  std::vector<DracoSource>& sources = p.sources;
  // Bits (or grids) of every quantized attribute: a budget where one applies, else `bits`.
  const auto bits_of = [&](const DracoSource& s) {
    switch (s.kind) {
      case DracoKind::Position: return options.bits.position;
      case DracoKind::Normal: return options.bits.normal;
      case DracoKind::Color: return options.bits.color;
      case DracoKind::TexCoord: return options.bits.texcoord;
      case DracoKind::Generic: break;
    }
    return options.bits.generic;
  };
  std::vector<double> shrink(sources.size(), 1.0);
  for (std::size_t k = 0; k < sources.size(); ++k) {
    DracoSource& s = sources[k];
    if (!s.quantized) continue;
    if (s.budget <= 0) {
      set_bits(s, bits_of(s));
    } else if (s.kind == DracoKind::Normal) {
      s.bits = normal_bits_for(s.budget);
    } else {
      choose_step(s, k == 0 && p.mesh ? &p.referenced : nullptr, 1.0, name);
    }
  }
  std::unique_ptr<draco::PointCloud> pc = build(p, sources);
  const bool any_budget =
      std::any_of(sources.begin(), sources.end(), [](const DracoSource& s) { return s.budget > 0; });

  DracoEncodedMesh out;
  DracoStats& st = out.stats;
  constexpr int kMaxEncodes = 12;
  for (int attempt = 1;; ++attempt) {
    report_progress(options.progress, 0.1 + 0.8 * (attempt - 1) / kMaxEncodes, "draco");
    const Clock::time_point t_encode = Clock::now();
    out.bytes = encode_once(*pc, p, sources, options, name);
    const double encode_seconds = seconds_since(t_encode);
    io_detail::DracoDecodedMesh dec = decode_draco_mesh(
        std::span<const std::byte>(reinterpret_cast<const std::byte*>(out.bytes.data()),
                                   out.bytes.size()),
        std::string(name) + " (written)");
    const Measured m = measure_errors(p, sources, dec, options);
    st = DracoStats{};
    st.encodes = attempt;
    st.encode_seconds = encode_seconds;
    st.bytes = out.bytes.size();
    st.raw_bytes = p.raw_bytes;
    st.ratio = st.bytes ? double(st.raw_bytes) / double(st.bytes) : 0;
    st.points = p.points;
    st.triangles = p.triangles.size();
    st.decoded_points = dec.mesh.points.size();
    st.decoded_triangles = dec.mesh.polys.size();
    st.lost_triangles =
        st.triangles > st.decoded_triangles ? st.triangles - st.decoded_triangles : 0;
    st.degenerate_input_triangles = p.degenerate_input;
    st.unreferenced_points = static_cast<std::size_t>(
        std::count(p.referenced.begin(), p.referenced.end(), char{0}));
    if (options.method == DracoMethod::Sequential && p.mesh) st.unreferenced_points = 0;
    st.max_position_error = m.position;
    st.dropped = p.dropped;
    for (std::size_t k = 0; k < sources.size(); ++k) {
      const DracoSource& s = sources[k];
      st.attributes.push_back({s.name, s.quantized ? s.bits : 0,
                               s.quantized && s.kind != DracoKind::Normal ? s.step : 0.0,
                               s.budget, m.arrays[k]});
    }
    out.attributes.clear();
    for (const DracoSource& s : sources) out.attributes.push_back({s.name, s.unique_id, s.kind});
    if (m.unmatched > 0) {
      throw Error(std::string(name) + ": internal check failed: " + std::to_string(m.unmatched) +
                  " points have no decoded counterpart");
    }
    // Refine what missed its budget, or positions when faces were lost.
    bool again = false;
    const bool faces_lost = options.keep_faces && sources[0].budget > 0 &&
                            st.lost_triangles > p.degenerate_input;
    for (std::size_t k = 0; k < sources.size(); ++k) {
      DracoSource& s = sources[k];
      if (s.budget <= 0) continue;
      const bool missed = m.arrays[k] > s.budget;
      if (!missed && !(k == 0 && faces_lost)) continue;
      if (s.bits >= 30) continue;
      again = true;
      if (s.kind == DracoKind::Normal) {
        ++s.bits;
      } else if (missed) {
        shrink[k] *= std::min(0.99, s.budget / m.arrays[k]);
        choose_step(s, k == 0 && p.mesh ? &p.referenced : nullptr, shrink[k], name);
      } else {
        if (!set_step(s, s.step * 0.5)) again = false;
      }
    }
    if (!again || attempt >= kMaxEncodes || !any_budget) {
      for (std::size_t k = 0; k < sources.size(); ++k) {
        if (sources[k].budget > 0 && m.arrays[k] > sources[k].budget) {
          throw Error(
              fmt::format("{}: could not meet the error budget of '{}' ({:g}): measured {:g}", name,
                          sources[k].name, sources[k].budget, m.arrays[k]));
        }
      }
      if (st.lost_triangles > p.degenerate_input) {
        st.note = std::to_string(st.lost_triangles - p.degenerate_input) +
                  " triangles lost to quantization" +
                  (sources[0].budget > 0 && options.keep_faces
                       ? std::string(" even at 30 bits")
                       : std::string(" (give a position budget or more bits to keep them)"));
      } else if (st.lost_triangles > 0) {
        st.note = std::to_string(st.lost_triangles) +
                  " triangles were degenerate in the input (repeated points): no quantization "
                  "keeps them";
      }
      out.decoded = std::move(dec.mesh);
      break;
    }
  }
  out.stats.total_seconds = seconds_since(t_start);
  report_progress(options.progress, 1.0, "draco");
  return out;
}

}  // namespace io_detail

DracoEncodeResult encode_draco(const PolyData& mesh, const DracoWriteOptions& options,
                               std::string_view name) {
  io_detail::DracoEncodedMesh e = io_detail::encode_draco_mesh(mesh, options, {}, name);
  return {std::move(e.bytes), std::move(e.stats)};
}

DracoStats write_draco(const PolyData& mesh, const std::filesystem::path& path,
                       const DracoWriteOptions& options) {
  AtomicFile out(path);
  auto [bytes, stats] = encode_draco(mesh, options, path.string());
  out.reserve(bytes.size());
  out.stream().write(reinterpret_cast<const char*>(bytes.data()),
                     static_cast<std::streamsize>(bytes.size()));
  out.commit();
  return stats;
}

PolyData read_draco(std::span<const std::byte> data, std::string_view name) {
  return io_detail::decode_draco_mesh(data, name).mesh;
}

PolyData read_draco(const std::filesystem::path& path, const ProgressCallback& progress) {
  return io_detail::read_with_progress(
      path, progress, [&](const io_detail::FileSource& src, io_detail::Progress*, std::uint64_t) {
        return read_draco(src.bytes, path.string());
      });
}

}  // namespace isoforge
