// The verification report: report.md for people (summary, failures, a table of every check
// with measured and required values, then the cases with their notes) and report.json with the
// same data for tools.

#include "report.hpp"

#include <fmt/core.h>

#include <ctime>

#include "isoforge/io/atomic_file.hpp"
#include "isoforge/version.hpp"

namespace isoforge::verify {

namespace {

std::string json_escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '"':
        o += "\\\"";
        break;
      case '\\':
        o += "\\\\";
        break;
      case '\n':
        o += "\\n";
        break;
      case '\t':
        o += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          o += fmt::format("\\u{:04x}", static_cast<int>(c));
        } else {
          o += c;
        }
    }
  }
  return o;
}

std::string md_cell(const std::string& s) {
  std::string o;
  for (char c : s)
    o += (c == '|') ? std::string("\\|") : (c == '\n' ? std::string(" ") : std::string(1, c));
  return o;
}

}  // namespace

void write_report(const std::filesystem::path& dir, const std::vector<CaseResult>& results,
                  const RunInfo& info) {
  std::filesystem::create_directories(dir);
  std::size_t passed = 0, checks = 0, failed_checks = 0;
  for (const auto& r : results) {
    passed += r.pass() ? 1 : 0;
    checks += r.checks.size();
    for (const auto& c : r.checks) failed_checks += c.pass ? 0 : 1;
  }

  std::string md;
  md += fmt::format(
      "# isoforge verification report\n\nisoforge {} — **{} of {} cases passed** "
      "({} checks, {} failed)",
      kVersion, passed, results.size(), checks, failed_checks);
  if (info.seconds > 0) md += fmt::format(" in {:.1f} s", info.seconds);
  md += ".\n\n";
  if (!info.command.empty()) md += fmt::format("Command: `{}`\n\n", info.command);
  if (passed != results.size()) {
    md += "## Failures\n\n";
    for (const auto& r : results) {
      if (!r.error.empty()) md += fmt::format("- `{}`: error: {}\n", r.name, md_cell(r.error));
      if (r.error.empty() && r.checks.empty()) md += fmt::format("- `{}`: no checks ran\n", r.name);
      for (const auto& c : r.checks) {
        if (!c.pass) {
          md += fmt::format("- `{}`: {}: measured {}, required {}\n", r.name, md_cell(c.name),
                            md_cell(c.measured), md_cell(c.expected));
        }
      }
    }
    md += "\n";
  }
  md += "## Summary\n\n| case | checks | result | seconds |\n|---|---|---|---|\n";
  for (const auto& r : results) {
    md += fmt::format("| {} | {} | {} | {:.2f} |\n", r.name, r.checks.size(),
                      r.pass() ? "pass" : "**FAIL**", r.seconds);
  }
  md += "\n## Checks\n\n| case | check | measured | required | result |\n|---|---|---|---|---|\n";
  for (const auto& r : results) {
    if (!r.error.empty()) {
      md += fmt::format("| {} | (error) | {} | | **FAIL** |\n", r.name, md_cell(r.error));
      continue;
    }
    bool first = true;
    for (const auto& c : r.checks) {
      md += fmt::format("| {} | {} | {} | {} | {} |\n", first ? r.name : "", md_cell(c.name),
                        md_cell(c.measured), md_cell(c.expected), c.pass ? "pass" : "**FAIL**");
      first = false;
    }
  }
  md += "\n## Cases\n\n";
  for (const auto& r : results) {
    md += fmt::format("- `{}` ({:.2f} s, {}): {}\n", r.name, r.seconds,
                      r.pass() ? "pass" : "**FAIL**", md_cell(r.description));
    for (const auto& n : r.notes)
      md += fmt::format("  - {}: {}\n", md_cell(n.name), md_cell(n.value));
  }
  write_file_atomic(dir / "report.md", md);

  std::string js = "{\n";
  js += fmt::format(
      "  \"version\": \"{}\",\n  \"command\": \"{}\",\n  \"seconds\": {:.3f},\n"
      "  \"passed\": {},\n  \"total\": {},\n  \"cases\": [\n",
      kVersion, json_escape(info.command), info.seconds, passed, results.size());
  for (std::size_t i = 0; i < results.size(); ++i) {
    const auto& r = results[i];
    js += fmt::format(
        "    {{\"name\": \"{}\", \"description\": \"{}\", \"pass\": {}, "
        "\"seconds\": {:.4f}, \"error\": \"{}\",\n     \"checks\": [",
        json_escape(r.name), json_escape(r.description), r.pass() ? "true" : "false", r.seconds,
        json_escape(r.error));
    for (std::size_t k = 0; k < r.checks.size(); ++k) {
      const auto& c = r.checks[k];
      js += fmt::format(
          "{}{{\"name\": \"{}\", \"measured\": \"{}\", \"required\": \"{}\", \"pass\": {}}}",
          k ? ",\n       " : "\n       ", json_escape(c.name), json_escape(c.measured),
          json_escape(c.expected), c.pass ? "true" : "false");
    }
    js += "],\n     \"notes\": [";
    for (std::size_t k = 0; k < r.notes.size(); ++k) {
      js += fmt::format("{}{{\"name\": \"{}\", \"value\": \"{}\"}}", k ? ",\n       " : "\n       ",
                        json_escape(r.notes[k].name), json_escape(r.notes[k].value));
    }
    js += fmt::format("]}}{}\n", i + 1 < results.size() ? "," : "");
  }
  js += "  ]\n}\n";
  write_file_atomic(dir / "report.json", js);
}

}  // namespace isoforge::verify
