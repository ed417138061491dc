// isoforge figures --out DIR [--only FIG...]: the chapter's figures as datasets, .glb files, PNG
// pictures (headless Chromium through the viewer) and one HTML page (docs/figures.md).

#include <fmt/core.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <sstream>

#include "commands.hpp"
#include "common.hpp"
#include "figures/figure.hpp"
#include "isoforge/core/error.hpp"
#include "isoforge/io/atomic_file.hpp"
#include "isoforge/io/gltf.hpp"
#include "progress_bar.hpp"

#ifndef ISOFORGE_SOURCE_DIR
#define ISOFORGE_SOURCE_DIR ""
#endif

namespace isoforge::cli {

namespace {

namespace fs = std::filesystem;
using figures::Figure;

// What one figure gave.
struct Done {
  const Figure* figure = nullptr;
  std::string stem;                // "fig_1_31"
  std::vector<std::string> files;  // relative to DIR
  std::string counts, check;
  bool ok = false;
  double ms = 0;
  std::string query;  // the viewer's parameters for this figure
  std::string png;    // "" = not rendered
  std::string render_note;
};

std::string extension_of(const Dataset& ds) {
  switch (ds.index()) {
    case 0: return ".vti";
    case 1: return ".vts";
    case 2: return ".vtp";
    default: return ".vtu";
  }
}

// Percent-encoding of a URL query value.
std::string url_encode(std::string_view s) {
  std::string out;
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (std::isalnum(u) || c == '-' || c == '_' || c == '.' || c == '~') {
      out += c;
    } else {
      out += fmt::format("%{:02X}", u);
    }
  }
  return out;
}

std::string html_escape(std::string_view s) {
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '&': out += "&amp;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string json_escape(std::string_view s) {
  std::string out;
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
  return out;
}

// The figure named on the command line: "1.31", "fig_1_31" or "1_31" (case-insensitive "A").
const Figure* find_figure(std::string name) {
  std::transform(name.begin(), name.end(), name.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (name.rfind("fig_", 0) == 0 || name.rfind("fig.", 0) == 0) name = name.substr(4);
  std::replace(name.begin(), name.end(), '_', '.');
  for (const Figure& f : figures::all()) {
    if (f.id == name) return &f;
  }
  return nullptr;
}

// The figure's meshes written as one .glb, coloured as the chapter colours them.
void write_picture(figures::Output& out, const fs::path& path) {
  std::vector<std::optional<GltfLegend>> legends;
  for (figures::Mesh& m : out.meshes) {
    std::optional<GltfLegend> legend;
    if (!m.color_by.empty()) {
      ColormapOptions co;
      co.map = m.map;
      co.range = m.range;
      const ColormapStats s = add_colors(m.data, m.color_by, co);
      GltfLegend l;
      l.array = m.color_by;
      l.colormap = to_string(m.map);
      l.min = s.range[0];
      l.max = s.range[1];
      l.colors = colormap_table(m.map, 16);
      legend = std::move(l);
    } else {
      DataArray colors("Colors", ScalarType::UInt8, 3, m.data.num_points());
      for (std::size_t i = 0; i < m.data.num_points(); ++i) {
        for (int c = 0; c < 3; ++c) colors.set(i, c, m.color[std::size_t(c)]);
      }
      m.data.point_data.add(std::move(colors));
    }
    legends.push_back(std::move(legend));
  }
  std::vector<GltfMesh> meshes;
  for (std::size_t i = 0; i < out.meshes.size(); ++i) {
    meshes.push_back(GltfMesh{out.meshes[i].name, out.meshes[i].data, legends[i], "Colors"});
  }
  GltfWriteOptions o;
  o.codec = GltfCodec::Draco;
  o.arrays = false;  // the picture needs positions, normals and colours only
  (void)write_gltf(meshes, path, o);
}

std::string viewer_query(const Figure& f, const figures::Output& out, const std::string& stem) {
  std::string q = "glb=" + url_encode("../" + stem + "/" + stem + ".glb");
  q += fmt::format("&view={:g},{:g},{:g}&up={:g},{:g},{:g}", f.view[0], f.view[1], f.view[2],
                   f.up[0], f.up[1], f.up[2]);
  std::map<double, std::vector<std::string>> by_opacity;
  for (const auto& m : out.meshes) {
    if (m.opacity < 1) q += "&opacity=" + url_encode(fmt::format("{}:{:g}", m.name, m.opacity));
  }
  return q;
}

// PATH lookup of a program. "" if not found.
std::string find_program(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::stringstream ss(path ? path : "");
  std::string dir;
  while (std::getline(ss, dir, ':')) {
    if (dir.empty()) continue;
    const fs::path p = fs::path(dir) / name;
    if (::access(p.c_str(), X_OK) == 0) return p.string();
  }
  return "";
}

std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (const char c : s) {
    if (c == '\'') {
      out += "'\\''";
    } else {
      out += c;
    }
  }
  return out + "'";
}

// The renderer script (viewer/render_figures.mjs beside viewer/node_modules).
fs::path find_renderer() {
  if (const char* env = std::getenv("ISOFORGE_FIGURES_RENDERER"); env && *env) return env;
  return fs::path(ISOFORGE_SOURCE_DIR) / "viewer" / "render_figures.mjs";
}

void write_text(const fs::path& path, const std::string& text) { write_file_atomic(path, text); }

std::string figures_json(const std::vector<Done>& done) {
  std::string j = "[\n";
  for (std::size_t i = 0; i < done.size(); ++i) {
    const Done& d = done[i];
    j += fmt::format("  {{\"id\": \"{}\", \"stem\": \"{}\", \"query\": \"{}\", \"ok\": {}}}{}\n",
                     json_escape(d.figure->id), d.stem, json_escape(d.query),
                     d.ok ? "true" : "false", i + 1 < done.size() ? "," : "");
  }
  return j + "]\n";
}

std::string index_html(const std::vector<Done>& done, bool rendered) {
  std::string h =
      "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
      "<title>isoforge: the chapter's figures</title>\n<link rel=\"icon\" href=\"data:,\">\n"
      "<style>\n"
      "body { font: 14px/1.45 system-ui, sans-serif; margin: 0 auto; max-width: 1100px; "
      "padding: 16px; color: #222; }\n"
      ".grid { display: grid; grid-template-columns: repeat(auto-fill, minmax(330px, 1fr)); "
      "gap: 18px; }\n"
      ".fig { border: 1px solid #ccd; border-radius: 6px; padding: 10px; background: #fafafc; }\n"
      ".fig img, .fig .none { width: 100%; aspect-ratio: 4 / 3; display: block; "
      "background: #1e2126; border-radius: 4px; }\n"
      ".fig .none { color: #bbb; display: flex; align-items: center; justify-content: center; }\n"
      ".fig h2 { font-size: 15px; margin: 0 0 4px; }\n"
      ".fig p { margin: 6px 0; }\n"
      ".num { font-size: 12px; color: #444; }\n.fail { color: #b00020; font-weight: 600; }\n"
      ".files { font-size: 12px; }\n#note { background: #fff4d6; padding: 6px 10px; "
      "border-radius: 4px; display: none; }\n"
      "</style>\n</head>\n<body>\n<h1>The chapter's figures, made by isoforge</h1>\n"
      "<p>Each figure below was computed by <code>isoforge figures</code> with the chapter's "
      "parameters (source: <code>src/cli/figures/</code>); the datasets are VTK XML files for "
      "ParaView, the <code>.glb</code> files open in any glTF viewer. "
      "See <code>docs/figures.md</code>.</p>\n"
      "<p id=\"note\">Opened from the file system: the pictures and numbers are here, but the "
      "interactive viewer needs a server. Run <code>isoforge view DIR</code> on this directory "
      "and open the address it prints.</p>\n<div class=\"grid\">\n";
  for (const Done& d : done) {
    const Figure& f = *d.figure;
    h += fmt::format("<div class=\"fig\" id=\"{}\">\n<h2>Fig. {} — {}</h2>\n", d.stem, f.id,
                     html_escape(f.title));
    if (!d.png.empty()) {
      h += fmt::format("<a class=\"viewer\" href=\"viewer/index.html?{}\"><img src=\"{}\" "
                       "alt=\"Fig. {}\" loading=\"lazy\"></a>\n",
                       html_escape(d.query), d.png, f.id);
    } else {
      h += fmt::format("<div class=\"none\">{}</div>\n",
                       html_escape(rendered ? "no picture: " + d.render_note
                                            : "no picture (rendering skipped)"));
    }
    h += fmt::format("<p>{}</p>\n", html_escape(f.caption));
    h += fmt::format("<p class=\"num\">{}<br>{}{}<br>{:.0f} ms</p>\n", html_escape(d.counts),
                     d.ok ? "" : "<span class=\"fail\">CHECK FAILED:</span> ",
                     html_escape(d.check), d.ms);
    h += "<p class=\"files\"><a class=\"viewer\" href=\"viewer/index.html?" +
         html_escape(d.query) + "\">open in the viewer</a> · files:";
    for (const auto& file : d.files) {
      h += fmt::format(" <a href=\"{}\">{}</a>", file, fs::path(file).filename().string());
    }
    h += "</p>\n</div>\n";
  }
  h += "</div>\n<script>\n"
       "if (location.protocol === 'file:') {\n"
       "  document.getElementById('note').style.display = 'block';\n"
       "  for (const a of document.querySelectorAll('a.viewer')) {\n"
       "    a.title = 'the viewer needs a server: isoforge view on this directory';\n"
       "  }\n"
       "}\n</script>\n</body>\n</html>\n";
  return h;
}

}  // namespace

