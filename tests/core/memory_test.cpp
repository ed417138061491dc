#include "isoforge/core/memory.hpp"

#include <gtest/gtest.h>

#include <limits>

#include "isoforge/core/error.hpp"
#include "isoforge/implicit/parse.hpp"
#include "isoforge/implicit/sample.hpp"
#include "isoforge/implicit/sample_sparse.hpp"
#include "isoforge/model/attractor.hpp"
#include "isoforge/model/distance.hpp"
#include "isoforge/model/implicit_modeller.hpp"
#include "support/expect_error.hpp"

namespace isoforge {
using test::error_message;
namespace {

TEST(Memory, PhysicalMemoryIsKnownOnLinux) {
  // sysconf reports it on every Linux; a machine with less than 64 MB does not run these tests.
  EXPECT_GT(physical_memory(), std::uint64_t{64} << 20);
}

TEST(Memory, FormatsBytesInDecimalUnitsWithThreeDigits) {
  EXPECT_EQ(format_bytes(0), "0 B");
  EXPECT_EQ(format_bytes(512), "512 B");
  EXPECT_EQ(format_bytes(3200), "3.2 kB");
  EXPECT_EQ(format_bytes(999'999), "1 MB");  // rounds up a unit, never "1e+03 kB"
  EXPECT_EQ(format_bytes(3000.0 * 3000 * 3000 * 4), "108 GB");  // the 3000³ Float32 volume
  EXPECT_EQ(format_bytes(4e15), "4 PB");
}

TEST(Memory, FormatsDims) {
  EXPECT_EQ(format_dims({3000, 3000, 3000}), "3000³");
  EXPECT_EQ(format_dims({300, 200, 100}), "300 x 200 x 100");
}

TEST(Memory, RefusesWhatExceedsPhysicalMemoryNamingBothSizes) {
  const double have = static_cast<double>(physical_memory());
  EXPECT_NO_THROW(require_memory(1, "one byte"));
  EXPECT_NO_THROW(require_memory(have, "all of it"));
  const std::string m = error_message([&] { require_memory(2 * have, "sample: a big volume"); });
  EXPECT_EQ(m, "sample: a big volume needs " + format_bytes(2 * have) + "; this machine has " +
                   format_bytes(have));
  EXPECT_THROW(require_memory(std::numeric_limits<double>::quiet_NaN(), "x"), Error);
  EXPECT_THROW(require_memory(std::numeric_limits<double>::infinity(), "x"), Error);
}

TEST(Memory, RefusesAVolumeByItsDimsAndType) {
  EXPECT_EQ(error_message([] {
              require_volume_memory("sample", {100000, 100000, 100000}, "Float32", 4);
            }),
            "sample: a 100000³ Float32 volume needs 4 PB; this machine has " +
                format_bytes(static_cast<double>(physical_memory())));
  EXPECT_NO_THROW(require_volume_memory("sample", {64, 64, 64}, "Float32", 4));
}

// The library entry points that allocate dense volumes refuse before allocating: each of these
// requests would need petabytes (they ended in std::bad_alloc after growing to gigabytes).
TEST(Memory, DenseEntryPointsRefuseHugeVolumesAtOnce) {
  const Dims huge{100000, 100000, 100000};
  Bounds box;
  box.min = {-1, -1, -1};
  box.max = {1, 1, 1};
  const GridSpec g = GridSpec::from_bounds(box, huge);
  EXPECT_NE(error_message([&] {
              (void)sample_image(parse_implicit("sphere()"), g);
            }).find("sample: a 100000³ Float32 volume needs 4 PB"),
            std::string::npos);

  PolyData line;
  line.points.push_back({0, 0, 0});
  line.points.push_back({1, 0, 0});
  line.lines.add({0, 1});
  DistanceOptions d;
  d.max_distance = 0.1;
  EXPECT_NE(error_message([&] {
              (void)distance_image(line, g, d);
            }).find("distance: a 100000³ Float32 volume needs 4 PB"),
            std::string::npos);

  ImplicitModellerOptions m;
  m.sample_dimensions = huge;
  m.output_type = ScalarType::UInt8;  // a Float64 field and its UInt8 copy: 9 bytes a sample
  EXPECT_NE(error_message([&] {
              (void)implicit_modeller(line, m);
            }).find("implicit modeller: a 100000³ UInt8 volume needs 9 PB"),
            std::string::npos);

  TrajectoryOptions t;
  t.dims = huge;
  t.steps = 1;
  EXPECT_NE(error_message([&] {
              (void)lorenz_density({}, t);
            }).find("trajectory density: a 100000³ UInt32 volume needs 4 PB"),
            std::string::npos);
}

// A sparse narrow band scales with the surface's area: a sphere of radius 0.8 in a 100000³ grid
// of [-1, 1]³ has an area of about 4π (40000)² = 2e10 voxels², i.e. ~5e8 leaves of ~2 kB.
TEST(Memory, SparseSampleRefusesABandThatCannotFit) {
  Bounds box;
  box.min = {-1, -1, -1};
  box.max = {1, 1, 1};
  GridSpec g;
  g.origin = box.min;
  const double h = 2.0 / 99999;
  g.spacing = {h, h, h};
  g.dims = {100000, 100000, 100000};
  const std::string m =
      error_message([&] { (void)sample_level_set(parse_implicit("sphere(r=0.8)"), g); });
  EXPECT_NE(m.find("sparse sample: a narrow band (half width 3) of about"), std::string::npos) << m;
  EXPECT_NE(m.find("leaves (8³ voxels) in a 100000³ grid needs"), std::string::npos) << m;

  // A tiny sphere in the same grid has a small band: it is sampled.
  const auto [grid, stats] = sample_level_set(parse_implicit("sphere(r=0.0002)"), g);
  EXPECT_GT(stats.active_voxels, 0u);
  EXPECT_EQ(grid->activeVoxelCount(), stats.active_voxels);
}

}  // namespace
}  // namespace isoforge
