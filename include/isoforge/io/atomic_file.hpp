#pragma once
/// \file
/// Atomic file output: write to a temporary file beside the target, rename on success.

#include <filesystem>
#include <fstream>
#include <string>

namespace isoforge {

/// Writes a file atomically. The data goes to a uniquely named temporary file in the target's
/// directory; `commit()` flushes it, checks for errors and renames it over the target. If
/// `commit()` is never reached (an exception, an early return) the destructor removes the
/// temporary file, so a failed write leaves no partial file and never clobbers an existing one.
///
/// \code
///   AtomicFile out(path);
///   out.stream() << "...";
///   out.commit();
/// \endcode
class AtomicFile {
 public:
  /// Creates the temporary file. \throw Error naming `target` if it cannot be created (e.g. the
  /// directory does not exist or is not writable).
  explicit AtomicFile(std::filesystem::path target);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  /// Binary output stream on the temporary file.
  [[nodiscard]] std::ofstream& stream() { return stream_; }
  /// Path of the temporary file, for libraries that insist on writing a path themselves
  /// (OpenVDB, Draco); the stream is closed first when this is called.
  [[nodiscard]] const std::filesystem::path& temp_path();
  [[nodiscard]] const std::filesystem::path& target() const { return target_; }

  /// Flushes, checks the stream state and renames onto the target.
  /// \throw Error naming the target if writing or renaming failed (the temp file is removed).
  void commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path temp_;
  std::ofstream stream_;
  bool committed_ = false;
};

/// Writes `contents` to `path` atomically. \throw Error on failure.
void write_file_atomic(const std::filesystem::path& path, std::string_view contents);

}  // namespace isoforge
