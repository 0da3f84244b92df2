#pragma once
// Random-access byte sources a tileset is read from. The runtime only ever asks for ranges
// (header, node table, one chunk blob), so a file, a memory buffer and an HTTP server with
// range requests all look the same.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "terralod/core/result.h"

namespace terralod {

class ByteSource {
 public:
  virtual ~ByteSource() = default;
  /// Total size in bytes.
  virtual uint64_t size() const = 0;
  /// Reads exactly `length` bytes at `offset`; fails (never short-reads) past the end.
  /// Thread-safe.
  virtual Result<std::vector<uint8_t>> read(uint64_t offset, uint64_t length) const = 0;
  /// A name for error messages (path or URL).
  virtual const std::string& name() const = 0;
};

/// A local file read with pread.
Result<std::unique_ptr<ByteSource>> openFileSource(const std::string& path);

/// A buffer in memory (tests, fuzzing).
std::unique_ptr<ByteSource> makeMemorySource(std::vector<uint8_t> bytes, std::string name);

}  // namespace terralod
