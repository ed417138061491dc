#pragma once
// Writes the verification report: report.md (a table a person reads) and report.json.

#include <filesystem>
#include <string>
#include <vector>

#include "catalogue.hpp"

namespace isoforge::verify {

/// What produced the results: the command line and the total run time.
struct RunInfo {
  std::string command;
  double seconds = 0;
};

/// Writes dir/report.md (summary, failures, one table row per check, then each case's
/// description, time and notes) and dir/report.json (the same data). Creates `dir`.
void write_report(const std::filesystem::path& dir, const std::vector<CaseResult>& results,
                  const RunInfo& info = {});

}  // namespace isoforge::verify
