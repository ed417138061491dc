#include "isoforge/io/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/statfs.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <limits>
#include <random>
#include <system_error>

#include <ext/stdio_filebuf.h>

#include "isoforge/core/error.hpp"

namespace isoforge {

namespace fs = std::filesystem;

namespace {

using FileBuffer = __gnu_cxx::stdio_filebuf<char>;
constexpr std::size_t kBufferSize = std::size_t{64} << 10;  // larger writes bypass it

// ---- the registry of temporary files being written, for remove_temporary_files() ----
// Fixed slots with their own path buffers, so a signal handler reads them without locks or
// allocation: a slot is claimed (0 -> 1), filled, published (2), and freed (0) by its owner.
constexpr int kSlots = 64;              // files written at once; more are written unregistered
constexpr std::size_t kPathMax = 4096;  // PATH_MAX on Linux

struct Slot {
  std::atomic<int> state{0};  // 0 free, 1 being filled, 2 live
  char path[kPathMax];
};
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler reads the slots");

std::array<Slot, kSlots> g_slots;

int register_temp(const std::string& path) {
  if (path.size() >= kPathMax) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (g_slots[i].state.compare_exchange_strong(expected, 1, std::memory_order_acquire)) {
      std::memcpy(g_slots[i].path, path.c_str(), path.size() + 1);
      g_slots[i].state.store(2, std::memory_order_release);
      return i;
    }
  }
  return -1;
}

void unregister_temp(int& slot) {
  if (slot >= 0) g_slots[static_cast<std::size_t>(slot)].state.store(0, std::memory_order_release);
  slot = -1;
}

// `p` with symbolic links followed (the file a link chain points to, which need not exist).
fs::path resolve_links(const fs::path& p) {
  fs::path r = p;
  for (int depth = 0; depth < 40; ++depth) {  // Linux's own limit (ELOOP)
    std::error_code ec;
    if (!fs::is_symlink(r, ec)) return r;
    const fs::path to = fs::read_symlink(r, ec);
    if (ec) return r;
    r = to.is_absolute() ? to : r.parent_path() / to;
  }
  throw Error(p.string() + ": too many levels of symbolic links");
}

fs::path directory_of(const fs::path& p) {
  return p.parent_path().empty() ? fs::path(".") : p.parent_path();
}

void remove_file(const fs::path& p) {
  std::error_code ec;
  fs::remove(p, ec);
}

// Allocates `bytes` of disk space for the file `fd` beyond its end (its size unchanged), where
// that makes writing cheaper: ext4 and XFS, which otherwise allocate blocks as pages are written
// (delayed allocation, a third of the cost of a write(2) into the page cache). Elsewhere it does
// nothing: tmpfs, for one, would zero memory pages for it. Nor when the estimate is more than a
// quarter of the free space: an estimate above the file's size would hold space that other
// programs may need while it is written. True if it was tried: a failed fallocate may still have
// allocated a part, which commit() frees too.
bool preallocate(int fd, std::uint64_t bytes) {
  if (bytes < (std::uint64_t{1} << 20)) return false;  // allocating as it goes costs little
  constexpr decltype(statfs::f_type) kExt4 = 0xEF53, kXfs = 0x58465342;
  struct statfs info {};
  if (::fstatfs(fd, &info) != 0 || (info.f_type != kExt4 && info.f_type != kXfs)) return false;
  const double free_bytes = static_cast<double>(info.f_bavail) * static_cast<double>(info.f_bsize);
  if (static_cast<double>(bytes) > free_bytes / 4) return false;
  const auto most = static_cast<std::uint64_t>(std::numeric_limits<off_t>::max());
  (void)::fallocate(fd, FALLOC_FL_KEEP_SIZE, 0, static_cast<off_t>(std::min(bytes, most)));
  return true;
}

}  // namespace

void check_writable(const fs::path& path) {
  const fs::path resolved = resolve_links(path);
  const fs::path dir = directory_of(resolved);
  if (::access(dir.c_str(), W_OK | X_OK) != 0) {
    throw Error(path.string() + ": cannot create a file in '" + dir.string() +
                "': " + std::strerror(errno));
  }
  std::error_code ec;
  if (fs::is_directory(resolved, ec)) throw Error(path.string() + ": is a directory");
}

void remove_temporary_files() noexcept {
  for (Slot& s : g_slots) {
    if (s.state.load(std::memory_order_acquire) == 2) ::unlink(s.path);
  }
}

AtomicFile::AtomicFile(fs::path target) : target_(std::move(target)) {
  check_writable(target_);
  resolved_ = resolve_links(target_);
}

