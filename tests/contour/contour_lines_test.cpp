// Marching squares on 2D/1D images, isolines and crossing points of polygonal data.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <set>

#include "contour/tables.hpp"
#include "isoforge/contour/contour.hpp"
#include "isoforge/io/io.hpp"
#include "support/result.hpp"
#include "support/expect_error.hpp"

using namespace isoforge;

namespace {

ImageData image_of(Dims dims, const std::vector<float>& values, Vec3 spacing = {1, 1, 1},
                   Vec3 origin = {0, 0, 0}) {
  ImageData img;
  img.dims = dims;
  img.spacing = spacing;
  img.origin = origin;
  img.point_data.add(DataArray::from_vector<float>("s", 1, values), AttributeRole::Scalars);
  return img;
}

std::size_t sz(Index i) {
  return static_cast<std::size_t>(i);
}

// Structural checks of polylines: no polyline shorter than one segment, no zero-length or
// repeated-point segment, every point used. Returns how many segment ends use each point.
std::vector<int> check_polylines(const PolyData& pd, const std::string& what) {
  std::vector<int> uses(pd.points.size(), 0);
  for (std::size_t c = 0; c < pd.lines.size(); ++c) {
    auto ids = pd.lines.cell(c);
    EXPECT_GE(ids.size(), 2u) << what;
    for (std::size_t k = 0; k + 1 < ids.size(); ++k) {
      EXPECT_NE(ids[k], ids[k + 1]) << what;
      EXPECT_GT(norm2(pd.points[sz(ids[k])] - pd.points[sz(ids[k + 1])]), 0.0) << what;
      ++uses[sz(ids[k])];
      ++uses[sz(ids[k + 1])];
    }
  }
  for (std::size_t p = 0; p < uses.size(); ++p) EXPECT_GT(uses[p], 0) << what << " point " << p;
  return uses;
}

// Every polyline closed, every point on exactly one loop, once (twice as a segment end).
void expect_closed_loops(const PolyData& pd, const std::string& what) {
  const std::vector<int> uses = check_polylines(pd, what);
  for (std::size_t c = 0; c < pd.lines.size(); ++c) {
    auto ids = pd.lines.cell(c);
    ASSERT_GE(ids.size(), 4u) << what;  // a loop has at least three points
    EXPECT_EQ(ids.front(), ids.back()) << what;
  }
  for (std::size_t p = 0; p < uses.size(); ++p) EXPECT_EQ(uses[p], 2) << what << " point " << p;
}

// Signed area of a closed polyline projected on the plane of axes a, b.
double signed_area(const PolyData& pd, std::size_t line, int a = 0, int b = 1) {
  auto ids = pd.lines.cell(line);
  double s = 0;
  for (std::size_t k = 0; k + 1 < ids.size(); ++k) {
    const Vec3 p = pd.points[sz(ids[k])], q = pd.points[sz(ids[k + 1])];
    s += p[a] * q[b] - q[a] * p[b];
  }
  return s / 2;
}

std::size_t segments(const PolyData& pd) {
  std::size_t n = 0;
  for (std::size_t c = 0; c < pd.lines.size(); ++c) n += pd.lines.cell_size(c) - 1;
  return n;
}

PolyData read_polydata(const char* name) {
  Dataset ds = read(std::string(ISOFORGE_DATA_DIR) + "/" + name);
  EXPECT_TRUE(std::holds_alternative<PolyData>(ds)) << name;
  return std::get<PolyData>(std::move(ds));
}

// Point array "<axis>" holding one coordinate of every point.
void add_coordinate_array(PolyData& pd, int axis, const char* name) {
  DataArray a(name, ScalarType::Float32, 1, pd.points.size());
  for (std::size_t i = 0; i < pd.points.size(); ++i) a.set(i, 0, pd.points[i][axis]);
  pd.point_data.add(std::move(a));
}

}  // namespace

TEST(ContourLines, HandComputedDiamond) {
  // One sample above in the middle of a 3x3 image: four crossings at the middle of the four
  // edges around it, one closed counter-clockwise loop.
  std::vector<float> v(9, 0.0f);
  v[4] = 1.0f;
  ContourOptions o;
  o.values = {0.5};
  ContourStats st;
  const PolyData pd = test::split_result(contour(image_of({3, 3, 1}, v), o), st);
  EXPECT_EQ(st.points, 4u);
  EXPECT_EQ(st.cells, 4u);
  EXPECT_EQ(st.ambiguous_faces, 0u);
  ASSERT_EQ(pd.points.size(), 4u);
  ASSERT_EQ(pd.lines.size(), 1u);
  EXPECT_TRUE(pd.verts.empty());
  EXPECT_TRUE(pd.polys.empty());
  ASSERT_EQ(pd.lines.cell_size(0), 5u);
  expect_closed_loops(pd, "diamond");
  std::set<std::array<double, 2>> expected{{1, 0.5}, {0.5, 1}, {1.5, 1}, {1, 1.5}}, got;
  for (std::size_t i = 0; i < 4; ++i) got.insert({pd.points[i].x, pd.points[i].y});
  EXPECT_EQ(got, expected);
  EXPECT_DOUBLE_EQ(signed_area(pd, 0), 0.5);
  o.flip = true;
  EXPECT_DOUBLE_EQ(signed_area(contour(image_of({3, 3, 1}, v), o).output, 0), -0.5);
}

