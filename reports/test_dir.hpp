#pragma once
// Test-only helper: a fresh directory under $ORTHOSONAR_TEST_OUT (set by ctest) or the
// system temp dir, never the working directory.
#include <cstdlib>
#include <filesystem>
#include <string>

namespace orthosonar::reports::testing {

inline std::filesystem::path test_dir(const std::string& name) {
  const char* env = std::getenv("ORTHOSONAR_TEST_OUT");
  const std::filesystem::path base =
      env && *env ? std::filesystem::path(env) : std::filesystem::temp_directory_path() / "orthosonar_test_out";
  const auto dir = base / "reports" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace orthosonar::reports::testing
