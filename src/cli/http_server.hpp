#pragma once
// A minimal static HTTP/1.1 server for `isoforge view` (POSIX sockets): GET and HEAD of a fixed
// set of URL paths, each mapped to a file or to bytes in memory. A request for anything else is
// 404 (there is no directory lookup, so no path can reach outside the set), other methods 405.
// One request per connection (Connection: close), handled in turn on the calling thread.

#include <filesystem>
#include <map>
#include <string>

namespace isoforge::cli {

class StaticServer {
 public:
  StaticServer() = default;
  ~StaticServer();
  StaticServer(const StaticServer&) = delete;
  StaticServer& operator=(const StaticServer&) = delete;

  /// Serves `file` at `url` (which starts with '/'); the content type comes from the extension.
  void add_file(const std::string& url, const std::filesystem::path& file);
  /// Serves `body` at `url` with `content_type`.
  void add_content(const std::string& url, std::string body, std::string content_type);
  /// Every regular file under `dir` at `prefix` + its relative path ("/" + "three/build/x.js").
  void add_directory(const std::string& prefix, const std::filesystem::path& dir);

  /// Binds to `host` (an IPv4 address) and `port` (0: a free one) and listens.
  /// \throw Error naming the address if that fails. Returns the bound port.
  int listen(const std::string& host, int port);

  /// Serves until a byte can be read from `stop_fd` (a self-pipe written by a signal handler),
  /// or for `seconds` when it is > 0. \throw Error if the listening socket fails.
  void serve(int stop_fd, double seconds = 0);

  /// Number of requests answered (any status).
  [[nodiscard]] std::size_t requests() const { return requests_; }

 private:
  struct Entry {
    std::filesystem::path file;  // empty: `body`
    std::string body;
    std::string content_type;
  };
  void handle(int client);

  std::map<std::string, Entry> entries_;
  int listen_fd_ = -1;
  std::size_t requests_ = 0;
};

}  // namespace isoforge::cli
