#pragma once
// One zstd frame holding `raw` (recording its content size, no checksum: the blobs' CRCs cover
// them): how chunk blobs of every kind are stored.

#include <zstd.h>

#include <cassert>
#include <cstdint>
#include <span>
#include <vector>

namespace terralod {

inline std::vector<uint8_t> zstdFrame(std::span<const uint8_t> raw, int level) {
  std::vector<uint8_t> frame(ZSTD_compressBound(raw.size()));
  const size_t n = ZSTD_compress(frame.data(), frame.size(), raw.data(), raw.size(), level);
  assert(!ZSTD_isError(n));
  frame.resize(n);
  return frame;
}

}  // namespace terralod
