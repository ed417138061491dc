// A minimal static HTTP/1.1 server (see http_server.hpp).

#include "http_server.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <vector>

#include "isoforge/core/error.hpp"

namespace isoforge::cli {

namespace {

constexpr int kRequestTimeoutMs = 5000;      // a client that sends nothing is dropped
constexpr std::size_t kMaxRequestBytes = 16384;  // request line + headers

std::string content_type_of(const std::filesystem::path& file) {
  const std::string ext = file.extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js" || ext == ".mjs") return "text/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".json") return "application/json";
  if (ext == ".wasm") return "application/wasm";
  if (ext == ".glb") return "model/gltf-binary";
  if (ext == ".png") return "image/png";
  return "application/octet-stream";
}

// Writes all of `data`; false if the client went away.
bool send_all(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::send(fd, data, size, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    data += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

bool send_status(int fd, int code, const char* reason) {
  const std::string body = std::to_string(code) + " " + reason + "\n";
  const std::string head = "HTTP/1.1 " + std::to_string(code) + " " + reason +
                           "\r\nContent-Type: text/plain\r\nContent-Length: " +
                           std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n";
  return send_all(fd, head.data(), head.size()) && send_all(fd, body.data(), body.size());
}

}  // namespace

StaticServer::~StaticServer() {
  if (listen_fd_ >= 0) ::close(listen_fd_);
}

void StaticServer::add_file(const std::string& url, const std::filesystem::path& file) {
  entries_[url] = Entry{file, {}, content_type_of(file)};
}

void StaticServer::add_content(const std::string& url, std::string body, std::string content_type) {
  entries_[url] = Entry{{}, std::move(body), std::move(content_type)};
}

void StaticServer::add_directory(const std::string& prefix, const std::filesystem::path& dir) {
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    add_file(prefix + std::filesystem::relative(e.path(), dir).generic_string(), e.path());
  }
}

int StaticServer::listen(const std::string& host, int port) {
  const std::string where = host + ":" + std::to_string(port);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<std::uint16_t>(port));
  if (::inet_pton(AF_INET, host.c_str(), &addr.sin_addr) != 1) {
    throw Error(where + ": not an IPv4 address");
  }
  listen_fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (listen_fd_ < 0) throw Error(std::string("cannot create a socket: ") + std::strerror(errno));
  const int one = 1;
  ::setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  if (::bind(listen_fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    throw Error(where + ": cannot listen: " + std::strerror(errno));
  }
  if (::listen(listen_fd_, 64) != 0) throw Error(where + ": cannot listen: " + std::strerror(errno));
  socklen_t len = sizeof addr;
  ::getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&addr), &len);
  return ntohs(addr.sin_port);
}

void StaticServer::serve(int stop_fd, double seconds) {
  const auto end = std::chrono::steady_clock::now() +
                   std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                       std::chrono::duration<double>(seconds));
  for (;;) {
    int timeout_ms = -1;
    if (seconds > 0) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          end - std::chrono::steady_clock::now());
      if (left.count() <= 0) return;
      timeout_ms = static_cast<int>(std::min<long long>(left.count(), 1 << 30));
    }
    pollfd fds[2] = {{listen_fd_, POLLIN, 0}, {stop_fd, POLLIN, 0}};
    const int n = ::poll(fds, 2, timeout_ms);
    if (n < 0) {
      if (errno == EINTR) continue;  // the signal's byte is in the pipe: seen next round
      throw Error(std::string("poll failed: ") + std::strerror(errno));
    }
    if (fds[1].revents) return;
    if (fds[0].revents & POLLIN) {
      const int client = ::accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC);
      if (client < 0) continue;  // the client went away already, or EINTR
      timeval timeout{5, 0};  // a client that stops reading is dropped
      ::setsockopt(client, SOL_SOCKET, SO_SNDTIMEO, &timeout, sizeof timeout);
      handle(client);
      ::close(client);
    }
  }
}

void StaticServer::handle(int client) {
  ++requests_;
  // Read up to the end of the headers (the body of a GET is ignored).
  std::string request;
  char buf[4096];
  while (request.find("\r\n\r\n") == std::string::npos) {
    if (request.size() > kMaxRequestBytes) {
      send_status(client, 431, "Request Header Fields Too Large");
      return;
    }
    pollfd p{client, POLLIN, 0};
    if (::poll(&p, 1, kRequestTimeoutMs) <= 0) return;
    const ssize_t n = ::recv(client, buf, sizeof buf, 0);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    request.append(buf, static_cast<std::size_t>(n));
  }
  const std::size_t eol = request.find("\r\n");
  const std::string line = request.substr(0, eol);
  const std::size_t sp1 = line.find(' ');
  const std::size_t sp2 = sp1 == std::string::npos ? sp1 : line.find(' ', sp1 + 1);
  if (sp2 == std::string::npos) {
    send_status(client, 400, "Bad Request");
    return;
  }
  const std::string method = line.substr(0, sp1);
  std::string target = line.substr(sp1 + 1, sp2 - sp1 - 1);
  if (method != "GET" && method != "HEAD") {
    send_status(client, 405, "Method Not Allowed");
    return;
  }
  target = target.substr(0, target.find_first_of("?#"));
  if (target == "/") target = "/index.html";
  const auto it = entries_.find(target);  // exact match only: no path is ever built from it
  if (it == entries_.end()) {
    send_status(client, 404, "Not Found");
    return;
  }
  const Entry& e = it->second;
  std::ifstream in;
  std::size_t size = e.body.size();
  if (!e.file.empty()) {
    in.open(e.file, std::ios::binary);
    std::error_code ec;
    const auto s = std::filesystem::file_size(e.file, ec);
    if (!in || ec) {
      send_status(client, 404, "Not Found");
      return;
    }
    size = static_cast<std::size_t>(s);
  }
  const std::string head = "HTTP/1.1 200 OK\r\nContent-Type: " + e.content_type +
                           "\r\nContent-Length: " + std::to_string(size) +
                           "\r\nCache-Control: no-store\r\nConnection: close\r\n\r\n";
  if (!send_all(client, head.data(), head.size()) || method == "HEAD") return;
  if (e.file.empty()) {
    send_all(client, e.body.data(), e.body.size());
    return;
  }
  std::vector<char> chunk(std::size_t{1} << 16);
  while (in) {
    in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    const auto got = static_cast<std::size_t>(in.gcount());
    if (got == 0 || !send_all(client, chunk.data(), got)) return;
  }
}

}  // namespace isoforge::cli