TEST(ContourLines, HandComputedSaddlePixel) {
  // One pixel, diagonal corners (0,0) and (1,1) above: the decider compares (a0 − c)(a1 − c) =
  // 0.45 with (b0 − c)(b1 − c); each resolution gives two open segments, each cutting off one
  // corner: the below corners when the above ones are connected, the above corners otherwise.
  for (const float below : {-2.0f, 0.45f}) {
    const std::vector<float> v{1.0f, below, below, 1.4f};
    ContourOptions o;
    o.values = {0.5};
    ContourStats st;
    const PolyData pd = test::split_result(contour(image_of({2, 2, 1}, v), o), st);
    EXPECT_EQ(st.ambiguous_faces, 1u);
    ASSERT_EQ(pd.lines.size(), 2u);
    ASSERT_EQ(pd.points.size(), 4u);
    const bool connected = below == 0.45f;
    EXPECT_EQ(contour_detail::above_connected(1.0, below, 1.4, below, 0.5), connected);
    std::set<std::array<double, 2>> corners;
    for (std::size_t c = 0; c < 2; ++c) {
      auto ids = pd.lines.cell(c);
      ASSERT_EQ(ids.size(), 2u);
      const Vec3 a = pd.points[sz(ids[0])], b = pd.points[sz(ids[1])];
      // One point lies on a horizontal side (y = 0 or 1), the other on a vertical one; the corner
      // cut off is where those sides meet.
      const bool a_horizontal = a.y == 0 || a.y == 1;
      const double cx = a_horizontal ? b.x : a.x, cy = a_horizontal ? a.y : b.y;
      corners.insert({cx, cy});
      // Above on the left: the corner cut off lies left of a->b exactly when it is above.
      const double side = (b.x - a.x) * (cy - a.y) - (b.y - a.y) * (cx - a.x);
      EXPECT_EQ(side > 0, cx == cy) << "below = " << below;
    }
    const std::set<std::array<double, 2>> expected =
        connected ? std::set<std::array<double, 2>>{{1, 0}, {0, 1}}
                  : std::set<std::array<double, 2>>{{0, 0}, {1, 1}};
    EXPECT_EQ(corners, expected) << "below = " << below;
  }
}

TEST(ContourLines, EveryPixelCaseClosesCounterClockwise) {
  // The middle pixel of a 4x4 image takes every above/below pattern with random magnitudes in a
  // below-valued border: closed loops around the above corners, counter-clockwise (above on
  // the left), one loop per above component; both saddle resolutions occur.
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> mag(0.05f, 1.0f);
  int saddle_loops[3] = {0, 0, 0};
  for (unsigned c = 0; c < 16; ++c) {
    for (int trial = 0; trial < 40; ++trial) {
      std::vector<float> v(16, -1.0f);
      float corner[4];
      const int ci[4] = {1, 2, 2, 1}, cj[4] = {1, 1, 2, 2};  // cyclic order
      for (int k = 0; k < 4; ++k) {
        corner[k] = ((c >> k) & 1) ? mag(rng) : -mag(rng);
        v[sz(ci[k] + 4 * cj[k])] = corner[k];
      }
      for (const bool flip : {false, true}) {
        ContourOptions o;
        o.flip = flip;
        ContourStats st;
        const PolyData pd = test::split_result(contour(image_of({4, 4, 1}, v), o), st);
        const std::string what = "case " + std::to_string(c);
        if (c == 0) {
          EXPECT_EQ(pd.lines.size(), 0u);
          continue;
        }
        expect_closed_loops(pd, what);
        EXPECT_EQ(st.cells, segments(pd));
        EXPECT_EQ(st.points, pd.points.size());
        std::size_t loops = 1;
        if (c == 5 || c == 10) {
          EXPECT_EQ(st.ambiguous_faces, 1u);
          loops = contour_detail::above_connected(corner[0], corner[1], corner[2], corner[3], 0.0)
                      ? 1
                      : 2;
          if (!flip) ++saddle_loops[loops];
        }
        EXPECT_EQ(pd.lines.size(), loops) << what;
        for (std::size_t l = 0; l < pd.lines.size(); ++l) {
          EXPECT_GT(flip ? -signed_area(pd, l) : signed_area(pd, l), 0) << what;
        }
        // Points: one per crossed edge (every edge between an above and a below sample).
        std::size_t crossed = 0;
        for (int j = 0; j < 4; ++j)
          for (int i = 0; i < 4; ++i) {
            const bool a = v[sz(i + 4 * j)] >= 0;
            if (i + 1 < 4) crossed += a != (v[sz(i + 1 + 4 * j)] >= 0);
            if (j + 1 < 4) crossed += a != (v[sz(i + 4 * (j + 1))] >= 0);
          }
        EXPECT_EQ(pd.points.size(), crossed) << what;
      }
    }
  }
  EXPECT_GT(saddle_loops[1], 0);
  EXPECT_GT(saddle_loops[2], 0);
}

TEST(ContourLines, RandomFieldsGiveClosedLoopsInsideABelowBorder) {
  // Random signs in the interior of a below-valued border: all loops closed, each point on one
  // loop, saddles and all.
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.01f, 1.0f);
  std::bernoulli_distribution coin(0.5);
  for (int trial = 0; trial < 200; ++trial) {
    const Index n = 12;
    std::vector<float> v(sz(n * n), -1.0f);
    for (Index j = 1; j + 1 < n; ++j)
      for (Index i = 1; i + 1 < n; ++i) v[sz(i + n * j)] = coin(rng) ? u(rng) : -u(rng);
    ContourStats st;
    const PolyData pd = test::split_result(contour(image_of({n, n, 1}, v), {}), st);
    expect_closed_loops(pd, "trial " + std::to_string(trial));
    EXPECT_EQ(st.cells, segments(pd));
    // The loops bound the above region: their signed areas sum to its area's sign (positive).
    double total = 0;
    for (std::size_t l = 0; l < pd.lines.size(); ++l) total += signed_area(pd, l);
    if (!pd.lines.empty()) {
      EXPECT_GT(total, 0);
    }
  }
}

