#pragma once
// Writes a tileset atomically: everything goes to a temporary file beside the target (unnamed
// where the file system allows; AtomicFile), whose header stays zero (so it never looks like a
// tileset) until finish() writes the tables and header, syncs, and puts it in place of the
// target. An interrupted build leaves no file that opens as valid, and never touches an
// existing output before the new one is complete.

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "terralod/core/atomic_file.h"
#include "terralod/format/tileset_format.h"

namespace terralod {

class TilesetWriter {
 public:
  /// Fails with a clear message when the target's directory is missing or not writable.
  static Result<std::unique_ptr<TilesetWriter>> create(const std::string& path);
  ~TilesetWriter() = default;  ///< removes the temporary file unless finish() succeeded
  TilesetWriter(const TilesetWriter&) = delete;
  TilesetWriter& operator=(const TilesetWriter&) = delete;

  /// Appends a chunk blob; returns its offset. Not thread-safe.
  Result<uint64_t> appendBlob(std::span<const uint8_t> bytes);

  /// Completes the file. Fills in the offsets, sizes and CRCs of the header.
  Status finish(TilesetHeader header, const std::vector<NodeRecord>& nodes,
                const std::string& metadata);

  const std::string& path() const { return mFile.path(); }

 private:
  explicit TilesetWriter(AtomicFile file) : mFile(std::move(file)) {}

  AtomicFile mFile;
};

}  // namespace terralod
