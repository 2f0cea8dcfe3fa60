// Helpers shared by the tests: where the third-party meshes are, and a way to
// skip a test with a message when they are absent (a user's machine).
#pragma once
#include <doctest/doctest.h>

#include <filesystem>
#include <string>

namespace anisurf::test {

// Path of a file in ../shared (meshes/, bench/inputs/ ...), or "" if absent.
inline std::string shared_file(const std::string& relative) {
  std::filesystem::path p = std::filesystem::path(ANISURF_SHARED_DIR) / relative;
  return std::filesystem::exists(p) ? p.string() : std::string();
}
// Path of a file under tests/data.
inline std::string data_file(const std::string& relative) {
  return (std::filesystem::path(ANISURF_TEST_DATA_DIR) / relative).string();
}
// A fresh temporary directory for a test's outputs.
inline std::filesystem::path temp_dir(const std::string& name) {
  auto d = std::filesystem::temp_directory_path() / ("anisurf_test_" + name);
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

}  // namespace anisurf::test

// Skips the rest of a test case (with a message) if a shared file is missing.
#define ANISURF_REQUIRE_SHARED(var, rel)                                   \
  const std::string var = ::anisurf::test::shared_file(rel);               \
  if (var.empty()) {                                                        \
    MESSAGE("skipped: ../shared/" rel " not found (no shared test data)"); \
    return;                                                                 \
  }