TEST(ContourLines, CircleAreaConvergesAtSecondOrder) {
  const double r = 0.7, cx = 0.013, cy = -0.021;
  const double exact = std::numbers::pi * r * r;
  std::vector<double> h, err;
  for (Index n : {17, 33, 65, 129, 257}) {
    const double step = 2.0 / static_cast<double>(n - 1);
    std::vector<float> v(sz(n * n));
    for (Index j = 0; j < n; ++j)
      for (Index i = 0; i < n; ++i) {
        const double x = -1 + step * static_cast<double>(i), y = -1 + step * static_cast<double>(j);
        v[sz(i + n * j)] = static_cast<float>(r - std::hypot(x - cx, y - cy));  // above inside
      }
    const PolyData pd = contour(image_of({n, n, 1}, v, {step, step, 1}, {-1, -1, 0})).output;
    ASSERT_EQ(pd.lines.size(), 1u) << n;
    expect_closed_loops(pd, "n = " + std::to_string(n));
    const double area = signed_area(pd, 0);
    EXPECT_GT(area, 0);  // counter-clockwise around the maximum
    h.push_back(step);
    err.push_back(std::abs(area - exact) / exact);
  }
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < h.size(); ++i) {
    const double x = std::log(h[i]), y = std::log(err[i]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  const double m = static_cast<double>(h.size());
  const double slope = (m * sxy - sx * sy) / (m * sxx - sx * sx);
  EXPECT_GT(slope, 1.7);
  EXPECT_LT(slope, 2.4);
  EXPECT_LT(err.back(), 1e-4);
}

TEST(ContourLines, SameContourInEveryPlane) {
  // The same 2D field as an xy, xz and yz image: identical lines; points with the axes permuted.
  const Index nu = 23, nv = 17;
  std::vector<float> v(sz(nu * nv));
  for (Index j = 0; j < nv; ++j)
    for (Index i = 0; i < nu; ++i) {
      const double x = static_cast<double>(i) / 7, y = static_cast<double>(j) / 5;
      v[sz(i + nu * j)] = static_cast<float>(std::sin(x) * std::cos(1.3 * y) + 0.1 * x);
    }
  ContourOptions o;
  o.values = {-0.3, 0.0, 0.4};
  const PolyData xy = contour(image_of({nu, nv, 1}, v, {0.5, 0.25, 1}), o).output;
  const PolyData xz = contour(image_of({nu, 1, nv}, v, {0.5, 1, 0.25}), o).output;
  const PolyData yz = contour(image_of({1, nu, nv}, v, {1, 0.5, 0.25}), o).output;
  ASSERT_GT(xy.lines.size(), 0u);
  EXPECT_TRUE(xy.lines == xz.lines);
  EXPECT_TRUE(xy.lines == yz.lines);
  ASSERT_EQ(xy.points.size(), xz.points.size());
  ASSERT_EQ(xy.points.size(), yz.points.size());
  for (std::size_t i = 0; i < xy.points.size(); ++i) {
    const Vec3 p = xy.points[i];
    EXPECT_EQ(xz.points[i], (Vec3{p.x, 0, p.y}));
    EXPECT_EQ(yz.points[i], (Vec3{0, p.x, p.y}));
  }
  EXPECT_TRUE(xy.point_data == xz.point_data);
}

TEST(ContourLines, IntegerDataAtAnIntegerValueHasNoDegeneracies) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> d(0, 2);
  for (int trial = 0; trial < 100; ++trial) {
    const Index n = 14;
    std::vector<float> v(sz(n * n), 0.0f);
    for (Index j = 1; j + 1 < n; ++j)
      for (Index i = 1; i + 1 < n; ++i) v[sz(i + n * j)] = static_cast<float>(d(rng));
    ContourOptions o;
    o.values = {1.0};  // many samples equal the isovalue
    const PolyData pd = contour(image_of({n, n, 1}, v), o).output;
    ASSERT_GT(pd.lines.size(), 0u);
    expect_closed_loops(pd, "trial " + std::to_string(trial));  // also: no zero-length segment
    std::vector<std::array<double, 3>> pts;
    for (std::size_t i = 0; i < pd.points.size(); ++i)
      pts.push_back({pd.points[i].x, pd.points[i].y, pd.points[i].z});
    std::sort(pts.begin(), pts.end());
    EXPECT_EQ(std::adjacent_find(pts.begin(), pts.end()), pts.end()) << "trial " << trial;
  }
}

// A NaN sample is undefined: the loop around the one above sample loses the crossing toward it
// and becomes one open polyline through the other three crossings.
TEST(ContourLines, NaNSamplesOpenTheLine) {
  std::vector<float> v(25, -1.0f);
  v[12] = 1.0f;  // (2, 2)
  v[13] = std::numeric_limits<float>::quiet_NaN();
  ContourStats st;
  const PolyData pd = test::split_result(contour(image_of({5, 5, 1}, v)), st);
  ASSERT_EQ(pd.lines.size(), 1u);
  EXPECT_EQ(pd.lines.cell_size(0), 3u);
  EXPECT_EQ(pd.points.size(), 3u);
  EXPECT_EQ(st.points, 3u);
  EXPECT_EQ(st.cells, 2u);  // segments
  for (std::size_t i = 0; i < pd.points.size(); ++i) {
    ASSERT_TRUE(is_finite(pd.points[i]));
    EXPECT_NE(pd.points[i], (Vec3{2.5, 2, 0}));
  }
}

TEST(ContourLines, OneDimensionalImagesGiveVertices) {
  const std::vector<float> v{0, 2, 3, 1, -1, 4, 4};
  for (int axis = 0; axis < 3; ++axis) {
    Dims dims{1, 1, 1};
    dims[sz(axis)] = 7;
    Vec3 spacing{1, 1, 1};
    spacing[axis] = 0.5;
    ImageData img = image_of(dims, v, spacing);
    DataArray cells("edge", ScalarType::Int32, 1, 6);
    for (std::size_t c = 0; c < 6; ++c) cells.set(c, 0, static_cast<double>(c));
    img.cell_data.add(std::move(cells));
    ContourOptions o;
    o.values = {1.5};
    ContourStats st;
    const PolyData pd = test::split_result(contour(img, o), st);
    // Crossed edges 0-1 (t = 0.75), 2-3 (t = 0.75), 4-5 (t = 0.5).
    ASSERT_EQ(pd.points.size(), 3u);
    ASSERT_EQ(pd.verts.size(), 3u);
    EXPECT_TRUE(pd.lines.empty());
    EXPECT_EQ(st.cells, 3u);
    const double at[3] = {0.375, 1.375, 2.25};
    const int edge[3] = {0, 2, 4};
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_EQ(pd.verts.cell(k)[0], static_cast<Index>(k));
      EXPECT_DOUBLE_EQ(pd.points[k][axis], at[k]);
      EXPECT_EQ(pd.cell_data.get("edge").get(k), edge[k]);
      EXPECT_NEAR(pd.point_data.get("s").get(k), 1.5, 1e-6);
    }
  }
  // A single sample: nothing, but still the output layout.
  const PolyData none = contour(image_of({1, 1, 1}, {3.0f}), {}).output;
  EXPECT_EQ(none.points.size(), 0u);
  EXPECT_TRUE(none.point_data.has("IsovalueIndex"));
}

