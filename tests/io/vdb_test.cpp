// Tests of OpenVDB io (io/vdb.hpp): round trips, pruning, inspection, errors, robustness
// against truncated and corrupted files, atomic writing.

#include "isoforge/io/vdb.hpp"

#include <gtest/gtest.h>
#include <openvdb/io/Stream.h>
#include <openvdb/tools/LevelSetSphere.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "isoforge/io/io.hpp"
#include "isoforge/sparse/convert.hpp"
#include "isoforge/sparse/grid.hpp"
#include "support/scratch.hpp"
#include "support/expect_error.hpp"
#include "support/sample_datasets.hpp"

using namespace isoforge;
namespace fs = std::filesystem;

namespace {

fs::path tmp_dir() {
  const fs::path dir = fs::path(ISOFORGE_TEST_TMP) / "vdb" / isoforge::test::current_test_id();
  fs::create_directories(dir);
  return dir;
}

std::vector<char> file_bytes(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

void write_bytes(const fs::path& p, const char* data, std::size_t n) {
  std::ofstream f(p, std::ios::binary | std::ios::trunc);
  f.write(data, static_cast<std::streamsize>(n));
}

std::span<const std::byte> as_span(const std::vector<char>& b) {
  return std::as_bytes(std::span(b.data(), b.size()));
}

using isoforge::test::expect_error;

// image_to_vdb with the options given in order.
openvdb::FloatGrid::Ptr to_vdb(const ImageData& img, std::string array = {}, float background = 0.0f,
                               float tolerance = 0.0f) {
  return image_to_vdb(img, {std::move(array), background, tolerance});
}

// Three grids: a level set sphere, a vec3s grid, the sphere image as a float grid.
fs::path write_three_grids(const std::string& file) {
  ensure_openvdb_initialized();
  auto ls =
      openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(5.0f, openvdb::Vec3f(1, 2, 3), 0.5f);
  ls->setName("ls");
  auto vel = openvdb::Vec3SGrid::create();
  vel->setName("vel");
  vel->tree().setValue(openvdb::Coord(1, 2, 3), openvdb::Vec3s(1, 2, 3));
  vel->tree().setValue(openvdb::Coord(-4, 0, 7), openvdb::Vec3s(0, 0, 1));
  auto dist = to_vdb(test::sphere_distance_image(), "distance", 0.0f, 0.5f);
  const fs::path p = tmp_dir() / file;
  write_vdb({ls, vel, dist}, p);
  return p;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Round trips and conversion
// ---------------------------------------------------------------------------------------------

TEST(Vdb, RoundTripImageToFileToImageIsExact) {
  const ImageData img = test::sphere_distance_image();
  // A background no sample equals: every voxel is active, the bbox is the whole image.
  auto grid = to_vdb(img, {}, -1000.0f, 0.0f);
  EXPECT_EQ(grid->getName(), "distance");
  EXPECT_EQ(grid->getGridClass(), openvdb::GRID_UNKNOWN);
  EXPECT_EQ(grid->activeVoxelCount(), img.num_points());
  const fs::path p = tmp_dir() / "roundtrip.vdb";
  write_vdb(*grid, p);
  const auto back_grid = read_vdb_grid(p);
  ASSERT_TRUE(back_grid);
  EXPECT_EQ(back_grid->getName(), "distance");
  const ImageData back = vdb_to_image(*back_grid);
  EXPECT_EQ(back.dims, img.dims);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(back.origin[a], img.origin[a], 1e-12);
    EXPECT_NEAR(back.spacing[a], img.spacing[a], 1e-12);
  }
  ASSERT_NE(back.point_data.scalars(), nullptr);
  EXPECT_EQ(back.point_data.scalars()->name(), "distance");
  EXPECT_EQ(back.point_data.get("distance"), img.point_data.get("distance"));
}

TEST(Vdb, FileFormatPlumbingThroughIoReadWrite) {
  const ImageData img = test::sphere_distance_image("density");
  const fs::path p = tmp_dir() / "plumbing.vdb";
  WriteOptions wo;
  wo.vdb_tolerance = 0.0;
  ImageData shifted = img;
  // Make every value non-zero so that the whole image stays active.
  for (float& x : shifted.point_data.get("density").values<float>()) x += 100;
  write(Dataset(shifted), p, wo);
  const Dataset ds = read(p);
  const ImageData* back = std::get_if<ImageData>(&ds);
  ASSERT_NE(back, nullptr);
  EXPECT_EQ(back->dims, img.dims);
  EXPECT_EQ(back->point_data.get("density"), shifted.point_data.get("density"));
}

// ---------------------------------------------------------------------------------------------
// Reading and inspecting
// ---------------------------------------------------------------------------------------------

TEST(Vdb, InspectListsNamesTypesClassesAndCounts) {
  const fs::path p = write_three_grids("three.vdb");
  const auto infos = inspect_vdb(p);
  ASSERT_EQ(infos.size(), 3u);
  EXPECT_EQ(infos[0].name, "ls");
  EXPECT_EQ(infos[0].type, "float");
  EXPECT_EQ(infos[0].grid_class, "level set");
  EXPECT_DOUBLE_EQ(infos[0].voxel_size, 0.5);
  EXPECT_EQ(infos[1].name, "vel");
  EXPECT_EQ(infos[1].type, "vec3s");
  EXPECT_EQ(infos[1].grid_class, "unknown");
  EXPECT_EQ(infos[1].active_voxels, 2u);
  EXPECT_EQ(infos[1].active_bbox,
            openvdb::CoordBBox(openvdb::Coord(-4, 0, 3), openvdb::Coord(1, 2, 7)));
  EXPECT_EQ(infos[2].name, "distance");
  EXPECT_DOUBLE_EQ(infos[2].voxel_size, 0.2);
  // Counts and boxes agree with the grids themselves.
  const auto ls = read_vdb_grid(p, "ls");
  EXPECT_EQ(infos[0].active_voxels, ls->activeVoxelCount());
  EXPECT_EQ(infos[0].active_bbox, ls->evalActiveVoxelBoundingBox());
  const auto dist = read_vdb_grid(p, "distance");
  EXPECT_EQ(infos[2].active_voxels, dist->activeVoxelCount());
  EXPECT_EQ(infos[2].active_bbox, dist->evalActiveVoxelBoundingBox());
}

TEST(Vdb, InspectComputesStatisticsWhenTheFileHasNone) {
  ensure_openvdb_initialized();
  auto g = openvdb::FloatGrid::create(0.0f);
  g->setName("nostats");
  g->tree().setValue(openvdb::Coord(5, 6, 7), 1.0f);
  g->tree().setValue(openvdb::Coord(9, 6, 7), 1.0f);
  const fs::path p = tmp_dir() / "nostats.vdb";
  openvdb::io::File f(p.string());
  f.setGridStatsMetadataEnabled(false);
  f.write({g});
  f.close();
  const auto infos = inspect_vdb(p);
  ASSERT_EQ(infos.size(), 1u);
  EXPECT_EQ(infos[0].active_voxels, 2u);
  EXPECT_EQ(infos[0].active_bbox,
            openvdb::CoordBBox(openvdb::Coord(5, 6, 7), openvdb::Coord(9, 6, 7)));
}

TEST(Vdb, ReadsFirstFloatGridOrByName) {
  const fs::path p = write_three_grids("three_by_name.vdb");
  EXPECT_EQ(read_vdb_grid(p)->getName(), "ls");
  EXPECT_EQ(read_vdb_grid(p, "distance")->getName(), "distance");
  EXPECT_EQ(read_vdb_grid(p, "ls")->getGridClass(), openvdb::GRID_LEVEL_SET);
}

TEST(Vdb, ReadsEveryCompressionHalfFloatAndStreams) {
  ensure_openvdb_initialized();
  auto ls =
      openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(4.0f, openvdb::Vec3f(0, 0, 0), 0.5f);
  ls->setName("s");
  using namespace openvdb::io;
  for (std::uint32_t comp :
       {std::uint32_t(COMPRESS_NONE), std::uint32_t(COMPRESS_ZIP),
        std::uint32_t(COMPRESS_ACTIVE_MASK), std::uint32_t(COMPRESS_ZIP | COMPRESS_ACTIVE_MASK),
        std::uint32_t(COMPRESS_BLOSC | COMPRESS_ACTIVE_MASK)}) {
    for (bool half : {false, true}) {
      for (bool stream : {false, true}) {
        SCOPED_TRACE("compression " + std::to_string(comp) + (half ? " half" : "") +
                     (stream ? " stream" : " file"));
        auto g = ls->deepCopy();
        g->setSaveFloatAsHalf(half);
        std::vector<char> bytes;
        if (stream) {
          std::ostringstream os;
          Stream s(os);
          s.setCompression(comp);
          s.write({g});
          const std::string str = os.str();
          bytes.assign(str.begin(), str.end());
        } else {
          const fs::path p = tmp_dir() / "comp.vdb";
          File f(p.string());
          f.setCompression(comp);
          f.write({g});
          f.close();
          bytes = file_bytes(p);
        }
        const auto r = read_vdb_grid(as_span(bytes), "mem.vdb");
        ASSERT_TRUE(r);
        EXPECT_EQ(r->activeVoxelCount(), ls->activeVoxelCount());
        // Values survive (half floats to half precision).
        const double tol = half ? 2e-3 : 0.0;
        auto acc = r->getConstAccessor();
        for (auto it = ls->cbeginValueOn(); it; ++it) {
          ASSERT_NEAR(acc.getValue(it.getCoord()), *it, tol);
        }
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Errors
// ---------------------------------------------------------------------------------------------

TEST(VdbErrors, MissingAndNonVdbFiles) {
  const fs::path missing = tmp_dir() / "does_not_exist.vdb";
  expect_error([&] { (void)read_vdb_grid(missing); }, "does_not_exist.vdb: file does not exist");
  expect_error([&] { (void)inspect_vdb(missing); }, "does not exist");
  const fs::path text = tmp_dir() / "text.vdb";
  const std::string s = "this is not a VDB file, just some text that is long enough\n";
  write_bytes(text, s.data(), s.size());
  expect_error([&] { (void)read_vdb_grid(text); }, "text.vdb: byte 0: not a VDB file");
  expect_error([&] { (void)inspect_vdb(text); }, "not a VDB file");
  const fs::path empty = tmp_dir() / "empty.vdb";
  write_bytes(empty, "", 0);
  expect_error([&] { (void)read_vdb_grid(empty); }, "empty.vdb: not a VDB file");
  expect_error([&] { (void)read_vdb_grid(tmp_dir()); }, "is a directory");
}

TEST(VdbErrors, GridSelection) {
  const fs::path p = write_three_grids("three_errors.vdb");
  expect_error([&] { (void)read_vdb_grid(p, "nope"); },
               "no float grid named 'nope' (grids: 'ls' (float), 'vel' (vec3s), 'distance' "
               "(float))");
  expect_error([&] { (void)read_vdb_grid(p, "vel"); },
               "grid 'vel' is a vec3s grid, not a float grid");
  // A file with no float grid at all.
  auto vel = openvdb::Vec3SGrid::create();
  vel->setName("v");
  const fs::path q = tmp_dir() / "vec_only.vdb";
  write_vdb({vel}, q);
  expect_error([&] { (void)read_vdb_grid(q); }, "holds no float grid (grids: 'v' (vec3s))");
}

TEST(VdbErrors, TruncatedFilesAtEveryOffsetGiveErrors) {
  const fs::path p = write_three_grids("three_trunc.vdb");
  const std::vector<char> bytes = file_bytes(p);
  ASSERT_GT(bytes.size(), 1000u);
  // In memory: every truncation.
  std::size_t errors = 0;
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    try {
      (void)read_vdb_grid(std::as_bytes(std::span(bytes.data(), n)), "t.vdb", "distance");
      ADD_FAILURE() << "truncation at " << n << " was accepted";
    } catch (const Error& e) {
      ++errors;
      const std::string m = e.what();
      if (n >= 8) {
        EXPECT_NE(m.find("truncated"), std::string::npos) << n << ": " << m;
      }
    }
  }
  EXPECT_EQ(errors, bytes.size());
  // On disk: a spread of truncations through read_vdb_grid and inspect_vdb.
  const fs::path t = tmp_dir() / "truncated.vdb";
  for (std::size_t n : {std::size_t{3}, std::size_t{8}, std::size_t{20}, std::size_t{100},
                        bytes.size() / 3, bytes.size() / 2, bytes.size() - 100, bytes.size() - 1}) {
    write_bytes(t, bytes.data(), n);
    expect_error([&] { (void)read_vdb_grid(t); }, "truncated.vdb");
    expect_error([&] { (void)inspect_vdb(t); }, n < 8 ? "not a VDB file" : "truncated");
  }
  // The whole directory is checked: a truncated last grid rejects the file even when the
  // requested grid is intact, and the message names the grid that is cut.
  write_bytes(t, bytes.data(), bytes.size() - 10);
  expect_error([&] { (void)read_vdb_grid(t, "ls"); }, "truncated: grid 'distance' ends at byte");
}

TEST(VdbErrors, CorruptedFilesNeverCrash) {
  ensure_openvdb_initialized();
  auto ls =
      openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(4.0f, openvdb::Vec3f(0, 0, 0), 0.5f);
  std::vector<std::vector<char>> inputs;
  using namespace openvdb::io;
  for (std::uint32_t comp :
       {std::uint32_t(COMPRESS_BLOSC | COMPRESS_ACTIVE_MASK),
        std::uint32_t(COMPRESS_ZIP | COMPRESS_ACTIVE_MASK), std::uint32_t(COMPRESS_NONE)}) {
    std::ostringstream os;
    Stream s(os);
    s.setCompression(comp);
    s.write({ls});
    const std::string str = os.str();
    inputs.emplace_back(str.begin(), str.end());
    const fs::path p = tmp_dir() / "corrupt_src.vdb";
    File f(p.string());
    f.setCompression(comp);
    f.write({ls});
    f.close();
    inputs.push_back(file_bytes(p));
  }
  std::mt19937 rng(42);
  int ok = 0, rejected = 0;
  for (int it = 0; it < 1500; ++it) {
    std::vector<char> b = inputs[static_cast<std::size_t>(it) % inputs.size()];
    const int changes = 1 + static_cast<int>(rng() % 4);
    for (int c = 0; c < changes; ++c) {
      const std::size_t pos = rng() % b.size();
      if (rng() % 2) {
        b[pos] = static_cast<char>(b[pos] ^ (1 << (rng() % 8)));
      } else if (pos + 4 <= b.size()) {
        const std::uint32_t v = rng();
        std::memcpy(&b[pos], &v, 4);
      }
    }
    try {
      (void)read_vdb_grid(as_span(b), "corrupt.vdb");
      ++ok;
    } catch (const Error& e) {
      ++rejected;
      EXPECT_EQ(std::string(e.what()).rfind("corrupt.vdb: ", 0), 0u) << e.what();
    }
  }
  EXPECT_GT(rejected, 100);
  EXPECT_GT(ok, 100);  // flips in float values or masks' unused bits are legal files
}

// ---------------------------------------------------------------------------------------------
// Atomic writing
// ---------------------------------------------------------------------------------------------

namespace {

// Metadata whose serialisation throws: makes OpenVDB fail in the middle of writing a file.
class ThrowingMetadata final : public openvdb::Metadata {
 public:
  openvdb::Name typeName() const override { return "isoforge_test_throwing"; }
  openvdb::Metadata::Ptr copy() const override { return std::make_shared<ThrowingMetadata>(); }
  void copy(const openvdb::Metadata&) override {}
  std::string str() const override { return ""; }
  bool asBool() const override { return false; }
  openvdb::Index32 size() const override { return 4; }

 protected:
  void readValue(std::istream&, openvdb::Index32) override {}
  void writeValue(std::ostream&) const override {
    throw std::runtime_error("refusing to serialise");
  }
};

}  // namespace

TEST(VdbWrite, FailureLeavesAnExistingFileUnchanged) {
  const fs::path dir = tmp_dir() / "atomic";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path p = dir / "keep.vdb";
  auto good = to_vdb(test::sphere_distance_image(), {}, 0.0f, 0.5f);
  write_vdb(*good, p);
  const std::vector<char> before = file_bytes(p);
  ASSERT_FALSE(before.empty());
  expect_error(
      [&] {
        write_vdb(std::vector<openvdb::GridBase::Ptr>{good, nullptr}, p);
      },
      "grid 1 is null");
  expect_error([&] { write_vdb(std::vector<openvdb::GridBase::Ptr>{}, p); }, "no grids to write");
  EXPECT_EQ(file_bytes(p), before);
  // OpenVDB fails half-way through writing (after the temporary file was created and the first
  // grid written): the target is untouched.
  auto bad = good->deepCopy();
  bad->setName("bad");
  bad->insertMeta("explodes", ThrowingMetadata());
  expect_error(
      [&] {
        write_vdb(std::vector<openvdb::GridBase::Ptr>{good, bad}, p);
      },
      "keep.vdb: cannot write VDB file: refusing to serialise");
  EXPECT_EQ(file_bytes(p), before);
  // No temporary file is left behind.
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1u);
  // Writing into a missing directory fails cleanly.
  expect_error([&] { write_vdb(*good, dir / "no_such_dir" / "x.vdb"); }, "x.vdb");
  // A successful overwrite replaces the file.
  auto other = to_vdb(test::sphere_distance_image("other"), {}, 0.0f, 0.1f);
  write_vdb(*other, p);
  EXPECT_NE(file_bytes(p), before);
  EXPECT_EQ(read_vdb_grid(p)->getName(), "other");
}
