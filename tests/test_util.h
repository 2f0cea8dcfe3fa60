// Helpers shared by the tests: where the third-party meshes are, and a way to
// skip a test with a message when they are absent (a user's machine).
#pragma once
#include <doctest/doctest.h>

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "geometry/parallel_chunks.h"

namespace anisurf::test {

// The engine's thread limit (parallel_chunks.h) set for a scope, restored
// at its end: a test compares results on one thread and on several.
struct ThreadLimitScope {
  int saved = thread_limit().load();
  explicit ThreadLimitScope(int n) { thread_limit() = n; }
  ~ThreadLimitScope() { thread_limit() = saved; }
};

// Path of a file in ../shared (meshes/, bench/inputs/ ...), or "" if absent.
inline std::string shared_file(const std::string& relative) {
  std::filesystem::path p = std::filesystem::path(ANISURF_SHARED_DIR) / relative;
  return std::filesystem::exists(p) ? p.string() : std::string();
}
// Path of a file under tests/data.
inline std::string data_file(const std::string& relative) {
  return (std::filesystem::path(ANISURF_TEST_DATA_DIR) / relative).string();
}
// Path of a file of the project's assets/ (the demo).
inline std::string asset_file(const std::string& name) {
  return (std::filesystem::path(ANISURF_TEST_DATA_DIR) / ".." / ".." / "assets" / name).lexically_normal().string();
}
// The bytes of a file ("" if it cannot be read).
inline std::string file_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
// A fresh temporary directory for a test's outputs.
inline std::filesystem::path temp_dir(const std::string& name) {
  auto d = std::filesystem::temp_directory_path() / ("anisurf_test_" + name);
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

// Runs a shell command and returns its standard output; *exit_code gets the
// command's exit code (-1 if it did not exit normally or could not start).
inline std::string capture(const std::string& cmd, int* exit_code = nullptr) {
  std::string out;
  if (exit_code) *exit_code = -1;
  FILE* f = popen(cmd.c_str(), "r");
  if (!f) return out;
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) out.append(buf, n);
  const int status = pclose(f);
  if (exit_code) *exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

// The lines a terminal shows after `text`: '\r' returns to the start of the
// line and overwrites, '\n' (or "\r\n") starts a new line; trailing spaces
// dropped. The last element is what follows the last '\n'.
inline std::vector<std::string> render_terminal(const std::string& text) {
  std::vector<std::string> lines(1);
  std::size_t col = 0;
  for (char c : text) {
    if (c == '\r') {
      col = 0;
    } else if (c == '\n') {
      lines.emplace_back();
      col = 0;
    } else {
      std::string& l = lines.back();
      if (col < l.size())
        l[col] = c;
      else
        l.push_back(c);
      ++col;
    }
  }
  for (auto& l : lines)
    while (!l.empty() && l.back() == ' ') l.pop_back();
  return lines;
}

}  // namespace anisurf::test

// Skips the rest of a test case (with a message) if a shared file is missing.
#define ANISURF_REQUIRE_SHARED(var, rel)                                   \
  const std::string var = ::anisurf::test::shared_file(rel);               \
  if (var.empty()) {                                                        \
    MESSAGE("skipped: ../shared/" rel " not found (no shared test data)"); \
    return;                                                                 \
  }