TEST(ContourLines, AttributesIsovalueIndexAndNormals) {
  const Index n = 40;
  const double step = 2.0 / (n - 1);
  std::vector<float> v(sz(n * n));
  DataArray x("x", ScalarType::Float64, 1, sz(n * n));
  for (Index j = 0; j < n; ++j)
    for (Index i = 0; i < n; ++i) {
      const double px = -1 + step * static_cast<double>(i), py = -1 + step * static_cast<double>(j);
      v[sz(i + n * j)] = static_cast<float>(px * px + py * py);  // increasing outward
      x.set(sz(i + n * j), 0, px);
    }
  ImageData img = image_of({n, n, 1}, v, {step, step, 1}, {-1, -1, 0});
  img.point_data.add(std::move(x));
  ContourOptions o;
  o.values = {0.1, 0.3, 0.5};
  o.normals = ContourNormals::Gradient;
  for (const bool flip : {false, true}) {
    o.flip = flip;
    const PolyData pd = contour(img, o).output;
    ASSERT_EQ(pd.lines.size(), 3u);
    const DataArray& idx = pd.point_data.get("IsovalueIndex");
    const DataArray& xi = pd.point_data.get("x");
    const DataArray& s = pd.point_data.get("s");
    const DataArray* nrm = pd.point_data.normals();
    ASSERT_NE(nrm, nullptr);
    for (std::size_t i = 0; i < pd.points.size(); ++i) {
      EXPECT_NEAR(xi.get(i), pd.points[i].x, 1e-6);
      EXPECT_NEAR(s.get(i), o.values[sz(static_cast<Index>(idx.get(i)))], 2e-3);
      const Vec3 nn{nrm->get(i, 0), nrm->get(i, 1), nrm->get(i, 2)};
      EXPECT_NEAR(norm(nn), 1.0, 1e-5);
      EXPECT_EQ(nn.z, 0.0);
      const double radial = dot(nn, pd.points[i] / norm(pd.points[i]));
      EXPECT_GT(flip ? -radial : radial, 0.95);
    }
    for (std::size_t l = 0; l < 3; ++l) {
      // Values increase outward: the above region is outside, on the left: clockwise loops.
      EXPECT_LT(flip ? -signed_area(pd, l) : signed_area(pd, l), 0);
      auto ids = pd.lines.cell(l);
      for (Index id : ids) EXPECT_EQ(idx.get(sz(id)), static_cast<double>(l));
    }
  }
}

TEST(ContourLines, CellDataBreaksPolylinesOnlyWhereItChanges) {
  // A circle over pixels whose "half" cell value is 0 left of x = 0 and 1 right of it: two
  // polylines, each carrying its half's value. Unique per-pixel values leave single segments.
  const Index n = 30;
  const double step = 2.0 / (n - 1);
  std::vector<float> v(sz(n * n));
  for (Index j = 0; j < n; ++j)
    for (Index i = 0; i < n; ++i) {
      const double px = -1 + step * static_cast<double>(i) + 0.01,
                   py = -1 + step * static_cast<double>(j);
      v[sz(i + n * j)] = static_cast<float>(0.7 - std::hypot(px, py));
    }
  ImageData img = image_of({n, n, 1}, v, {step, step, 1}, {-1, -1, 0});
  const std::size_t nc = sz((n - 1) * (n - 1));
  DataArray half("half", ScalarType::UInt8, 1, nc), id("id", ScalarType::Int32, 1, nc);
  for (Index j = 0; j + 1 < n; ++j)
    for (Index i = 0; i + 1 < n; ++i) {
      half.set(sz(i + (n - 1) * j), 0, 2 * i + 1 < n - 1 ? 0 : 1);
      id.set(sz(i + (n - 1) * j), 0, static_cast<double>(i + (n - 1) * j));
    }
  img.cell_data.add(std::move(half));
  ContourStats st;
  PolyData pd = test::split_result(contour(img, {}), st);
  ASSERT_EQ(pd.lines.size(), 2u);
  EXPECT_EQ(segments(pd), st.cells);
  for (std::size_t l = 0; l < 2; ++l) {
    auto ids = pd.lines.cell(l);
    EXPECT_NE(ids.front(), ids.back());
    const double h = pd.cell_data.get("half").get(l);
    for (std::size_t k = 0; k + 1 < ids.size(); ++k) {
      const double mid = (pd.points[sz(ids[k])].x + pd.points[sz(ids[k + 1])].x) / 2;
      const auto i = static_cast<Index>(std::floor((mid + 1) / step));  // the segment's pixel
      EXPECT_EQ(2 * i + 1 < n - 1 ? 0.0 : 1.0, h);
    }
  }
  // Without attributes: one closed loop again.
  ContourOptions plain;
  plain.interpolate_attributes = false;
  EXPECT_EQ(contour(img, plain).output.lines.size(), 1u);
  img.cell_data.add(std::move(id));
  pd = test::split_result(contour(img, {}), st);
  EXPECT_EQ(pd.lines.size(), st.cells);
  const DataArray& ids = pd.cell_data.get("id");
  for (std::size_t l = 0; l < pd.lines.size(); ++l) {
    auto c = pd.lines.cell(l);
    ASSERT_EQ(c.size(), 2u);
    const Vec3 mid = (pd.points[sz(c[0])] + pd.points[sz(c[1])]) / 2.0;
    const auto i = static_cast<Index>(std::floor((mid.x + 1) / step));
    const auto j = static_cast<Index>(std::floor((mid.y + 1) / step));
    EXPECT_EQ(static_cast<Index>(ids.get(l)), i + (n - 1) * j);
  }
}

