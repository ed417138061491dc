// Streamlines in analytic fields: straight lines in uniform flow, circles in rigid rotation at
// the integrators' orders, stagnation at a saddle, the same lines on every dataset type.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <numbers>

#include "isoforge/filters/streamline.hpp"
#include "isoforge/filters/probe.hpp"
#include "support/expect_error.hpp"

using namespace isoforge;
using isoforge::test::expect_error;

namespace {

// Image data of `dims` points spanning [lo, hi] with the vector field f as "V" (active
// vectors) and the scalar x + 2y as "s".
template <class F>
ImageData field_image(Dims dims, Vec3 lo, Vec3 hi, F f) {
  ImageData img;
  img.dims = dims;
  img.origin = lo;
  for (int a = 0; a < 3; ++a) {
    img.spacing[a] = dims[a] > 1 ? (hi[a] - lo[a]) / double(dims[a] - 1) : 1.0;
  }
  const std::size_t n = img.num_points();
  DataArray v("V", ScalarType::Float64, 3, n), s("s", ScalarType::Float32, 1, n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 p = img.point(Index(i));
    const Vec3 u = f(p);
    for (int c = 0; c < 3; ++c) v.set(i, c, u[c]);
    s.set(i, 0, p.x + 2 * p.y);
  }
  img.point_data.add(std::move(v), AttributeRole::Vectors);
  img.point_data.add(std::move(s), AttributeRole::Scalars);
  return img;
}

Vec3 rotation(const Vec3& p) { return {-p.y, p.x, 0}; }

PolyData seed_points(std::initializer_list<Vec3> points) {
  PolyData s;
  for (const Vec3& p : points) s.points.push_back(p);
  return s;
}

std::span<const Index> line_ids(const PolyData& out, std::size_t l) { return out.lines.cell(l); }

Vec3 at(const PolyData& out, Index id) { return out.points[std::size_t(id)]; }

// Error at the end of one revolution-long line from (0.5, 0, 0) in rigid rotation: the distance
// from its last point to the exact solution at that point's integration time.
double rotation_error(StreamIntegrator integrator, double step) {
  const ImageData img = field_image({21, 21, 3}, {-1, -1, -0.1}, {1, 1, 0.1}, rotation);
  StreamlineOptions o;
  o.integrator = integrator;
  o.direction = StreamDirection::Forward;
  o.step = step;
  o.max_length = 2 * std::numbers::pi * 0.5;
  o.max_steps = 100000;
  o.vorticity = false;
  const auto [out, stats] = streamlines(img, seed_points({{0.5, 0, 0}}), o);
  EXPECT_EQ(stats.lines, 1u);
  const auto ids = line_ids(out, 0);
  const Index last = ids.back();
  const double t = out.point_data.get("IntegrationTime").get(std::size_t(last));
  const Vec3 exact{0.5 * std::cos(t), 0.5 * std::sin(t), 0};
  EXPECT_GT(t, 6.0);  // about 2π
  return norm(at(out, last) - exact);
}

// The voxels split into six tetrahedra each around their main diagonal (a conforming mesh).
UnstructuredGrid split_into_tetrahedra(const UnstructuredGrid& voxels) {
  UnstructuredGrid tets;
  tets.points = voxels.points;
  tets.point_data = voxels.point_data;
  for (std::size_t c = 0; c < voxels.cells.size(); ++c) {
    const auto v = voxels.cells.cell(c);  // voxel order: corner (a, b, c) at a + 2b + 4c
    static constexpr int kPaths[6][2] = {{1, 2}, {1, 4}, {2, 1}, {2, 4}, {4, 1}, {4, 2}};
    for (const auto& p : kPaths) {
      tets.add_cell(CellType::Tetra, {v[0], v[std::size_t(p[0])],
                                      v[std::size_t(p[0] | p[1])], v[7]});
    }
  }
  return tets;
}
}  // namespace

