// Tests for the NRRD and MetaImage raw volume readers.

#include "support/mutate.hpp"
#include "support/scratch.hpp"
#include "isoforge/io/raw_volume.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "isoforge/io/io.hpp"

using namespace isoforge;
namespace fs = std::filesystem;
using isoforge::test::data_path;

namespace {

fs::path scratch(const std::string& name) {
  return isoforge::test::scratch_dir("raw_volume", name);
}

std::vector<std::byte> bytes_of(const std::string& s) {
  const auto* p = reinterpret_cast<const std::byte*>(s.data());
  return std::vector<std::byte>(p, p + s.size());  // (memcpy into an empty vector's null data is UB)
}

std::string str_of(const std::vector<std::byte>& b) {
  return std::string(reinterpret_cast<const char*>(b.data()), b.size());
}

void write_file(const fs::path& p, const std::string& s) {
  std::ofstream out(p, std::ios::binary);
  out.write(s.data(), static_cast<std::streamsize>(s.size()));
}

std::string hex_bytes(const std::string& hex) {
  std::string out;
  for (std::size_t i = 0; i + 1 < hex.size(); i += 2) {
    out += static_cast<char>(std::stoi(hex.substr(i, 2), nullptr, 16));
  }
  return out;
}

template <class T>
std::string raw_values(const std::vector<T>& v, bool big) {
  std::string s;
  for (T x : v) {
    char b[sizeof(T)];
    std::memcpy(b, &x, sizeof(T));
    if (big != (std::endian::native == std::endian::big)) std::reverse(b, b + sizeof(T));
    s.append(b, sizeof(T));
  }
  return s;
}

void expect_error_with(const std::function<void()>& f, std::initializer_list<std::string> parts) {
  try {
    f();
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    const std::string msg = e.what();
    for (const auto& p : parts) {
      EXPECT_NE(msg.find(p), std::string::npos) << "message '" << msg << "' lacks '" << p << "'";
    }
  }
}

ImageData nrrd_text(const std::string& text, const fs::path& dir = "/nonexistent-dir") {
  return read_nrrd(bytes_of(text), "t.nrrd", dir);
}
ImageData mha_text(const std::string& text, const fs::path& dir = "/nonexistent-dir") {
  return read_metaimage(bytes_of(text), "t.mha", dir);
}

/// Only isoforge::Error may escape for any prefix or random mutation of `full`.
template <class Reader>
std::size_t robustness(Reader read, const std::vector<std::byte>& full, int mutations) {
  std::size_t rejected = 0;
  for (std::size_t n = 0; n < full.size(); ++n) {
    const std::vector<std::byte> part(full.begin(), full.begin() + static_cast<std::ptrdiff_t>(n));
    rejected += test::rejects_only_with_error(read, part, "prefix " + std::to_string(n));
  }
  std::mt19937 rng(99);
  for (int r = 0; r < mutations; ++r) {
    (void)test::rejects_only_with_error(read, test::mutate(full, rng, 3, "0123456789-%() \n:=,"),
                                        "mutation " + std::to_string(r));
  }
  return rejected;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Real data

TEST(Nrrd, ReadsHeadsq) {
  const ImageData img = read_nrrd(data_path("headsq/quarter.nhdr"));
  EXPECT_EQ(img.dims, (Dims{64, 64, 93}));
  EXPECT_EQ(img.spacing, (Vec3{3.2, 3.2, 1.5}));
  EXPECT_EQ(img.origin, (Vec3{0, 0, 0}));
  const DataArray* s = img.point_data.scalars();
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->name(), "Scalars");
  EXPECT_EQ(s->type(), ScalarType::Int16);
  EXPECT_EQ(s->tuples(), 64u * 64u * 93u);
  const auto [lo, hi] = s->range();
  EXPECT_EQ(lo, 0.0);
  EXPECT_EQ(hi, 3926.0);
  // Voxels against the slice files' little-endian bytes, read independently.
  for (auto [i, j, k] : {std::array<int, 3>{10, 20, 49}, {0, 0, 0}, {63, 63, 92}, {32, 40, 70}}) {
    const auto slice = read_file_bytes(data_path("headsq/quarter." + std::to_string(k + 1)));
    const std::size_t off = 2 * static_cast<std::size_t>(i + 64 * j);
    const auto v = static_cast<std::int16_t>(std::to_integer<std::uint16_t>(slice[off]) |
                                             (std::to_integer<std::uint16_t>(slice[off + 1]) << 8));
    EXPECT_EQ(s->get(static_cast<std::size_t>(img.point_id(i, j, k))), v)
        << i << " " << j << " " << k;
  }
  EXPECT_EQ(s->get(static_cast<std::size_t>(img.point_id(10, 20, 49))), 102);
  EXPECT_NO_THROW(img.validate());
}

TEST(MetaImage, ReadsHeadMRVolume) {
  const ImageData img = read_metaimage(data_path("HeadMRVolume.mhd"));
  EXPECT_EQ(img.dims, (Dims{48, 62, 42}));
  EXPECT_EQ(img.spacing, (Vec3{4, 4, 4}));
  const DataArray* s = img.point_data.scalars();
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->type(), ScalarType::UInt8);
  const auto [lo, hi] = s->range();
  EXPECT_EQ(lo, 0.0);
  EXPECT_EQ(hi, 255.0);
  const auto raw = read_file_bytes(data_path("HeadMRVolume.raw"));
  ASSERT_EQ(raw.size(), 48u * 62u * 42u);
  for (std::size_t id : {0u, 5u + 48u * (30u + 62u * 20u), 124991u, 60000u}) {
    EXPECT_EQ(s->get(id), std::to_integer<int>(raw[id])) << id;
  }
  EXPECT_EQ(s->get(5u + 48u * (30u + 62u * 20u)), 38);
  // In-memory header with a base directory.
  const auto header = read_file_bytes(data_path("HeadMRVolume.mhd"));
  EXPECT_EQ(read_metaimage(header, "HeadMRVolume.mhd", ISOFORGE_DATA_DIR), img);
}