TEST(ContourLines, DeterministicForAnyThreadCount) {
  const Index nu = 701, nv = 533;
  std::vector<float> v(sz(nu * nv));
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> noise(-0.05f, 0.05f);
  for (Index j = 0; j < nv; ++j)
    for (Index i = 0; i < nu; ++i) {
      v[sz(i + nu * j)] = static_cast<float>(std::sin(0.05 * static_cast<double>(i)) *
                                             std::cos(0.07 * static_cast<double>(j))) +
                          noise(rng);
    }
  ContourOptions o;
  o.values = {-0.2, 0.0, 0.31};
  o.normals = ContourNormals::Gradient;
  PolyData one;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = contour(image_of({nu, 1, nv}, v), o).output;
  }
  const PolyData many = contour(image_of({nu, 1, nv}, v), o).output;
  EXPECT_TRUE(one == many);
  EXPECT_GT(many.lines.size(), 100u);
}

TEST(ContourLines, BadInputIsAClearError) {
  ImageData img = image_of({3, 3, 1}, std::vector<float>(9, 0.0f));
  auto expect_error = [](const Dataset& ds, const ContourOptions& o, const std::string& text) {
    test::expect_error([&] { (void)contour(ds, o); }, text);
  };
  ContourOptions o;
  o.values = {};
  expect_error(img, o, "no isovalues");
  o.values = {std::numeric_limits<double>::quiet_NaN()};
  expect_error(img, o, "not finite");
  o.values = {0};
  o.array = "missing";
  expect_error(img, o, "'missing'");
  img.point_data.add(DataArray("v3", ScalarType::Float32, 3, 9));
  o.array = "v3";
  expect_error(img, o, "3 components");
  PolyData pd;
  pd.points = Points(3);
  pd.polys.add({0, 1, 2});
  o.array = "";
  expect_error(pd, o, "no active point scalars");
  pd.point_data.add(DataArray("s", ScalarType::Float32, 1, 3), AttributeRole::Scalars);
  // Normals from triangles ask for a surface; these contours are lines (their normals were zero).
  o.normals = ContourNormals::Triangles;
  expect_error(pd, o, "normals from triangles need a surface");
  expect_error(img, o, "normals from triangles need a surface");
  UnstructuredGrid tri;
  tri.points = Points(3);
  tri.add_cell(CellType::Triangle, {0, 1, 2});
  tri.point_data.add(DataArray("s", ScalarType::Float32, 1, 3), AttributeRole::Scalars);
  expect_error(tri, o, "normals from triangles need a surface");
  o.normals = ContourNormals::Gradient;
  EXPECT_NO_THROW((void)contour(pd, o));
  o.normals = ContourNormals::None;
  pd.polys.add({0, 1, 7});
  EXPECT_THROW((void)contour(pd, o), Error);
}

// ------------------------------------------------------------------------------------------------
// Polygonal data.

TEST(ContourPolyData, TorsoCutByZIsClosedOrEndsOnTheBorder) {
  PolyData torso = read_polydata("Torso.vtp");
  ASSERT_EQ(torso.points.size(), 12015u);
  add_coordinate_array(torso, 2, "z");
  ContourOptions o;
  o.array = "z";
  for (int k = 0; k < 46; ++k) o.values.push_back(-620.0 + 15.0 * k);  // -620 .. 55
  ContourStats st;
  const PolyData pd = test::split_result(contour(torso, o), st);
  ASSERT_GT(pd.lines.size(), 46u);
  EXPECT_TRUE(pd.polys.empty());
  EXPECT_EQ(st.cells, segments(pd));
  check_polylines(pd, "torso");
  // Border edges of the surface (used by one polygon) and every point's crossing on them.
  std::map<std::pair<Index, Index>, int> edge_uses;
  for (std::size_t c = 0; c < torso.polys.size(); ++c) {
    auto ids = torso.polys.cell(c);
    for (std::size_t k = 0; k < ids.size(); ++k) {
      Index a = ids[k], b = ids[(k + 1) % ids.size()];
      ++edge_uses[{std::min(a, b), std::max(a, b)}];
    }
  }
  std::size_t non_manifold = 0;
  double max_dz = 0;  // crossings stay 1/1024 of an edge away from its ends
  for (const auto& [e, n] : edge_uses) {
    non_manifold += n > 2;
    max_dz = std::max(max_dz, std::abs(torso.points[sz(e.first)].z - torso.points[sz(e.second)].z));
  }
  const double tol = max_dz / 1024 + 1e-4;
  const DataArray& idx = pd.point_data.get("IsovalueIndex");
  const DataArray& z = pd.point_data.get("z");
  std::size_t border_crossings = 0;
  std::set<std::pair<int, std::array<float, 3>>> border_points;
  for (const auto& [e, n] : edge_uses) {
    if (n != 1) continue;
    const Vec3 a = torso.points[sz(e.first)], b = torso.points[sz(e.second)];
    for (std::size_t v = 0; v < o.values.size(); ++v) {
      const double za = static_cast<float>(a.z), zb = static_cast<float>(b.z);
      if ((za >= o.values[v]) == (zb >= o.values[v])) continue;
      const double t = contour_detail::crossing(za, zb, o.values[v]);
      const Vec3 p = a + (b - a) * t;
      border_points.insert(
          {static_cast<int>(v),
           {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)}});
      ++border_crossings;
    }
  }
  std::size_t open_ends = 0, closed = 0;
  for (std::size_t l = 0; l < pd.lines.size(); ++l) {
    auto ids = pd.lines.cell(l);
    const double iso = o.values[sz(static_cast<Index>(idx.get(sz(ids[0]))))];
    for (Index id : ids) {
      EXPECT_EQ(idx.get(sz(id)), idx.get(sz(ids[0])));
      EXPECT_NEAR(z.get(sz(id)), iso, tol);
      EXPECT_NEAR(pd.points[sz(id)].z, iso, tol);
    }
    if (ids.front() == ids.back()) {
      ++closed;
      continue;
    }
    for (Index end : {ids.front(), ids.back()}) {
      const Vec3 p = pd.points[sz(end)];
      const std::array<float, 3> key{static_cast<float>(p.x), static_cast<float>(p.y),
                                     static_cast<float>(p.z)};
      EXPECT_TRUE(border_points.count({static_cast<int>(idx.get(sz(end))), key})) << "line " << l;
      ++open_ends;
    }
  }
  EXPECT_GT(closed, 0u);
  // Every crossing on the border ends a polyline (the surface has no non-manifold edges).
  EXPECT_EQ(non_manifold, 0u);
  EXPECT_EQ(open_ends, border_crossings);
}