TEST(Streamlines, UniformFlowGivesStraightLinesToTheBoundary) {
  const ImageData img = field_image({11, 11, 11}, {0, 0, 0}, {1, 1, 1},
                                    [](const Vec3&) { return Vec3{1, 0, 0}; });
  StreamlineOptions o;
  o.integrator = StreamIntegrator::RK4;
  const auto [out, stats] = streamlines(img, seed_points({{0.35, 0.5, 0.25}}), o);
  ASSERT_EQ(stats.lines, 2u);  // forward, then backward
  EXPECT_EQ(stats.by_reason[size_t(StreamTermination::OutOfDomain)], 2u);
  EXPECT_NEAR(stats.cell_length, std::sqrt(3.0) / 10, 1e-12);
  const DataArray& reason = out.cell_data.get("ReasonForTermination");
  const DataArray& seed = out.cell_data.get("SeedIds");
  for (std::size_t l = 0; l < 2; ++l) {
    EXPECT_EQ(reason.get(l), double(StreamTermination::OutOfDomain));
    EXPECT_EQ(seed.get(l), 0.0);
    const auto ids = line_ids(out, l);
    EXPECT_EQ(at(out, ids.front()).x, 0.35f);
    for (const Index id : ids) {
      EXPECT_NEAR(at(out, id).y, 0.5, 1e-6);
      EXPECT_NEAR(at(out, id).z, 0.25, 1e-6);
    }
    // The steps are halved near the boundary: the line ends within step/1024 of it.
    const double end = at(out, ids.back()).x;
    EXPECT_NEAR(end, l == 0 ? 1.0 : 0.0, 2 * 0.2 * stats.cell_length / 1024 + 1e-6);
    // Time and arc length: speed 1, so |time| = arc length = distance from the seed.
    const double arc = out.point_data.get("ArcLength").get(std::size_t(ids.back()));
    const double time = out.point_data.get("IntegrationTime").get(std::size_t(ids.back()));
    EXPECT_NEAR(arc, std::abs(end - 0.35), 1e-6);
    EXPECT_NEAR(time, l == 0 ? arc : -arc, 1e-9);
  }
  // The scalar x + 2y interpolated exactly (trilinear interpolation of a linear field).
  const DataArray& s = out.point_data.get("s");
  for (std::size_t i = 0; i < out.points.size(); ++i) {
    const Vec3 p = out.points[i];
    EXPECT_NEAR(s.get(i), p.x + 2 * p.y, 1e-5);
  }
}

TEST(Streamlines, RotationClosesAtEachIntegratorsOrder) {
  // Global error ~ step^order: halving the step divides it by about 2^order.
  const double e2a = rotation_error(StreamIntegrator::RK2, 0.4);
  const double e2b = rotation_error(StreamIntegrator::RK2, 0.2);
  EXPECT_GT(e2a / e2b, 3.0);
  EXPECT_LT(e2a / e2b, 5.5);
  const double e4a = rotation_error(StreamIntegrator::RK4, 0.8);
  const double e4b = rotation_error(StreamIntegrator::RK4, 0.4);
  EXPECT_GT(e4a / e4b, 11.0);
  EXPECT_LT(e4a / e4b, 22.0);
  EXPECT_LT(e4b, e2b / 20);  // RK4 with twice RK2's step
}

TEST(Streamlines, Rk45KeepsItsErrorBelowTheTolerance) {
  const ImageData img = field_image({21, 21, 3}, {-1, -1, -0.1}, {1, 1, 0.1}, rotation);
  for (const double tol : {1e-5, 1e-8}) {
    StreamlineOptions o;
    o.direction = StreamDirection::Forward;
    o.max_error = tol;
    o.max_step = 2;
    o.max_length = 2 * std::numbers::pi * 0.5;
    o.vorticity = false;
    const auto [out, stats] = streamlines(img, seed_points({{0.5, 0, 0}}), o);
    ASSERT_EQ(stats.lines, 1u);
    const auto ids = line_ids(out, 0);
    const DataArray& time = out.point_data.get("IntegrationTime");
    double worst = 0;
    for (const Index id : ids) {
      const double t = time.get(std::size_t(id));
      worst = std::max(worst, norm(at(out, id) - Vec3{0.5 * std::cos(t), 0.5 * std::sin(t), 0}));
    }
    // Local errors below tol (cell lengths), summed over the steps taken.
    EXPECT_LT(worst, tol * stats.cell_length * double(stats.steps) + 1e-7) << tol;
    EXPECT_EQ(stats.by_reason[size_t(StreamTermination::OutOfLength)], 1u);
  }
}