AtomicFile::~AtomicFile() {
  if (!committed_ && !temp_.empty()) {
    (void)close_stream();
    remove_file(temp_);
  }
  unregister_temp(slot_);
}

void AtomicFile::create_temp() {
  const fs::path dir = directory_of(resolved_);
  const std::string base = (dir / ("." + resolved_.filename().string() + ".tmp.")).string();
  // A new name with O_EXCL as mkstemp does, but created with mode 0666 so that the umask
  // gives a new file its usual mode (mkstemp's 0600 would stick).
  static constexpr char kChars[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
  thread_local std::mt19937_64 random{std::random_device{}()};
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::string name = base;
    for (int i = 0; i < 6; ++i) name += kChars[random() % (sizeof kChars - 1)];
    const int fd = ::open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) {
      if (errno == EEXIST) continue;
      throw Error(target_.string() + ": cannot create a temporary file in '" + dir.string() +
                  "': " + std::strerror(errno));
    }
    temp_ = name;
    slot_ = register_temp(name);
    reserved_ = preallocate(fd, reserve_);
    // The stream writes to this descriptor. Opening the file again by name to write (as
    // std::ofstream does, with O_TRUNC) would mark it on ext4 as a file replaced by truncation,
    // which the file system starts writing to disk when it is closed (auto_da_alloc): CPU time
    // in close(), and a later truncate waits for the disk.
    auto buffer = std::make_unique<FileBuffer>(fd, std::ios::out | std::ios::binary, kBufferSize);
    if (!buffer->is_open()) {
      ::close(fd);
      remove_file(temp_);
      unregister_temp(slot_);
      temp_.clear();
      throw Error(target_.string() + ": cannot open temporary file for writing");
    }
    stream_.rdbuf(buffer.get());  // and clears the stream's state
    buffer_ = std::move(buffer);
    return;
  }
  throw Error(target_.string() + ": cannot find a free temporary file name in '" + dir.string() +
              "'");
}

std::string AtomicFile::close_stream() {
  if (!buffer_) return {};
  std::string error;
  auto& buffer = static_cast<FileBuffer&>(*buffer_);
  stream_.flush();
  if (!stream_.good()) error = "write failed (disk full or I/O error)";
  // Space reserved beyond what was written goes back (truncating to the size frees it).
  struct stat written {};
  if (error.empty() && reserved_ &&
      (::fstat(buffer.fd(), &written) != 0 || ::ftruncate(buffer.fd(), written.st_size) != 0)) {
    error = std::string("cannot free the space reserved for it: ") + std::strerror(errno);
  }
  if (!buffer.close() && error.empty()) {
    error = std::string("closing it failed (disk full or I/O error): ") + std::strerror(errno);
  }
  stream_.rdbuf(nullptr);
  buffer_.reset();
  reserved_ = false;
  return error;
}

std::ostream& AtomicFile::stream() {
  if (temp_.empty()) create_temp();
  return stream_;
}

const fs::path& AtomicFile::temp_path() {
  if (temp_.empty()) create_temp();
  if (const std::string error = close_stream(); !error.empty()) {
    throw Error(target_.string() + ": " + error);
  }
  return temp_;
}

void AtomicFile::commit() {
  if (committed_) return;
  if (temp_.empty()) create_temp();  // nothing was written: an empty file
  const std::string error = close_stream();
  const auto fail = [&](const std::string& what) {
    remove_file(temp_);
    unregister_temp(slot_);
    committed_ = true;  // nothing left to clean up
    throw Error(target_.string() + ": " + what);
  };
  if (!error.empty()) fail(error + "; the target was not changed");
  // Replacing a file keeps its permissions (a new one has the umask's, from the open above).
  struct stat st {};
  if (::stat(resolved_.c_str(), &st) == 0 && S_ISREG(st.st_mode) &&
      ::chmod(temp_.c_str(), st.st_mode & 07777) != 0) {
    fail(std::string("cannot give the new file the mode of the old one: ") + std::strerror(errno));
  }
  std::error_code ec;
  fs::rename(temp_, resolved_, ec);
  if (ec) fail("cannot move the written file into place: " + ec.message());
  unregister_temp(slot_);
  committed_ = true;
}

void write_file_atomic(const fs::path& path, std::string_view contents) {
  AtomicFile f(path);
  f.reserve(contents.size());
  f.stream().write(contents.data(), static_cast<std::streamsize>(contents.size()));
  f.commit();
}

}  // namespace isoforge