TEST(ContourPolyData, QuadAndStripIsolinesMatchTheirTriangles) {
  // A height field as quads, as triangles (each quad split) and as triangle strips (one per row):
  // closed loops on a below border; strips and triangles give the same points and segments.
  const Index n = 16;
  PolyData quads, tris, strips;
  Points pts(sz(n * n));
  std::vector<float> f(sz(n * n));
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(-1, 1);
  for (Index j = 0; j < n; ++j)
    for (Index i = 0; i < n; ++i) {
      pts.set(sz(i + n * j), {static_cast<double>(i), static_cast<double>(j),
                              0.1 * static_cast<double>(i * j % 3)});
      f[sz(i + n * j)] = (i == 0 || j == 0 || i == n - 1 || j == n - 1) ? -1.0f : u(rng);
    }
  for (PolyData* pd : {&quads, &tris, &strips}) {
    pd->points = pts;
    pd->point_data.add(DataArray::from_vector<float>("f", 1, f), AttributeRole::Scalars);
  }
  for (Index j = 0; j + 1 < n; ++j) {
    std::vector<Index> strip;
    for (Index i = 0; i + 1 < n; ++i) {
      const Index a = i + n * j, b = a + 1, c = a + 1 + n, d = a + n;
      quads.polys.add({a, b, c, d});
      tris.polys.add({a, b, c});
      tris.polys.add({a, c, d});
    }
    for (Index i = 0; i < n; ++i) {
      strip.push_back(i + n * (j + 1));
      strip.push_back(i + n * j);
    }
    strips.strips.add(strip);
  }
  ContourStats sq, st, ss;
  const PolyData lq = test::split_result(contour(quads, {}), sq), lt = test::split_result(contour(tris, {}), st),
                 ls = test::split_result(contour(strips, {}), ss);
  expect_closed_loops(lq, "quads");
  expect_closed_loops(lt, "triangles");
  expect_closed_loops(ls, "strips");
  EXPECT_GT(sq.ambiguous_faces, 0u);
  EXPECT_EQ(ss.points, st.points);
  EXPECT_EQ(ss.cells, st.cells);
  // Counter-clockwise around the above regions seen from +z (the polygons' normal): each loop
  // encloses positive area unless it is a hole of the above region; total positive.
  for (const PolyData* pd : {&lq, &lt, &ls}) {
    double total = 0;
    for (std::size_t l = 0; l < pd->lines.size(); ++l) total += signed_area(*pd, l);
    EXPECT_GT(total, 0);
  }
  // Strip triangles alternate, but are consistently oriented: same loops as the triangles.
  std::multiset<double> at, as;
  for (std::size_t l = 0; l < lt.lines.size(); ++l) at.insert(std::round(signed_area(lt, l) * 1e6));
  for (std::size_t l = 0; l < ls.lines.size(); ++l) as.insert(std::round(signed_area(ls, l) * 1e6));
  EXPECT_EQ(at, as);
}

TEST(ContourPolyData, LinesGiveOneVertexPerCrossedSegment) {
  PolyData hello = read_polydata("hello.vtk");
  ASSERT_EQ(hello.lines.size(), 15u);
  // s = x + 0.37 y crosses the vertical and the horizontal strokes.
  DataArray sv("s", ScalarType::Float64, 1, hello.points.size());
  for (std::size_t i = 0; i < hello.points.size(); ++i)
    sv.set(i, 0, hello.points[i].x + 0.37 * hello.points[i].y);
  hello.point_data.add(std::move(sv));
  DataArray seg("segment", ScalarType::Int32, 1, hello.lines.size());
  for (std::size_t c = 0; c < hello.lines.size(); ++c) seg.set(c, 0, static_cast<double>(c));
  hello.cell_data.add(std::move(seg));
  ContourOptions o;
  o.array = "s";
  for (int k = 1; k < 20; ++k) o.values.push_back(0.5 * k);
  ContourStats st;
  const PolyData pd = test::split_result(contour(hello, o), st);
  std::size_t crossed = 0;
  for (std::size_t c = 0; c < hello.lines.size(); ++c) {
    auto ids = hello.lines.cell(c);
    for (std::size_t k = 0; k + 1 < ids.size(); ++k)
      for (double v : o.values)
        crossed += (hello.point_data.get("s").get(sz(ids[k])) >= v) !=
                   (hello.point_data.get("s").get(sz(ids[k + 1])) >= v);
  }
  ASSERT_GT(crossed, 10u);
  EXPECT_EQ(pd.verts.size(), crossed);
  EXPECT_EQ(st.cells, crossed);
  EXPECT_TRUE(pd.lines.empty());
  const DataArray& idx = pd.point_data.get("IsovalueIndex");
  const DataArray& cell = pd.cell_data.get("segment");
  for (std::size_t c = 0; c < pd.verts.size(); ++c) {
    const Index p = pd.verts.cell(c)[0];
    const double v = o.values[sz(static_cast<Index>(idx.get(sz(p))))];
    // (within the 1/1024 clamp of segments along which s changes by at most 2)
    EXPECT_NEAR(pd.points[sz(p)].x + 0.37 * pd.points[sz(p)].y, v, 2.0 / 1024 + 1e-6);
    // The vertex lies on its source segment.
    auto ids = hello.lines.cell(sz(static_cast<Index>(cell.get(c))));
    const Vec3 a = hello.points[sz(ids.front())], b = hello.points[sz(ids.back())];
    EXPECT_NEAR(norm(cross(b - a, pd.points[sz(p)] - a)), 0.0, 1e-5);
  }
  // Vertices of polygonal data carry no isolines.
  PolyData verts;
  verts.points = hello.points;
  verts.point_data = hello.point_data;
  for (Index i = 0; i < 10; ++i) verts.verts.add({i});
  EXPECT_EQ(contour(verts, o).output.num_cells(), 0u);
}

