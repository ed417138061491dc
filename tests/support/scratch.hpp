#pragma once
// Per-test scratch directories and the checked-in data. ctest runs every test case as its own
// process, in parallel, so two cases must never share a directory: the path includes the running
// test's full name.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace isoforge::test {

/// "Suite.Name/param" of the running test, with characters unsafe in paths replaced by '_'.
inline std::string current_test_id() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string id = info ? std::string(info->test_suite_name()) + "." + info->name() : "no_test";
  for (char& c : id) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '.' || c == '-' || c == '_';
    if (!ok) c = '_';
  }
  return id;
}

/// A fresh, empty directory ISOFORGE_TEST_TMP/<module>/<test id>/<name>.
inline std::filesystem::path scratch_dir(const std::string& module, const std::string& name) {
  const auto dir = std::filesystem::path(ISOFORGE_TEST_TMP) / module / current_test_id() / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// A file of the checked-in data/ directory.
inline std::filesystem::path data_path(const std::string& name) {
  return std::filesystem::path(ISOFORGE_DATA_DIR) / name;
}

/// The whole content of a file (empty if it cannot be read).
inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace isoforge::test