TEST(Nrrd, HeadsqHeaderPrefixesAreErrors) {
  const auto header = read_file_bytes(data_path("headsq/quarter.nhdr"));
  const fs::path dir = data_path("headsq");
  auto read = [&](const std::vector<std::byte>& b) { return read_nrrd(b, "quarter.nhdr", dir); };
  const std::size_t rejected = robustness(read, header, 1500);
  // Every strict prefix fails except the one missing only the final newline.
  EXPECT_EQ(rejected, header.size() - 1);
}

TEST(Nrrd, ShortOrMissingSliceIsNamed) {
  const fs::path dir = scratch("headsq_short");
  for (const auto& e : fs::directory_iterator(data_path("headsq")))
    fs::copy(e.path(), dir / e.path().filename());
  const auto slice = read_file_bytes(dir / "quarter.17");
  for (std::size_t n : {0u, 1u, 4096u, 8191u}) {
    write_file(dir / "quarter.17", str_of(slice).substr(0, n));
    expect_error_with([&] { (void)read_nrrd(dir / "quarter.nhdr"); },
                      {"quarter.nhdr", "data file 'quarter.17'", "too short", "needs 8192"});
  }
  fs::remove(dir / "quarter.60");
  expect_error_with([&] { (void)read_nrrd(dir / "quarter.nhdr"); },
                    {"quarter.nhdr", "data file 'quarter.17'"});  // the first bad file is reported
  write_file(dir / "quarter.17", str_of(slice));
  expect_error_with([&] { (void)read_nrrd(dir / "quarter.nhdr"); },
                    {"quarter.nhdr", "data file 'quarter.60'", "does not exist"});
}

TEST(MetaImage, ShortOrMissingRawIsNamed) {
  const fs::path dir = scratch("mr_short");
  fs::copy(data_path("HeadMRVolume.mhd"), dir / "HeadMRVolume.mhd");
  const auto raw = str_of(read_file_bytes(data_path("HeadMRVolume.raw")));
  expect_error_with([&] { (void)read_metaimage(dir / "HeadMRVolume.mhd"); },
                    {"HeadMRVolume.mhd", "data file 'HeadMRVolume.raw'", "does not exist"});
  for (std::size_t k = 0; k < 30; ++k) {
    write_file(dir / "HeadMRVolume.raw", raw.substr(0, raw.size() * k / 30));
    expect_error_with([&] { (void)read_metaimage(dir / "HeadMRVolume.mhd"); },
                      {"HeadMRVolume.mhd", "data file 'HeadMRVolume.raw'", "too short"});
  }
  fs::create_directory(dir / "HeadMRVolume.raw.d");
  std::string h = str_of(read_file_bytes(data_path("HeadMRVolume.mhd")));
  h.replace(h.find("HeadMRVolume.raw"), 16, "HeadMRVolume.raw.d");
  write_file(dir / "dir.mhd", h);
  expect_error_with([&] { (void)read_metaimage(dir / "dir.mhd"); },
                    {"dir.mhd", "not a regular file"});
}

// ---------------------------------------------------------------------------------------------
// NRRD: hand-made files

