// isoforge-verify: the accuracy verification suite (see docs/verification.md).

#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <chrono>

#include "catalogue.hpp"
#include "isoforge/io/io.hpp"
#include "mesh_checks.hpp"
#include "report.hpp"

using namespace isoforge;
using namespace isoforge::verify;

namespace {

int run_cases(const std::vector<Case>& cases, const std::string& report_dir) {
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
      if (!ch.pass) fmt::print("    FAIL {}: measured {}, required {}\n", ch.name, ch.measured, ch.expected);
    }
    if (!r.error.empty()) fmt::print("    ERROR {}\n", r.error);
    results.push_back(std::move(r));
  }
  std::size_t passed = 0;
  for (const auto& r : results) passed += r.pass() ? 1 : 0;
  fmt::print("{} of {} cases passed\n", passed, results.size());
  if (!report_dir.empty()) {
    write_report(report_dir, results);
    fmt::print("report: {}/report.md, {}/report.json\n", report_dir, report_dir);
  }
  return passed == results.size() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"isoforge-verify: re-checks isoforge results with CGAL's exact predicates and "
               "against analytic truth", "isoforge-verify"};
  std::vector<Case> catalogue;
  add_io_cases(catalogue);

  bool list = false, all = false, quick = false;
  std::vector<std::string> names;
  std::string report_dir;
  app.add_flag("--list", list, "List the cases");
  app.add_flag("--all", all, "Run every case");
  app.add_flag("--quick", quick, "Run the quick subset (minutes; part of make test)");
  app.add_option("--case", names, "Run the named case(s)");
  app.add_option("--report", report_dir, "Write report.md and report.json into this directory");

  auto* mesh_cmd = app.add_subcommand("mesh", "Check a mesh file: closed, manifold, orientation, "
                                              "degenerate faces, self-intersections, genus, volume");
  std::string mesh_file;
  bool no_si = false;
  mesh_cmd->add_option("file", mesh_file, "Mesh file (.vtp .vtk .ply .off)")->required();
  mesh_cmd->add_flag("--no-self-intersections", no_si, "Skip the exact self-intersection test");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (*mesh_cmd) {
      const Dataset ds = read(mesh_file);
      const auto* pd = std::get_if<PolyData>(&ds);
      if (!pd) throw Error(mesh_file + ": is " + std::string(dataset_type_name(ds)) + ", not a polygonal mesh");
      MeshCheckOptions o;
      o.self_intersections = !no_si;
      fmt::print("{}\n{}", mesh_file, format_report(check_mesh(*pd, o)));
      return 0;
    }
    if (list) {
      for (const auto& c : catalogue) fmt::print("{:<40} {}{}\n", c.name, c.quick ? "[quick] " : "", c.description);
      return 0;
    }
    std::vector<Case> selected;
    for (const auto& c : catalogue) {
      bool named = std::find(names.begin(), names.end(), c.name) != names.end();
      if (all || (quick && c.quick) || named) selected.push_back(c);
    }
    for (const auto& n : names) {
      if (std::none_of(catalogue.begin(), catalogue.end(), [&](const Case& c) { return c.name == n; })) {
        throw Error("--case: no case named '" + n + "' (see --list)");
      }
    }
    if (selected.empty()) throw Error("nothing to run: give --all, --quick, --case NAME or --list");
    return run_cases(selected, report_dir);
  } catch (const Error& e) {
    fmt::print(stderr, "isoforge-verify: error: {}\n", e.what());
    return 2;
  }
}