TEST(ContourPolyData, FranTextureCoordinatesAreInterpolated) {
  PolyData fran = read_polydata("fran_cut.vtk");
  add_coordinate_array(fran, 1, "y");
  const DataArray* tc = fran.point_data.tcoords();
  ASSERT_NE(tc, nullptr);
  ASSERT_EQ(tc->components(), 2);
  ContourOptions o;
  o.array = "y";
  o.values = {-0.18, -0.15, -0.12, -0.09, -0.06};
  const PolyData pd = contour(fran, o).output;
  ASSERT_GT(pd.lines.size(), 0u);
  check_polylines(pd, "fran");
  const DataArray* out_tc = pd.point_data.tcoords();
  ASSERT_NE(out_tc, nullptr);
  EXPECT_EQ(out_tc->name(), tc->name());
  // Expected texture coordinates of every crossed edge's point, keyed by its exact position.
  const DataArray& y = fran.point_data.get("y");
  std::map<std::pair<int, std::array<float, 3>>, std::array<double, 2>> expected;
  for (std::size_t c = 0; c < fran.polys.size(); ++c) {
    auto ids = fran.polys.cell(c);
    for (std::size_t k = 0; k < ids.size(); ++k) {
      const Index a = std::min(ids[k], ids[(k + 1) % ids.size()]),
                  b = std::max(ids[k], ids[(k + 1) % ids.size()]);
      for (std::size_t v = 0; v < o.values.size(); ++v) {
        const double ya = y.get(sz(a)), yb = y.get(sz(b));
        if ((ya >= o.values[v]) == (yb >= o.values[v])) continue;
        const double t = contour_detail::crossing(ya, yb, o.values[v]);
        const Vec3 p = fran.points[sz(a)] + (fran.points[sz(b)] - fran.points[sz(a)]) * t;
        expected[{static_cast<int>(v),
                  {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)}}] = {
            (1 - t) * tc->get(sz(a), 0) + t * tc->get(sz(b), 0),
            (1 - t) * tc->get(sz(a), 1) + t * tc->get(sz(b), 1)};
      }
    }
  }
  EXPECT_EQ(expected.size(), pd.points.size());
  const DataArray& idx = pd.point_data.get("IsovalueIndex");
  for (std::size_t i = 0; i < pd.points.size(); ++i) {
    const Vec3 p = pd.points[i];
    auto it = expected.find(
        {static_cast<int>(idx.get(i)),
         {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)}});
    ASSERT_NE(it, expected.end()) << i;
    EXPECT_NEAR(out_tc->get(i, 0), it->second[0], 1e-6);
    EXPECT_NEAR(out_tc->get(i, 1), it->second[1], 1e-6);
  }
}

TEST(ContourPolyData, LongPolygonsPairTheirCrossingsByTheMeanValue) {
  // A hexagon with alternating corners above: six crossings, three segments cutting off the
  // below corners when the mean is at or above the isovalue, the above corners otherwise.
  for (const double above : {2.0, 0.5}) {
    PolyData hex;
    std::vector<double> f;
    for (int k = 0; k < 6; ++k) {
      const double a = std::numbers::pi / 3 * k;
      hex.points.push_back({std::cos(a), std::sin(a), 0});
      f.push_back(k % 2 ? -1.0 : above);
    }
    hex.polys.add({0, 1, 2, 3, 4, 5});
    hex.point_data.add(DataArray::from_vector<double>("f", 1, f), AttributeRole::Scalars);
    ContourStats st;
    const PolyData pd = test::split_result(contour(hex, {}), st);
    ASSERT_EQ(pd.lines.size(), 3u);
    ASSERT_EQ(pd.points.size(), 6u);
    EXPECT_EQ(st.cells, 3u);
    EXPECT_EQ(st.ambiguous_faces, 0u);  // only quads count as asymptotic-decider decisions
    const bool connected = (3 * above - 3) / 6 >= 0;
    for (std::size_t l = 0; l < 3; ++l) {
      auto ids = pd.lines.cell(l);
      ASSERT_EQ(ids.size(), 2u);
      const Vec3 a = pd.points[sz(ids[0])], b = pd.points[sz(ids[1])];
      // The corner cut off: the hexagon corner nearest the segment's midpoint.
      const Vec3 mid = (a + b) / 2.0;
      int corner = 0;
      for (int k = 1; k < 6; ++k) {
        const double ak = std::numbers::pi / 3 * k, a0 = std::numbers::pi / 3 * corner;
        if (norm(mid - Vec3{std::cos(ak), std::sin(ak), 0}) <
            norm(mid - Vec3{std::cos(a0), std::sin(a0), 0}))
          corner = k;
      }
      EXPECT_EQ(corner % 2 == 1, connected) << "above = " << above;
      // Above on the left, seen from +z (the hexagon's normal).
      const Vec3 c{std::cos(std::numbers::pi / 3 * corner), std::sin(std::numbers::pi / 3 * corner),
                   0};
      EXPECT_EQ(cross(b - a, c - a).z > 0, corner % 2 == 0);
    }
  }
}

