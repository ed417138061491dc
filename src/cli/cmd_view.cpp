// isoforge view FILE...: shows files in the browser viewer (viewer/), served on 127.0.0.1.

#include <fcntl.h>
#include <signal.h>
#include <poll.h>
#include <stdlib.h>
#include <unistd.h>

#include <fmt/core.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <memory>

#include "commands.hpp"
#include "common.hpp"
#include "http_server.hpp"
#include "isoforge/io/gltf.hpp"
#include "isoforge/io/io.hpp"
#include "progress_bar.hpp"

namespace isoforge::cli {

namespace {

namespace fs = std::filesystem;

// SIGINT/SIGTERM/SIGHUP write a byte here; the server loop and the conversions watch it.
int g_stop_pipe[2] = {-1, -1};

void on_stop_signal(int) {
  const int saved = errno;
  const char byte = 1;
  [[maybe_unused]] const auto n = ::write(g_stop_pipe[1], &byte, 1);
  errno = saved;
}

// Installs on_stop_signal for the command's lifetime; restores the previous handlers after.
class StopSignals {
 public:
  StopSignals() {
    if (::pipe2(g_stop_pipe, O_CLOEXEC | O_NONBLOCK) != 0) {
      throw Error(std::string("cannot create a pipe: ") + std::strerror(errno));
    }
    for (int i = 0; i < 3; ++i) {
      struct sigaction sa {};
      sa.sa_handler = on_stop_signal;
      ::sigemptyset(&sa.sa_mask);
      ::sigaction(kSignals[i], &sa, &old_[i]);
    }
  }
  ~StopSignals() {
    for (int i = 0; i < 3; ++i) ::sigaction(kSignals[i], &old_[i], nullptr);
    ::close(g_stop_pipe[0]);
    ::close(g_stop_pipe[1]);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
  [[nodiscard]] static bool requested() {
    pollfd p{g_stop_pipe[0], POLLIN, 0};
    return ::poll(&p, 1, 0) > 0;
  }

 private:
  static constexpr int kSignals[3] = {SIGINT, SIGTERM, SIGHUP};
  struct sigaction old_[3] {};
};

// A fresh temporary directory, removed with its contents at the end.
class TempDir {
 public:
  TempDir() {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = (tmp && *tmp ? std::string(tmp) : std::string("/tmp")) + "/isoforge-view-XXXXXX";
    if (!::mkdtemp(pattern.data())) {
      throw Error(pattern + ": cannot create a temporary directory: " + std::strerror(errno));
    }
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  [[nodiscard]] const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// The viewer's files, or an error saying how to get them.
fs::path viewer_dir() {
  std::string looked_in;
  fs::path dir = find_viewer_dir(looked_in);
  if (dir.empty()) {
    throw Error("the viewer's files (index.html and three.js) are not in " + looked_in +
                ": build the target 'viewer' (it runs npm ci in viewer/), or set "
                "ISOFORGE_VIEWER_DIR");
  }
  return dir;
}

std::string json_string(std::string_view s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      out += fmt::format("\\u{:04x}", static_cast<unsigned>(c));
    } else {
      out += c;
    }
  }
  return out + "\"";
}

// A file name safe in a URL path: letters, digits, '.', '-', '_' (others become '_').
std::string url_name(std::string_view name) {
  std::string out;
  for (const char c : name) {
    const auto u = static_cast<unsigned char>(c);
    out += std::isalnum(u) || c == '.' || c == '-' || c == '_' ? c : '_';
  }
  return out.empty() ? "file" : out;
}

}  // namespace

void add_view_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::vector<std::string> files;
    std::int64_t port = 0;
    std::string codec = "none";
    double seconds = 0;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("view", "Show meshes in the browser viewer (three.js), served "
                                         "on 127.0.0.1");
  cmd->add_option("files", args->files, "Files to show: .glb as they are; any polygonal data "
                                        "(.vtp .vtk .ply .off ...) is converted to .glb first; "
                                        "or one directory with an index.html (a figure gallery "
                                        "of 'isoforge figures'), served as it is")
      ->required();
  cmd->add_option("--port", args->port, "TCP port on 127.0.0.1 (0: a free one)")
      ->transform(integer_in(0, 65535));
  cmd->add_option("--codec", args->codec, "Codec of the converted files: none (fastest to load), meshopt or draco")
      ->check(CLI::IsMember({"none", "meshopt", "draco"}));
  cmd->add_option("--for", args->seconds,
                  "Stop by itself after this many seconds (> 0; for scripts); default: until Ctrl-C")
      ->check(positive_number());
  cmd->footer(
      "Prints the page's URL on stdout (open it in a browser) and serves the viewer and the\n"
      "files until Ctrl-C (SIGINT) or SIGTERM, then removes the converted files and exits 0.\n"
      "Only GET of the page, its scripts and the given files is answered. The page has a\n"
      "mesh list with visibility toggles, orbit controls, a wireframe toggle, the colour\n"
      "legend of coloured meshes and a screenshot button (see docs/viewer.md).\n"
      "Examples:\n"
      "  isoforge view data/bunny.ply data/fran_cut.vtk --for 2   (serves for 2 seconds, then stops)");
  cmd->callback([args, &ctx] {
    const fs::path assets = viewer_dir();
    StopSignals stop;
    StaticServer server;
    // A directory: its files as they are (the figure gallery; its viewer/ is the viewer's copy).
    if (std::error_code ec; args->files.size() == 1 && fs::is_directory(args->files[0], ec)) {
      const fs::path dir = args->files[0];
      if (!fs::is_regular_file(dir / "index.html", ec)) {
        throw Error(dir.string() + ": a directory without index.html (give files, or the output "
                                   "directory of 'isoforge figures')");
      }
      server.add_directory("/", dir);
      if (!fs::is_directory(dir / "viewer", ec)) server.add_directory("/viewer/", assets);
      const int port = server.listen("127.0.0.1", static_cast<int>(args->port));
      fmt::print("http://127.0.0.1:{}/\n", port);
      std::fflush(stdout);
      if (!ctx.quiet) fmt::print(stderr, "serving {}; Ctrl-C stops\n", dir.string());
      server.serve(g_stop_pipe[0], args->seconds);
      if (!ctx.quiet) fmt::print(stderr, "stopped after {} request(s)\n", server.requests());
      return;
    }
    TempDir temp;
    server.add_directory("/", assets);
    std::string list = "[";
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    for (std::size_t i = 0; i < args->files.size(); ++i) {
      const fs::path in = args->files[i];
      fs::path glb = in;
      if (format_of(in.string()) != FileFormat::Glb) {
        bar.stage("reading");
        const PolyData pd = read_polydata(in.string(), bar, "view: only polygonal data can be shown");
        glb = temp.path() / (std::to_string(i) + ".glb");
        GltfWriteOptions o;
        o.codec = gltf_codec_from_name(args->codec);
        const GltfMesh mesh{in.stem().string(), pd};
        (void)write_gltf(std::span(&mesh, 1), glb, o);
      } else {
        // Readable and a binary glTF at all (the page reports anything deeper).
        const auto bytes = read_file_bytes(in);
        if (bytes.size() < 12 || std::memcmp(bytes.data(), "glTF", 4) != 0) {
          throw Error(in.string() + ": byte 0: not a binary glTF file (no 'glTF' magic)");
        }
      }
      if (StopSignals::requested()) return;
      const std::string name = in.stem().string() + ".glb";
      const std::string url = "files/" + std::to_string(i) + "/" + url_name(name);
      server.add_file("/" + url, glb);
      list += (i ? "," : "") + fmt::format("{{\"name\":{},\"url\":{}}}", json_string(name), json_string(url));
    }
    bar.finish();
    server.add_content("/files.json", list + "]", "application/json");
    const int port = server.listen("127.0.0.1", static_cast<int>(args->port));
    fmt::print("http://127.0.0.1:{}/\n", port);
    std::fflush(stdout);
    if (!ctx.quiet) fmt::print(stderr, "serving {} file(s); Ctrl-C stops\n", args->files.size());
    server.serve(g_stop_pipe[0], args->seconds);
    if (!ctx.quiet) fmt::print(stderr, "stopped after {} request(s)\n", server.requests());
  });
}

}  // namespace isoforge::cli
