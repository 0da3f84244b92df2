#pragma once
// Test scaffolding shared by every test executable: scratch directories, test data paths, and
// reading a whole file.

#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>

namespace terralod::test {

/// A fresh empty directory under /tmp, removed with everything in it when the object goes away.
class TempDir {
 public:
  TempDir() {
    char name[] = "/tmp/terralod-test-XXXXXX";
    mPath = mkdtemp(name);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(mPath, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return mPath; }
  std::string file(const std::string& name) const { return (mPath / name).string(); }

 private:
  std::filesystem::path mPath;
};

/// A file under tests/data.
inline std::string testData(const std::string& name) {
  return std::string(TERRALOD_TEST_DATA) + "/" + name;
}

/// A whole file's bytes (empty when it cannot be read).
inline std::string readWholeFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace terralod::test
