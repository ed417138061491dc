#include "isoforge/io/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

#include "isoforge/core/error.hpp"

namespace isoforge {

AtomicFile::AtomicFile(std::filesystem::path target) : target_(std::move(target)) {
  std::filesystem::path dir = target_.parent_path();
  if (dir.empty()) dir = ".";
  std::string pattern = (dir / ("." + target_.filename().string() + ".tmp.XXXXXX")).string();
  int fd = ::mkstemp(pattern.data());
  if (fd < 0) {
    throw Error(target_.string() + ": cannot create a temporary file in '" + dir.string() +
                "': " + std::strerror(errno));
  }
  ::close(fd);
  temp_ = pattern;
  stream_.open(temp_, std::ios::binary | std::ios::trunc);
  if (!stream_) {
    std::error_code ec;
    std::filesystem::remove(temp_, ec);
    throw Error(target_.string() + ": cannot open temporary file for writing");
  }
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    if (stream_.is_open()) stream_.close();
    std::error_code ec;
    std::filesystem::remove(temp_, ec);
  }
}

const std::filesystem::path& AtomicFile::temp_path() {
  if (stream_.is_open()) stream_.close();
  return temp_;
}

void AtomicFile::commit() {
  if (committed_) return;
  bool ok = true;
  if (stream_.is_open()) {
    stream_.flush();
    ok = static_cast<bool>(stream_);
    stream_.close();
    ok = ok && !stream_.fail();
  }
  if (!ok) {
    std::error_code ec;
    std::filesystem::remove(temp_, ec);
    committed_ = true;  // nothing left to clean up
    throw Error(target_.string() + ": write failed (disk full or I/O error); the target was not changed");
  }
  // Give the file the permissions a plain open() would (mkstemp uses 0600).
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::chmod(temp_.c_str(), 0666 & ~mask);
  std::error_code ec;
  std::filesystem::rename(temp_, target_, ec);
  if (ec) {
    std::error_code ec2;
    std::filesystem::remove(temp_, ec2);
    committed_ = true;
    throw Error(target_.string() + ": cannot move the written file into place: " + ec.message());
  }
  committed_ = true;
}

void write_file_atomic(const std::filesystem::path& path, std::string_view contents) {
  AtomicFile f(path);
  f.stream().write(contents.data(), static_cast<std::streamsize>(contents.size()));
  f.commit();
}

}  // namespace isoforge
