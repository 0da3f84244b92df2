#pragma once
// Test inputs that are slow to make (a tileset built from a DEM) and the same for many tests:
// made once per build of the program that makes them, and shared by every test process of a
// `make test` (gtest_discover_tests runs each test in its own process, so a suite's
// SetUpTestSuite alone would make them once per test).

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <filesystem>
#include <functional>
#include <string>
#include <system_error>

#include "temp_dir.h"

namespace terralod::test {

/// What identifies a program's build: its size and modification time. A directory made by it
/// is made again when it is rebuilt.
inline std::string programStamp(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto size = fs::file_size(path, ec);
  const auto time = fs::last_write_time(path, ec).time_since_epoch().count();
  return std::to_string(size) + "-" + std::to_string(time);
}

/// The running test program's stamp (for inputs it makes in-process).
inline std::string selfStamp() {
  std::error_code ec;
  return programStamp(std::filesystem::read_symlink("/proc/self/exe", ec).string());
}

struct SharedDirectory {
  std::filesystem::path path;
  std::string error;  ///< empty when `path` holds what `make` made
  std::string file(const std::string& name) const { return (path / name).string(); }
};

/// The directory `name` made by `make(dir)` (which fills a fresh, empty `dir` and returns ""
/// or an error message) for `stamp` (the inputs and the maker's build): the first caller makes
/// it, in a scratch directory renamed into place, while callers in other processes wait on a
/// lock and then reuse it. It lives in the build tree's test cache (TERRALOD_TEST_CACHE);
/// directories of the same name with another stamp are removed. Tests must not modify it.
inline SharedDirectory sharedDirectory(const std::string& name, const std::string& stamp,
                                       const std::function<std::string(const std::string&)>& make) {
  namespace fs = std::filesystem;
  const fs::path cache = TERRALOD_TEST_CACHE;
  std::error_code ec;
  fs::create_directories(cache, ec);
  const std::string key = name + "@" + std::to_string(std::hash<std::string>{}(stamp));
  const fs::path lockPath = cache / (name + ".lock");
  const int lock = open(lockPath.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
  if (lock < 0) return {{}, "cannot open " + lockPath.string()};
  flock(lock, LOCK_EX);  // released by close, or by the kernel if this process dies
  SharedDirectory result{cache / key, {}};
  if (!fs::exists(result.path / ".complete")) {
    for (const auto& e : fs::directory_iterator(cache, ec))
      if (e.path().filename().string().starts_with(name + "@")) fs::remove_all(e.path(), ec);
    const fs::path scratch = cache / (key + ".making");
    fs::remove_all(scratch, ec);
    fs::create_directories(scratch, ec);
    result.error = make(scratch.string());
    if (result.error.empty()) {
      fs::rename(scratch, result.path, ec);
      // The marker last: a directory without it (a maker killed half-way) is made again.
      if (!ec)
        close(open((result.path / ".complete").c_str(), O_CREAT | O_WRONLY | O_CLOEXEC, 0644));
      if (ec) result.error = "cannot rename " + scratch.string() + ": " + ec.message();
    }
    fs::remove_all(scratch, ec);
  }
  close(lock);
  return result;
}

}  // namespace terralod::test
