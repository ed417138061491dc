// isoforge-verify: the accuracy verification suite (see docs/verification.md).

#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>

#include "accuracy.hpp"
#include "bench_commands.hpp"
#include "catalogue.hpp"
#include "decimate_inputs.hpp"
#include "isoforge/implicit/parse.hpp"
#include "isoforge/io/io.hpp"
#include "isoforge/version.hpp"
#include "mesh_checks.hpp"
#include "report.hpp"

using namespace isoforge;
using namespace isoforge::verify;

namespace {

int run_cases(const std::vector<Case>& cases, const std::string& report_dir, bool verbose,
              const std::string& command) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<CaseResult> results;
  for (const auto& c : cases) {
    CaseResult r;
    r.name = c.name;
    r.description = c.description;
    const auto t0 = std::chrono::steady_clock::now();
    try {
      c.run(r);
    } catch (const std::exception& e) {
      r.error = e.what();
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    fmt::print("{:<40} {:>4} checks  {:7.2f} s  {}\n", r.name, r.checks.size(), r.seconds,
               r.pass() ? "pass" : "FAIL");
    for (const auto& ch : r.checks) {
      if (!ch.pass || verbose) {
        fmt::print("    {} {}: measured {}, required {}\n", ch.pass ? "pass" : "FAIL", ch.name,
                   ch.measured, ch.expected);
      }
    }
    if (verbose) {
      for (const auto& n : r.notes) fmt::print("    note {}: {}\n", n.name, n.value);
    }
    if (!r.error.empty()) fmt::print("    ERROR {}\n", r.error);
    std::fflush(stdout);
    results.push_back(std::move(r));
  }
  std::size_t passed = 0;
  for (const auto& r : results) passed += r.pass() ? 1 : 0;
  const double total =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  fmt::print("{} of {} cases passed ({:.1f} s)\n", passed, results.size(), total);
  if (!report_dir.empty()) {
    write_report(report_dir, results, {command, total});
    fmt::print("report: {}/report.md, {}/report.json\n", report_dir, report_dir);
  }
  return passed == results.size() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "isoforge-verify: re-checks isoforge results with CGAL's exact predicates and "
      "against analytic truth",
      "isoforge-verify"};
  std::vector<Case> catalogue;
  add_shape_cases(catalogue);
  add_volume_cases(catalogue);
  add_select_cases(catalogue);
  add_threshold_cases(catalogue);
  add_io_cases(catalogue);
  add_model_cases(catalogue);
  add_decimate_cases(catalogue);
  add_probe_cases(catalogue);
  add_glyph_cases(catalogue);
  add_cut_cases(catalogue);

  app.set_version_flag("--version", std::string(kVersion));
  bool list = false, all = false, quick = false, verbose = false;
  std::vector<std::string> names;
  std::string report_dir;
  app.add_flag("--list", list, "List the cases");
  app.add_flag("--all", all, "Run every case");
  app.add_flag("--quick", quick, "Run the quick subset (about 20 s; part of make test)");
  app.add_option("--case", names, "Run the named case(s) or group(s), e.g. shape/torus");
  app.add_option("--report", report_dir, "Write report.md and report.json into this directory");
  app.add_flag("-v,--verbose", verbose, "Print every check and note, not only failures");

