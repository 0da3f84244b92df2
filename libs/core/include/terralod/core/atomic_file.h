#pragma once
// An output file that appears complete or not at all: bytes go to a hidden temporary file
// beside the target, and commit() syncs it and renames it over the target. Until then an
// existing file at the target is untouched; an error or a destroyed uncommitted AtomicFile
// removes the temporary file, so nothing partial is ever left behind.

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "terralod/core/result.h"

namespace terralod {

class AtomicFile {
 public:
  /// Opens the temporary file. Fails with a message naming `path` when the target is a
  /// directory, its directory is missing, or it is not writable.
  static Result<AtomicFile> create(const std::string& path);
  ~AtomicFile();  ///< removes the temporary file unless commit() succeeded
  AtomicFile(AtomicFile&& other) noexcept;
  AtomicFile& operator=(AtomicFile&&) = delete;
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  /// Appends bytes (buffered). Not thread-safe.
  Status write(std::span<const uint8_t> bytes);
  Status write(std::string_view text) {
    return write(std::span(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
  }
  /// Overwrites bytes already written, at `offset` (e.g. a header filled in last). Not
  /// thread-safe.
  Status writeAt(uint64_t offset, std::span<const uint8_t> bytes);
  /// Flushes, syncs and renames the file into place, then syncs the directory so the rename
  /// survives a crash. Call once, after the last write.
  Status commit();

  const std::string& path() const { return mPath; }
  uint64_t bytesWritten() const { return mBytes; }

 private:
  AtomicFile(std::string path, std::string tempPath, int fd);
  Status flush();
  Status writeAll(const uint8_t* data, size_t size);

  std::string mPath, mTempPath;
  int mFd = -1;
  uint64_t mBytes = 0;
  std::vector<uint8_t> mBuffer;
  bool mCommitted = false;
};

}  // namespace terralod