TEST(Nrrd, AttachedBigEndianFloatWithSpaceDirections) {
  std::vector<float> v(12);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = 0.5f * static_cast<float>(i) - 2.0f;
  const std::string text =
      "NRRD0005\n# a comment\ntype: float\ndimension: 3\nspace: right-anterior-superior\n"
      "sizes: 3 2 2\nspace directions: (0.5,0,0) (0, 0.25, 0) (0,0,-2)\n"
      "space origin: (1,2.5,-3)\nendian: big\nencoding: raw\nkinds: domain domain domain\n"
      "key:=value\ncontent: test\n\n" +
      raw_values(v, true);
  const ImageData img = nrrd_text(text);
  EXPECT_EQ(img.dims, (Dims{3, 2, 2}));
  EXPECT_EQ(img.spacing, (Vec3{0.5, 0.25, -2}));
  EXPECT_EQ(img.origin, (Vec3{1, 2.5, -3}));
  const DataArray& s = *img.point_data.scalars();
  EXPECT_EQ(s.type(), ScalarType::Float32);
  for (std::size_t i = 0; i < v.size(); ++i) EXPECT_EQ(s.get(i), v[i]);
}

TEST(Nrrd, TwoDimensionalWithByteAndLineSkip) {
  const std::vector<std::uint16_t> v = {1, 2, 3, 4, 500, 600, 700, 800, 65535, 0, 9, 10};
  const std::string text =
      "NRRD0004\ntype: unsigned short\ndimension: 2\nsizes: 4 3\nspacings: 0.5 2\nendian: little\n"
      "encoding: raw\nline skip: 2\nbyte skip: 3\n\nfirst junk line\nsecond\nABC" +
      raw_values(v, false);
  const ImageData img = nrrd_text(text);
  EXPECT_EQ(img.dims, (Dims{4, 3, 1}));
  EXPECT_EQ(img.spacing, (Vec3{0.5, 2, 1}));
  const DataArray& s = *img.point_data.scalars();
  EXPECT_EQ(s.type(), ScalarType::UInt16);
  for (std::size_t i = 0; i < v.size(); ++i) EXPECT_EQ(s.get(i), v[i]);
}

TEST(Nrrd, DetachedPatternListAndByteSkipMinusOne) {
  const fs::path dir = scratch("nrrd_lists");
  // sizes 2 2 3 as int32: three files of four values, numbered 000, 002, 004.
  for (int f = 0; f < 3; ++f) {
    std::vector<std::int32_t> v;
    for (int i = 0; i < 4; ++i) v.push_back(-100000 * f + i);
    char name[32];
    std::snprintf(name, sizeof(name), "slice%03d.raw", 2 * f);
    write_file(dir / name, "HEADER" + raw_values(v, true));
  }
  const std::string head =
      "NRRD0004\ntype: int32\ndimension: 3\nsizes: 2 2 3\nendian: big\nencoding: raw\n";
  auto check = [](const ImageData& img) {
    const DataArray& s = *img.point_data.scalars();
    EXPECT_EQ(s.type(), ScalarType::Int32);
    EXPECT_EQ(s.get(0), 0);
    EXPECT_EQ(s.get(3), 3);
    EXPECT_EQ(s.get(4), -100000);
    EXPECT_EQ(s.get(11), -200000 + 3);
  };
  check(nrrd_text(head + "byte skip: 6\ndata file: slice%03d.raw 0 4 2\n", dir));
  check(nrrd_text(head + "byte skip: -1\ndata file: slice%03d.raw 0 4 2 2\n", dir));
  check(nrrd_text(
      head + "byte skip: 6\ndata file: LIST\nslice000.raw\nslice002.raw\nslice004.raw\n", dir));
  // Reverse order reads the slices backwards.
  const ImageData rev = nrrd_text(head + "byte skip: 6\ndatafile: slice%03d.raw 4 0 -2\n", dir);
  EXPECT_EQ(rev.point_data.scalars()->get(0), -200000);
  // A single file holding everything (LIST with subdim 3).
  std::string all;
  for (int i = 0; i < 12; ++i) all += raw_values(std::vector<std::int32_t>{i * 7}, true);
  write_file(dir / "all.raw", all);
  const ImageData one = nrrd_text(head + "data file: LIST 3\nall.raw\n", dir);
  EXPECT_EQ(one.point_data.scalars()->get(11), 77);
  const ImageData single = nrrd_text(head + "data file: all.raw\n", dir);
  EXPECT_EQ(single, one);
  // The path variant resolves relative to the header's directory.
  write_file(dir / "h.nhdr", head + "data file: all.raw\n");
  EXPECT_EQ(read_nrrd(dir / "h.nhdr"), one);
}