TEST(Streamlines, StopsAtStagnation) {
  const ImageData img = field_image({21, 21, 3}, {-1, -1, -0.1}, {1, 1, 0.1},
                                    [](const Vec3& p) { return Vec3{p.x, -p.y, 0}; });
  // A seed on the saddle point: zero speed, no line.
  StreamlineOptions o;
  {
    const auto [out, stats] = streamlines(img, seed_points({{0, 0, 0}}), o);
    EXPECT_EQ(stats.lines, 0u);
    EXPECT_EQ(stats.by_reason[size_t(StreamTermination::Stagnation)], 2u);
  }
  // Flowing into the saddle along y: stops where the speed falls to the threshold.
  o.direction = StreamDirection::Forward;
  o.terminal_speed = 0.1;
  o.integrator = StreamIntegrator::RK4;
  o.step = 0.1;
  const auto [out, stats] = streamlines(img, seed_points({{0, 0.8, 0}}), o);
  ASSERT_EQ(stats.lines, 1u);
  EXPECT_EQ(out.cell_data.get("ReasonForTermination").get(0),
            double(StreamTermination::Stagnation));
  const Vec3 end = at(out, line_ids(out, 0).back());
  EXPECT_LE(end.y, 0.1);
  EXPECT_GT(end.y, 0.1 - 0.1 * stats.cell_length - 1e-9);
  EXPECT_NEAR(end.x, 0, 1e-9);
}

TEST(Streamlines, MaxStepsAndSeedsOutside) {
  const ImageData img = field_image({11, 11, 11}, {0, 0, 0}, {1, 1, 1},
                                    [](const Vec3&) { return Vec3{0, 0, 1}; });
  StreamlineOptions o;
  o.max_steps = 3;
  o.direction = StreamDirection::Forward;
  o.integrator = StreamIntegrator::RK2;
  const auto [out, stats] =
      streamlines(img, seed_points({{2, 0, 0}, {0.5, 0.5, 0.1}, {0.5, 0.5, -1e-3}}), o);
  EXPECT_EQ(stats.seeds, 3u);
  EXPECT_EQ(stats.seeds_outside, 2u);
  ASSERT_EQ(stats.lines, 1u);
  EXPECT_EQ(line_ids(out, 0).size(), 4u);
  EXPECT_EQ(out.cell_data.get("SeedIds").get(0), 1.0);
  EXPECT_EQ(out.cell_data.get("ReasonForTermination").get(0),
            double(StreamTermination::OutOfSteps));
}

TEST(Streamlines, VorticityOfAHelicalFlow) {
  // v = (−y, x, 1): curl (0, 0, 2) everywhere; angular velocity ½ ω·v/|v| = 1/|v|.
  const ImageData img = field_image({9, 9, 9}, {-1, -1, -1}, {1, 1, 1}, [](const Vec3& p) {
    return Vec3{-p.y, p.x, 1};
  });
  StreamlineOptions o;
  o.max_length = 1;
  const auto [out, stats] = streamlines(img, seed_points({{0.3, 0.2, 0}}), o);
  ASSERT_EQ(stats.lines, 2u);
  const DataArray& w = out.point_data.get("Vorticity");
  const DataArray& a = out.point_data.get("AngularVelocity");
  const DataArray& v = out.point_data.get("V");
  for (std::size_t i = 0; i < out.points.size(); ++i) {
    EXPECT_NEAR(w.get(i, 0), 0, 1e-5);
    EXPECT_NEAR(w.get(i, 1), 0, 1e-5);
    EXPECT_NEAR(w.get(i, 2), 2, 1e-5);
    const Vec3 vi{v.get(i, 0), v.get(i, 1), v.get(i, 2)};
    EXPECT_NEAR(a.get(i), 1 / norm(vi), 1e-5);
  }
  // |v| is constant along a helix about the z axis: the rotation grows as time / |v|; the
  // normals are unit, perpendicular to the flow, and active (ribbons use them).
  const DataArray& rotation = out.point_data.get("Rotation");
  const DataArray& time = out.point_data.get("IntegrationTime");
  const DataArray& normals = *out.point_data.normals();
  EXPECT_EQ(normals.name(), "Normals");
  for (std::size_t i = 0; i < out.points.size(); ++i) {
    const Vec3 vi{v.get(i, 0), v.get(i, 1), v.get(i, 2)};
    EXPECT_NEAR(rotation.get(i), time.get(i) / norm(vi), 1e-4);
    const Vec3 ni{normals.get(i, 0), normals.get(i, 1), normals.get(i, 2)};
    EXPECT_NEAR(norm(ni), 1, 1e-5);
    EXPECT_NEAR(dot(ni, vi) / norm(vi), 0, 1e-5);
  }
}

