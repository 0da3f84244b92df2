// Fuzzes the chunk geometry decoder (decodeChunk): zstd frame, payload header, part headers,
// meshoptimizer's vertex and index streams. Input: one mode byte, then the data. With mode bit
// 0 clear the data is the stored blob as it is; with it set the data is the decompressed
// payload, which the harness compresses first, so mutations reach the payload's fields
// instead of breaking the zstd frame.

#include <zstd.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "terralod/format/chunk_codec.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const std::span<const uint8_t> input(data + 1, size - 1);
  std::vector<uint8_t> blob(input.begin(), input.end());
  if (data[0] & 1) {
    static ZSTD_CCtx* const context = ZSTD_createCCtx();  // one for the process: fast inputs
    blob.resize(ZSTD_compressBound(input.size()));
    const size_t n =
        ZSTD_compressCCtx(context, blob.data(), blob.size(), input.data(), input.size(), 1);
    if (ZSTD_isError(n)) __builtin_trap();
    blob.resize(n);
  }
  auto chunk = terralod::decodeChunk(blob, "fuzz chunk");
  if (!chunk) return 0;
  // What the decoder promises a renderer: every index names a vertex of its part.
  for (const terralod::ChunkPart& part : chunk->parts) {
    if (part.surfaceIndexCount > part.indices.size() || part.indices.size() % 3 != 0)
      __builtin_trap();
    for (uint32_t index : part.indices)
      if (index >= part.vertices.size()) __builtin_trap();
  }
  return 0;
}