TEST(Nrrd, GzipEncoding) {
  // 12 big-endian int16 values -6..5, gzip-compressed (Python gzip, mtime 0).
  const std::string gz = hex_bytes(
      "1f8b080000000000020305c181010020088030d2faffdfb470f35ab6cfafc02248366700b48ef1eb18000000");
  const ImageData img = nrrd_text(
      "NRRD0004\ntype: short\ndimension: 3\nsizes: 3 2 2\nendian: big\nencoding: gzip\n\n" + gz);
  const DataArray& s = *img.point_data.scalars();
  for (std::size_t i = 0; i < 12; ++i) EXPECT_EQ(s.get(i), static_cast<double>(i) - 6.0);
  // Truncated or corrupt compressed data.
  expect_error_with(
      [&] {
        (void)nrrd_text(
            "NRRD0004\ntype: short\ndimension: 3\nsizes: 3 2 2\nendian: big\nencoding: gzip\n\n" +
            gz.substr(0, 20));
      },
      {"t.nrrd", "attached data", "truncated"});
  std::string bad = gz;
  bad[12] = static_cast<char>(bad[12] ^ 0x55);
  expect_error_with(
      [&] {
        (void)nrrd_text(
            "NRRD0004\ntype: short\ndimension: 3\nsizes: 3 2 2\nendian: big\nencoding: gz\n\n" +
            bad);
      },
      {"t.nrrd", "attached data"});
  // A header that asks for far more than the compressed bytes can hold fails before allocating.
  expect_error_with(
      [&] {
        (void)nrrd_text(
            "NRRD0004\ntype: double\ndimension: 3\nsizes: 100000 100000 100\nendian: big\n"
            "encoding: gzip\n\n" +
            gz);
      },
      {"t.nrrd", "cannot hold"});
}

// ---------------------------------------------------------------------------------------------
// NRRD: bad input

namespace {
const std::string kNrrd = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n";
const std::string kEight = "\x01\x02\x03\x04\x05\x06\x07\x08";
}  // namespace

