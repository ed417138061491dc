#pragma once
// The Draco options of the commands that write compressed meshes (convert to .drc; the glTF
// writer's Draco codec can share them): quantization bits or an error budget, level, method.

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "isoforge/io/draco.hpp"
#include "isoforge/io/gltf.hpp"

namespace isoforge::cli {

struct DracoCli {
  double max_error = 0, max_error_rel = 0;
  std::vector<std::string> array_errors;  // NAME=E
  int bits = 11, normal_bits = 8, color_bits = 8, texcoord_bits = 10, generic_bits = 8;
  int level = 7;
  bool sequential = false;
  std::vector<CLI::Option*> options;  // every option added, for require_meaningful
  CLI::Option *max_error_opt = nullptr, *max_error_rel_opt = nullptr, *bits_opt = nullptr;
  CLI::Option* level_opt = nullptr;  // not in `options`: VTK XML output takes it too
};

/// Adds --max-error, --max-error-rel, --array-error, --bits, --normal-bits, --color-bits,
/// --texcoord-bits, --generic-bits, --level, --sequential to `cmd`.
void add_draco_options(CLI::App& cmd, DracoCli& d);

/// \throw UsageError if a Draco option is given while `meaningful` is false (`why` says what
/// they apply to), or options contradict each other (--bits with a budget, two budgets), or
/// --level is above 10 for Draco output. (--level itself is checked by the caller: it also
/// serves VTK XML output.)
void check_draco_options(const DracoCli& d, bool meaningful, const std::string& why);

/// The library options (after check_draco_options). \throw UsageError for a malformed
/// --array-error.
[[nodiscard]] DracoWriteOptions draco_write_options(const DracoCli& d);

/// Tunes the C library's allocator of this process for Draco's many growing vectors (glibc: keep
/// freed memory instead of unmapping it). Call before reading the input.
void keep_freed_memory();

/// Prints what the verifying decode measured (stderr, unless quiet).
void print_draco_stats(const DracoStats& st, const std::string& path);
/// Prints what a glTF write did: counts, size, codec stats (Draco: per mesh as above).
void print_gltf_stats(const GltfWriteStats& st, const std::string& path);

}  // namespace isoforge::cli
