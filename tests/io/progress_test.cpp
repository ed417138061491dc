// Progress of reading and writing: every reader and writer that can take long reports the
// fraction done as it goes (not only 0 and 1), monotonically, ending at 1; returning false
// cancels (and a cancelled write leaves the target as it was).

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "isoforge/core/error.hpp"
#include "isoforge/io/io.hpp"
#include "isoforge/io/plot3d.hpp"
#include "support/scratch.hpp"

using namespace isoforge;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  return isoforge::test::scratch_dir("progress", name);
}

/// Records the fractions a callback is given.
struct Recorder {
  std::vector<double> fractions;
  ProgressCallback callback() {
    return [this](double f) {
      fractions.push_back(f);
      return true;
    };
  }
};

/// Progress worth the name on a multi-megabyte file: several distinct fractions (more than the
/// 0 and 1 a reader that reports only at its ends would give), in [0, 1], never going back,
/// ending at 1.
void expect_progress(const std::vector<double>& f, const std::string& what) {
  ASSERT_FALSE(f.empty()) << what << ": no progress reported";
  for (std::size_t i = 0; i < f.size(); ++i) {
    EXPECT_GE(f[i], 0.0) << what;
    EXPECT_LE(f[i], 1.0) << what;
    if (i > 0) {
      EXPECT_GE(f[i], f[i - 1]) << what << ": goes back at report " << i;
    }
  }
  EXPECT_EQ(f.back(), 1.0) << what;
  EXPECT_GT(std::set<double>(f.begin(), f.end()).size(), 2u) << what << ": only the ends";
}

/// Incompressible values (an LCG), so that compressed files are multi-megabyte too.
std::vector<float> noise(std::size_t n) {
  std::vector<float> v(n);
  std::uint32_t x = 12345;
  for (auto& f : v) {
    x = x * 1664525u + 1013904223u;
    f = static_cast<float>(x >> 8) / 16777216.0f;
  }
  return v;
}

/// A 128³ image (8 MB of Float32 noise).
ImageData big_image() {
  ImageData img;
  img.dims = {128, 128, 128};
  img.point_data.add(DataArray::from_vector("noise", 1, noise(128 * 128 * 128)),
                     AttributeRole::Scalars);
  return img;
}

/// A triangle mesh of 300k points and 600k triangles (~10 MB as binary PLY).
PolyData big_mesh() {
  PolyData m;
  const std::size_t n = 300'000;
  const std::vector<float> r = noise(3 * n);
  for (std::size_t i = 0; i < n; ++i) m.points.push_back({r[3 * i], r[3 * i + 1], r[3 * i + 2]});
  for (std::size_t i = 0; i + 2 < n; i += 1) {
    if (i % 2 == 0) m.polys.add({Index(i), Index(i + 1), Index(i + 2)});
    m.polys.add({Index(i), Index(i + 2), Index(i + 1)});
  }
  return m;
}

void write_and_read(const Dataset& ds, const fs::path& path, WriteOptions wo = {}) {
  Recorder w, r;
  wo.progress = w.callback();
  write(ds, path, wo);
  expect_progress(w.fractions, "writing " + path.filename().string());
  ReadOptions ro;
  ro.progress = r.callback();
  (void)read(path, ro);
  expect_progress(r.fractions, "reading " + path.filename().string());
}

void write_bytes(const fs::path& path, const void* data, std::size_t n) {
  std::ofstream out(path, std::ios::binary);
  out.write(static_cast<const char*>(data), static_cast<std::streamsize>(n));
}

}  // namespace

TEST(IoProgress, VtkXmlCompressedAndRaw) {
  const fs::path dir = scratch("xml");
  write_and_read(big_image(), dir / "a.vti");
  WriteOptions raw;
  raw.compress = false;
  write_and_read(big_image(), dir / "b.vti", raw);
  write_and_read(big_mesh(), dir / "m.vtp");
}

TEST(IoProgress, VtkXmlAscii) {
  const fs::path dir = scratch("xml_ascii");
  WriteOptions ascii;
  ascii.binary = false;
  write_and_read(big_mesh(), dir / "m.vtp", ascii);
}

TEST(IoProgress, VtkLegacyBinaryAndAscii) {
  const fs::path dir = scratch("legacy");
  write_and_read(big_image(), dir / "a.vtk");
  WriteOptions ascii;
  ascii.binary = false;
  write_and_read(big_mesh(), dir / "m.vtk", ascii);
}

TEST(IoProgress, Ply) {
  const fs::path dir = scratch("ply");
  write_and_read(big_mesh(), dir / "m.ply");
}