TEST(NrrdBad, Magic) {
  expect_error_with([] { (void)nrrd_text("NRRD0X04\n"); }, {"t.nrrd:1", "bad magic"});
  expect_error_with([] { (void)nrrd_text(""); }, {"t.nrrd", "empty"});
}
TEST(NrrdBad, UnknownFieldAndType) {
  expect_error_with([] { (void)nrrd_text(kNrrd + "colour: blue\n\n" + kEight); },
                    {"t.nrrd:6", "unknown field 'colour'"});
  expect_error_with(
      [] { (void)nrrd_text("NRRD0004\ntype: quad\ndimension: 1\nsizes: 1\nencoding: raw\n\nx"); },
      {"t.nrrd:2", "unknown type 'quad'"});
  expect_error_with([] { (void)nrrd_text(kNrrd + "no colon here\n"); },
                    {"t.nrrd:6", "field: value"});
}
TEST(NrrdBad, ControlBytesInQuotedContentAreEscaped) {
  // A NUL in a header value cut the message short ("unknown type 'fl"): the whole value is shown,
  // with every unprintable byte as \xNN, and nothing after it in the message is lost.
  using namespace std::string_literals;
  expect_error_with(
      [] { (void)nrrd_text("NRRD0004\ntype: fl\0oat\ndimension: 1\nsizes: 1\nencoding: raw\n\nx"s); },
      {"t.nrrd:2", "unknown type 'fl\\x00oat'"});
  expect_error_with([] { (void)nrrd_text(kNrrd + "col\x1b[31mour: blue\n\n" + kEight); },
                    {"t.nrrd:6", "unknown field 'col\\x1b[31mour'"});
  expect_error_with([] { (void)nrrd_text("NRRD0004\ntype: uchar\ndimension: 1\nsizes: 1\nencoding: ra\0w\n\nx"s); },
                    {"t.nrrd:5", "encoding ra\\x00w not supported (raw and gzip are)"});
}
TEST(NrrdBad, DuplicateAndMissingFields) {
  expect_error_with([] { (void)nrrd_text(kNrrd + "sizes: 2 2 2\n\n" + kEight); },
                    {"t.nrrd:6", "duplicate field 'sizes'"});
  expect_error_with([] { (void)nrrd_text("NRRD0004\ntype: uchar\nsizes: 2\nencoding: raw\n\nab"); },
                    {"t.nrrd", "missing required field 'dimension'"});
  expect_error_with(
      [] { (void)nrrd_text("NRRD0004\ntype: short\ndimension: 1\nsizes: 1\nencoding: raw\n\nab"); },
      {"t.nrrd", "missing field 'endian'"});
}
TEST(NrrdBad, Dimensions) {
  expect_error_with(
      [] {
        (void)nrrd_text("NRRD0004\ntype: uchar\ndimension: 4\nsizes: 1 2 2 2\nencoding: raw\n\n");
      },
      {"t.nrrd:3", "dimension 4 is not supported"});
  expect_error_with(
      [] { (void)nrrd_text("NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2\nencoding: raw\n\n"); },
      {"t.nrrd:4", "sizes has 2 values, dimension is 3"});
  expect_error_with(
      [] {
        (void)nrrd_text("NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 -2 2\nencoding: raw\n\n");
      },
      {"t.nrrd:4", "size -2 of axis 1"});
  expect_error_with(
      [] {
        (void)nrrd_text(
            "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 9000000000 9000000000 9000000000\n"
            "encoding: raw\n\n");
      },
      {"t.nrrd:4", "overflow"});
  expect_error_with(
      [] {
        (void)nrrd_text("NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 x 2\nencoding: raw\n\n");
      },
      {"t.nrrd:4", "found 'x'"});
}
TEST(NrrdBad, NonDiagonalSpaceDirections) {
  expect_error_with(
      [] { (void)nrrd_text(kNrrd + "space directions: (1,0,0) (0,0.7,0.7) (0,0,1)\n\n" + kEight); },
      {"t.nrrd:6", "not axis-aligned"});
  expect_error_with(
      [] { (void)nrrd_text(kNrrd + "space directions: (1,0,0) (0,1,0)\n\n" + kEight); },
      {"t.nrrd:6", "space directions has 2 entries"});
  expect_error_with(
      [] { (void)nrrd_text(kNrrd + "space directions: (1,0,0 (0,1,0) (0,0,1)\n\n" + kEight); },
      {"t.nrrd:6"});
  expect_error_with([] { (void)nrrd_text(kNrrd + "spacings: 1 0 1\n\n" + kEight); },
                    {"t.nrrd:6", "spacing 0.000000 of axis 1"});
  expect_error_with(
      [] {
        (void)nrrd_text(kNrrd + "spacings: 1 1 1\nspace directions: (1,0,0) (0,1,0) (0,0,1)\n\n" +
                        kEight);
      },
      {"t.nrrd:7", "both 'spacings' and 'space directions'"});
}
TEST(NrrdBad, Encoding) {
  expect_error_with(
      [] {
        (void)nrrd_text("NRRD0004\ntype: uchar\ndimension: 1\nsizes: 1\nencoding: bzip2\n\nx");
      },
      {"t.nrrd:5", "encoding bzip2 not supported"});
  expect_error_with(
      [] {
        (void)nrrd_text("NRRD0004\ntype: uchar\ndimension: 1\nsizes: 1\nencoding: ascii\n\nx");
      },
      {"t.nrrd:5", "encoding ascii not supported"});
}
TEST(NrrdBad, AttachedDataTruncated) {
  expect_error_with([] { (void)nrrd_text(kNrrd + "\n" + kEight.substr(0, 7)); },
                    {"t.nrrd: byte 69", "truncated: attached data needs 8 bytes after byte 62"});
  expect_error_with([] { (void)nrrd_text(kNrrd + "byte skip: 4\n\n" + kEight); },
                    {"t.nrrd", "truncated"});
  expect_error_with([] { (void)nrrd_text(kNrrd + "line skip: 3\n\n" + kEight); },
                    {"t.nrrd", "line skip 3 runs past the end"});
  expect_error_with([] { (void)nrrd_text(kNrrd); },
                    {"t.nrrd", "no 'data file' field and no attached data"});
  expect_error_with([] { (void)nrrd_text(kNrrd + "byte skip: -2\n\n" + kEight); },
                    {"t.nrrd:6", "byte skip -2 is negative"});
}
TEST(NrrdBad, DataFiles) {
  const fs::path dir = scratch("nrrd_bad_files");
  write_file(dir / "four.raw", "abcd");
  expect_error_with([&] { (void)nrrd_text(kNrrd + "data file: missing.raw\n", dir); },
                    {"t.nrrd", "data file 'missing.raw'", "does not exist"});
  expect_error_with([&] { (void)nrrd_text(kNrrd + "data file: four.raw\n", dir); },
                    {"t.nrrd", "data file 'four.raw'", "too short: 4 bytes, needs 8"});
  expect_error_with([&] { (void)nrrd_text(kNrrd + "data file: four%d.raw 1 3 1\n", dir); },
                    {"t.nrrd:6", "names 3 files, the sizes need 2"});
  expect_error_with([&] { (void)nrrd_text(kNrrd + "data file: four%s.raw 1 2 1\n", dir); },
                    {"t.nrrd:6", "unsupported conversion"});
  expect_error_with([&] { (void)nrrd_text(kNrrd + "data file: four%d%d.raw 1 2 1\n", dir); },
                    {"t.nrrd:6", "more than one conversion"});
  expect_error_with([&] { (void)nrrd_text(kNrrd + "data file: four%d.raw 1 2 0\n", dir); },
                    {"t.nrrd:6", "step is 0"});
  expect_error_with([&] { (void)nrrd_text(kNrrd + "data file: four%d.raw 2 1 1\n", dir); },
                    {"t.nrrd:6", "cannot be reached"});
  expect_error_with([&] { (void)nrrd_text(kNrrd + "data file: LIST\nfour.raw\n", dir); },
                    {"t.nrrd:6", "LIST names 1 files, the sizes need 2"});
  expect_error_with([&] { (void)nrrd_text(kNrrd + "data file: LIST 7\nfour.raw\n", dir); },
                    {"t.nrrd:6", "subdimension 7"});
  // Two 4-byte files hold the 8 bytes.
  EXPECT_EQ(
      nrrd_text(kNrrd + "data file: LIST\nfour.raw\nfour.raw\n", dir).point_data.scalars()->get(7),
      'd');
  // A huge pattern list fails at the first missing file without building every name.
  expect_error_with(
      [&] {
        (void)nrrd_text(
            "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 1 1 4000000000\nencoding: raw\n"
            "data file: x%d.raw 1 4000000000 1\n",
            dir);
      },
      {"t.nrrd", "data file 'x1.raw'", "does not exist"});
}
TEST(NrrdBad, MutatedHeadersOnlyThrowError) {
  const fs::path dir = scratch("nrrd_mut");
  write_file(dir / "d.raw", std::string(64, 'x'));
  const std::string attached = kNrrd + "spacings: 1 2 3\nspace origin: (1,2,3)\n\n" + kEight;
  robustness([](const auto& b) { return read_nrrd(b, "m.nrrd", "/nonexistent"); },
             bytes_of(attached), 3000);
  const std::string detached =
      "NRRD0004\ntype: short\ndimension: 3\nsizes: 2 2 2\nendian: little\n"
      "encoding: raw\nbyte skip: 4\ndata file: d.raw\n";
  robustness([&](const auto& b) { return read_nrrd(b, "m.nhdr", dir); }, bytes_of(detached), 3000);
}

