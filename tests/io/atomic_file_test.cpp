#include "support/scratch.hpp"
#include "isoforge/io/atomic_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <sys/stat.h>
#include <unistd.h>

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

namespace {

unsigned mode_of(const fs::path& p) {
  struct stat st {};
  EXPECT_EQ(::stat(p.c_str(), &st), 0) << p;
  return st.st_mode & 07777;
}

// Sets the process umask for one scope (the tests of a file run in one process, one at a time).
struct Umask {
  explicit Umask(mode_t m) : old(::umask(m)) {}
  ~Umask() { ::umask(old); }
  mode_t old;
};

}  // namespace

TEST(AtomicFile, ReplacingAFileKeepsItsMode) {
  const fs::path dir = scratch("mode");
  const Umask u(022);
  write_file_atomic(dir / "secret", "one");
  ASSERT_EQ(::chmod((dir / "secret").c_str(), 0600), 0);
  write_file_atomic(dir / "secret", "two");  // was widened to 0644 (0666 & ~umask)
  EXPECT_EQ(slurp(dir / "secret"), "two");
  EXPECT_EQ(mode_of(dir / "secret"), 0600u);
  ASSERT_EQ(::chmod((dir / "secret").c_str(), 0750), 0);
  write_file_atomic(dir / "secret", "three");
  EXPECT_EQ(mode_of(dir / "secret"), 0750u);
}

TEST(AtomicFile, NewFilesGetTheUmaskDefault) {
  const fs::path dir = scratch("umask");
  {
    const Umask u(022);
    write_file_atomic(dir / "a", "a");
  }
  {
    const Umask u(077);
    write_file_atomic(dir / "b", "b");
  }
  EXPECT_EQ(mode_of(dir / "a"), 0644u);
  EXPECT_EQ(mode_of(dir / "b"), 0600u);
}

TEST(AtomicFile, WritesThroughASymbolicLink) {
  const fs::path dir = scratch("symlink");
  fs::create_directories(dir / "real");
  write_file_atomic(dir / "real" / "data.vtk", "old");
  fs::create_symlink("real/data.vtk", dir / "link.vtk");  // relative, as `ln -s` makes them
  fs::create_symlink("link.vtk", dir / "link2.vtk");      // and a chain of two
  write_file_atomic(dir / "link2.vtk", "new");
  EXPECT_TRUE(fs::is_symlink(dir / "link.vtk"));  // the links stay links (they became files)
  EXPECT_TRUE(fs::is_symlink(dir / "link2.vtk"));
  EXPECT_EQ(slurp(dir / "real" / "data.vtk"), "new");
  EXPECT_EQ(entries(dir), 3u);          // no temp file beside the links ...
  EXPECT_EQ(entries(dir / "real"), 1u);  // ... nor beside the file
}

TEST(AtomicFile, ADanglingSymbolicLinkCreatesTheFileItPointsTo) {
  const fs::path dir = scratch("dangling");
  fs::create_symlink("target.txt", dir / "link.txt");
  write_file_atomic(dir / "link.txt", "made");
  EXPECT_TRUE(fs::is_symlink(dir / "link.txt"));
  EXPECT_EQ(slurp(dir / "target.txt"), "made");
}

TEST(AtomicFile, TheTemporaryFileAppearsOnlyWhenWritingBegins) {
  const fs::path dir = scratch("lazy");
  AtomicFile f(dir / "late.txt");
  EXPECT_EQ(entries(dir), 0u);  // constructed (the path checked) while the work goes on
  f.stream() << "x";
  EXPECT_EQ(entries(dir), 1u);
  f.commit();
  EXPECT_EQ(slurp(dir / "late.txt"), "x");
}

TEST(AtomicFile, CheckWritableFailsAtOnceAndCreatesNothing) {
  const fs::path dir = scratch("check");
  EXPECT_NO_THROW(check_writable(dir / "fine.txt"));
  EXPECT_EQ(entries(dir), 0u);
  EXPECT_THROW(check_writable(dir / "no" / "dir" / "x.txt"), Error);
  EXPECT_THROW(check_writable(dir), Error);  // a directory is not a file to replace
}

TEST(AtomicFile, RemoveTemporaryFilesRemovesWhatIsBeingWritten) {
  // What a SIGINT/SIGTERM handler calls: every uncommitted temporary file goes, committed
  // outputs and other files stay.
  const fs::path dir = scratch("signal");
  write_file_atomic(dir / "done.txt", "kept");
  AtomicFile a(dir / "a.txt");
  AtomicFile b(dir / "b.txt");
  a.stream() << "partial";
  b.stream() << "partial";
  EXPECT_EQ(entries(dir), 3u);
  remove_temporary_files();
  EXPECT_EQ(entries(dir), 1u);
  EXPECT_EQ(slurp(dir / "done.txt"), "kept");
  EXPECT_THROW(a.commit(), Error);  // its file is gone: a clear error, not a half file
  EXPECT_FALSE(fs::exists(dir / "a.txt"));
}
