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

/// What a source has done so far, for benchmarks and diagnostics. Sources that do not count
/// (file, memory) report zeros.
struct SourceStats {
  uint64_t bytesRead = 0;  ///< payload bytes received, also by attempts that were retried
  uint64_t requests = 0;   ///< requests sent (HTTP: every attempt, the size probe included)
  uint64_t retries = 0;    ///< attempts repeated after a transient failure
  uint64_t failures = 0;   ///< read calls that returned an error
};

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
  /// Counters since the source was opened. Thread-safe.
  virtual SourceStats stats() const { return {}; }
};

/// A local file read with pread.
Result<std::unique_ptr<ByteSource>> openFileSource(const std::string& path);

/// A buffer in memory (tests, fuzzing).
std::unique_ptr<ByteSource> makeMemorySource(std::vector<uint8_t> bytes, std::string name);

}  // namespace terralod
