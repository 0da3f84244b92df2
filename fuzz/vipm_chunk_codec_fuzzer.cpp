// Fuzzes the VIPM chunk decoder (decodeVipmChunk) and what a loader thread does next with a
// blob that decodes: unpacking and the O(n) reconstruction of its index buffers, which must
// refuse inconsistent collapse orders rather than misbehave. Input: one mode byte, then the
// data. With mode bit 0 clear the data is the stored blob; with it set the data is the
// decompressed payload, which the harness compresses first (as chunk_codec_fuzzer does).

#include <zstd.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "terralod/format/vipm_chunk_codec.h"
#include "terralod/vipm/vipm_levels.h"
#include "terralod/vipm/vipm_storage.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const std::span<const uint8_t> input(data + 1, size - 1);
  std::vector<uint8_t> blob(input.begin(), input.end());
  if (data[0] & 1) {
    static ZSTD_CCtx* const context = ZSTD_createCCtx();
    blob.resize(ZSTD_compressBound(input.size()));
    const size_t n =
        ZSTD_compressCCtx(context, blob.data(), blob.size(), input.data(), input.size(), 1);
    if (ZSTD_isError(n)) __builtin_trap();
    blob.resize(n);
  }
  auto chunk = terralod::decodeVipmChunk(blob, "fuzz chunk");
  if (!chunk) return 0;
  const terralod::UnpackedChunk unpacked = terralod::unpackChunk(*chunk);
  auto levels = terralod::VipmLevels::reconstruct(unpacked.mesh, unpacked.materials);
  if (!levels) return 0;
  // What reconstruction promises a renderer: at every level, each part's drawn indices name
  // active vertices.
  const uint32_t r = levels->collapseCount();
  for (uint32_t j : {r, r / 2, 0u}) {
    levels->setApplied(j);
    for (const terralod::VipmPart& part : levels->parts()) {
      const uint32_t drawn = levels->drawnTriangles(part);
      if (size_t(drawn) * 3 > part.indices.size()) __builtin_trap();
      for (uint32_t i = 0; i < 3 * drawn; ++i)
        if (part.indices[i] >= levels->activeVertices()) __builtin_trap();
    }
  }
  return 0;
}
