#pragma once
// The catalogue of verification cases and the results they produce.

#include <functional>
#include <string>
#include <vector>

#include <fmt/core.h>

namespace isoforge::verify {

/// One measured property against its expectation.
struct Check {
  std::string name;
  std::string measured;
  std::string expected;  ///< the tolerance or exact value required
  bool pass = false;
};

/// A measured figure reported without a requirement (sizes, timings, context for the checks).
struct Note {
  std::string name;
  std::string value;
};

struct CaseResult {
  std::string name;
  std::string description;
  std::vector<Check> checks;
  std::vector<Note> notes;
  double seconds = 0;
  std::string error;  ///< an exception stopped the case (counts as a failure)
  [[nodiscard]] bool pass() const {
    if (!error.empty() || checks.empty()) return false;
    for (const auto& c : checks)
      if (!c.pass) return false;
    return true;
  }

  void equal(const std::string& what, auto measured, auto expected) {
    checks.push_back(
        {what, fmt::format("{}", measured), fmt::format("= {}", expected), measured == expected});
  }
  void at_most(const std::string& what, double measured, double limit) {
    checks.push_back({what, fmt::format("{:.6g}", measured), fmt::format("<= {:.6g}", limit),
                      measured <= limit});
  }
  void at_least(const std::string& what, double measured, double limit) {
    checks.push_back({what, fmt::format("{:.6g}", measured), fmt::format(">= {:.6g}", limit),
                      measured >= limit});
  }
  void is_true(const std::string& what, bool value) {
    checks.push_back({what, value ? "yes" : "no", "yes", value});
  }
  /// measured in [lo, hi].
  void within(const std::string& what, double measured, double lo, double hi) {
    checks.push_back({what, fmt::format("{:.4g}", measured),
                      fmt::format("in [{:.4g}, {:.4g}]", lo, hi),
                      measured >= lo && measured <= hi});
  }
  void note(const std::string& what, const std::string& value) { notes.push_back({what, value}); }
};

struct Case {
  std::string name;         ///< "group/name"
  std::string description;  ///< one line for --list and the report
  bool quick = false;       ///< part of --quick (runs under make test)
  std::function<void(CaseResult&)> run;
};

/// Registration functions, one per group of cases.
void add_io_cases(std::vector<Case>& cases);
void add_shape_cases(std::vector<Case>& cases);     ///< shape/, convergence/, dense-vs-sparse/
void add_volume_cases(std::vector<Case>& cases);    ///< random/, real/
void add_select_cases(std::vector<Case>& cases);    ///< select/, side/
void add_model_cases(std::vector<Case>& cases);     ///< model/ (distance fields, figures 1.25-1.28)
void add_decimate_cases(std::vector<Case>& cases);  ///< decimate/ (certified, compared with CGAL)
void add_probe_cases(std::vector<Case>& cases);     ///< probe/ (every cell type, linear fields)
void add_threshold_cases(std::vector<Case>& cases);  ///< surface/, threshold/
void add_glyph_cases(std::vector<Case>& cases);     ///< glyph/, normals/, tube/
void add_cut_cases(std::vector<Case>& cases);       ///< cut/, clip/ (on F = c, closed, conservative)

}  // namespace isoforge::verify
