#include "support/scratch.hpp"
#include "isoforge/io/atomic_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "isoforge/core/error.hpp"

using namespace isoforge;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  return isoforge::test::scratch_dir("atomic", name);
}

using isoforge::test::slurp;

std::size_t entries(const fs::path& dir) {
  return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}));
}

}  // namespace

TEST(AtomicFile, CommitCreatesTheFile) {
  const fs::path dir = scratch("commit");
  {
    AtomicFile f(dir / "a.txt");
    f.stream() << "hello";
    EXPECT_FALSE(fs::exists(dir / "a.txt"));  // nothing visible before commit
    f.commit();
  }
  EXPECT_EQ(slurp(dir / "a.txt"), "hello");
  EXPECT_EQ(entries(dir), 1u);  // no temp file left behind
}

TEST(AtomicFile, AbandonedWriteKeepsTheOldFileAndLeavesNoTemp) {
  const fs::path dir = scratch("abandon");
  write_file_atomic(dir / "good.txt", "good data");
  try {
    AtomicFile f(dir / "good.txt");
    f.stream() << "half written";
    throw Error("simulated failure in the middle of a write");
  } catch (const Error&) {
  }
  EXPECT_EQ(slurp(dir / "good.txt"), "good data");
  EXPECT_EQ(entries(dir), 1u);
}

TEST(AtomicFile, MissingDirectoryIsAClearError) {
  const fs::path dir = scratch("missing");
  try {
    AtomicFile f(dir / "no" / "such" / "dir" / "x.txt");
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("x.txt"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("cannot create"), std::string::npos) << e.what();
  }
}

TEST(AtomicFile, TempPathForLibrariesThatWriteByName) {
  const fs::path dir = scratch("temppath");
  AtomicFile f(dir / "lib.bin");
  {
    std::ofstream o(f.temp_path(), std::ios::binary);
    o << "written by another library";
  }
  EXPECT_EQ(f.temp_path().parent_path(), dir);  // same directory, so rename is atomic
  f.commit();
  EXPECT_EQ(slurp(dir / "lib.bin"), "written by another library");
}

TEST(AtomicFile, OverwriteReplacesContents) {
  const fs::path dir = scratch("overwrite");
  write_file_atomic(dir / "f", "one");
  write_file_atomic(dir / "f", "two");
  EXPECT_EQ(slurp(dir / "f"), "two");
  EXPECT_EQ(entries(dir), 1u);
}
