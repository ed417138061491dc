#pragma once
// The subcommands of isoforge-verify that serve the decimation benchmark
// (verify/bench/decimate.sh): one metric for every decimator's output, and the CGAL peer.

#include <string>
#include <vector>

namespace isoforge::verify {

struct DistanceCommand {
  std::string reference;                ///< the input of the decimation
  std::vector<std::string> meshes;      ///< the outputs to measure against it
  double spacing = 0;                   ///< sample spacing; 0 = half the reference's mean edge
  std::size_t max_samples = 2'000'000;  ///< about, per mesh (see bench_commands.cpp)
  bool check = false;                   ///< also the exact mesh checks of each output
};

/// `isoforge-verify distance REF MESH...`: one JSON line per mesh (see docs/verification.md).
/// Returns the exit status.
int run_distance(const DistanceCommand& command);

struct DecimateCommand {
  std::string input, output;
  std::size_t target = 0;     ///< triangles
  std::string policy = "gh";  ///< gh (Garland-Heckbert plane quadrics) or lt (Lindstrom-Turk)
};

/// `isoforge-verify decimate IN -o OUT --target N --policy gh|lt`: CGAL's edge collapse, one
/// JSON line. Returns the exit status.
int run_cgal_decimate(const DecimateCommand& command);

/// `isoforge-verify make-mesh KIND OUT`: writes one of the decimation inputs
/// (`decimation_input`). Returns the exit status.
int run_make_mesh(const std::string& kind, const std::string& output);

}  // namespace isoforge::verify
