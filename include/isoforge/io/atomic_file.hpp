#pragma once
/// \file
/// Atomic file output: write to a temporary file beside the target, rename on success.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <ostream>
#include <streambuf>
#include <string>
#include <string_view>

namespace isoforge {

/// Writes a file atomically. The data goes to a uniquely named temporary file
/// (`.NAME.tmp.XXXXXX`) in the target's directory, created when writing begins (the first call
/// of `stream()` or `temp_path()`); `commit()` flushes it, checks for errors and renames it over
/// the target. If `commit()` is never reached (an exception, an early return) the destructor
/// removes the temporary file, so a failed write leaves no partial file and never clobbers an
/// existing one; a program killed by a signal removes it with `remove_temporary_files()`.
///
/// - **Mode**: replacing a file keeps its permission bits; a new file gets those of a plain
///   `open(…, 0666)` under the umask.
/// - **Symbolic links**: a target that is a symbolic link (or a chain of them) is written
///   through: the file it points to is replaced, the link stays.
///
/// \code
///   AtomicFile out(path);
///   out.stream() << "...";
///   out.commit();
/// \endcode
class AtomicFile {
 public:
  /// Checks that the file can be created (`check_writable`); creates nothing yet.
  /// \throw Error naming `target` if its directory does not exist or is not writable.
  explicit AtomicFile(std::filesystem::path target);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  /// Binary output stream on the temporary file (created on the first call), seekable.
  /// \throw Error naming the target if it cannot be created.
  [[nodiscard]] std::ostream& stream();
  /// A hint that the file will be about `bytes` long. On ext4 and XFS, when that is at most a
  /// quarter of the free space, the disk space is then allocated up front (fallocate, the
  /// file's size unchanged), which makes the writes about a third cheaper than allocating as
  /// they go (docs/algorithms/reading_writing.md); `commit()` frees what was not written. Call it
  /// before the first `stream()`. Failures (no space for the estimate, another file system) are
  /// ignored: the writes report real errors as before.
  void reserve(std::uint64_t bytes) { reserve_ = bytes; }
  /// Path of the temporary file (created on the first call), for libraries that insist on
  /// writing a path themselves (OpenVDB, Draco); the stream is closed first.
  [[nodiscard]] const std::filesystem::path& temp_path();
  /// The path as given (possibly a symbolic link).
  [[nodiscard]] const std::filesystem::path& target() const { return target_; }

  /// Flushes, checks the stream state and renames onto the target (the file a symbolic link
  /// points to), with the mode described above.
  /// \throw Error naming the target if writing or renaming failed (the temp file is removed).
  void commit();

 private:
  void create_temp();
  /// Flushes and closes the stream (freeing unused reserved space); the error, or empty.
  std::string close_stream();

  std::filesystem::path target_;    // as given
  std::filesystem::path resolved_;  // target_ with symbolic links followed: what is replaced
  std::filesystem::path temp_;      // empty until writing begins
  std::unique_ptr<std::streambuf> buffer_;  // on the temporary file's descriptor
  std::ostream stream_{nullptr};
  int slot_ = -1;  // registry slot of temp_ (see remove_temporary_files)
  std::uint64_t reserve_ = 0;  // bytes to allocate when the file is created
  bool reserved_ = false;      // space may have been allocated beyond the end of the file
  bool committed_ = false;
};

/// Writes `contents` to `path` atomically. \throw Error on failure.
void write_file_atomic(const std::filesystem::path& path, std::string_view contents);

/// \throw Error "PATH: cannot create a file in 'DIR': REASON" unless the directory `path` would
/// be written in (through symbolic links) exists and is writable. Creates nothing: programs call
/// it before long work so that a bad output path fails at once.
void check_writable(const std::filesystem::path& path);

/// Removes (`unlink`) the temporary file of every `AtomicFile` of this process that is being
/// written and not committed. Async-signal-safe: meant for a SIGINT/SIGTERM handler, which then
/// re-raises the signal with its default action. The library installs no handler itself.
void remove_temporary_files() noexcept;

}  // namespace isoforge
