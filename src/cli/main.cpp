// The isoforge command: one subcommand per algorithm (CLI11).

#include <fmt/core.h>

#include <tbb/global_control.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <csignal>
#include <cstdio>
#include <exception>
#include <functional>
#include <new>
#include <optional>
#include <string>
#include <string_view>

#include "commands.hpp"
#include "common.hpp"
#include "isoforge/core/error.hpp"
#include "isoforge/io/atomic_file.hpp"
#include "isoforge/version.hpp"

namespace {

constexpr std::int64_t kMaxThreads = 4096;  // far above any machine's cores; a typo guard

// The deepest subcommand named on the command line ("" if none), for the usage hint.
std::string parsed_subcommand(const CLI::App& app) {
  std::string path;
  const CLI::App* a = &app;
  while (!a->get_subcommands().empty()) {
    a = a->get_subcommands().front();
    path += " " + a->get_name();
  }
  return path;
}

// Every error is printed on one line: line breaks become spaces and other control bytes (a NUL
// quoted from a file, an escape sequence) are shown as \xNN.
std::string one_line(std::string_view message) {
  std::string out;
  for (const char c : message) {
    if (c == '\n' || c == '\r' || c == '\t') {
      out += ' ';
    } else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      out += fmt::format("\\x{:02x}", static_cast<unsigned char>(c));
    } else {
      out += c;
    }
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

// SIGINT, SIGTERM, SIGHUP: remove the temporary file being written (an output is renamed into
// place only when complete, so there is no partial output to remove), then die of the signal
// with its default action, so that the exit status says which one.
void on_fatal_signal(int sig) {
  isoforge::remove_temporary_files();
  ::signal(sig, SIG_DFL);
  ::raise(sig);  // delivered when the handler returns (the signal is blocked until then)
}

void install_signal_handlers() {
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction old {};
    // Inherited as ignored (nohup, a background job of a script): keep ignoring it.
    if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
    struct sigaction sa {};
    sa.sa_handler = on_fatal_signal;
    ::sigemptyset(&sa.sa_mask);
    ::sigaction(sig, &sa, nullptr);
  }
}

// No option or argument takes an empty value: `-a ''` is a mistake (an unset shell variable),
// never "not given". A flag given both ways (`--cap --no-cap`) is a contradiction, not "the last
// one wins".
void reject_empty_and_contradictory_values(const CLI::App& app) {
  for (const CLI::App* a = &app; a != nullptr;) {
    for (const CLI::Option* opt : a->get_options()) {
      if (opt->count() == 0) continue;
      const auto& results = opt->results();
      if (!opt->get_fnames().empty() && opt->get_expected_min() == 0) {  // a flag
        if (std::adjacent_find(results.begin(), results.end(), std::not_equal_to<>()) !=
            results.end()) {
          std::string names;  // "--cap, --no-cap": the names without CLI11's "{false}"
          bool skip = false;
          for (const char c : opt->get_name(false, true)) {
            skip = (skip || c == '{') && c != '}';
            if (!skip && c != '}') names += c == ',' ? std::string(", ") : std::string(1, c);
          }
          throw CLI::ValidationError(opt->get_name(), "given both ways (" + names + ")");
        }
        continue;
      }
      for (const std::string& value : results) {
        if (value.empty())
          throw CLI::ValidationError(opt->get_name(), "an empty value is not allowed");
      }
    }
    const auto subs = a->get_subcommands();
    a = subs.empty() ? nullptr : subs.front();
  }
}

}  // namespace

int main(int argc, char** argv) {
  using namespace isoforge::cli;
#if defined(__x86_64__)
  if (!__builtin_cpu_supports("popcnt") || !__builtin_cpu_supports("sse4.2")) {
    fmt::print(stderr, "isoforge: error: this build needs an x86-64-v2 CPU (POPCNT, SSE4.2); "
                       "rebuild with -DISOFORGE_X86_64_V2=OFF\n");
    return kExitError;
  }
#endif
  install_signal_handlers();
  CLI::App app{
      "isoforge: scientific visualization algorithms (contouring, implicit modeling, cutting,\n"
      "probing, decimation) on VTK, PLY, PLOT3D, NRRD and OpenVDB data.\n"
      "Run 'isoforge SUBCOMMAND --help' for the options and examples of each subcommand.",
      "isoforge"};
  app.set_version_flag("--version", std::string(isoforge::kVersion));
  app.require_subcommand(1);
  app.footer(
      "Exit status: 0 success (also --help, --version); 1 the work failed (an unreadable or\n"
      "invalid input file, not enough memory, an output that cannot be written); 2 usage error\n"
      "(an unknown, missing, malformed, out-of-range or contradictory option); 3 internal error\n"
      "(a bug). Every error is one line on stderr: 'isoforge: error: MESSAGE'.");
  Context ctx;
  app.fallthrough();  // global options may also follow the subcommand
  app.add_flag("-q,--quiet", ctx.quiet, "No progress bar or informational messages on stderr");
  std::int64_t threads = 0;
  app.add_option("--threads", threads,
                 "Worker threads for every subcommand (default: all cores); results do not "
                 "depend on it")
      ->transform(integer_in(1, kMaxThreads));
  // Set once the whole command line is parsed and before the subcommand runs; TBB (and OpenVDB,
  // which uses TBB) then never runs more than `threads` workers.
  std::optional<tbb::global_control> thread_limit;
  app.parse_complete_callback([&] {
    reject_empty_and_contradictory_values(app);
    if (threads > 0) {
      thread_limit.emplace(tbb::global_control::max_allowed_parallelism,
                           static_cast<std::size_t>(threads));
    }
  });
  add_info_command(app, ctx);
  add_convert_command(app, ctx);
  add_sample_command(app, ctx);
  add_select_command(app, ctx);
  add_contour_command(app, ctx);
  add_distance_command(app, ctx);
  add_offset_command(app, ctx);
  add_csg_command(app, ctx);
  add_attractor_command(app, ctx);
  add_point_load_command(app, ctx);
  add_decimate_command(app, ctx);
  add_fit_command(app, ctx);
  add_view_command(app, ctx);
  add_colormap_command(app, ctx);
  add_probe_command(app, ctx);
  add_subsample_command(app, ctx);
  add_threshold_command(app, ctx);
  add_surface_command(app, ctx);
  add_elevation_command(app, ctx);
  add_warp_command(app, ctx);
  add_gradient_command(app, ctx);
  add_calc_command(app, ctx);
  add_glyph_command(app, ctx);
  add_tensor_glyph_command(app, ctx);
  add_normals_command(app, ctx);
  add_tube_command(app, ctx);
  add_streamlines_command(app, ctx);
  add_cut_command(app, ctx);
  add_clip_command(app, ctx);
  add_figures_command(app, ctx);
  add_xml_compression_options(app);  // --compressor/--level on every subcommand writing VTK XML
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help, --version
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    const std::string sub = parsed_subcommand(app);
    fmt::print(stderr, "isoforge: error: {}{} (see 'isoforge{} --help')\n",
               sub.empty() ? "" : sub.substr(1) + ": ", one_line(e.what()), sub);
    return kExitUsage;
  } catch (const isoforge::Error& e) {
    fmt::print(stderr, "isoforge: error: {}\n", one_line(e.what()));
    return kExitError;
  } catch (const std::bad_alloc&) {
    fmt::print(stderr, "isoforge: error: out of memory\n");
    return kExitError;
  } catch (const std::exception& e) {
    fmt::print(stderr, "isoforge: error: internal error: {}\n", one_line(e.what()));
    return kExitInternal;
  }
  return kExitOk;
}