TEST(Streamlines, SameLinesOnEveryDatasetType) {
  const ImageData img = field_image({9, 9, 5}, {-1, -1, -0.5}, {1, 1, 0.5}, [](const Vec3& p) {
    return Vec3{-p.y, p.x, 0.2};
  });
  StructuredGrid grid;
  grid.dims = img.dims;
  for (std::size_t i = 0; i < img.num_points(); ++i) grid.points.push_back(img.point(Index(i)));
  grid.point_data = img.point_data;
  const UnstructuredGrid voxels = to_unstructured(img);
  const UnstructuredGrid tets = split_into_tetrahedra(voxels);
  const PolyData seeds = seed_points({{0.4, 0.1, -0.3}, {-0.2, -0.5, 0.1}});
  StreamlineOptions o;
  o.integrator = StreamIntegrator::RK4;
  o.max_length = 3;
  const auto reference = streamlines(img, seeds, o);
  ASSERT_EQ(reference.stats.lines, 4u);
  for (const Dataset& ds : {Dataset(grid), Dataset(voxels), Dataset(tets)}) {
    // Steps are in mean cell lengths: the tetrahedra are 6 times as many, so the same world step
    // is cbrt(6) of theirs.
    StreamlineOptions so = o;
    if (num_cells(ds) == 6 * num_cells(img)) so.step *= std::cbrt(6.0);
    const auto r = streamlines(ds, seeds, so);
    ASSERT_EQ(r.stats.lines, 4u) << dataset_type_name(ds);
    ASSERT_EQ(r.output.points.size(), reference.output.points.size()) << dataset_type_name(ds);
    for (std::size_t i = 0; i < r.output.points.size(); ++i) {
      EXPECT_LT(norm(r.output.points[i] - reference.output.points[i]), 1e-5);
    }
    const DataArray& w = r.output.point_data.get("Vorticity");
    for (std::size_t i = 0; i < r.output.points.size(); ++i) EXPECT_NEAR(w.get(i, 2), 2, 1e-4);
  }
}

TEST(Streamlines, TetrahedraAroundANotchAndThroughInvalidFaces) {
  // An L-shaped domain (one quadrant of the box cut out): lines around the z axis leave it
  // through the notch's faces, inside the domain's bounds, where the tetrahedra's walk hands over
  // to the exact locator. The voxels (the generic cell path) and their tetrahedra give the same
  // lines; every tetrahedron twice (each face then has two or four cells, the walk scans for
  // neighbours) changes nothing.
  const ImageData img = field_image({9, 9, 5}, {-1, -1, -0.5}, {1, 1, 0.5}, [](const Vec3& p) {
    return Vec3{-p.y, p.x, 0.2};
  });
  const UnstructuredGrid all = to_unstructured(img);
  UnstructuredGrid voxels;
  voxels.points = all.points;
  voxels.point_data = all.point_data;
  for (std::size_t c = 0; c < all.cells.size(); ++c) {
    const auto v = all.cells.cell(c);
    const Vec3 centre = (all.points[std::size_t(v[0])] + all.points[std::size_t(v[7])]) * 0.5;
    if (centre.x > 0 && centre.y > 0) continue;  // the notch
    voxels.add_cell(CellType::Voxel, std::vector<Index>(v.begin(), v.end()));
  }
  const UnstructuredGrid tets = split_into_tetrahedra(voxels);
  UnstructuredGrid doubled = tets;  // every tetrahedron twice: no face has one neighbour
  for (std::size_t c = 0; c < tets.cells.size(); ++c) {
    const auto v = tets.cells.cell(c);
    doubled.add_cell(CellType::Tetra, std::vector<Index>(v.begin(), v.end()));
  }
  const PolyData seeds = seed_points({{0.4, -0.3, -0.3}, {-0.5, -0.2, 0.1}, {-0.3, 0.6, 0.2}});
  StreamlineOptions o;
  o.integrator = StreamIntegrator::RK4;
  o.max_length = 6;
  const auto reference = streamlines(voxels, seeds, o);
  ASSERT_EQ(reference.stats.lines, 6u);
  std::size_t at_notch = 0;  // line ends on the notch's faces x = 0 or y = 0
  const DataArray& reasons = reference.output.cell_data.get("ReasonForTermination");
  for (std::size_t l = 0; l < reference.output.lines.size(); ++l) {
    const Vec3 end = at(reference.output, line_ids(reference.output, l).back());
    if (reasons.get(l) == double(StreamTermination::OutOfDomain) && end.x > -1e-3 &&
        end.y > -1e-3) {
      ++at_notch;
    }
  }
  EXPECT_GE(at_notch, 2u);
  for (const UnstructuredGrid* mesh : {&tets, static_cast<const UnstructuredGrid*>(&doubled)}) {
    // Steps are in mean cell lengths (the bounds' diagonal / ∛cells): the same world step.
    StreamlineOptions so = o;
    so.step *= std::cbrt(double(mesh->cells.size()) / double(voxels.cells.size()));
    const auto r = streamlines(*mesh, seeds, so);
    ASSERT_EQ(r.stats.lines, 6u);
    ASSERT_EQ(r.output.points.size(), reference.output.points.size());
    for (std::size_t i = 0; i < r.output.points.size(); ++i) {
      EXPECT_LT(norm(r.output.points[i] - reference.output.points[i]), 1e-5);
    }
    EXPECT_TRUE(r.output.cell_data.get("ReasonForTermination") == reasons);
    const DataArray& w = r.output.point_data.get("Vorticity");
    for (std::size_t i = 0; i < r.output.points.size(); ++i) EXPECT_NEAR(w.get(i, 2), 2, 1e-4);
  }
}

