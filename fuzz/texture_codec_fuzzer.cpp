// Fuzzes the texture blob decoder (decodeTexture): header, CRC, layer headers, mip sizes.
// Input: one mode byte, then the blob. Unless mode bit 0 is set the harness writes the blob's
// CRC-32 (bytes [12, end) into bytes 8..11) first, so mutations reach the fields behind it.

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "terralod/format/texture_codec.h"
#include "terralod/format/tileset_format.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  std::vector<uint8_t> blob(data + 1, data + size);
  if (!(data[0] & 1) && blob.size() >= 12) {
    const uint32_t crc = terralod::crc32Of(std::span(blob).subspan(12));
    std::memcpy(blob.data() + 8, &crc, sizeof crc);
  }
  auto texture = terralod::decodeTexture(blob, "fuzz texture");
  if (!texture) return 0;
  // What the decoder promises an uploader: every mip holds exactly its blocks.
  for (const terralod::TextureLayer& layer : texture->layers) {
    if (layer.mips.size() != terralod::mipCount(layer.size)) __builtin_trap();
    for (uint32_t m = 0; m < layer.mips.size(); ++m)
      if (layer.mips[m].size() != terralod::mipBytes(layer.encoding, layer.size, m))
        __builtin_trap();
  }
  return 0;
}
