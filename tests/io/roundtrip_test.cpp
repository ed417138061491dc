// Format-agnostic io (io.hpp): every format x dataset type it can hold round-trips through
// write() + read(); every real file in data/ reads with the expected counts; a format that
// cannot hold a dataset is a clear error that writes nothing.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "support/scratch.hpp"
#include "isoforge/io/io.hpp"
#include "support/sample_datasets.hpp"
#include "support/expect_error.hpp"

using namespace isoforge;
using isoforge::test::error_message;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  return isoforge::test::scratch_dir("roundtrip", name);
}


struct Case {
  std::string name;
  Dataset ds;
  std::vector<std::string> extensions;  // formats that hold this dataset losslessly
};

std::vector<Case> lossless_cases() {
  return {
      {"image", test::sample_image(), {".vtk", ".vti"}},
      {"structured", test::sample_structured(), {".vtk", ".vts"}},
      {"poly", test::sample_poly(), {".vtk", ".vtp"}},
      {"unstructured", test::sample_unstructured(), {".vtk", ".vtu"}},
  };
}

}  // namespace

TEST(RoundTrip, VtkFormatsAreLosslessForEveryDatasetType) {
  const fs::path dir = scratch("lossless");
  for (const auto& c : lossless_cases()) {
    for (const auto& ext : c.extensions) {
      for (bool binary : {true, false}) {
        for (std::string version : {"4.2", "5.1"}) {
          if (ext != ".vtk" && version == "5.1") continue;  // version applies to legacy only
          WriteOptions wo;
          wo.binary = binary;
          wo.vtk_legacy_version = version;
          const fs::path p = dir / (c.name + (binary ? "_bin_" : "_asc_") + version + ext);
          write(c.ds, p, wo);
          const Dataset back = read(p);
          EXPECT_EQ(back.index(), c.ds.index()) << p;
          EXPECT_TRUE(back == c.ds) << "round trip changed " << p;
        }
      }
    }
  }
}

TEST(RoundTrip, MeshFormatsKeepGeometryAndTopology) {
  const fs::path dir = scratch("mesh");
  const PolyData mesh = test::sample_poly(/*surface_only=*/true);
  for (std::string ext : {".ply", ".off"}) {
    for (bool binary : {true, false}) {
      WriteOptions wo;
      wo.binary = binary;
      const fs::path p = dir / ((binary ? "bin" : "asc") + ext);
      write(mesh, p, wo);
      const auto back = std::get<PolyData>(read(p));
      ASSERT_EQ(back.points.size(), mesh.points.size()) << p;
      for (std::size_t i = 0; i < mesh.points.size(); ++i) EXPECT_EQ(back.points[i], mesh.points[i]);
      EXPECT_EQ(back.polys, mesh.polys) << p;
      if (ext == ".ply") {  // PLY carries point arrays as vertex properties
        ASSERT_NE(back.point_data.normals(), nullptr);
        EXPECT_EQ(*back.point_data.normals(), *mesh.point_data.normals());
      }
    }
  }
  // OBJ is write-only: check its records.
  write(mesh, dir / "m.obj");
  std::ifstream in(dir / "m.obj");
  std::string line;
  int v = 0, vn = 0, f = 0;
  while (std::getline(in, line)) {
    if (line.rfind("v ", 0) == 0) ++v;
    if (line.rfind("vn ", 0) == 0) ++vn;
    if (line.rfind("f ", 0) == 0) ++f;
  }
  EXPECT_EQ(v, 5);
  EXPECT_EQ(vn, 5);
  EXPECT_EQ(f, 5);
}