TEST(IoProgress, OffAndObjWriting) {
  const fs::path dir = scratch("off_obj");
  write_and_read(big_mesh(), dir / "m.off");
  Recorder w;
  WriteOptions wo;
  wo.progress = w.callback();
  write(big_mesh(), dir / "m.obj", wo);
  expect_progress(w.fractions, "writing m.obj");
}

TEST(IoProgress, NrrdDetachedAndAttached) {
  const fs::path dir = scratch("nrrd");
  const std::vector<float> v = noise(128 * 128 * 128);
  write_bytes(dir / "v.raw", v.data(), v.size() * sizeof(float));
  const std::string head =
      "NRRD0004\ntype: float\ndimension: 3\nsizes: 128 128 128\nendian: little\nencoding: raw\n";
  const std::string detached = head + "data file: v.raw\n";
  write_bytes(dir / "v.nhdr", detached.data(), detached.size());
  std::string attached = head + "\n";
  attached.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(float));
  write_bytes(dir / "a.nrrd", attached.data(), attached.size());
  for (const char* name : {"v.nhdr", "a.nrrd"}) {
    Recorder r;
    ReadOptions ro;
    ro.progress = r.callback();
    (void)read(dir / name, ro);
    expect_progress(r.fractions, name);
  }
}

TEST(IoProgress, MetaImage) {
  const fs::path dir = scratch("mhd");
  const std::vector<float> v = noise(128 * 128 * 128);
  write_bytes(dir / "v.raw", v.data(), v.size() * sizeof(float));
  const std::string head =
      "ObjectType = Image\nNDims = 3\nDimSize = 128 128 128\nElementType = MET_FLOAT\n"
      "BinaryDataByteOrderMSB = False\nElementDataFile = v.raw\n";
  write_bytes(dir / "v.mhd", head.data(), head.size());
  Recorder r;
  ReadOptions ro;
  ro.progress = r.callback();
  (void)read(dir / "v.mhd", ro);
  expect_progress(r.fractions, "v.mhd");
}

TEST(IoProgress, Plot3dGridAndSolution) {
  // Whole-format single grid, little endian, no iblank: dims, then x, y, z (float32); the
  // solution: dims, fsmach alpha re time, then five variables.
  const fs::path dir = scratch("plot3d");
  const std::int32_t d[3] = {100, 100, 100};
  const std::size_t n = 100 * 100 * 100;
  std::vector<float> xyz = noise(3 * n);
  std::string g(reinterpret_cast<const char*>(d), sizeof d);
  g.append(reinterpret_cast<const char*>(xyz.data()), xyz.size() * sizeof(float));
  write_bytes(dir / "g.bin", g.data(), g.size());
  std::vector<float> q = noise(4 + 5 * n);
  for (std::size_t i = 4; i < 4 + n; ++i) q[i] += 1.0f;  // density > 0
  std::string qs(reinterpret_cast<const char*>(d), sizeof d);
  qs.append(reinterpret_cast<const char*>(q.data()), q.size() * sizeof(float));
  write_bytes(dir / "q.bin", qs.data(), qs.size());
  Recorder r;
  ReadOptions ro;
  ro.plot3d_q = dir / "q.bin";
  ro.progress = r.callback();
  const Dataset ds = read(dir / "g.bin", ro);
  EXPECT_TRUE(point_data(ds).has("Density"));
  expect_progress(r.fractions, "g.bin + q.bin");
}

TEST(IoProgress, CancellingAReadThrowsCancelled) {
  const fs::path dir = scratch("cancel_read");
  write(big_image(), dir / "a.vti");
  ReadOptions ro;
  int calls = 0;
  ro.progress = [&calls](double) { return ++calls < 3; };
  EXPECT_THROW((void)read(dir / "a.vti", ro), Cancelled);
  EXPECT_EQ(calls, 3);  // it stopped at the first refusal
}

TEST(IoProgress, CancellingAWriteLeavesTheTargetUnchanged) {
  const fs::path dir = scratch("cancel_write");
  write(PolyData{}, dir / "m.ply");
  const auto before = fs::file_size(dir / "m.ply");
  for (const char* name : {"m.ply", "m.vtp", "m.vtk", "m.off", "m.obj"}) {
    if (std::string(name) != "m.ply") write(PolyData{}, dir / name);
    WriteOptions wo;
    wo.progress = [](double f) { return f < 0.5; };
    EXPECT_THROW(write(big_mesh(), dir / name, wo), Cancelled) << name;
  }
  EXPECT_EQ(fs::file_size(dir / "m.ply"), before);
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    ++files;
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
  }
  EXPECT_EQ(files, 5u);
}
