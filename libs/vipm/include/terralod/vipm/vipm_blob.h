#pragma once
// A stored VIPM chunk made ready to draw or measure: decoded (format/vipm_chunk_codec.h),
// unpacked and reconstructed (vipm_levels.h) in one call, as every reader of the blobs does.

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/format/vipm_chunk_codec.h"
#include "terralod/vipm/vipm_levels.h"
#include "terralod/vipm/vipm_storage.h"

namespace terralod {

struct LoadedVipmChunk {
  VipmChunkData data;
  UnpackedChunk unpacked;
  VipmLevels levels;  ///< at the finest level
};

/// Fails with "<subject>: corrupt VIPM chunk: <problem>" when the blob does not decode or its
/// collapses do not replay. `fade`: as VipmLevels::reconstruct.
Result<LoadedVipmChunk> loadVipmChunk(std::span<const uint8_t> blob, const std::string& subject,
                                      MaterialFade fade = MaterialFade::kKeep);

/// Per vertex: grid x, grid y and the height above data.zBase, as the renderer holds them
/// (single precision keeps the stored steps exactly above the base; absolute heights would not).
std::vector<std::array<float, 3>> positionsAboveBase(const LoadedVipmChunk& chunk);

}  // namespace terralod
