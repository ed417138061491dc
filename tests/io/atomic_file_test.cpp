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

namespace {

// Bytes of disk the file occupies (st_blocks counts 512-byte units).
std::uint64_t allocated_bytes(const fs::path& p) {
  struct stat st {};
  EXPECT_EQ(::stat(p.c_str(), &st), 0) << p;
  return static_cast<std::uint64_t>(st.st_blocks) * 512;
}

std::string pattern(std::size_t n) {
  std::string s(n, '\0');
  for (std::size_t i = 0; i < n; ++i) s[i] = static_cast<char>('a' + (i * 7 + i / 4096) % 26);
  return s;
}

}  // namespace

TEST(AtomicFile, ReservedSpaceNotWrittenIsFreedAtCommit) {
  // 8 MiB reserved, 3 MiB + 5 bytes written: the file has what was written and occupies its
  // size rounded up to blocks, not the reservation (where the file system preallocates).
  const fs::path dir = scratch("reserve");
  const std::string data = pattern((std::size_t{3} << 20) + 5);
  AtomicFile f(dir / "r.bin");
  f.reserve(std::uint64_t{8} << 20);
  f.stream().write(data.data(), static_cast<std::streamsize>(data.size()));
  f.commit();
  EXPECT_EQ(slurp(dir / "r.bin"), data);
  EXPECT_LE(allocated_bytes(dir / "r.bin"), data.size() + 65536);
  EXPECT_EQ(entries(dir), 1u);
}

TEST(AtomicFile, AReservationTooSmallOrTooLargeOnlyLosesTheHint) {
  const fs::path dir = scratch("reserve_wrong");
  const std::string data = pattern(std::size_t{5} << 20);
  for (const std::uint64_t hint : {std::uint64_t{1} << 20, std::uint64_t{1} << 62}) {
    AtomicFile f(dir / "w.bin");
    f.reserve(hint);  // 2^62 bytes: more than any disk; the file system refuses, writing goes on
    f.stream().write(data.data(), static_cast<std::streamsize>(data.size()));
    f.commit();
    EXPECT_EQ(slurp(dir / "w.bin"), data) << hint;
    EXPECT_LE(allocated_bytes(dir / "w.bin"), data.size() + 65536) << hint;
  }
  EXPECT_EQ(entries(dir), 1u);
}

TEST(AtomicFile, AnAbandonedReservedFileLeavesNothing) {
  const fs::path dir = scratch("reserve_abandon");
  {
    AtomicFile f(dir / "gone.bin");
    f.reserve(std::uint64_t{16} << 20);
    f.stream() << "started";
    EXPECT_EQ(entries(dir), 1u);
  }
  EXPECT_EQ(entries(dir), 0u);
}

TEST(AtomicFile, TheStreamSeeksBackToFillInPlaces) {
  // The VTK XML writer leaves fixed-width places for offsets and fills them in afterwards.
  const fs::path dir = scratch("seek");
  const std::string big = pattern(std::size_t{1} << 20);  // past the stream's buffer
  AtomicFile f(dir / "s.bin");
  std::ostream& os = f.stream();
  os << "head:????;";
  os.write(big.data(), static_cast<std::streamsize>(big.size()));
  const std::streampos end = os.tellp();
  EXPECT_EQ(static_cast<std::size_t>(end), 10 + big.size());
  os.seekp(5);
  os << "done";
  os.seekp(end);
  os << "tail";
  f.commit();
  EXPECT_EQ(slurp(dir / "s.bin"), "head:done;" + big + "tail");
}

TEST(AtomicFile, TempPathClosesTheStreamForALibraryThatReopensIt) {
  const fs::path dir = scratch("temp_path_reserved");
  AtomicFile f(dir / "lib.bin");
  f.reserve(std::uint64_t{4} << 20);
  f.stream() << "ignored";
  const fs::path temp = f.temp_path();
  { std::ofstream(temp, std::ios::binary) << "from the library"; }
  f.commit();
  EXPECT_EQ(slurp(dir / "lib.bin"), "from the library");
  EXPECT_LE(allocated_bytes(dir / "lib.bin"), std::uint64_t{65536});
}