// ---------------------------------------------------------------------------------------------
// MetaImage: hand-made files

TEST(MetaImage, MhaLocalBigEndianTwoChannels) {
  std::vector<std::int16_t> v;
  for (int i = 0; i < 3 * 2 * 2; ++i) v.push_back(static_cast<std::int16_t>(i * 1000 - 6000));
  const std::string text =
      "ObjectType = Image\nNDims = 2\nDimSize = 3 2\nElementNumberOfChannels = 2\n"
      "ElementSpacing = 0.5 0.25\nOffset = -1 2\nTransformMatrix = 1 0 0 1\n"
      "BinaryData = True\nBinaryDataByteOrderMSB = True\nCompressedData = False\n"
      "ElementType = MET_SHORT\nElementDataFile = LOCAL\n" +
      raw_values(v, true);
  const ImageData img = mha_text(text);
  EXPECT_EQ(img.dims, (Dims{3, 2, 1}));
  EXPECT_EQ(img.spacing, (Vec3{0.5, 0.25, 1}));
  EXPECT_EQ(img.origin, (Vec3{-1, 2, 0}));
  const DataArray& s = *img.point_data.scalars();
  EXPECT_EQ(s.type(), ScalarType::Int16);
  EXPECT_EQ(s.components(), 2);
  EXPECT_EQ(s.tuples(), 6u);
  EXPECT_EQ(s.get(0, 0), -6000);
  EXPECT_EQ(s.get(5, 1), 5000);
}

TEST(MetaImage, ElementTypesAndHeaderSize) {
  const std::vector<double> values = {-1.5, 0.25, 3e10, -7};
  const std::string tail = "NDims = 1\nDimSize = 4\nElementByteOrderMSB = False\n";
  const ImageData d =
      mha_text(tail + "HeaderSize = 5\nElementType = MET_DOUBLE\nElementDataFile = LOCAL\n" +
               "xxxxx" + raw_values(values, false));
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(d.point_data.scalars()->get(i), values[i]);
  const ImageData e =
      mha_text(tail + "HeaderSize = -1\nElementType = MET_UINT\nElementDataFile = LOCAL\n" +
               "junk" + raw_values(std::vector<std::uint32_t>{1, 2, 4000000000u, 4}, false));
  EXPECT_EQ(e.point_data.scalars()->type(), ScalarType::UInt32);
  EXPECT_EQ(e.point_data.scalars()->get(2), 4000000000.0);
  const std::pair<const char*, ScalarType> types[] = {
      {"MET_CHAR", ScalarType::Int8},       {"MET_UCHAR", ScalarType::UInt8},
      {"MET_SHORT", ScalarType::Int16},     {"MET_USHORT", ScalarType::UInt16},
      {"MET_INT", ScalarType::Int32},       {"MET_UINT", ScalarType::UInt32},
      {"MET_LONG_LONG", ScalarType::Int64}, {"MET_ULONG_LONG", ScalarType::UInt64},
      {"MET_FLOAT", ScalarType::Float32},   {"MET_DOUBLE", ScalarType::Float64}};
  for (const auto& [name, type] : types) {
    const ImageData img = mha_text(tail + "ElementType = " + name + "\nElementDataFile = LOCAL\n" +
                                   std::string(32, '\0'));
    EXPECT_EQ(img.point_data.scalars()->type(), type) << name;
  }
}