  auto* mesh_cmd = app.add_subcommand("mesh",
                                      "Check a mesh file: closed, manifold, orientation, "
                                      "degenerate faces, self-intersections, genus, volume");
  std::string mesh_file, compare_file, implicit;
  std::vector<std::string> required;
  double spacing = 0;
  bool no_si = false;
  mesh_cmd->add_option("file", mesh_file, "Mesh file (.vtp .vtk .ply .off)")->required();
  mesh_cmd->add_flag("--no-self-intersections", no_si, "Skip the exact self-intersection test");
  mesh_cmd
      ->add_option("--require", required,
                   "Exit with status 1, naming the failures, unless these checks pass "
                   "(comma-separated: closed,manifold,oriented,no-self-intersections)")
      ->delimiter(',')
      ->check(CLI::IsMember(mesh_requirement_names()));
  mesh_cmd->add_option("--compare", compare_file,
                       "Also measure the distance both ways to this mesh (AABB-tree sampling)");
  mesh_cmd->add_option("--implicit", implicit,
                       "Also measure |F| over the mesh for this implicit function (an exact "
                       "distance for sphere, torus, plane, box, ...; see docs/implicit.md)");
  mesh_cmd->add_option("--spacing", spacing,
                       "Sample spacing for --compare/--implicit (default: 1/4 of the mean edge)");
  auto* distance_cmd = app.add_subcommand(
      "distance",
      "Distance of meshes to a reference (approximate Hausdorff and RMS, absolute and relative "
      "to the reference's diagonal): one JSON line per mesh");
  DistanceCommand distance;
  distance_cmd
      ->add_option("reference", distance.reference,
                   "The reference mesh (e.g. the input of a decimation)")
      ->required();
  distance_cmd->add_option("meshes", distance.meshes, "Meshes to measure against it")->required();
  distance_cmd->add_option("--spacing", distance.spacing,
                           "Sample spacing (default: 1/2 of the reference's mean edge)");
  distance_cmd->add_option("--max-samples", distance.max_samples,
                           "About this many samples per mesh at most (default 2e6)");
  distance_cmd->add_flag("--check", distance.check,
                         "Also the exact mesh checks of each mesh (self-intersections, manifold, "
                         "borders, genus)");
  auto* decimate_cmd = app.add_subcommand(
      "decimate",
      "CGAL's edge-collapse simplification to a face count (the benchmark's CGAL peer): one "
      "JSON line");
  DecimateCommand decimate;
  decimate_cmd->add_option("input", decimate.input, "Mesh file")->required();
  decimate_cmd->add_option("-o,--output", decimate.output, "Output mesh file")->required();
  decimate_cmd->add_option("--target", decimate.target, "Target triangle count")->required();
  decimate_cmd
      ->add_option("--policy", decimate.policy,
                   "gh: Garland-Heckbert plane quadrics; lt: Lindstrom-Turk")
      ->check(CLI::IsMember({"gh", "lt"}));
  auto* make_mesh_cmd = app.add_subcommand("make-mesh",
                                           "Write an input of the decimation cases (bunny, headsq, "
                                           "noisy-sphere, open-bunny, glued-spheres)");
  std::string make_mesh_kind, make_mesh_out;
  make_mesh_cmd->add_option("kind", make_mesh_kind, "What to build")
      ->required()
      ->check(CLI::IsMember(decimation_input_kinds()));
  make_mesh_cmd->add_option("output", make_mesh_out, "Output mesh file")->required();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;  // --help, --version; else a usage error
  }
  try {
    if (*distance_cmd) return run_distance(distance);
    if (*decimate_cmd) return run_cgal_decimate(decimate);
    if (*make_mesh_cmd) return run_make_mesh(make_mesh_kind, make_mesh_out);
    if (*mesh_cmd) {
      const Dataset ds = read(mesh_file);
      const auto* pd = std::get_if<PolyData>(&ds);
      if (!pd)
        throw Error(mesh_file + ": is " + std::string(dataset_type_name(ds)) +
                    ", not a polygonal mesh");
      if (no_si &&
          std::find(required.begin(), required.end(), "no-self-intersections") != required.end()) {
        throw Error("--require no-self-intersections contradicts --no-self-intersections");
      }
      MeshCheckOptions o;
      o.self_intersections = !no_si;
      const MeshReport report = check_mesh(*pd, o);
      fmt::print("{}\n{}", mesh_file, format_report(report));
      if (spacing <= 0) spacing = 0.25 * mean_edge_length(*pd);
      if (!implicit.empty()) {
        const ImplicitFunction f = parse_implicit(implicit);
        const Samples s = sample_mesh(*pd, spacing);
        double worst = 0, sum = 0, wsum = 0;
        for (std::size_t i = 0; i < s.points.size(); ++i) {
          const double v = std::abs(f.value(s.points[i]));
          worst = std::max(worst, v);
          sum += s.weights[i] * v * v;
          wsum += s.weights[i];
        }
        fmt::print("|F| over {} samples (spacing {:.4g}): max {:.6g}  RMS {:.6g}\n",
                   s.points.size(), spacing, worst, wsum > 0 ? std::sqrt(sum / wsum) : 0.0);
      }
      if (!compare_file.empty()) {
        const Dataset other = read(compare_file);
        const auto* po = std::get_if<PolyData>(&other);
        if (!po) throw Error(compare_file + ": not a polygonal mesh");
        const DistanceReport d = mesh_to_mesh_distance(*pd, *po, spacing);
        fmt::print(
            "distance to {} (spacing {:.4g}):\n  this -> other: max {:.6g}  RMS {:.6g} "
            "({} samples)\n  other -> this: max {:.6g}  RMS {:.6g} ({} samples)\n"
            "  Hausdorff (approximate, from samples): {:.6g}\n",
            compare_file, spacing, d.max_a_to_b, d.rms_a_to_b, d.samples_a, d.max_b_to_a,
            d.rms_b_to_a, d.samples_b, d.hausdorff());
      }
      if (required.empty()) return 0;
      const std::vector<std::string> failed = failed_requirements(report, required);
      if (!failed.empty()) {
        std::string list;
        for (const auto& f : failed) list += (list.empty() ? "" : ", ") + f;
        std::fflush(stdout);
        fmt::print(stderr, "isoforge-verify: {}: required checks failed: {}\n", mesh_file, list);
        return 1;
      }
      std::string list;
      for (const auto& n : required) list += (list.empty() ? "" : ", ") + n;
      fmt::print("required checks passed: {}\n", list);
      return 0;
    }
    if (list) {
      for (const auto& c : catalogue)
        fmt::print("{:<40} {}{}\n", c.name, c.quick ? "[quick] " : "", c.description);
      return 0;
    }
    // A --case name selects that case, or every case under it as a group ("shape/torus").
    const auto matches = [](const std::string& name, const std::string& pattern) {
      return name == pattern || (name.size() > pattern.size() && name.starts_with(pattern) &&
                                 (pattern.back() == '/' || name[pattern.size()] == '/'));
    };
    std::vector<Case> selected;
    for (const auto& c : catalogue) {
      const bool named = std::any_of(names.begin(), names.end(),
                                     [&](const auto& n) { return matches(c.name, n); });
      if (all || (quick && c.quick) || named) selected.push_back(c);
    }
    for (const auto& n : names) {
      if (std::none_of(catalogue.begin(), catalogue.end(),
                       [&](const Case& c) { return matches(c.name, n); })) {
        throw Error("--case: no case or group named '" + n + "' (see --list)");
      }
    }
    if (selected.empty()) throw Error("nothing to run: give --all, --quick, --case NAME or --list");
    std::string command = "isoforge-verify";
    for (int i = 1; i < argc; ++i) command += std::string(" ") + argv[i];
    return run_cases(selected, report_dir, verbose, command);
  } catch (const Error& e) {
    fmt::print(stderr, "isoforge-verify: error: {}\n", e.what());
    return 2;
  }
}