void add_figures_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string out;
    std::vector<std::string> only;
    std::string data;
    bool no_render = false;
    bool list = false;
    std::string chromium = "/usr/bin/chromium";
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "figures", "The chapter's figures: datasets, .glb, PNG pictures and an HTML page");
  auto* out_opt = cmd->add_option("-o,--out", args->out, "Output directory (created; files in it are replaced)");
  cmd->add_option("--only", args->only, "Only these figures: 1.31 or fig_1_31 (see --list)");
  cmd->add_option("--data", args->data,
                  "The data directory (default: ./data, else the source tree's data/)");
  auto* no_render_opt = cmd->add_flag("--no-render", args->no_render, "No PNG pictures (no Chromium run)");
  auto* chromium_opt = cmd->add_option("--chromium", args->chromium, "Chromium for the pictures (default /usr/bin/chromium)");
  cmd->add_flag("--list", args->list, "List the figures and exit");
  cmd->footer(
      "Writes DIR/fig_1_NN/ (VTK XML datasets, fig_1_NN.glb, fig_1_NN.png), DIR/index.html\n"
      "(every figure with its caption, picture, numbers and a viewer link; open it from the\n"
      "file system, or run 'isoforge view DIR' for the interactive viewer) and prints one\n"
      "summary line per figure. Pictures need node, the viewer's npm packages (make deps) and\n"
      "Chromium; without them they are skipped with a message. Exit status 1 if a figure's\n"
      "check fails. See docs/figures.md.\n"
      "Examples:\n"
      "  isoforge figures --list\n"
      "  isoforge figures -o out/figs --only 1.24a 1.31 --no-render\n"
      "  isoforge view out/figs --for 1   (the gallery in the viewer, served for 1 second)");
  cmd->callback([args, out_opt, no_render_opt, chromium_opt, &ctx] {
    if (args->list) {
      for (const Figure& f : figures::all()) fmt::print("{:<6} {}\n", f.id, f.title);
      return;
    }
    require_meaningful(chromium_opt, !args->no_render, "does nothing with --no-render");
    (void)no_render_opt;
    std::vector<const Figure*> todo;
    for (const std::string& name : args->only) {
      const Figure* f = find_figure(name);
      if (!f) {
        std::string known;
        for (const Figure& g : figures::all()) known += " " + std::string(g.id);
        throw UsageError("--only: no figure '" + name + "' (known:" + known + ")");
      }
      if (std::find(todo.begin(), todo.end(), f) == todo.end()) todo.push_back(f);
    }
    if (todo.empty()) {
      for (const Figure& f : figures::all()) todo.push_back(&f);
    }
    if (out_opt->count() == 0) throw UsageError("--out: required (the output directory)");
    figures::Context fc;
    std::error_code ec;
    if (!args->data.empty()) {
      fc.data = args->data;
      if (!fs::is_directory(fc.data, ec)) throw UsageError("--data: " + args->data + ": not a directory");
    } else {
      fc.data = fs::is_directory("data", ec) ? fs::path("data") : fs::path(ISOFORGE_SOURCE_DIR) / "data";
    }
    const fs::path dir = args->out;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir)) {
      throw Error(args->out + ": cannot create the output directory: " + ec.message());
    }
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    const bool lines = !ctx.quiet && !bar.enabled();  // a line per figure when there is no bar
    std::vector<Done> done;
    const auto all_t0 = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < todo.size(); ++i) {
      const Figure& f = *todo[i];
      Done d;
      d.figure = &f;
      d.stem = figures::file_stem(f.id);
      bar.stage(fmt::format("[{}/{}] Fig. {}", i + 1, todo.size(), f.id));
      fc.progress = bar.callback();
      const auto t0 = std::chrono::steady_clock::now();
      figures::Output out = f.make(fc);
      d.ms = elapsed_ms(t0);
      const fs::path sub = dir / d.stem;
      fs::create_directories(sub, ec);
      if (ec) throw Error(sub.string() + ": cannot create the directory: " + ec.message());
      for (const auto& [name, ds] : out.datasets) {
        const std::string file = name + extension_of(ds);
        write(ds, sub / file);
        d.files.push_back(d.stem + "/" + file);
      }
      write_picture(out, sub / (d.stem + ".glb"));
      d.files.push_back(d.stem + "/" + d.stem + ".glb");
      d.counts = std::move(out.counts);
      d.check = std::move(out.check);
      d.ok = out.ok;
      d.query = viewer_query(f, out, d.stem);
      if (lines) {
        fmt::print(stderr, "[{}/{}] Fig. {:<6} {:>7.0f} ms  {}\n", i + 1, todo.size(), f.id, d.ms,
                   d.ok ? "ok" : "CHECK FAILED");
      }
      done.push_back(std::move(d));
    }
    bar.finish();
    write_text(dir / "figures.json", figures_json(done));

    // The viewer, copied beside the figures so that the page's links work from any static
    // server (isoforge view DIR).
    std::string looked_in;
    const fs::path viewer = find_viewer_dir(looked_in);
    std::string skip;
    if (viewer.empty()) {
      skip = "the viewer's files are not in " + looked_in + " (build the target 'viewer')";
    } else {
      fs::copy(viewer, dir / "viewer",
               fs::copy_options::recursive | fs::copy_options::overwrite_existing, ec);
      if (ec) throw Error((dir / "viewer").string() + ": cannot copy the viewer: " + ec.message());
    }
    bool rendered = false;
    double render_ms = 0;
    if (args->no_render) {
      skip = "--no-render";
    } else if (skip.empty()) {
      const std::string node = find_program("node");
      const fs::path script = find_renderer();
      if (node.empty()) {
        skip = "node (Node.js) is not installed (make deps)";
      } else if (!fs::is_regular_file(script, ec)) {
        skip = script.string() + " not found (set ISOFORGE_FIGURES_RENDERER)";
      } else if (!fs::is_directory(script.parent_path() / "node_modules" / "playwright-core", ec)) {
        skip = "the viewer's npm packages are not installed (make deps, or npm ci in viewer/)";
      } else if (::access(args->chromium.c_str(), X_OK) != 0) {
        skip = "no Chromium at " + args->chromium + " (install Debian's chromium: make deps)";
      } else {
        const auto t0 = std::chrono::steady_clock::now();
        const std::string command = shell_quote(node) + " " + shell_quote(script.string()) + " " +
                                    shell_quote(fs::absolute(dir).string()) + " " +
                                    shell_quote(args->chromium);
        bar.stage("rendering");
        std::FILE* p = ::popen(command.c_str(), "r");
        if (!p) throw Error("cannot run " + node + ": " + std::strerror(errno));
        std::map<std::string, std::pair<bool, std::string>> result;  // stem -> ok, note
        char buf[4096];
        std::size_t count = 0;
        std::string log;
        while (std::fgets(buf, sizeof buf, p)) {
          std::string line(buf);
          while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
          std::istringstream ls(line);
          std::string word, stem;
          ls >> word >> stem;
          std::string rest;
          std::getline(ls, rest);
          if (!rest.empty() && rest.front() == ' ') rest.erase(0, 1);
          if (word == "rendered" || word == "failed") {
            result[stem] = {word == "rendered", rest};
            bar.update(double(++count) / double(done.size()));
          } else {
            log += line + "\n";
          }
        }
        const int status = ::pclose(p);
        bar.finish();
        render_ms = elapsed_ms(t0);
        rendered = true;
        for (Done& d : done) {
          const auto it = result.find(d.stem);
          if (it != result.end() && it->second.first) {
            d.png = d.stem + "/" + d.stem + ".png";
            d.render_note = it->second.second;
          } else {
            d.render_note = it != result.end() ? it->second.second : "the renderer gave no picture";
          }
        }
        if (status != 0 && result.empty()) {
          warn("figures: the renderer failed: " + (log.empty() ? std::string("(no output)") : log));
        }
      }
    }
    write_text(dir / "index.html", index_html(done, rendered));

    // The summary table.
    fmt::print("{:<6} {:<44} {:>8}  {:<4} {}\n", "fig", "counts", "ms", "ok", "check");
    std::size_t failed = 0;
    for (const Done& d : done) {
      failed += d.ok ? 0 : 1;
      fmt::print("{:<6} {:<44} {:>8.0f}  {:<4} {}{}\n", d.figure->id, d.counts, d.ms,
                 d.ok ? "ok" : "FAIL", d.check,
                 !rendered ? "" : d.png.empty() ? " [no picture: " + d.render_note + "]"
                                                : " [png " + d.render_note + "]");
    }
    const double total = elapsed_ms(all_t0);
    if (!skip.empty()) {
      fmt::print("pictures skipped: {}\n", skip);
    } else {
      fmt::print("pictures: {:.0f} ms\n", render_ms);
    }
    fmt::print("{} figure(s), {} check(s) failed, {:.1f} s; open {}\n", done.size(), failed,
               total / 1000, (dir / "index.html").string());
    if (failed) throw Error(fmt::format("figures: {} figure check(s) failed (see the table)", failed));
    for (const Done& d : done) {
      if (rendered && d.png.empty()) {
        throw Error("figures: Fig. " + std::string(d.figure->id) + ": no picture: " + d.render_note);
      }
    }
  });
}

}  // namespace isoforge::cli
