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
      case '"': o += "\\\""; break;
      case '\\': o += "\\\\"; break;
      case '\n': o += "\\n"; break;
      case '\t': o += "\\t"; break;
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
  for (char c : s) o += (c == '|') ? std::string("\\|") : (c == '\n' ? std::string(" ") : std::string(1, c));
  return o;
}

}  // namespace

void write_report(const std::filesystem::path& dir, const std::vector<CaseResult>& results) {
  std::filesystem::create_directories(dir);
  std::size_t passed = 0;
  for (const auto& r : results) passed += r.pass() ? 1 : 0;

  std::string md;
  md += fmt::format("# isoforge verification report\n\nisoforge {} — {} of {} cases passed.\n\n",
                    kVersion, passed, results.size());
  md += "| case | check | measured | required | result |\n|---|---|---|---|---|\n";
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
    md += fmt::format("- `{}` ({:.2f} s): {}\n", r.name, r.seconds, r.description);
  }
  write_file_atomic(dir / "report.md", md);

  std::string js = "{\n";
  js += fmt::format("  \"version\": \"{}\",\n  \"passed\": {},\n  \"total\": {},\n  \"cases\": [\n",
                    kVersion, passed, results.size());
  for (std::size_t i = 0; i < results.size(); ++i) {
    const auto& r = results[i];
    js += fmt::format("    {{\"name\": \"{}\", \"pass\": {}, \"seconds\": {:.4f}, \"error\": \"{}\", \"checks\": [",
                      json_escape(r.name), r.pass() ? "true" : "false", r.seconds, json_escape(r.error));
    for (std::size_t k = 0; k < r.checks.size(); ++k) {
      const auto& c = r.checks[k];
      js += fmt::format("{}{{\"name\": \"{}\", \"measured\": \"{}\", \"required\": \"{}\", \"pass\": {}}}",
                        k ? ", " : "", json_escape(c.name), json_escape(c.measured),
                        json_escape(c.expected), c.pass ? "true" : "false");
    }
    js += fmt::format("]}}{}\n", i + 1 < results.size() ? "," : "");
  }
  js += "  ]\n}\n";
  write_file_atomic(dir / "report.json", js);
}

}  // namespace isoforge::verify
