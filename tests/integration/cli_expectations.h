#pragma once
// What every integration test expects of a failed command, and of the files it leaves.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "cli_runner.h"

namespace terralod::test {

/// Exit status 1 and exactly one stderr line, "terralod: error: ...", containing `expected`.
inline void expectOneErrorLine(const RunResult& r, const std::string& expected) {
  EXPECT_EQ(r.exitCode, 1);
  const auto lines = r.errLines();
  ASSERT_EQ(lines.size(), 1u) << r.err;
  EXPECT_EQ(lines[0].rfind("terralod: error: ", 0), 0u) << lines[0];
  EXPECT_NE(lines[0].find(expected), std::string::npos) << lines[0];
}

/// The names in a directory, sorted (to compare before and after a failed command).
inline std::vector<std::string> filesIn(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace terralod::test
