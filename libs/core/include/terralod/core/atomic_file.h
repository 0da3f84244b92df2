#pragma once
// An output file that appears complete or not at all. Bytes go to a temporary file in the
// target's directory; commit() syncs it and links or renames it over the target. Until then
// an existing file at the target is untouched; an error or a destroyed uncommitted AtomicFile
// removes the temporary file, so nothing partial is ever left behind.
//
// Where the file system allows (Linux O_TMPFILE: ext4, XFS, btrfs, tmpfs) the temporary file
// has no name at all until commit(), so a process killed at any point (SIGKILL, power loss)
// leaves nothing behind either. Elsewhere it is a hidden `.<name>.partial-XXXXXX` beside the
// target, which a killed process leaves behind (never at the target's path).

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "terralod/core/result.h"

namespace terralod {

class AtomicFile {
 public:
  enum class Temporary {
    kUnnamedIfPossible,  ///< O_TMPFILE where supported, else a named temporary file
    kNamed,              ///< always a hidden named file (the fallback, for tests)
  };

  /// Opens the temporary file. Fails with a message naming `path` when the target is a
  /// directory, its directory is missing, or it is not writable.
  static Result<AtomicFile> create(const std::string& path,
                                   Temporary temporary = Temporary::kUnnamedIfPossible);
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
  /// kSynced: the file and its name survive a crash once commit() returns. kUnsynced: only
  /// atomic (the name appears with the whole file), for files that are checked on reading and
  /// made again when lost (a staged build's hand-overs between jobs); skips two fsyncs.
  enum class Durability { kSynced, kUnsynced };
  /// Flushes, (syncs) and puts the file in place, then (syncs) the directory. Call once, after
  /// the last write.
  Status commit(Durability durability = Durability::kSynced);

  const std::string& path() const { return mPath; }
  uint64_t bytesWritten() const { return mBytes; }
  /// Whether the temporary file has no name (O_TMPFILE).
  bool unnamed() const { return mTempPath.empty(); }

 private:
  AtomicFile(std::string path, std::string tempPath, int fd);
  Status flush();
  Status writeAll(const uint8_t* data, size_t size);
  Status linkIntoPlace();

  std::string mPath, mTempPath;  ///< mTempPath is empty for an unnamed temporary file
  int mFd = -1;
  uint64_t mBytes = 0;
  std::vector<uint8_t> mBuffer;
  bool mCommitted = false;
};

}  // namespace terralod
