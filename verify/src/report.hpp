#pragma once
// Writes the verification report: report.md (a table a person reads) and report.json.

#include <filesystem>
#include <vector>

#include "catalogue.hpp"

namespace isoforge::verify {

void write_report(const std::filesystem::path& dir, const std::vector<CaseResult>& results);

}  // namespace isoforge::verify
