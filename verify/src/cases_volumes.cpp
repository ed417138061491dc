// Verification cases for contouring volumes that are not smooth shapes: random scalar volumes
// (uniform noise, smoothed noise, quantized noise whose samples hit the isovalues exactly; several
// seeds and isovalues), which stress the ambiguous cube cases and the asymptotic decider, and the
// real volumes headsq (CT) and ironProt at full resolution. Surfaces that reach the volume's
// boundary may only have borders there; padded volumes must give closed outward surfaces.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include "case_support.hpp"
#include "isoforge/contour/contour.hpp"
#include "isoforge/io/io.hpp"

namespace isoforge::verify {

namespace {

enum class Noise { Uniform, Smooth, Quantized };

// Noise on n^3 samples over [0, 1]^3 (origin 0, spacing 1 / (n - 1)).
ImageData noise_volume(Noise kind, Index n, unsigned seed) {
  ImageData img;
  img.dims = {n, n, n};
  const double h = 1.0 / static_cast<double>(n - 1);
  img.spacing = {h, h, h};
  const auto un = static_cast<std::size_t>(n);
  std::vector<float> v(un * un * un);
  std::mt19937 rng(seed);
  if (kind == Noise::Quantized) {
    std::uniform_int_distribution<int> d(0, 4);
    for (float& x : v) x = static_cast<float>(d(rng));
  } else {
    std::uniform_real_distribution<float> d(0.0f, 1.0f);
    for (float& x : v) x = d(rng);
  }
  if (kind == Noise::Smooth) {
    // Three passes of a 3-tap box filter along each axis (clamped at the ends): features a few
    // samples wide, many saddles.
    std::vector<float> t(v.size());
    const std::size_t stride[3] = {1, un, un * un};
    for (int pass = 0; pass < 3; ++pass) {
      for (int axis = 0; axis < 3; ++axis) {
        const std::size_t s = stride[axis];
        for (std::size_t id = 0; id < v.size(); ++id) {
          const std::size_t c = (id / s) % un;
          const float lo = v[c > 0 ? id - s : id], hi = v[c + 1 < un ? id + s : id];
          t[id] = (lo + v[id] + hi) / 3.0f;
        }
        v.swap(t);
      }
    }
  }
  img.point_data.add(DataArray::from_vector<float>("noise", 1, v), AttributeRole::Scalars);
  return img;
}

// Sets the boundary layer of samples to `value` (below every isovalue: closed surfaces).
void pad(ImageData& img, float value) {
  auto v = img.point_data.get("noise").values<float>();
  const Dims d = img.dims;
  for (Index k = 0; k < d[2]; ++k)
    for (Index j = 0; j < d[1]; ++j)
      for (Index i = 0; i < d[0]; ++i) {
        if (i == 0 || j == 0 || k == 0 || i == d[0] - 1 || j == d[1] - 1 || k == d[2] - 1) {
          v[static_cast<std::size_t>(img.point_id(i, j, k))] = value;
        }
      }
}

// Tolerance for "on a face plane of the domain": a few float ulps of the domain's coordinates.
double boundary_tolerance(const Bounds& b) {
  double m = 0;
  for (int a = 0; a < 3; ++a) m = std::max({m, std::abs(b.min[a]), std::abs(b.max[a])});
  return 8 * m * 0x1p-23;
}

// Sums of the counts over several surfaces, then the usual checks on the sums.
struct Totals {
  MeshReport m;
  BorderReport b;
  bool all_checked = true;
  bool all_outward = true;
  void add(const MeshReport& x, const BorderReport& y) {
    m.border_edges += x.border_edges;
    m.non_manifold_edges += x.non_manifold_edges;
    m.non_manifold_vertices += x.non_manifold_vertices;
    m.inconsistent_edges += x.inconsistent_edges;
    m.degenerate_faces += x.degenerate_faces;
    m.duplicate_points += x.duplicate_points;
    m.self_intersections += x.self_intersections;
    all_checked = all_checked && x.self_intersection_checked;
    all_outward = all_outward && x.outward;
    b.border_edges += y.border_edges;
    b.off_boundary += y.off_boundary;
  }
};

void noise_case(CaseResult& r, Noise kind, Index n, unsigned seed, bool padded) {
  ImageData img = noise_volume(kind, n, seed);
  std::vector<double> isovalues;
  if (kind == Noise::Uniform) isovalues = {0.25, 0.5, 0.75};
  if (kind == Noise::Quantized) isovalues = {1.0, 2.0, 2.5, 3.0};
  if (kind == Noise::Smooth) {
    // Mean and mean +- one standard deviation of the smoothed samples.
    const auto v = img.point_data.get("noise").values<float>();
    double s = 0, s2 = 0;
    for (float x : v) {
      s += x;
      s2 += static_cast<double>(x) * x;
    }
    const double mean = s / static_cast<double>(v.size());
    const double sd = std::sqrt(std::max(0.0, s2 / static_cast<double>(v.size()) - mean * mean));
    isovalues = {mean - sd, mean, mean + sd};
  }
  if (padded) pad(img, -1.0f);
  const Bounds domain = img.bounds();
  Totals tot;
  std::size_t triangles = 0, components = 0, ambiguous = 0;
  for (double iso : isovalues) {
    ContourOptions o;
    o.values = {iso};
    o.flip = true;  // high values inside: outward surfaces around them
    const auto [mesh, st] = contour_image(img, o);
    if (mesh.polys.empty()) throw Error(fmt::format("no surface at isovalue {}", iso));
    const MeshReport m = check_mesh(mesh);
    tot.add(m, check_borders(mesh, domain, boundary_tolerance(domain)));
    triangles += m.faces;
    components += m.components.size();
    ambiguous += st.ambiguous_faces;
  }
  r.note("isovalues", fmt::format("{:.4g}", fmt::join(isovalues, ", ")));
  r.note("triangles / components / ambiguous faces (all isovalues)",
         fmt::format("{} / {} / {}", triangles, components, ambiguous));
  if (padded) {
    tot.m.outward = tot.all_outward;
    tot.m.self_intersection_checked = tot.all_checked;
    record_closed_surface(r, tot.m);
  } else {
    tot.m.self_intersection_checked = tot.all_checked;
    record_bordered_surface(r, tot.m, tot.b);
    r.note("border edges (all on the volume boundary)", fmt::format("{}", tot.b.border_edges));
  }
}

void real_case(CaseResult& r, const std::string& file, double iso, bool flip) {
  const auto path = std::filesystem::path(ISOFORGE_DATA_DIR) / file;
  const Dataset ds = read(path);
  const auto* img = std::get_if<ImageData>(&ds);
  if (!img) throw Error(file + ": not image data");
  ContourOptions o;
  o.values = {iso};
  o.flip = flip;
  const auto [mesh, st] = contour_image(*img, o);
  const MeshReport m = check_mesh(mesh);
  const Bounds domain = img->bounds();
  const BorderReport b = check_borders(mesh, domain, boundary_tolerance(domain));
  r.note("volume", fmt::format("{} x {} x {}", img->dims[0], img->dims[1], img->dims[2]));
  note_mesh(r, m);
  r.note("ambiguous faces", fmt::format("{}", st.ambiguous_faces));
  r.note("border edges (all on the volume boundary)", fmt::format("{}", b.border_edges));
  r.at_least("triangles", static_cast<double>(m.faces), 1);
  record_bordered_surface(r, m, b);
}

}  // namespace

void add_volume_cases(std::vector<Case>& cases) {
  for (unsigned seed : {1u, 2u, 3u}) {
    for (bool padded : {false, true}) {
      const std::string tag = padded ? "padded" : "open";
      cases.push_back({fmt::format("random/uniform-24/seed{}/{}", seed, tag),
                       fmt::format("uniform noise 24^3 at 0.25, 0.5, 0.75{}",
                                   padded ? ", boundary layer below every isovalue (closed)"
                                          : " (borders on the boundary)"),
                       true, [seed, padded](CaseResult& r) {
                         noise_case(r, Noise::Uniform, 24, seed, padded);
                       }});
    }
    cases.push_back({fmt::format("random/uniform-64/seed{}/open", seed),
                     "uniform noise 64^3 at 0.25, 0.5, 0.75 (borders on the boundary)", false,
                     [seed](CaseResult& r) { noise_case(r, Noise::Uniform, 64, seed, false); }});
    cases.push_back({fmt::format("random/quantized-24/seed{}/padded", seed),
                     "integer noise 0..4 on 24^3 at 1, 2, 2.5, 3: samples equal to the isovalue",
                     true,
                     [seed](CaseResult& r) { noise_case(r, Noise::Quantized, 24, seed, true); }});
  }
  for (unsigned seed : {1u, 2u}) {
    for (bool padded : {false, true}) {
      cases.push_back(
          {fmt::format("random/smooth-48/seed{}/{}", seed, padded ? "padded" : "open"),
           "box-filtered noise 48^3 at mean and mean +- one standard deviation", seed == 1,
           [seed, padded](CaseResult& r) { noise_case(r, Noise::Smooth, 48, seed, padded); }});
    }
  }
  cases.push_back({"real/headsq/1150", "headsq quarter CT 64x64x93 at 1150 (skin), flipped", true,
                   [](CaseResult& r) { real_case(r, "headsq/quarter.nhdr", 1150, true); }});
  cases.push_back({"real/headsq/2000", "headsq quarter CT 64x64x93 at 2000, flipped", true,
                   [](CaseResult& r) { real_case(r, "headsq/quarter.nhdr", 2000, true); }});
  cases.push_back({"real/ironProt/64", "ironProt 68^3 at 64", true,
                   [](CaseResult& r) { real_case(r, "ironProt.vtk", 64, true); }});
  cases.push_back({"real/ironProt/128", "ironProt 68^3 at 128", true,
                   [](CaseResult& r) { real_case(r, "ironProt.vtk", 128, true); }});
}

}  // namespace isoforge::verify