TEST(Streamlines, FlatImageData) {
  const ImageData img = field_image({21, 21, 1}, {-1, -1, 0}, {1, 1, 0}, rotation);
  StreamlineOptions o;
  o.direction = StreamDirection::Forward;
  o.max_length = 2;
  const auto [out, stats] = streamlines(img, seed_points({{0.5, 0, 0}, {0.5, 0, 0.1}}), o);
  EXPECT_EQ(stats.seeds_outside, 1u);  // off the image's plane
  ASSERT_EQ(stats.lines, 1u);
  for (std::size_t i = 0; i < out.points.size(); ++i) {
    EXPECT_NEAR(norm(out.points[i]), 0.5, 1e-5);
  }
}

TEST(Streamlines, SameOutputForAnyThreadCount) {
  const ImageData img = field_image({17, 17, 17}, {-1, -1, -1}, {1, 1, 1}, [](const Vec3& p) {
    return Vec3{-p.y + 0.3 * p.z, p.x, 0.5 - p.z * p.z};
  });
  PolyData seeds = probe_line({-0.8, -0.7, -0.6}, {0.7, 0.8, 0.6}, 200);
  StreamlineOptions o;
  o.max_steps = 300;
  const auto many = streamlines(img, seeds, o);
  StreamlineResult one;
  {
    tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    one = streamlines(img, seeds, o);
  }
  EXPECT_EQ(many.output, one.output);
  EXPECT_EQ(many.stats.steps, one.stats.steps);
}

TEST(Streamlines, RejectsBadOptionsAndInputs) {
  const ImageData img = field_image({5, 5, 5}, {0, 0, 0}, {1, 1, 1},
                                    [](const Vec3&) { return Vec3{1, 0, 0}; });
  const PolyData seeds = seed_points({{0.5, 0.5, 0.5}});
  auto with = [](auto set) {
    StreamlineOptions o;
    set(o);
    return o;
  };
  expect_error([&] { (void)streamlines(img, seeds, with([](auto& o) { o.step = 0; })); },
               "step must be positive");
  expect_error([&] { (void)streamlines(img, seeds, with([](auto& o) { o.step = NAN; })); },
               "step must be positive");
  expect_error([&] { (void)streamlines(img, seeds, with([](auto& o) { o.min_step = 2; })); },
               "min_step 2 exceeds max_step 1");
  expect_error([&] { (void)streamlines(img, seeds, with([](auto& o) { o.max_steps = 0; })); },
               "max_steps");
  expect_error([&] { (void)streamlines(img, seeds, with([](auto& o) { o.max_length = -1; })); },
               "max_length");
  expect_error(
      [&] { (void)streamlines(img, seeds, with([](auto& o) { o.terminal_speed = -1; })); },
      "terminal_speed");
  expect_error([&] { (void)streamlines(img, seeds, with([](auto& o) { o.vectors = "W"; })); },
               "no point array 'W'");
  expect_error([&] { (void)streamlines(img, seeds, with([](auto& o) { o.vectors = "s"; })); },
               "has 1 component");
  expect_error([&] { (void)streamlines(img, seed_points({{NAN, 0, 0}}), {}); },
               "seed 0 is not a finite point");
  UnstructuredGrid no_cells;
  no_cells.points.push_back({0, 0, 0});
  no_cells.point_data.add(DataArray("V", ScalarType::Float32, 3, 1), AttributeRole::Vectors);
  expect_error([&] { (void)streamlines(no_cells, seeds, {}); }, "the input has no cells");
  ImageData one_point = img;  // a single vertex cell: no length
  one_point.dims = {1, 1, 1};
  one_point.point_data.clear();
  one_point.point_data.add(DataArray("V", ScalarType::Float32, 3, 1), AttributeRole::Vectors);
  expect_error([&] { (void)streamlines(one_point, seeds, {}); }, "span no length");
}