TEST(MetaImage, CompressedLocalAndFileLists) {
  // Bytes 0..47 zlib-compressed (Python zlib, level 9).
  const std::string z = hex_bytes(
      "78da6360646266616563e7e0e4e2e6e1e5e3171014121611151397909492969195935750545256515553d7d0d4d2"
      "d6d1d5d3070048280469");
  const ImageData img = mha_text(
      "NDims = 3\nDimSize = 4 4 3\nElementType = MET_UCHAR\nCompressedData = True\n"
      "CompressedDataSize = " +
      std::to_string(z.size()) + "\nElementDataFile = LOCAL\n" + z);
  for (std::size_t i = 0; i < 48; ++i)
    EXPECT_EQ(img.point_data.scalars()->get(i), static_cast<double>(i));
  expect_error_with(
      [&] {
        (void)mha_text(
            "NDims = 3\nDimSize = 4 4 3\nElementType = MET_UCHAR\nCompressedData = True\n"
            "ElementDataFile = LOCAL\n" +
            z.substr(0, z.size() / 2));
      },
      {"t.mha", "attached data"});

  const fs::path dir = scratch("mha_lists");
  write_file(dir / "s1.raw", std::string("\x01\x02\x03\x04", 4));
  write_file(dir / "s2.raw", std::string("\x05\x06\x07\x08", 4));
  const std::string head = "NDims = 3\nDimSize = 2 2 2\nElementType = MET_UCHAR\n";
  const ImageData a = mha_text(head + "ElementDataFile = s%d.raw 1 2 1\n", dir);
  const ImageData b = mha_text(head + "ElementDataFile = LIST\ns1.raw\ns2.raw\n", dir);
  EXPECT_EQ(a, b);
  EXPECT_EQ(a.point_data.scalars()->get(7), 8);
  write_file(dir / "h.mhd", head + "ElementDataFile = LIST 2\ns1.raw\ns2.raw\n");
  EXPECT_EQ(read_metaimage(dir / "h.mhd"), a);
  // MetaIO's own spelling of the files' dimension.
  write_file(dir / "h2d.mhd", head + "ElementDataFile = LIST 2D\ns1.raw\ns2.raw\n");
  EXPECT_EQ(read_metaimage(dir / "h2d.mhd"), a);
}

// ---------------------------------------------------------------------------------------------
// MetaImage: bad input

namespace {
const std::string kMha = "NDims = 3\nDimSize = 2 2 2\nElementType = MET_UCHAR\n";
}