TEST(ContourPolyData, JoiningIgnoresInconsistentOrientationAndStopsAtJunctions) {
  // A quad grid with every other quad reversed: the loops still join into closed polylines, each
  // running along the direction most of its segments have.
  const Index n = 12;
  PolyData pd;
  std::vector<double> f;
  for (Index j = 0; j < n; ++j)
    for (Index i = 0; i < n; ++i) {
      pd.points.push_back({static_cast<double>(i), static_cast<double>(j), 0});
      f.push_back(0.3 *
                  (4.0 - std::hypot(static_cast<double>(i) - 5.3, static_cast<double>(j) - 5.6)));
    }
  for (Index j = 0; j + 1 < n; ++j)
    for (Index i = 0; i + 1 < n; ++i) {
      const Index a = i + n * j;
      if ((i + j) % 2) {
        pd.polys.add({a, a + n, a + n + 1, a + 1});
      } else {
        pd.polys.add({a, a + 1, a + n + 1, a + n});
      }
    }
  pd.point_data.add(DataArray::from_vector<double>("f", 1, f), AttributeRole::Scalars);
  const PolyData out = contour(pd, {}).output;
  ASSERT_EQ(out.lines.size(), 1u);
  auto ids = out.lines.cell(0);
  EXPECT_EQ(ids.front(), ids.back());
  EXPECT_EQ(ids.size(), out.points.size() + 1);
  // Three triangles on one edge (a fin): the point on that edge ends three polylines.
  PolyData fin;
  fin.points.push_back({0, 0, 0});
  fin.points.push_back({0, 0, 1});
  fin.points.push_back({1, 0, 0.5});
  fin.points.push_back({-1, 0, 0.5});
  fin.points.push_back({0, 1, 0.5});
  fin.polys.add({0, 1, 2});
  fin.polys.add({1, 0, 3});
  fin.polys.add({0, 1, 4});
  fin.point_data.add(DataArray::from_vector<double>("z", 1, {0, 1, 0.7, 0.7, 0.7}),
                     AttributeRole::Scalars);
  ContourOptions o;
  o.values = {0.5};
  const PolyData cut = contour(fin, o).output;
  ASSERT_EQ(cut.lines.size(), 3u);
  ASSERT_EQ(cut.points.size(), 4u);
  std::map<Index, int> ends;
  for (std::size_t l = 0; l < 3; ++l) {
    ASSERT_EQ(cut.lines.cell_size(l), 2u);
    ++ends[cut.lines.cell(l)[0]];
    ++ends[cut.lines.cell(l)[1]];
  }
  int shared = 0;
  for (const auto& [p, k] : ends) shared += k == 3;
  EXPECT_EQ(shared, 1);
}

TEST(ContourPolyData, GradientNormalsLieInTheSurface) {
  // A tilted plane with f = x: the in-surface gradient, the plane's direction of steepest x.
  PolyData pd;
  const Index n = 9;
  for (Index j = 0; j < n; ++j)
    for (Index i = 0; i < n; ++i)
      pd.points.push_back({0.25 * static_cast<double>(i), 0.25 * static_cast<double>(j),
                           0.5 * 0.25 * static_cast<double>(i)});
  for (Index j = 0; j + 1 < n; ++j)
    for (Index i = 0; i + 1 < n; ++i) {
      const Index a = i + n * j;
      pd.polys.add({a, a + 1, a + n + 1});
      pd.polys.add({a, a + n + 1, a + n});
    }
  add_coordinate_array(pd, 0, "x");
  ContourOptions o;
  o.array = "x";
  o.values = {0.3, 1.1};
  o.normals = ContourNormals::Gradient;
  const PolyData out = contour(pd, o).output;
  ASSERT_EQ(out.lines.size(), 2u);
  const Vec3 expected = Vec3{1, 0, 0.5} / norm(Vec3{1, 0, 0.5});
  const DataArray* nrm = out.point_data.normals();
  ASSERT_NE(nrm, nullptr);
  for (std::size_t i = 0; i < out.points.size(); ++i) {
    EXPECT_NEAR(nrm->get(i, 0), expected.x, 1e-6);
    EXPECT_NEAR(nrm->get(i, 1), expected.y, 1e-6);
    EXPECT_NEAR(nrm->get(i, 2), expected.z, 1e-6);
  }
}

TEST(ContourLines, ProgressAndCancellation) {
  const Index n = 64;
  std::vector<float> v(sz(n * n));
  for (Index j = 0; j < n; ++j)
    for (Index i = 0; i < n; ++i)
      v[sz(i + n * j)] = static_cast<float>(std::sin(0.2 * static_cast<double>(i)) +
                                            std::cos(0.3 * static_cast<double>(j)));
  const ImageData img = image_of({n, n, 1}, v);
  ContourOptions o;
  o.values = {-0.5, 0.0, 0.5, 1.0};
  std::vector<double> seen;
  o.progress = [&](double f) {
    seen.push_back(f);
    return true;
  };
  (void)contour(img, o);
  // Every isovalue reports its passes and its end (0.25, 0.5, 0.75, 1), in order.
  ASSERT_GT(seen.size(), 4u);
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  for (double end : {0.25, 0.5, 0.75, 1.0}) {
    EXPECT_NE(std::find(seen.begin(), seen.end(), end), seen.end()) << end;
  }
  EXPECT_DOUBLE_EQ(seen.back(), 1.0);
  o.progress = [](double f) { return f < 0.5; };
  EXPECT_THROW((void)contour(img, o), Cancelled);
  PolyData torso = read_polydata("Torso.vtp");
  add_coordinate_array(torso, 2, "z");
  o.array = "z";
  EXPECT_THROW((void)contour(torso, o), Cancelled);
}