TEST(RoundTrip, VdbHoldsImageScalars) {
  const fs::path dir = scratch("vdb");
  ImageData img;
  img.dims = {5, 4, 3};
  img.origin = {-1, 0, 2};
  img.spacing = {0.5, 0.5, 0.5};
  DataArray s("density", ScalarType::Float32, 1, img.num_points());
  for (std::size_t i = 0; i < img.num_points(); ++i) s.set(i, 0, 1.0 + static_cast<double>(i));
  img.point_data.add(std::move(s), AttributeRole::Scalars);
  write(img, dir / "v.vdb");
  const auto back = std::get<ImageData>(read(dir / "v.vdb"));
  EXPECT_EQ(back.dims, img.dims);
  EXPECT_EQ(back.origin, img.origin);
  EXPECT_EQ(back.spacing, img.spacing);
  ASSERT_NE(back.point_data.scalars(), nullptr);
  EXPECT_EQ(back.point_data.scalars()->values<float>().size(), img.num_points());
  for (std::size_t i = 0; i < img.num_points(); ++i) {
    EXPECT_EQ(back.point_data.scalars()->get(i), img.point_data.scalars()->get(i));
  }
}

TEST(RoundTrip, FormatThatCannotHoldTheDatasetIsAnErrorAndWritesNothing) {
  const fs::path dir = scratch("mismatch");
  const UnstructuredGrid ug = test::sample_unstructured();
  for (std::string ext : {".ply", ".obj", ".off", ".vdb", ".vtp", ".vti"}) {
    const fs::path p = dir / ("ug" + ext);
    const std::string msg = error_message([&] { write(ug, p); });
    EXPECT_NE(msg.find("ug" + ext), std::string::npos) << msg;
    EXPECT_FALSE(fs::exists(p)) << p;
  }
  EXPECT_NE(error_message([&] { write(ug, dir / "x.nhdr"); }).find("not supported"), std::string::npos);
  EXPECT_NE(error_message([&] { write(ug, dir / "x.weird"); }).find("unknown file extension"),
            std::string::npos);
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(RoundTrip, MissingInputNamesTheFile) {
  const std::string msg = error_message([] { (void)read("/nonexistent/dir/file.vtk"); });
  EXPECT_NE(msg.find("/nonexistent/dir/file.vtk"), std::string::npos) << msg;
}

// ---- every real file in data/, through the generic reader, with its expected counts ----

struct RealFile {
  const char* path;
  const char* q;  // PLOT3D solution file or ""
  std::size_t index;  // Dataset alternative: 0 image, 1 structured, 2 poly, 3 unstructured
  std::size_t points;
  std::size_t cells;
};

TEST(RealData, EveryFileReadsWithExpectedCounts) {
  const RealFile files[] = {
      // Counts from data/README.md (verified there against the files' headers).
      {"combxyz.bin", "combq.bin", 1, 57 * 33 * 25, 56 * 32 * 24},
      {"fran_cut.vtk", "", 2, 2205, 4224},
      {"Torso.vtp", "", 2, 12015, 12448},
      {"bunny.ply", "", 2, 35947, 69451},
      {"hello.vtk", "", 2, 22, 15},
      {"headsq/quarter.nhdr", "", 0, 64 * 64 * 93, 63 * 63 * 92},
      {"HeadMRVolume.mhd", "", 0, 48 * 62 * 42, 47 * 61 * 41},
      {"ironProt.vtk", "", 0, 68 * 68 * 68, 67 * 67 * 67},
      {"post.vtk", "", 3, 2288, 8750},
      {"blow.vtk", "", 3, 687, 1057},
      {"office.binary.vtk", "", 1, 21 * 20 * 20, 20 * 19 * 19},
  };
  for (const auto& f : files) {
    ReadOptions ro;
    if (*f.q) ro.plot3d_q = fs::path(ISOFORGE_DATA_DIR) / f.q;
    const Dataset ds = read(fs::path(ISOFORGE_DATA_DIR) / f.path, ro);
    EXPECT_EQ(ds.index(), f.index) << f.path;
    EXPECT_EQ(num_points(ds), f.points) << f.path;
    EXPECT_EQ(num_cells(ds), f.cells) << f.path;
    EXPECT_NO_THROW(validate(ds)) << f.path;
  }
}