TEST(MetaImageBad, Magic) {
  expect_error_with([] { (void)mha_text("\x89PNG\r\n"); }, {"t.mha:1", "bad magic"});
  expect_error_with([] { (void)mha_text("Hello = 3\n"); }, {"t.mha:1", "bad magic"});
}
TEST(MetaImageBad, UnknownKeyAndType) {
  expect_error_with(
      [] { (void)mha_text(kMha + "Colour = blue\nElementDataFile = LOCAL\n" + kEight); },
      {"t.mha:4", "unknown key 'colour'"});
  expect_error_with(
      [] {
        (void)mha_text(
            "NDims = 1\nDimSize = 1\nElementType = MET_QUAD\nElementDataFile = LOCAL\nx");
      },
      {"t.mha:3", "unknown ElementType 'MET_QUAD'"});
  expect_error_with([] { (void)mha_text(kMha + "no equals sign\n"); }, {"t.mha:4", "Key = Value"});
  expect_error_with(
      [] { (void)mha_text(kMha + "ObjectType = Mesh\nElementDataFile = LOCAL\n" + kEight); },
      {"t.mha:4", "ObjectType 'Mesh'"});
}
TEST(MetaImageBad, Dimensions) {
  expect_error_with(
      [] {
        (void)mha_text(
            "NDims = 4\nDimSize = 1 2 2 2\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n");
      },
      {"t.mha:1", "NDims 4 is not supported"});
  expect_error_with(
      [] {
        (void)mha_text(
            "NDims = 3\nDimSize = 2 2\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n");
      },
      {"t.mha:2", "DimSize has 2 values, NDims is 3"});
  expect_error_with(
      [] {
        (void)mha_text(
            "NDims = 3\nDimSize = 2 0 2\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n");
      },
      {"t.mha:2", "size 0 of axis 1"});
  expect_error_with(
      [] {
        (void)mha_text(
            "NDims = 3\nDimSize = 4000000000 4000000000 4000000000\nElementType = MET_UCHAR\n"
            "ElementDataFile = LOCAL\n");
      },
      {"t.mha:2", "overflow"});
  expect_error_with(
      [] { (void)mha_text(kMha + "ElementSpacing = 1 0 1\nElementDataFile = LOCAL\n" + kEight); },
      {"t.mha:4", "ElementSpacing value 0.000000 of axis 1"});
  expect_error_with(
      [] {
        (void)mha_text(kMha + "ElementNumberOfChannels = 0\nElementDataFile = LOCAL\n" + kEight);
      },
      {"t.mha:4", "ElementNumberOfChannels 0"});
}
TEST(MetaImageBad, MissingKeys) {
  expect_error_with([] { (void)mha_text(kMha); },
                    {"t.mha", "missing required key 'ElementDataFile'"});
  expect_error_with(
      [] { (void)mha_text("NDims = 1\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n"); },
      {"t.mha", "missing required key 'DimSize'"});
}
TEST(MetaImageBad, Orientation) {
  expect_error_with(
      [] {
        (void)mha_text(kMha + "TransformMatrix = 0 1 0 1 0 0 0 0 1\nElementDataFile = LOCAL\n" +
                       kEight);
      },
      {"t.mha:4", "not the identity"});
}
TEST(MetaImageBad, DataProblems) {
  expect_error_with(
      [] { (void)mha_text(kMha + "ElementDataFile = LOCAL\n" + kEight.substr(0, 5)); },
      {"t.mha: byte", "truncated: attached data needs 8 bytes"});
  expect_error_with(
      [] { (void)mha_text(kMha + "BinaryData = False\nElementDataFile = LOCAL\n1 2 3 4 5 6 7 8"); },
      {"t.mha:4", "ASCII MetaImage"});
  expect_error_with(
      [] {
        (void)mha_text(kMha + "CompressedData = True\nElementDataFile = LOCAL\nnot zlib at all");
      },
      {"t.mha", "corrupt compressed data"});
  expect_error_with(
      [] {
        (void)mha_text(kMha + "ElementByteOrderMSB = Maybe\nElementDataFile = LOCAL\n" + kEight);
      },
      {"t.mha:4", "True or False"});
  expect_error_with([] { (void)mha_text(kMha + "ElementDataFile = gone.raw\n"); },
                    {"t.mha", "data file 'gone.raw'", "does not exist"});
  expect_error_with([] { (void)mha_text(kMha + "ElementDataFile = LIST\na.raw\n"); },
                    {"t.mha:4", "LIST names 1 files, the sizes need 2"});
}
TEST(MetaImageBad, MutatedHeadersOnlyThrowError) {
  const std::string text =
      "ObjectType = Image\nNDims = 3\nDimSize = 2 2 2\nElementSpacing = 1 2 3\n"
      "Offset = 0 0 0\nElementType = MET_SHORT\nElementByteOrderMSB = True\n"
      "ElementDataFile = LOCAL\n" +
      kEight + kEight;
  const auto full = bytes_of(text);
  const std::size_t rejected = robustness(
      [](const auto& b) { return read_metaimage(b, "m.mha", "/nonexistent"); }, full, 3000);
  EXPECT_EQ(rejected, full.size());  // every strict prefix lacks data
  const std::string z = hex_bytes(
      "78da6360646266616563e7e0e4e2e6e1e5e3171014121611151397909492969195935750545256515553d7d0d4d2"
      "d6d1d5d3070048280469");
  robustness([](const auto& b) { return read_metaimage(b, "z.mha", "/nonexistent"); },
             bytes_of("NDims = 3\nDimSize = 4 4 3\nElementType = MET_UCHAR\nCompressedData = True\n"
                      "ElementDataFile = LOCAL\n" +
                      z),
             3000);
}

// Large enough that the samples are copied from the files with pread (64 KiB or more), at an
// odd offset, and swapped: attached (.nrrd) and detached (.nhdr + several files) give the values.
TEST(Nrrd, LargeBigEndianSamplesFromTheFilesAtOddOffsets) {
  const fs::path dir = scratch("nrrd_large");
  std::vector<float> v(64 * 64 * 40);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = static_cast<float>(i) * 0.25f - 7.0f;
  const std::string head =
      "NRRD0004\ntype: float\ndimension: 3\nsizes: 64 64 40\nendian: big\nencoding: raw\n";
  write_file(dir / "a.nrrd", head + "byte skip: 3\n\nabc" + raw_values(v, true));
  const std::size_t slice = 64 * 64;  // one file a slice, each after a 5-byte header
  for (std::size_t k = 0; k < 40; ++k) {
    const auto b = v.begin() + static_cast<std::ptrdiff_t>(k * slice);
    write_file(dir / ("s" + std::to_string(k) + ".raw"),
               "12345" + raw_values(std::vector<float>(b, b + static_cast<std::ptrdiff_t>(slice)), true));
  }
  write_file(dir / "d.nhdr", head + "byte skip: 5\ndata file: s%d.raw 0 39 1\n");
  for (const char* f : {"a.nrrd", "d.nhdr"}) {
    const ImageData img = read_nrrd(dir / f);
    const DataArray& s = *img.point_data.scalars();
    ASSERT_EQ(s.size(), v.size()) << f;
    const auto got = s.values<float>();
    EXPECT_TRUE(std::equal(got.begin(), got.end(), v.begin())) << f;
  }
}
